#!/usr/bin/env bash
# Long runs where the pick between listing ahead and where the fluid is
# switches: the build with the rule before it (BEFORE: lists built ahead
# until one goes stale at its first step, then never again) against the
# build with the pick (AFTER), alternating, 1 thread, ROUNDS rounds
# (default 2):
#   - the composite kernel on 144 columns (3024 particles): Re = 10 at 10 U
#     to t = 2400, and Re = 1 at 28 U to t = 600 (`run`; its summary.json
#     to runs/, a line a run to long.txt);
#   - the bench's tiled scene of the composite kernel at 1e4 particles,
#     timed for 3000 steps (`bench --disordered`; its output to runs/, its
#     row to long.txt).
#   BEFORE=path/to/shearsph AFTER=path/to/shearsph ./ab-long.sh
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
import json
d = json.load(open('runs/re$1-$b-$r.json'))
print(f\"round $r 144 columns Re = $1 c0 = $2 t_end = $3 $b: {d['particles']} particles, {d['steps']} steps, \"
      f\"{d['neighbour_rebuilds']} rebuilds, {d['wall_s']:.2f} s, {1e9 * d['wall_s'] / d['particle_steps']:.1f} ns a particle-step, \"
      f\"class {d['class']}, eps_stat {d['eps_stat']:.4g}, linf_stat {d['linf_stat']:.4g}\")" | tee -a long.txt
    done
  done
  for b in before after; do
    bin=$BEFORE; [ $b = after ] && bin=$AFTER
    RAYON_NUM_THREADS=1 $bin bench --disordered --kernels composite --particles 1e4 --steps 3000 \
      --threads 1 --repeats 1 --no-bandwidth > "runs/tiled-1e4-3000-$b-$r.txt" 2>&1
    python3 - "runs/tiled-1e4-3000-$b-$r.txt" "$r" "$b" <<'PY' | tee -a long.txt
import sys
lines = open(sys.argv[1]).read().splitlines()
def row(header):
    i = next(k for k, l in enumerate(lines) if l.startswith('kernel') and header in l)
    return lines[i].split(), lines[i + 1].split()
head, a = row('ns/p-step')
_, b = row('list%')
# The pass table's last columns: list%, rebu, g, vec.
print(f"round {sys.argv[2]} tiled 1e4, 3000 steps {sys.argv[3]}: {a[1]} particles, "
      f"{b[-3]} rebuilds, list% {b[-4]}, {a[head.index('ns/p-step')]} ns a particle-step")
PY
  done
done
