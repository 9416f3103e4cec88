#!/usr/bin/env bash
# shearsph's `c0 --empirical` scene in shearsph and in PySPH 1.0b2, by two
# PySPH schemes (pysph_c0.py says every equation and every difference):
# `matched`, shearsph's scheme rebuilt equation by equation, and `tvf`,
# PySPH's own transport-velocity scheme as its stock Poiseuille example sets
# it up. Monaghan cubic spline in shearsph, square lattice h = d, N = 10,
# alpha 0.1 (TVF: none, as stock), starts jittered by 0.05 d (seeds 1.., the
# same SplitMix64 lattice in every code) or the perfect lattice (seed 0), a
# ladder of c0. Per rung and seed, shearsph runs first with `--horizon
# stationary` (docs/stationary.md), then each PySPH scheme runs to the same
# end time and is judged on the same window (the later half after the
# start-up) by the same statistics: eps_stat, the window mean of the 99th
# percentile of rho/rho0 - 1 over the fluid per frame (frames every B / 4U);
# linf_stat, the largest over the bands of the window-mean band velocity
# error against the start-up series, in U. Optional, not part of cargo test.
# Then pysph_c0_table.py prints the table: each code's class per rung and
# each code's fit eps_stat - eps0 = k (U / c0)^m over its rungs.
#
# A run whose JSON is already in OUT is not run again (the ladder, the
# bisection pysph_c0_bisect.py and a rerun share one folder).
#
# usage: bench/peers/pysph_c0.sh
# environment:
#   OUT      results folder (default target/peers/pysph-c0); per run
#            shearsph-re*-c*-s*.json / .csv (its summary and frames) and
#            pysph-SCHEME-re*-c*-s*.json / .csv (PySPH's); runs.jsonl, table.txt
#   RES      Reynolds numbers (default "1 10")
#   C0S      the c0 ladder in U (default "10 17.8 31.6 56.2")
#   SEEDS    jitter seeds, 0 the perfect lattice (default "1 2")
#   SCHEMES  PySPH schemes (default "matched tvf"); a scheme with a variant
#            of pysph_c0.py's TVF flags: tvf_pb0 (--tvf-pb 0, no background
#            pressure), tvf_cubic (--tvf-kernel cubic), tvf_walls (--tvf-walls
#            shearsph: the matched scheme's 380 particles)
#   JOBS     runs at a time (default 2); every run under nice -n 19
#            (PEERS_NICE), one thread (OMP_NUM_THREADS=1, RAYON_NUM_THREADS=1)
#   TABLE    0: no table at the end
#   SHEARSPH the binary (default: target/release/shearsph, built here)
set -euo pipefail

HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
OUT=${OUT:-$ROOT/target/peers/pysph-c0}
RES=${RES:-1 10}
C0S=${C0S:-10 17.8 31.6 56.2}
SEEDS=${SEEDS:-1 2}
SCHEMES=${SCHEMES:-matched tvf}
JOBS=${JOBS:-2}
NICE=${PEERS_NICE:-19}
VENV=$(bash "$HERE/pysph_setup.sh")
if [ -z "${SHEARSPH:-}" ]; then
  (cd "$ROOT" && nice -n "$NICE" cargo build --release --quiet)
  SHEARSPH="$ROOT/target/release/shearsph"
fi
mkdir -p "$OUT"
export OMP_NUM_THREADS=1 RAYON_NUM_THREADS=1
# shearsph's time-step factors are PySPH's fixed 0.5 and 0.125 (its defaults,
# half and 0.85 of the kernel's stable factors, are 0.946 and 0.156 on this
# lattice: docs/timestep.md)
SCENE=(--lattice square --h-over-d 1 --kernel monaghan --n 10 --alpha 0.1 --columns 20 --cfl 0.5 --viscous-dt 0.125)

flags() {  # a scheme's pysph_c0.py flags
  case $1 in
    matched) echo "--scheme matched" ;;
    tvf) echo "--scheme tvf" ;;
    tvf_pb0) echo "--scheme tvf --tvf-pb 0" ;;
    tvf_cubic) echo "--scheme tvf --tvf-kernel cubic" ;;
    tvf_walls) echo "--scheme tvf --tvf-walls shearsph" ;;
    *) echo "pysph_c0.sh: unknown scheme $1" >&2; exit 2 ;;
  esac
}

shearsph_run() {  # RE C0 SEED: shearsph's run of the scene, once (a lock per run)
  local re=$1 c0=$2 seed=$3 tag="re$1-c$2-s$3" work start=()
  exec 9> "$OUT/.lock-$tag"
  flock 9
  # (a run stopped by a signal printed `interrupted`: run it again)
  if [ ! -s "$OUT/shearsph-$tag.json" ] || grep -q '"outcome": "interrupted"' "$OUT/shearsph-$tag.json"; then
    if [ "$seed" != 0 ]; then start=(--jitter 0.05 --jitter-seed "$seed"); fi
    work=$(mktemp -d)
    nice -n "$NICE" "$SHEARSPH" run "${SCENE[@]}" "${start[@]}" --re "$re" --c0 "$c0" \
      --horizon stationary --out "$work/run" --force --quiet --json --no-particles \
      > "$OUT/shearsph-$tag.json" || true  # its exit status is the class (5: over-compressed)
    cp "$work/run/timeseries.csv" "$OUT/shearsph-$tag.csv"
    rm -rf "$work"
    echo "done shearsph $tag" >&2
  fi
  flock -u 9
}

one() {  # SCHEME RE C0 SEED: PySPH on shearsph's horizon and window
  local scheme=$1 re=$2 c0=$3 seed=$4 tag="re$2-c$3-s$4" t_end from jitter=0.05 work
  shearsph_run "$re" "$c0" "$seed"
  [ -s "$OUT/pysph-$scheme-$tag.json" ] && return 0
  # shearsph's end time and window; where its run failed, its horizon's
  # first checkpoint at this Re (the shortest of its stationary runs here)
  read -r t_end from < <(python3 - "$OUT" "$OUT/shearsph-$tag.json" <<'PY'
import glob, json, sys
s = json.load(open(sys.argv[2]))
if s.get("outcome", "ok") == "ok":
    print(s["t"], s["window_from"])
else:
    rs = [json.load(open(f)) for f in glob.glob(sys.argv[1] + "/shearsph-re*.json")]
    r = min((r for r in rs if r.get("re") == s["re"] and r.get("stationary")), key=lambda r: r["t"])
    print(r["t"], r["window_from"])
PY
)
  if [ "$seed" = 0 ]; then jitter=0; fi
  work=$(mktemp -d)
  # shellcheck disable=SC2046
  (cd "$HERE" && nice -n "$NICE" "$VENV/bin/python" pysph_c0.py $(flags "$scheme") --re "$re" \
    --c0 "$c0" --seed "$seed" --jitter "$jitter" --t-end "$t_end" --window-from "$from" \
    --timeseries "$OUT/pysph-$scheme-$tag.csv" --out "$work") | tail -n 1 > "$OUT/pysph-$scheme-$tag.json.part"
  mv "$OUT/pysph-$scheme-$tag.json.part" "$OUT/pysph-$scheme-$tag.json"
  rm -rf "$work"
  echo "done pysph $scheme $tag" >&2
}

for re in $RES; do
  for c0 in $C0S; do
    for seed in $SEEDS; do
      for scheme in $SCHEMES; do
        while [ "$(jobs -rp | wc -l)" -ge "$JOBS" ]; do sleep 1; done
        one "$scheme" "$re" "$c0" "$seed" &
      done
    done
  done
done
wait
if [ "${TABLE:-1}" != 0 ]; then
  python3 "$HERE/pysph_c0_table.py" "$OUT" | tee "$OUT/table.txt"
fi
