#!/usr/bin/env bash
# The same runs, longer: `--horizon-span 256` puts the first checkpoint at
# t_su + 256 t_s (the default's cap) and the later ones at 512 and
# 1024 t_s. (a) Morris's kernel at Re = 30, c0 = 10 U, cfl 0.5: on the
# square lattice at 17/10, the twelve lowest of seeds.sh's seeds 4-40 that
# stopped at the default's first checkpoint (t = 1485); on the triangular
# lattice at 13/10, seeds 1-3 (the CFL factor's grid's). (b) The empirical
# search's scenes, Monaghan's kernel at N = 10: Re = 1 at 28 U (the
# disordered bracket) and Re = 10 at 10 U, seeds 1-3. (c) The report's two
# discretisations (triangular at h = d, square at 13/10) for every kernel
# at Re = 30, c0 = 10 U, cfl 0.5, seeds 1-3 (the grid's). Each run's JSON
# and its timeseries.csv in OUT/NAME/.
#
# usage: longer.sh SHEARSPH OUT [JOBS]   (one thread a run)
set -euo pipefail
bin=$1 out=$2 jobs=${3:-2}
mkdir -p "$out"
{
  for s in 4 5 8 11 12 13 15 17 18 19 20 21; do echo "morris square 17/10 30 10 $s"; done
  for s in 1 2 3; do echo "morris triangular 13/10 30 10 $s"; done
  for s in 1 2 3; do echo "monaghan triangular 1 1 28 $s"; echo "monaghan triangular 1 10 10 $s"; done
  for k in monaghan morris wendland_c2 composite; do
    for s in 1 2 3; do echo "$k triangular 1 30 10 $s"; echo "$k square 13/10 30 10 $s"; done
  done
} | xargs -P "$jobs" -L 1 bash -c '
  k=$0 lat=$1 hd=$2 re=$3 c0=$4 s=$5
  name="$k-$lat-${hd/\//_}-re$re-c0$c0-seed$s"
  dest="'"$out"'/$name"
  [ -s "$dest/run.json" ] && exit 0
  RAYON_NUM_THREADS=1 "'"$bin"'" run --kernel "$k" --lattice "$lat" --h-over-d "$hd" \
    --n 10 --re "$re" --c0 "$c0" --cfl 0.5 --jitter 0.05 --jitter-seed "$s" \
    --horizon stationary --horizon-span 256 --out "$dest" --force --quiet --json \
    --no-particles > "$dest.json" || true
  mv "$dest.json" "$dest/run.json"
'
