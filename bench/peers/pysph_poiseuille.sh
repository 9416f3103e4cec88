#!/usr/bin/env bash
# PySPH 1.0b2's stock example pysph.examples.poiseuille (TVF scheme, quintic
# spline, dx = 1/60, 1440 fluid + 240 wall particles, Re = 0.0125, c0 = 10
# Vmax) next to shearsph on the matched scene (`shearsph bench --pysph-match`:
# quintic spline, 1690 particles, the same h / B, Re and c0, so the same dt in
# units of B^2 / nu), the same number of steps, run alternately on 1 thread and
# on THREADS. Then both codes laddered over resolution (PySPH's dx
# overridden, shearsph's `--layers`), each rung to the same t nu / B^2, on 1
# thread and on THREADS, the two codes' rungs alternating.
#
# Particle counts, one rule at every rung and in the matched rounds: PySPH's
# channel is its example's (0.4 Ly long in whole columns, 5 ghost layers per
# wall); shearsph's strip is the fewest columns holding at least as many
# particles as PySPH's channel at the same h / B (and no fewer than the
# kernel needs), so at the matched 30 layers 26 columns, 1690 against 1680.
# The smallest rungs are held to the kernel's narrowest strip: more particles
# than PySPH's there.
#
# Prints each matched round, the median throughputs (particle-steps per
# second, steps alone, set-up excluded in both), their ratio, both L_inf
# errors of the layer-mean velocity against the start-up series (a fraction
# of Vmax) at the time both reach; then each ladder (error against wall
# time) and the wall time each code needs to reach common accuracies
# (peer_summary.py: the first rung at or below, and interpolated on the
# ladder). Writes the runs, the summary, the ladder as CSV and its chart
# (wall time against error) into OUT. shearsph's walls are mirrored (no-slip
# at y = B, as PySPH's are); WALLS=zero runs the paper's walls at rest.
#
# usage: bench/peers/pysph_poiseuille.sh [STEPS=2000] [ROUNDS=3] [THREADS=2]
# environment:
#   OUT            where results go (default target/peers/pysph-STEPS; files
#                  are replaced whole, nothing else there is touched)
#   PYSPH_ROWS     PySPH's ladder: rows across the channel (default
#                  "60 48 40 30 24 20 16 12"; 60 is the example's dx)
#   SHEARSPH_LAYERS  shearsph's ladder: layers in the half-width (default
#                  "30 24 20 16 14 12 10 8 7 6"; 30 is the matched scene)
#   LADDER_THREADS thread counts of the ladders (default "1 THREADS")
#   LADDER=0       skip the ladders (ROUNDS=0 skips the matched rounds)
#   TARGETS        Linf/Vmax targets for the time to accuracy (default: see
#                  peer_summary.py)
#
# Timings on a machine that is doing other work are indicative only (OpenMP's
# spinning barriers make PySPH's 2-thread runs erratic then): the load
# average before and after is printed with the results.
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
OUT=${OUT:-$ROOT/target/peers/pysph-$STEPS}
PYSPH_ROWS=${PYSPH_ROWS:-60 48 40 30 24 20 16 12}
SHEARSPH_LAYERS=${SHEARSPH_LAYERS:-30 24 20 16 14 12 10 8 7 6}
LADDER_THREADS=${LADDER_THREADS:-$(printf '%s\n' 1 "$THREADS" | sort -nu | tr '\n' ' ')}
LADDER=${LADDER:-1}

VENV=$(bash "$HERE/pysph_setup.sh")
(cd "$ROOT" && cargo build --release --quiet)
BIN="$ROOT/target/release/shearsph"
mkdir -p "$OUT"
LOAD_BEFORE=$(cut -d' ' -f1-3 /proc/loadavg)

WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
pysph() {
  # pysph THREADS STEPS [ROWS]: PySPH prints its own lines first; the
  # helper's JSON is the last one.
  OMP_NUM_THREADS=$1 "$VENV/bin/python" "$HERE/pysph_poiseuille.py" "$2" "$WORK/pysph-run" ${3:+"$3"} | tail -n 1
}
shearsph() {
  # shearsph THREADS STEPS [LAYERS]
  "$BIN" bench --pysph-match --steps "$2" --threads "$1" --wall-velocity "$WALLS" ${3:+--layers "$3"}
}
# PySPH compiles the example's equations on first use (cached in ~/.pysph),
# once serial and once with OpenMP: a short untimed run of each first, so
# every timed run sees the same state.
for t in $(printf '%s\n' 1 "$THREADS" $LADDER_THREADS | sort -nu); do
  pysph "$t" 5 > /dev/null
  shearsph "$t" 5 > /dev/null
done

: > "$WORK/pysph.jsonl"
: > "$WORK/shearsph.jsonl"
ROUND_THREADS=$(printf '%s\n' 1 "$THREADS" | sort -nu | tr '\n' ' ')
for r in $(seq "$ROUNDS"); do  # ROUNDS=0: the ladders alone
  for t in $ROUND_THREADS; do  # 1 thread (the per-core ratio) and THREADS, alternating
    echo "round $r/$ROUNDS: pysph, $STEPS steps on $t thread(s)" >&2
    pysph "$t" "$STEPS" >> "$WORK/pysph.jsonl"
    echo "round $r/$ROUNDS: shearsph, $t thread(s)" >&2
    shearsph "$t" "$STEPS" >> "$WORK/shearsph.jsonl"
  done
done

# The ladders: the same flow to the same t nu / B^2 at other resolutions,
# one run per rung, the codes alternating rung by rung.
: > "$WORK/ladder.jsonl"
if [ "$LADDER" != 0 ]; then
  read -r -a ROWS_A <<< "$PYSPH_ROWS"
  read -r -a LAYERS_A <<< "$SHEARSPH_LAYERS"
  n=$(( ${#ROWS_A[@]} > ${#LAYERS_A[@]} ? ${#ROWS_A[@]} : ${#LAYERS_A[@]} ))
  for t in $LADDER_THREADS; do
    for ((i = 0; i < n; i++)); do
      if [ "$i" -lt "${#ROWS_A[@]}" ]; then
        echo "ladder, $t thread(s): pysph, ${ROWS_A[$i]} rows" >&2
        pysph "$t" "$STEPS" "${ROWS_A[$i]}" >> "$WORK/ladder.jsonl"
      fi
      if [ "$i" -lt "${#LAYERS_A[@]}" ]; then
        shearsph "$t" "$STEPS" "${LAYERS_A[$i]}" >> "$WORK/ladder.jsonl"
      fi
    done
  done
fi
LOAD_AFTER=$(cut -d' ' -f1-3 /proc/loadavg)

NOTE="machine: $(nproc) cores; load average (1, 5, 15 min) before $LOAD_BEFORE, after $LOAD_AFTER"
NOTE="$NOTE (above about 0.3 other work was running: the timings are then indicative only)"
NOTE="$NOTE
particle counts: at every rung shearsph's strip holds at least as many particles as PySPH's channel \
at the same h / B (fewest columns; the kernel's narrowest strip at the smallest rungs)"
SUMMARY_ARGS=(--load "$NOTE")
if [ -s "$WORK/pysph.jsonl" ]; then
  SUMMARY_ARGS+=(--peer "$WORK/pysph.jsonl" --ours "$WORK/shearsph.jsonl")
fi
if [ -s "$WORK/ladder.jsonl" ]; then
  SUMMARY_ARGS+=(--ladder "$WORK/ladder.jsonl" --csv "$OUT/ladder.csv")
fi
if [ -n "${TARGETS:-}" ]; then
  SUMMARY_ARGS+=(--targets "$TARGETS")
fi
python3 "$HERE/peer_summary.py" "${SUMMARY_ARGS[@]}" | tee "$WORK/summary.txt"
if [ -s "$WORK/ladder.jsonl" ]; then
  "$VENV/bin/python" "$HERE/peer_chart.py" "$OUT/ladder.csv" "$OUT/ladder.png" \
    "PySPH 1.0b2 (TVF) and shearsph, Poiseuille start-up to t nu/B^2 = $(python3 -c "import json;print(round(json.loads(open('$WORK/ladder.jsonl').readline())['tau'],3))")" \
    "load average before $LOAD_BEFORE, after $LOAD_AFTER (above about 0.3: indicative only)"
fi
# Into OUT, each file whole (rename within OUT's file system).
for f in pysph.jsonl shearsph.jsonl ladder.jsonl summary.txt; do  # ladder.csv, .png: written in place, atomically
  if [ -s "$WORK/$f" ]; then
    cp "$WORK/$f" "$OUT/.$f.tmp" && mv "$OUT/.$f.tmp" "$OUT/$f"
  fi
done
echo "results in $OUT" >&2
