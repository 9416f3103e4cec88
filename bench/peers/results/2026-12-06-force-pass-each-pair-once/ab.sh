#!/usr/bin/env bash
# main's force pass against the prototype (SHEARSPH_SYMMETRIC_PROTOTYPE), one
# binary built from main with each-pair-once.patch, alternating, 1 thread.
# Usage: ab.sh SHEARSPH_BINARY ROUNDS OUT_DIR; then summarise.py OUT_DIR ROUNDS.
set -euo pipefail
bin=$1; rounds=${2:-3}; out=$3
mkdir -p "$out"
for r in $(seq 1 "$rounds"); do
  for v in main proto; do
    if [ "$v" = proto ]; then export SHEARSPH_SYMMETRIC_PROTOTYPE=1; else unset SHEARSPH_SYMMETRIC_PROTOTYPE; fi
    "$bin" bench --disordered --particles 1e3,1e4,1e5 --threads 1 --repeats 3 --no-bandwidth --quiet > "$out/disordered-$v-$r.txt" 2>&1
  done
done
