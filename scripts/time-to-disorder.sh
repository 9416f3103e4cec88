#!/usr/bin/env bash
# How long the ordered, sheared lattice lasts: the time to disorder (the
# first frame with dy_rms >= 0.1 d, docs/stationary.md) of a start jittered
# by amplitude a (0: the perfect lattice, whose perturbation is round-off),
# against a, c0, Re and the kernel, each run to t = T_END on a strip as
# wide as the channel (--columns 18 at N = 10), frames every 2 t. Prints a
# markdown table; writes each run's summary under OUT.
#
# usage: scripts/time-to-disorder.sh [OUT=target/time-to-disorder] [T_END=2500]
#   VISCOUS_DT=F sets every run's viscous factor, CFL=F its CFL factor
#   (default: each kernel's own)
set -euo pipefail
cd "$(dirname "$0")/.."
OUT=${1:-target/time-to-disorder}
T_END=${2:-2500}
B=target/release/shearsph
[ -x "$B" ] || cargo build --release -q
mkdir -p "$OUT"
run() { # kernel lattice h re c0 a
  local dir="$OUT/$1-$2-${3//\//_}-re$4-c0$5-a$6"
  local jitter=()
  [ "$6" != 0 ] && jitter=(--jitter "$6" --jitter-seed 1)
  [ -n "${VISCOUS_DT:-}" ] && jitter+=(--viscous-dt "$VISCOUS_DT")
  [ -n "${CFL:-}" ] && jitter+=(--cfl "$CFL")
  "$B" run --kernel "$1" --lattice "$2" --h-over-d "$3" --n 10 --re "$4" --c0 "$5" \
    "${jitter[@]}" --columns 18 --t-end "$T_END" --output-interval 2 --eps-limit 1 \
    --no-particles --quiet --force --out "$dir" > /dev/null || true
  python3 - "$dir/summary.json" "$@" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
k, lat, h, re, c0, a = sys.argv[2:8]
t = s.get("t_disorder")
print(f"| {k} | {lat}, h = {h} d | {re} | {c0} | {a} | {t if t is not None else 'ordered to ' + format(s['t'], '.0f')} |")
PY
}
echo "| kernel | discretisation | Re | c0 / U | jitter a / d | time to disorder (U = d = 1) |"
echo "|---|---|---|---|---|---|"
for c0 in 5 10 20; do
  for a in 0.05 0.01 0.001 0.0001 0.00001 0; do
    run monaghan triangular 1 1 "$c0" "$a"
  done
done
for a in 0.001 0; do
  run monaghan triangular 1 10 10 "$a"
  run morris triangular 1 1 10 "$a"
  run wendland_c2 square 13/10 1 10 "$a"
  run composite triangular 1 1 10 "$a"
done
