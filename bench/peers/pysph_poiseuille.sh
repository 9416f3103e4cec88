#!/usr/bin/env bash
# PySPH 1.0b2's stock example pysph.examples.poiseuille (TVF scheme, quintic
# spline, dx = 1/60, 1440 fluid + 240 wall particles, Re = 0.0125, c0 = 10
# Vmax) next to shearsph on the matched scene (`shearsph bench --pysph-match`:
# quintic spline, 1650 particles, the same h / B, Re and c0, so the same dt in
# units of B^2 / nu), the same number of steps on the same number of threads,
# run alternately. Prints each round, the median throughputs (particle-steps
# per second, steps alone, set-up excluded in both), their ratio, and both
# L_inf errors of the layer-mean velocity against the start-up series, as a
# fraction of Vmax, at the time both reach. Then the same flow in shearsph at
# coarser resolutions, and the time the coarsest one no less accurate than
# PySPH takes against PySPH's. shearsph's walls are mirrored (no-slip at y =
# B, as PySPH's are); WALLS=zero runs the paper's walls at rest instead.
#
# usage: bench/peers/pysph_poiseuille.sh [STEPS=2000] [ROUNDS=3] [THREADS=2]
#
# Needs python3 (3.11 tested), gcc with OpenMP and network access to PyPI the
# first time (pysph_setup.sh builds the venv; see there what it takes).
set -euo pipefail

HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
STEPS=${1:-2000}
ROUNDS=${2:-3}
THREADS=${3:-2}
WALLS=${WALLS:-mirrored}

VENV=$(bash "$HERE/pysph_setup.sh")
(cd "$ROOT" && cargo build --release --quiet)
BIN="$ROOT/target/release/shearsph"

WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
export OMP_NUM_THREADS=$THREADS
pysph() {
  # PySPH prints its own lines first; the helper's JSON is the last one.
  "$VENV/bin/python" "$HERE/pysph_poiseuille.py" "$1" "$2" | tail -n 1
}
# PySPH compiles the example's equations on first use (cached in ~/.pysph):
# a short untimed run first, so every round sees the same state.
pysph 5 "$WORK/warm" > /dev/null
"$BIN" bench --pysph-match --steps 5 --threads "$THREADS" > /dev/null

for r in $(seq "$ROUNDS"); do
  echo "round $r/$ROUNDS: pysph, $STEPS steps on $THREADS threads" >&2
  pysph "$STEPS" "$WORK/pysph-$r" >> "$WORK/pysph.jsonl"
  echo "round $r/$ROUNDS: shearsph" >&2
  "$BIN" bench --pysph-match --steps "$STEPS" --threads "$THREADS" --wall-velocity "$WALLS" >> "$WORK/shearsph.jsonl"
done
# The time shearsph takes to reach PySPH's accuracy: the same flow to the
# same t nu / B^2 at coarser resolutions (one run each, same threads).
for n in 30 24 20 16 14 12 10 8 7 6; do
  "$BIN" bench --pysph-match --steps "$STEPS" --threads "$THREADS" --wall-velocity "$WALLS" --layers "$n" >> "$WORK/ladder.jsonl"
done
python3 "$HERE/peer_summary.py" "$WORK/pysph.jsonl" "$WORK/shearsph.jsonl" "$WORK/ladder.jsonl"
