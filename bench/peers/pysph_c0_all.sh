#!/usr/bin/env bash
# The whole check of shearsph's answer in PySPH (docs/validation.md), one
# command: the venv, PySPH's own compaction bound per scheme (matched and
# TVF) bisected the way `shearsph c0 --empirical` bisects its own
# (pysph_c0_bisect.py), the time to disorder of a 0.001 d jitter in each
# code, the runs that switch one TVF difference off, the ladder of c0 =
# shearsph's answer x {1/2, 1, 2} and 10 U from jittered and perfect starts,
# shearsph's own answers, then the tables (pysph_c0_table.py) and the
# agreement table (pysph_c0_summary.py). Runs already in OUT are reused, so
# an interrupted run resumes.
#
# usage: bench/peers/pysph_c0_all.sh
# environment: OUT (default target/peers/pysph-c0-all), SHEARSPH (default:
#   target/release/shearsph, built here), JOBS (default 2), PEERS_NICE (19);
#   LADDER=0 skips the ladder, ANSWERS=0 shearsph's `c0 --empirical` runs
#   (their outputs must then be in OUT as c0-empirical-re1.txt and
#   c0-empirical-re10.txt)
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
export OUT=${OUT:-$ROOT/target/peers/pysph-c0-all}
export JOBS=${JOBS:-2}
NICE=${PEERS_NICE:-19}
bash "$HERE/pysph_setup.sh" > /dev/null
if [ -z "${SHEARSPH:-}" ]; then
  (cd "$ROOT" && nice -n "$NICE" cargo build --release --quiet)
  SHEARSPH="$ROOT/target/release/shearsph"
fi
export SHEARSPH
export OMP_NUM_THREADS=1 RAYON_NUM_THREADS=1
mkdir -p "$OUT"

# shearsph's answers (its compaction bound: 31.6228 U at Re 1, 11.5518 U at Re 10)
if [ "${ANSWERS:-1}" != 0 ]; then
  for re in 1 10; do
    [ -s "$OUT/c0-empirical-re$re.txt" ] && continue
    nice -n "$NICE" "$SHEARSPH" c0 --empirical --lattice square --h-over-d 1 --kernel monaghan \
      --n 10 --re "$re" --alpha 0.1 --cfl 0.5 --viscous-dt 0.125 > "$OUT/c0-empirical-re$re.txt"
  done
fi

# PySPH's compaction bound per scheme, 3 seeds pooled, to 10 %: the matched
# scheme from the bracket its ladder gives (31.6228 U, shearsph's answer, and
# 56.2 U at Re 1; 10 U and 11.5518 U at Re 10), TVF from 10 U as shearsph's
# search starts
python3 "$HERE/pysph_c0_bisect.py" "$OUT" --re 10 --scheme matched --bracket 10 11.5518 | tee "$OUT/bisect-matched-re10.txt"
python3 "$HERE/pysph_c0_bisect.py" "$OUT" --re 1 --scheme matched --bracket 31.6228 56.2 | tee "$OUT/bisect-matched-re1.txt"
python3 "$HERE/pysph_c0_bisect.py" "$OUT" --re 10 --scheme tvf --first 10 | tee "$OUT/bisect-tvf-re10.txt"
python3 "$HERE/pysph_c0_bisect.py" "$OUT" --re 1 --scheme tvf --first 10 | tee "$OUT/bisect-tvf-re1.txt"

# the time to disorder of a 0.001 d jitter at 10 U, in every code
bash "$HERE/pysph_c0_disorder.sh" 1 10 0.001 500 | tee "$OUT/disorder-re1.txt"
bash "$HERE/pysph_c0_disorder.sh" 10 10 0.001 500 | tee "$OUT/disorder-re10.txt"

# TVF with one of its differences switched off, at 10 U, seed 1: no
# background pressure (both Re); the cubic spline instead of the quintic (Re 10)
SCHEMES=tvf_pb0 RES="1 10" C0S=10 SEEDS=1 TABLE=0 bash "$HERE/pysph_c0.sh"
SCHEMES=tvf_cubic RES=10 C0S=10 SEEDS=1 TABLE=0 bash "$HERE/pysph_c0.sh"

# the ladder: shearsph's answer x {1/2, 1, 2} and 10 U, jittered (seeds 1, 2)
# and perfect (seed 0) starts, both schemes
if [ "${LADDER:-1}" != 0 ]; then
  RES=1 C0S="10 15.8114 31.6228 63.2456" SEEDS="1 2 0" TABLE=0 bash "$HERE/pysph_c0.sh"
  RES=10 C0S="5.7759 10 11.5518 23.1036" SEEDS="1 2 0" TABLE=0 bash "$HERE/pysph_c0.sh"
fi

python3 "$HERE/pysph_c0_table.py" "$OUT" | tee "$OUT/table.txt"
python3 "$HERE/pysph_c0_summary.py" "$OUT" | tee "$OUT/summary.txt"
