#!/usr/bin/env bash
# `c0 --empirical` for Monaghan's kernel at N = 10, Re = 1 at the default
# factor 0.5 and at half its derived stable factor (0.92985 = 1.85969 / 2,
# `c0 --json`'s cfl_stable), the two alternating, 2 rounds, nothing else
# running: what a default of half each discretisation's derived factor
# would cost and give where the empirical search is slowest.
#
# usage: SHEARSPH=... re1.sh
set -euo pipefail
cd "$(dirname "$0")"
for round in 1 2; do
  for f in 0.5 0.9298452715689394; do
    tag=re1-cfl${f:0:6}-r$round
    /usr/bin/time -f "$tag: %e wall %U user %S sys" -a -o times.txt \
      "${SHEARSPH:-shearsph}" c0 --kernel monaghan --n 10 --re 1 --empirical --json \
      --quiet --cfl "$f" > "c0-$tag.json" || true
    gzip -9f "c0-$tag.json"
  done
done
