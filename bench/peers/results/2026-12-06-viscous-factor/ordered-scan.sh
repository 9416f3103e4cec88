#!/bin/bash
# The start-up from rest at Re = 1, c0 = 2 U (where the viscous limit binds),
# every kernel and shipped discretisation, at viscous factors 0.125-0.35:
# each run's class and its window's mean-flow L_inf / U.
# Usage: SHEARSPH=path/to/shearsph bash ordered-scan.sh > ordered-scan.txt
set -u
B=${SHEARSPH:-shearsph}
out=$(mktemp -d)
for k in monaghan morris wendland_c2 composite; do
  for disc in "triangular 1" "triangular 13/10" "square 1" "square 13/10" "square 17/10"; do
    set -- $disc
    line="$k $1 $2:"
    for f in 0.125 0.15 0.175 0.2 0.225 0.25 0.3 0.35; do
      o=$($B run --kernel $k --lattice $1 --h-over-d $2 --re 1 --c0 2 --viscous-dt $f --out "$out/run" --force 2>&1)
      cls=$(echo "$o" | grep "^class" | awk '{print $2}' | tr -d ':')
      linf=$(echo "$o" | grep -o "mean-flow L_inf / U = [0-9.e+-]*" | awk '{print $NF}')
      line="$line $f=${cls:-ERR}/$linf"
    done
    echo "$line"
  done
done
rm -rf "$out"
