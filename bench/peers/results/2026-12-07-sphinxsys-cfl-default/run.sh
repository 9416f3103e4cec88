#!/usr/bin/env bash
# The SPHinXsys-matched scene with shearsph at the CFL factor the peer
# figures pin (0.5) and at Wendland C2's own default (0.898), both viscous
# terms, alternating: PASSES passes of the four variants, each a whole
# bench/peers/sphinxsys_poiseuille.sh run (5 matched rounds on 1 and 2
# threads, then both ladders), into runs/PASS-VISCOUS-CFL/.
#
# usage: run.sh SRC [PASSES=2]   (SRC: shared/peers/sphinxsys-9f33297.tar.gz)
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../../../.." && pwd)
SRC=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
# From the project's root, so that the summaries name the folder relative to it.
cd "$ROOT"
HERE=${HERE#"$ROOT"/}
SCRIPT=bench/peers/sphinxsys_poiseuille.sh
PASSES=${2:-2}
for pass in $(seq "$PASSES"); do
  for viscous in lattice none; do
    for cfl in 0.5 default; do
      out="$HERE/runs/$pass-$viscous-$cfl"
      echo "pass $pass: VISCOUS=$viscous CFL=$cfl -> runs/$pass-$viscous-$cfl" >&2
      OUT="$out" VISCOUS="$viscous" CFL="$cfl" "$SCRIPT" "$SRC" 5 1 > /dev/null
    done
  done
done
python3 "$HERE/physical.py" "$HERE"/runs/* | tee "$HERE/summary.txt"
