#!/usr/bin/env bash
# The composite kernel on a wide strip (144 columns, 3024 particles), the
# build before the rule for an agitated fluid (BEFORE) against the build with
# it (AFTER), alternating, 1 thread, ROUNDS rounds (default 2): Re = 10 at
# 10 U to t = 2400, and Re = 1 at 28 U to t = 600. Each run's summary.json
# goes to runs/, and one line a run (its steps, rebuilds and wall seconds)
# to wide.txt.
#   BEFORE=path/to/shearsph AFTER=path/to/shearsph ./ab-wide.sh
set -eu
: "${BEFORE:?} ${AFTER:?}"
cd "$(dirname "$0")"
mkdir -p runs
for r in ${ROUNDS:-1 2}; do
  for scene in "10 10 2400" "1 28 600"; do
    set -- $scene
    for b in before after; do
      bin=$BEFORE; [ $b = after ] && bin=$AFTER
      out=$(mktemp -d)
      # The exit status is the run's class (4: inaccurate), not an error.
      RAYON_NUM_THREADS=1 $bin run --no-particles --kernel composite --n 10 --re "$1" --c0 "$2" \
        --jitter 0.05 --jitter-seed 1 --t-end "$3" --columns 144 --out "$out" --force > /dev/null || true
      cp "$out/summary.json" "runs/re$1-$b-$r.json"
      rm -r "$out"
      python3 -c "
import json, sys
d = json.load(open('runs/re$1-$b-$r.json'))
print(f\"round $r Re = $1 c0 = $2 t_end = $3 $b: {d['particles']} particles, {d['steps']} steps, \"
      f\"{d['neighbour_rebuilds']} rebuilds, {d['wall_s']:.2f} s, {1e9 * d['wall_s'] / d['particle_steps']:.1f} ns a particle-step, \"
      f\"class {d['class']}, eps_stat {d['eps_stat']:.4g}, linf_stat {d['linf_stat']:.4g}\")" | tee -a wide.txt
    done
  done
done
