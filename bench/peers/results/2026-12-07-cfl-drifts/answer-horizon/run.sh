#!/usr/bin/env bash
# The empirical answer for Morris's kernel on the square lattice at 17/10,
# N = 10, Re = 30, at the default horizon (64 shear times) and at four
# times it, side by side (one thread each), at the CFL factor 0.5 (the
# default when these ran; `--cfl 0.5` keeps them so).
#
# usage: run.sh SHEARSPH OUT
set -euo pipefail
bin=$1 out=$2
mkdir -p "$out"
for sp in 64 256; do
  RAYON_NUM_THREADS=1 "$bin" c0 --kernel morris --lattice square --h-over-d 17/10 --n 10 \
    --re 30 --cfl 0.5 --empirical --no-rules --horizon-span "$sp" --json --quiet > "$out/span$sp.json" &
done
wait
