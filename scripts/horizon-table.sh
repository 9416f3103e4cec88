#!/usr/bin/env bash
# The class of one jittered start (Monaghan, N = 10, Re = 1, alpha = 0.1,
# the paper's discretisation, 0.05 d, seed 2) against the run's length and
# c0: at fixed end times (judged on the later half of the time after the
# start-up, docs/stationary.md) and on the stationary horizon. Prints a
# markdown table, each cell the class and (eps_stat, mean-flow L_inf).
#
# usage: scripts/horizon-table.sh [OUT=target/horizon-table]
set -euo pipefail
cd "$(dirname "$0")/.."
OUT=${1:-target/horizon-table}
B=target/release/shearsph
[ -x "$B" ] || cargo build --release -q
mkdir -p "$OUT"
C0S="2.5 4 6 10 20"
printf '| t_end |'; for c in $C0S; do printf ' %s U |' "$c"; done; echo
printf '|---|'; for c in $C0S; do printf -- '---|'; done; echo
for t in 16.3 24.4 50 100 400 stationary; do
  printf '| %s |' "$t"
  for c in $C0S; do
    dir="$OUT/t$t-c$c"
    if [ "$t" = stationary ]; then horizon=(--horizon stationary); else horizon=(--t-end "$t"); fi
    "$B" run --re 1 --c0 "$c" --jitter 0.05 --jitter-seed 2 "${horizon[@]}" \
      --no-particles --quiet --force --out "$dir" > /dev/null || true
    python3 - "$dir/summary.json" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
print(f" {s['class']} ({s['eps_stat']:.3f}, {s['linf_stat']:.3f}{', t = %.0f' % s['t'] if s['horizon'] == 'stationary' else ''}) |", end="")
PY
  done
  echo
done
