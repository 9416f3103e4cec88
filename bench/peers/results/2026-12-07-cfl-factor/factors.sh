#!/usr/bin/env bash
# The derived CFL factor of every kernel and discretisation, as `c0` prints
# it (cfl_stable): lines "kernel lattice h_over_d factor" for threshold.sh.
#
# usage: factors.sh SHEARSPH > factors.txt
set -euo pipefail
bin=$1
for k in composite monaghan morris wendland_c2; do
  for disc in "triangular 1" "triangular 13/10" "square 1" "square 13/10" "square 17/10"; do
    set -- $disc
    f=$("$bin" c0 --kernel "$k" --lattice "$1" --h-over-d "$2" --c0 10 --json |
      python3 -c 'import json, sys; print(json.load(sys.stdin)["cfl_stable"])')
    echo "$k $1 $2 $f"
  done
done
