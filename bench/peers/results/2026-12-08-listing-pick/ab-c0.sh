#!/usr/bin/env bash
# `c0 --empirical` (N = 10, both cores) for the two kernels whose runs the
# pick between the ways of listing changed, the build before it (BEFORE)
# against the build with it (AFTER), alternating, ROUNDS rounds (default 2):
# Re = 1 and Re = 10. Each answer's JSON to runs/ (`c0-bits.py runs ...`
# compares them field by field), a line a run (its wall seconds, and the
# trial runs' steps and summed wall seconds) to c0.txt.
#   BEFORE=path/to/shearsph AFTER=path/to/shearsph ./ab-c0.sh
set -eu
: "${BEFORE:?} ${AFTER:?}"
cd "$(dirname "$0")"
mkdir -p runs
for r in ${ROUNDS:-1 2}; do
  for k in composite wendland_c2; do
    for re in 1 10; do
      for b in before after; do
        bin=$BEFORE; [ $b = after ] && bin=$AFTER
        start=$(date +%s.%N)
        $bin c0 --kernel $k --n 10 --re $re --empirical --json > "runs/$k-$re-$b.json"
        end=$(date +%s.%N)
        python3 - "runs/$k-$re-$b.json" "$r" "$k" "$re" "$b" "$start" "$end" <<'PY' | tee -a c0.txt
import json, sys
d = json.load(open(sys.argv[1]))
runs = [x for t in d["trials"] for x in ([t["perfect"]] if t.get("perfect") else []) + (t.get("seeds") or [])]
wall = float(sys.argv[7]) - float(sys.argv[6])
print(f"round {sys.argv[2]} {sys.argv[3]} Re = {sys.argv[4]} {sys.argv[5]}: {wall:.1f} s, "
      f"{len(runs)} trial runs, {sum(x['steps'] for x in runs)} steps, {sum(x['wall_s'] for x in runs):.1f} s in them")
PY
      done
    done
  done
done
