#!/usr/bin/env bash
# `c0 --kernel monaghan --n 10 --re RE --empirical --json --quiet`, the
# build before the default viscous factor became the kernel's own (OLD:
# 0.125) against the build after (NEW: 0.85 F*, 0.1586 here), alternating
# old, new, old, new ..., PAIRS pairs at each Re, each run's whole-process
# wall and CPU seconds by /usr/bin/time; then summarise.py prints the table.
#
#   ab.sh OLD_BIN NEW_BIN OUT [PAIRS=3] [RES="1 10"] [OLD_LABEL NEW_LABEL]
set -euo pipefail
old=${1:?usage: ab.sh OLD_BIN NEW_BIN OUT [PAIRS] [RES]} new=${2:?} out=${3:?}
pairs=${4:-3} res=${5:-1 10}
labels=("${@:6:2}")
mkdir -p "$out"
for re in $res; do
  for i in $(seq "$pairs"); do
    for side in old new; do
      bin=$old
      [ "$side" = new ] && bin=$new
      /usr/bin/time -f '%e %U %S' -o "$out/$side-re$re-$i.time" \
        "$bin" c0 --kernel monaghan --n 10 --re "$re" --empirical --json --quiet \
        > "$out/$side-re$re-$i.json"
    done
  done
done
python3 "$(dirname "$0")/summarise.py" "$out" "${labels[@]}"
