#!/usr/bin/env bash
# The composite kernel on the square lattice at h = d, from rest at Re = 30,
# c0 = 10 U, to the stationary horizon, at CFL factors 0.1 to 0.5: the
# perfect lattice and a 0.05 d jitter (seed 1). One line a run: the class,
# when the lattice lost its order (dy_rms >= 0.1 d), the largest compaction,
# and the stationary window's statistics (those of the last window for a
# failed run) or the failure.
#   bench/peers/results/2026-12-07-composite-square/runs.sh [SHEARSPH] > runs.txt
set -euo pipefail
bin=${1:-target/release/shearsph}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
for start in perfect jitter; do
  extra=()
  [ "$start" = jitter ] && extra=(--jitter 0.05 --jitter-seed 1)
  for cfl in 0.1 0.2 0.3 0.35 0.4 0.45 0.5; do
    # The exit code is the class's (docs/scenes.md): not an error here.
    { "$bin" run --kernel composite --lattice square --h-over-d 1 --n 10 --re 30 --c0 10 \
      --cfl "$cfl" --horizon stationary "${extra[@]}" --out "$out/run" --force \
      --no-particles --json --quiet || true; } |
      python3 -c '
import json, sys
d = json.load(sys.stdin)
start, cfl = sys.argv[1], sys.argv[2]
g = d.get
print("%-7s cfl %-4s: %-10s t = %7.1f (%d steps), ordered until t = %s, max eps %.4f, "
      "eps_stat %.4f, mean-flow L_inf %.3f U, dy_rms %.3f d, failure: %s"
      % (start, cfl, g("class"), g("t"), g("steps"), g("t_disorder"), g("max_eps"),
         g("eps_stat"), g("linf_stat"), g("dy_rms"), g("failure_reason")))
' "$start" "$cfl"
  done
done
