#!/usr/bin/env bash
# The time to disorder of a small jitter in shearsph and in PySPH, by each
# scheme of pysph_c0.py (matched: shearsph's scheme; tvf: PySPH's stock
# transport-velocity scheme): N = 10, Re = RE, c0 = C0 U, a jitter of
# JITTER d (seed 1, the same SplitMix64 stream in every code), to t = T_END,
# frames every B / 4U; t_disorder is the first frame with dy_rms >= 0.1 d.
# A run whose JSON is already in OUT is not run again.
# usage: bench/peers/pysph_c0_disorder.sh [RE=1] [C0=10] [JITTER=0.001] [T_END=500]
#   OUT (default target/peers/pysph-c0), SCHEMES (default "matched tvf"),
#   SHEARSPH (default: built here); every run under nice -n 19 (PEERS_NICE),
#   one thread
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
RE=${1:-1} C0=${2:-10} JITTER=${3:-0.001} T_END=${4:-500}
OUT=${OUT:-$ROOT/target/peers/pysph-c0}
SCHEMES=${SCHEMES:-matched tvf}
NICE=${PEERS_NICE:-19}
VENV=$(bash "$HERE/pysph_setup.sh")
if [ -z "${SHEARSPH:-}" ]; then
  (cd "$ROOT" && nice -n "$NICE" cargo build --release --quiet)
  SHEARSPH="$ROOT/target/release/shearsph"
fi
export OMP_NUM_THREADS=1 RAYON_NUM_THREADS=1
mkdir -p "$OUT"
tag="re$RE-c$C0-j$JITTER-s1"
if [ ! -s "$OUT/disorder-shearsph-$tag.json" ]; then
  work=$(mktemp -d)
  nice -n "$NICE" "$SHEARSPH" run --lattice square --h-over-d 1 --kernel monaghan \
    --n 10 --alpha 0.1 --columns 20 --cfl 0.5 --viscous-dt 0.125 --re "$RE" --c0 "$C0" --jitter "$JITTER" --jitter-seed 1 \
    --t-end "$T_END" --output-interval 2.5 --out "$work/run" --force --quiet --json --no-particles \
    > "$OUT/disorder-shearsph-$tag.json" || true  # the exit status is the class
  cp "$work/run/timeseries.csv" "$OUT/disorder-shearsph-$tag.csv"
  rm -rf "$work"
fi
for scheme in $SCHEMES; do
  [ -s "$OUT/disorder-pysph-$scheme-$tag.json" ] && continue
  (cd "$HERE" && nice -n "$NICE" "$VENV/bin/python" pysph_c0.py --scheme "$scheme" --re "$RE" \
    --c0 "$C0" --seed 1 --jitter "$JITTER" --t-end "$T_END" \
    --window-from "$(python3 -c "print($T_END / 2)")" \
    --timeseries "$OUT/disorder-pysph-$scheme-$tag.csv" --out "$(mktemp -d)") | tail -n 1 \
    > "$OUT/disorder-pysph-$scheme-$tag.json"
done
python3 - "$OUT" "$tag" $SCHEMES <<'PY'
import json, sys
out, tag, schemes = sys.argv[1], sys.argv[2], sys.argv[3:]
s = json.load(open("%s/disorder-shearsph-%s.json" % (out, tag)))
parts = ["shearsph %s" % s["t_disorder"]]
for sc in schemes:
    p = json.load(open("%s/disorder-pysph-%s-%s.json" % (out, sc, tag)))
    parts.append("pysph-%s %s" % (sc, "%.2f" % p["t_disorder"] if p["t_disorder"] is not None
                                  else "none by t = %g (dy_rms %.3g d)" % (p["t"], p["dy_rms"])))
print("time to disorder (dy_rms >= 0.1 d), jitter %s d seed 1, Re %g, c0 %g U: %s"
      % (tag.split("-j")[1].split("-")[0], s["re"], s["c0_over_u"], ", ".join(parts)))
PY
