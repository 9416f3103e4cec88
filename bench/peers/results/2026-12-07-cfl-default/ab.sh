#!/usr/bin/env bash
# `c0 --kernel monaghan --n 10 --re RE --empirical --json --quiet`, the
# build before the default CFL factor became the kernel's own (OLD: 0.5)
# against the build after (NEW: half the derived factor, at most 1: 0.9298
# here), alternating old, new, old, new ..., with the viscous default's
# runner (../2026-12-06-viscous-default/ab.sh), which prints the table.
#
#   ab.sh OLD_BIN NEW_BIN OUT [PAIRS=2] [RES="1 10"]
set -euo pipefail
old=${1:?usage: ab.sh OLD_BIN NEW_BIN OUT [PAIRS] [RES]} new=${2:?} out=${3:?}
"$(dirname "$0")/../2026-12-06-viscous-default/ab.sh" "$old" "$new" "$out" \
  "${4:-2}" "${5:-1 10}" "old (0.5)" "new (0.5 F*, max 1)"
