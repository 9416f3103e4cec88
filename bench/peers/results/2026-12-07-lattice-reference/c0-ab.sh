#!/usr/bin/env bash
# `c0 --kernel monaghan --n 10 --re RE --empirical --json --quiet`, the
# build before a lattice that keeps its order took the shear reference (OLD)
# against the build after (NEW), alternating old, new, old, new ..., with
# the viscous default's runner (../2026-12-06-viscous-default/ab.sh), which
# prints the table.
#
#   c0-ab.sh OLD_BIN NEW_BIN OUT [PAIRS=2] [RES="1 10"]
set -euo pipefail
old=${1:?usage: c0-ab.sh OLD_BIN NEW_BIN OUT [PAIRS] [RES]} new=${2:?} out=${3:?}
"$(dirname "$0")/../2026-12-06-viscous-default/ab.sh" "$old" "$new" "$out" \
  "${4:-2}" "${5:-1 10}" "old (lattice rule)" "new (shear reference)"
