#!/usr/bin/env bash
# The derived acoustic factor against runs: each kernel and discretisation
# at Re = 30, c0 = 100 U (the CFL limit binds, |v| about 1 % of c0), from
# rest to t = 40 (about 2,000 steps), the perfect lattice and a 0.05 d
# jitter (seed 1), at 0.9, 0.97, 1.03 and 1.1 times the factor `c0` prints
# (cfl_stable). One JSON a run in OUT/runs.
#
# usage: threshold.sh SHEARSPH FACTORS OUT [JOBS]
#   FACTORS: lines "kernel lattice h_over_d factor"
set -euo pipefail
bin=$1 factors=$2 out=$3 jobs=${4:-2}
mkdir -p "$out/runs"
while read -r k lat hd f; do
  for x in 0.9 0.97 1.03 1.1; do
    for s in 0 1; do
      echo "$k $lat $hd $(python3 -c "print(round($f * $x, 4))") $x $s"
    done
  done
done < "$factors" | xargs -P "$jobs" -L 1 bash -c '
  k=$0 lat=$1 hd=$2 cfl=$3 x=$4 s=$5
  dest="'"$out"'/runs/$k-$lat-${hd/\//_}-x$x-seed$s.json"
  [ -s "$dest" ] && exit 0
  jit=(--jitter 0.05 --jitter-seed "$s"); [ "$s" = 0 ] && jit=()
  tmp=$(mktemp -d)
  RAYON_NUM_THREADS=1 "'"$bin"'" run --kernel "$k" --lattice "$lat" --h-over-d "$hd" \
    --n 10 --re 30 --c0 100 --cfl "$cfl" "${jit[@]}" --t-end 40 \
    --out "$tmp" --force --quiet --json --no-particles > "$tmp/run.json" 2>/dev/null || true
  mv "$tmp/run.json" "$dest"; rm -rf "$tmp"
'
