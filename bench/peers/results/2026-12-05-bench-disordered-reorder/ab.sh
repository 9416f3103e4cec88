#!/usr/bin/env bash
# Alternating A/B of `bench --disordered` on 1 thread: the band reorder
# (AFTER) against the build before it (BEFORE), ROUNDS rounds, each
# binary's tables kept as round-R-{after,before}-{small,1e6}.txt.
set -euo pipefail
AFTER=${AFTER:?the binary with the reorder}
BEFORE=${BEFORE:?the binary before it}
ROUNDS=${ROUNDS:-2}
for r in $(seq 1 "$ROUNDS"); do
  for v in after before; do
    if [ $v = after ]; then bin=$AFTER; else bin=$BEFORE; fi
    "$bin" bench --disordered --particles 1e3,1e4,1e5 --threads 1 --repeats 3 \
      --no-bandwidth --quiet > "round-$r-$v-small.txt" 2>&1
    "$bin" bench --disordered --particles 1e6 --kernels monaghan,composite \
      --threads 1 --repeats 1 --no-bandwidth --quiet > "round-$r-$v-1e6.txt" 2>&1
  done
done
