#!/usr/bin/env bash
# Alternating A/B of two builds on the disordered scene, one thread.
set -u
A=$1; B=$2; OUT=$3; ROUNDS=$4
mkdir -p "$OUT"
for r in $(seq 1 "$ROUNDS"); do
  for w in a b; do
    if [ $w = a ]; then bin=$A; else bin=$B; fi
    "$bin" bench --disordered --kernels monaghan,composite,wendland_c2,morris --particles 1e3,1e5,1e6 --threads 1 --repeats 1 --no-bandwidth > "$OUT/$w-$r.txt" 2>&1
  done
done
