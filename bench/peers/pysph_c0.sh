#!/usr/bin/env bash
# shearsph's `c0 --empirical` scene in shearsph and in PySPH 1.0b2 with
# shearsph's scheme rebuilt equation by equation (pysph_c0.py says which and
# every difference): Monaghan cubic spline, square lattice h = d, N = 10,
# alpha 0.1, walls at rest, starts jittered by 0.05 d (seeds 1.., the same
# SplitMix64 lattice in both codes), a ladder of c0. Per rung and seed,
# shearsph runs first with `--horizon stationary` (docs/stationary.md), then
# PySPH runs to the same end time and is judged on the same window (the
# later half after the start-up) by the same statistics: eps_stat, the
# window mean of the 99th percentile of rho/rho0 - 1 over the fluid per
# frame (frames every B / 4U); linf_stat, the largest over the bands of the
# window-mean band velocity error against the start-up series, in U.
# Optional, not part of cargo test. Then pysph_c0_table.py prints the
# table, each code's class per rung and each code's fit
# eps_stat - eps0 = k (U / c0)^m over the ladder.
#
# usage: bench/peers/pysph_c0.sh
# environment:
#   OUT     results folder (default target/peers/pysph-c0); per run
#           shearsph-re*-c*-s*.json (its summary) and pysph-re*-c*-s*.json,
#           pysph-*.csv (PySPH's frames); runs.jsonl, table.txt
#   RES     Reynolds numbers (default "1 10")
#   C0S     the c0 ladder in U (default "10 17.8 31.6 56.2")
#   SEEDS   jitter seeds (default "1 2")
#   JOBS    runs at a time (default 2); PySPH and shearsph run under
#           nice -n 10, PySPH on one thread (OMP_NUM_THREADS=1)
#   SHEARSPH  the binary (default: target/release/shearsph, built here)
set -euo pipefail

HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
OUT=${OUT:-$ROOT/target/peers/pysph-c0}
RES=${RES:-1 10}
C0S=${C0S:-10 17.8 31.6 56.2}
SEEDS=${SEEDS:-1 2}
JOBS=${JOBS:-2}
VENV=$(bash "$HERE/pysph_setup.sh")
if [ -z "${SHEARSPH:-}" ]; then
  (cd "$ROOT" && nice -n 10 cargo build --release --quiet)
  SHEARSPH="$ROOT/target/release/shearsph"
fi
mkdir -p "$OUT"
SCENE=(--lattice square --h-over-d 1 --kernel monaghan --n 10 --alpha 0.1 --jitter 0.05)

one() {  # one RE C0 SEED: shearsph, then PySPH on shearsph's horizon and window
  local re=$1 c0=$2 seed=$3 tag="re$1-c$2-s$3" work
  work=$(mktemp -d)
  RAYON_NUM_THREADS=1 nice -n 10 "$SHEARSPH" run "${SCENE[@]}" --re "$re" --c0 "$c0" --jitter-seed "$seed" \
    --horizon stationary --out "$work/run" --force --quiet --json --no-particles \
    > "$OUT/shearsph-$tag.json" || true  # its exit status is the class (5: over-compressed)
  cp "$work/run/timeseries.csv" "$OUT/shearsph-$tag.csv"
  rm -rf "$work"
  local t_end from
  t_end=$(python3 -c "import json,sys;print(json.load(open(sys.argv[1]))['t'])" "$OUT/shearsph-$tag.json")
  from=$(python3 -c "import json,sys;print(json.load(open(sys.argv[1]))['window_from'])" "$OUT/shearsph-$tag.json")
  (cd "$HERE" && OMP_NUM_THREADS=1 nice -n 10 "$VENV/bin/python" pysph_c0.py --re "$re" --c0 "$c0" \
    --seed "$seed" --t-end "$t_end" --window-from "$from" --timeseries "$OUT/pysph-$tag.csv" \
    --out "$(mktemp -d)") | tail -n 1 > "$OUT/pysph-$tag.json"
  echo "done $tag" >&2
}

for re in $RES; do
  for c0 in $C0S; do
    for seed in $SEEDS; do
      while [ "$(jobs -rp | wc -l)" -ge "$JOBS" ]; do sleep 1; done
      one "$re" "$c0" "$seed" &
    done
  done
done
wait
python3 "$HERE/pysph_c0_table.py" "$OUT" | tee "$OUT/table.txt"
