#!/usr/bin/env bash
# The force pass's stencils on and off, alternating, in one binary built
# from main with stencil.patch applied (SHEARSPH_NO_STENCIL turns them
# off). Usage: ab.sh SHEARSPH_BINARY [ROUNDS]
set -euo pipefail
bin=$1
rounds=${2:-3}
out=$(dirname "$0")/runs
mkdir -p "$out"
for r in $(seq 1 "$rounds"); do
  for v in on off; do
    if [ "$v" = off ]; then export SHEARSPH_NO_STENCIL=1; else unset SHEARSPH_NO_STENCIL; fi
    "$bin" bench --pysph-match --columns 64 --threads 1 --steps 3000 2>/dev/null >"$out/pysph64-$v-$r.json"
    "$bin" bench --pysph-match --threads 1 --steps 2000 2>/dev/null >"$out/pysph-$v-$r.json"
  done
done
unset SHEARSPH_NO_STENCIL
python3 - "$out" "$rounds" <<'PY'
import json, sys
out, rounds = sys.argv[1], int(sys.argv[2])
for scene in ("pysph64", "pysph"):
    for r in range(1, rounds + 1):
        on = json.load(open(f"{out}/{scene}-on-{r}.json"))
        off = json.load(open(f"{out}/{scene}-off-{r}.json"))
        print(f"{scene} round {r}: {on['particles']} particles, wall off/on {off['wall_s'] / on['wall_s']:.2f}, "
              f"force pass off/on {off['forces_s'] / on['forces_s']:.2f}")
PY
