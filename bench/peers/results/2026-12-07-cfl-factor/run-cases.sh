#!/usr/bin/env bash
# Runs the cases on stdin, one a line, "KERNEL LATTICE H_OVER_D RE C0 CFL
# SEED" (seed 0 the perfect lattice, else a 0.05 d jitter of that seed),
# N = 10, each to its stationary window on one thread, JOBS at a time; one
# JSON a run in OUT/runs, a run already there kept. cfl-grid.sh's cases, and
# ../2026-12-07-cfl-drifts/seeds.sh's.
#
# usage: ... | run-cases.sh SHEARSPH OUT [JOBS]
set -euo pipefail
bin=$1 out=$2 jobs=${3:-2}
mkdir -p "$out/runs"
xargs -P "$jobs" -L 1 bash -c '
  k=$0 lat=$1 hd=$2 re=$3 c0=$4 f=$5 s=$6
  name="$k-$lat-${hd/\//_}-re$re-c0$c0-cfl$f-seed$s"
  dest="'"$out"'/runs/$name.json"
  [ -s "$dest" ] && exit 0
  jit=(--jitter 0.05 --jitter-seed "$s"); [ "$s" = 0 ] && jit=()
  tmp=$(mktemp -d)
  RAYON_NUM_THREADS=1 "'"$bin"'" run --kernel "$k" --lattice "$lat" --h-over-d "$hd" \
    --n 10 --re "$re" --c0 "$c0" --cfl "$f" "${jit[@]}" --horizon stationary \
    --out "$tmp" --force --quiet --json --no-particles > "$tmp/run.json" || true
  mv "$tmp/run.json" "$dest"; rm -rf "$tmp"
'
