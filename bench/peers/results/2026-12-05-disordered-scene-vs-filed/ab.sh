#!/bin/bash
# The disordered scene and long disordered runs: FILED (main when the
# disordered scene's speed was first asked for; see README.md) against NOW,
# alternating round by round, 1 thread.
#   FILED=path/to/shearsph-filed NOW=path/to/shearsph OUT=folder ./ab.sh
set -eu
: "${FILED:?} ${NOW:?} ${OUT:=.}"
for r in 1 2; do
  for t in filed now; do
    bin=$FILED; [ $t = now ] && bin=$NOW
    $bin bench --disordered --particles 1e3,1e4,1e5 --threads 1 --repeats 3 > "$OUT/bench-disordered-$t-$r.txt" 2>&1
  done
done
for r in 1 2; do
  for t in filed now; do
    bin=$FILED; [ $t = now ] && bin=$NOW
    /usr/bin/time -f "%e s %M KB" -o "$OUT/bench-1e6-$t-$r.time.txt" \
      $bin bench --disordered --kernels monaghan,composite --particles 1e3,1e6 --threads 1 --repeats 1 > "$OUT/bench-1e6-$t-$r.txt" 2>&1
  done
done
: > "$OUT/long-runs.txt"
for r in 1 2; do
  for k in monaghan morris wendland_c2 composite; do
    for re in 1 10; do
      c0=28; [ $re = 10 ] && c0=10
      for t in filed now; do
        bin=$FILED; [ $t = now ] && bin=$NOW
        run=$(mktemp -d); s=$(date +%s.%N)
        RAYON_NUM_THREADS=1 $bin run --no-particles --out "$run/run" --kernel $k --n 10 --re $re --c0 $c0 \
          --jitter 0.05 --jitter-seed 1 --t-end 2400 >/dev/null 2>&1 || true
        e=$(date +%s.%N)
        echo "$k re$re c0=$c0 round$r $t $(echo "$e - $s" | bc) rebuilds=$(grep -o '"neighbour_rebuilds": *[0-9]*' "$run/run/summary.json" | grep -o '[0-9]*$') steps=$(grep -o '"steps": *[0-9]*' "$run/run/summary.json" | grep -o '[0-9]*$')" >> "$OUT/long-runs.txt"
        rm -r "$run"
      done
    done
  done
done
