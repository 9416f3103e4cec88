#!/usr/bin/env bash
# The time to disorder of a small jitter in shearsph and in PySPH with
# shearsph's scheme (pysph_c0.py): N = 10, Re = RE, c0 = C0 U, a jitter of
# JITTER d (seed 1, the same lattice in both codes), to t = T_END, frames
# every B / 4U; t_disorder is the first frame with dy_rms >= 0.1 d.
# usage: bench/peers/pysph_c0_disorder.sh [RE=1] [C0=10] [JITTER=0.001] [T_END=500]
#   OUT (default target/peers/pysph-c0), SHEARSPH (default: built here)
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
RE=${1:-1} C0=${2:-10} JITTER=${3:-0.001} T_END=${4:-500}
OUT=${OUT:-$ROOT/target/peers/pysph-c0}
VENV=$(bash "$HERE/pysph_setup.sh")
if [ -z "${SHEARSPH:-}" ]; then
  (cd "$ROOT" && nice -n 10 cargo build --release --quiet)
  SHEARSPH="$ROOT/target/release/shearsph"
fi
mkdir -p "$OUT"
tag="re$RE-c$C0-j$JITTER-s1"
work=$(mktemp -d)
RAYON_NUM_THREADS=1 nice -n 10 "$SHEARSPH" run --lattice square --h-over-d 1 --kernel monaghan \
  --n 10 --alpha 0.1 --re "$RE" --c0 "$C0" --jitter "$JITTER" --jitter-seed 1 --t-end "$T_END" \
  --output-interval 2.5 --out "$work/run" --force --quiet --json --no-particles \
  > "$OUT/disorder-shearsph-$tag.json" || true  # the exit status is the class
cp "$work/run/timeseries.csv" "$OUT/disorder-shearsph-$tag.csv"
rm -rf "$work"
(cd "$HERE" && OMP_NUM_THREADS=1 nice -n 10 "$VENV/bin/python" pysph_c0.py --re "$RE" --c0 "$C0" \
  --seed 1 --jitter "$JITTER" --t-end "$T_END" --window-from "$(python3 -c "print($T_END / 2)")" \
  --timeseries "$OUT/disorder-pysph-$tag.csv" --out "$(mktemp -d)") | tail -n 1 \
  > "$OUT/disorder-pysph-$tag.json"
python3 - "$OUT/disorder-shearsph-$tag.json" "$OUT/disorder-pysph-$tag.json" <<'PY'
import json, sys
s, p = (json.load(open(f)) for f in sys.argv[1:])
print("time to disorder (dy_rms >= 0.1 d), jitter %g d seed 1, Re %g, c0 %g U: shearsph %s, pysph %s"
      % (p["jitter"], p["re"], p["c0_over_u"], s["t_disorder"], p["t_disorder"]))
PY
