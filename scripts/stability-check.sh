#!/usr/bin/env bash
# The linear stability of the sheared lattice checked against the solver:
# `shearsph stability --measure` for every shipped kernel on both lattices
# (h = d, N = 10, Re = 1, alpha = 0.1, the strip a jittered start runs on),
# the predicted leading growth rate beside the growth a nonlinear run from
# a 1e-4 d jitter (seed 1) measures; then the growth rate over c0 / U and
# Re (the stability map). Prints two markdown tables; writes each case's
# JSON under OUT (without the modes' particle lists, which
# `shearsph stability --mode-svg` draws). With `tables` as the second
# argument, only the tables, from the JSON already in OUT.
#
# usage: scripts/stability-check.sh [OUT=target/stability-check] [tables]
#   VISCOUS_DT=F sets every case's viscous factor, the linearised step's
#   and the measuring runs', CFL=F their CFL factor (default: each
#   kernel's own)
set -euo pipefail
cd "$(dirname "$0")/.."
OUT=${1:-target/stability-check}
B=target/release/shearsph
[ -x "$B" ] || cargo build --release -q
mkdir -p "$OUT"
KERNELS="composite monaghan morris wendland_c2"
# stdin's JSON without each result's "mode", to FILE.
strip() {
  python3 -c 'import json, sys
d = json.load(sys.stdin)
for r in d["results"]:
    r.pop("mode", None)
json.dump(d, open(sys.argv[1], "w"))' "$1"
}
if [ "${2:-}" != tables ]; then

for k in $KERNELS; do
  for lat in triangular square; do
    "$B" stability --kernel "$k" --lattice "$lat" --h-over-d 1 --n 10 --re 1 --alpha 0.1 \
      --c0-over-u 5,10,20 --measure --measure-t-end 800 ${VISCOUS_DT:+--viscous-dt "$VISCOUS_DT"} ${CFL:+--cfl "$CFL"} \
      --json | strip "$OUT/check-$k-$lat.json"
  done
done
for k in $KERNELS; do
  for lat in triangular square; do
    for re in 1 10; do
      "$B" stability --kernel "$k" --lattice "$lat" --h-over-d 1 --n 10 --re "$re" --alpha 0.1 \
        --c0-over-u 3,5,7,10,14,20,30,40 ${VISCOUS_DT:+--viscous-dt "$VISCOUS_DT"} ${CFL:+--cfl "$CFL"} \
        --json | strip "$OUT/map-$k-$lat-re$re.json"
    done
  done
done
fi

python3 - "$OUT" $KERNELS <<'PY'
import json, sys
out, kernels = sys.argv[1], sys.argv[2:]
def g(v, f="{:.3g}"):
    return "-" if v is None else f.format(v)
def fmt_rate(v):
    return "failed" if v is None else f"{v:.2e}"
print("| kernel | discretisation | c0 / U | predicted rate (sector q d) | predicted t_dis | measured t_dis | measured mean rate | predicted / mean | late slope | predicted / late | perfect lattice's dy_rms |")
print("|---|---|---|---|---|---|---|---|---|---|---|")
for k in kernels:
    for lat in ["triangular", "square"]:
        d = json.load(open(f"{out}/check-{k}-{lat}.json"))
        for r in d["results"]:
            m = r["measured"]
            rate = r["growth_rate"]
            q = next(s["q_d"] for s in r["sectors"] if s["j"] == r["most_unstable_j"])
            note = ""
            if m["floor"] >= 0.1:
                note = " (the perfect lattice disorders itself)"
            elif m["growth_rate"] is None and m["t_disorder"] is not None:
                note = " (no exponential phase above twice this)"
            mean, late = m["mean_rate"], m["growth_rate"]
            print(f"| {k} | {d['discretisation']}, {d['columns']} columns | {r['c0_over_u']:g} | {rate:.3e} ({q:.3f}) | "
                  f"{g(r['t_disorder_predicted'], '{:.3g}')} | {g(m['t_disorder'], '{:.0f}') if m['t_disorder'] is not None else 'ordered to ' + format(m['t_end'], '.0f')} | "
                  f"{g(mean, '{:.3e}')} | {g(rate / mean if mean else None, '{:.2f}')} | {g(late, '{:.3e}')} | "
                  f"{g(rate / late if late else None, '{:.2f}')} | {m['floor']:.4f}{note} |")
print()
c0s = None
rows = []
for k in kernels:
    for lat in ["triangular", "square"]:
        for re in [1, 10]:
            d = json.load(open(f"{out}/map-{k}-{lat}-re{re}.json"))
            c0s = [r["c0_over_u"] for r in d["results"]]
            rows.append(f"| {k} | {d['discretisation']} | {re} | " + " | ".join(fmt_rate(r["growth_rate"]) for r in d["results"]) + " |")
print("| kernel | discretisation | Re | " + " | ".join(f"{c:g} U" for c in c0s) + " |")
print("|---|---|---|" + "---|" * len(c0s))
print("\n".join(rows))
PY
