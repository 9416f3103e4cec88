#!/usr/bin/env bash
# Every A/B of this folder, in turn, on a quiet machine: BEFORE is main before
# the force pass fused its products (mul_add), AFTER the build with it.
#
#   measure.sh BEFORE_BIN AFTER_BIN
set -euo pipefail
before=${1:?usage: measure.sh BEFORE_BIN AFTER_BIN} after=${2:?}
here=$(cd "$(dirname "$0")" && pwd)
cd "$here"
results=$here/../2026-12-07-lattice-reference
# c0 --empirical, whole process, 2 pairs at Re = 1 and 10.
"$here/../2026-12-06-viscous-default/ab.sh" "$before" "$after" "$here/c0" 2 "1 10" \
  "before (products and sums apart)" "after (fused)" > c0-summary.txt 2>&1
# Long jittered runs to t = 2400, one thread, 2 rounds.
"$results/long-runs.sh" "$before" "$after" 2 > long-runs.txt
# The disordered scene, one thread, 2 alternating rounds.
for r in 1 2; do
  RAYON_NUM_THREADS=1 "$before" bench --disordered --particles 1e3,1e4,1e5 --threads 1 --repeats 3 \
    --no-bandwidth > "bench-disordered-before-$r.txt" 2>&1
  RAYON_NUM_THREADS=1 "$after" bench --disordered --particles 1e3,1e4,1e5 --threads 1 --repeats 3 \
    --no-bandwidth > "bench-disordered-after-$r.txt" 2>&1
done
# The ordered peer scenes.
for t in 1 2; do
  python3 "$here/../../../../scripts/ab-peer-scenes.py" --rounds 5 --threads "$t" "$before" "$after" \
    > "ab-peer-scenes-$t-thread.txt" 2>&1
done
# The search's bench, after alone.
"$after" bench --empirical --repeats 3 > bench-empirical.txt 2>&1
