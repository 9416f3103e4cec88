#!/usr/bin/env bash
# Long runs of a jittered start (4 times the default horizon), one thread,
# OLD and NEW alternating, ROUNDS rounds: `run --no-particles --kernel K --n 10
# --re RE --c0 C0 --jitter 0.05 --jitter-seed 1 --t-end 2400` at Re = 1 and
# 28 U (the answer's bracket at Re = 1) and Re = 10 and 10 U, every kernel;
# prints the wall seconds of each run (summary.json's wall_s), its steps and
# rebuilds.
#
#   long-runs.sh OLD_BIN NEW_BIN [ROUNDS=2]
set -euo pipefail
old=${1:?usage: long-runs.sh OLD_BIN NEW_BIN [ROUNDS]} new=${2:?} rounds=${3:-2}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
for r in $(seq "$rounds"); do
  for k in monaghan morris wendland_c2 composite; do
    for case in "1 28" "10 10"; do
      set -- $case
      for side in old new; do
        bin=$old
        [ "$side" = new ] && bin=$new
        RAYON_NUM_THREADS=1 "$bin" run --no-particles --kernel "$k" --n 10 --re "$1" --c0 "$2" \
          --jitter 0.05 --jitter-seed 1 --t-end 2400 --out "$work/run" --force > /dev/null 2>&1 || true
        python3 -c "import json,sys; s=json.load(open(sys.argv[1])); print(sys.argv[2], s['wall_s'], s['steps'], s['neighbour_rebuilds'], s['outcome'])" \
          "$work/run/summary.json" "round $r $k Re=$1 c0=$2 $side"
      done
    done
  done
done
