#!/usr/bin/env bash
# Is the report's verdict stable to its choice of perturbation (0.05 d, 3
# seeds)? Runs one small report (Monaghan's kernel, N = 10, Re = 1 and 30,
# every rule, the paper's discretisation) at 0.03, 0.05 and 0.1 d with 3 and
# 5 seeds, and prints each one's answer: which rules were sufficient and the
# smallest c0 ok on every seed.
#
#   scripts/report-perturbation-check.sh [OUT_DIR]   (default out/perturbation-check; about 80 s)
set -euo pipefail
root=$(git rev-parse --show-toplevel)
out=${1:-$root/out/perturbation-check}
mkdir -p "$out"
cargo build --release --quiet --bin shearsph
bin="$root/target/release/shearsph"
for case in "0.03 3" "0.05 3" "0.1 3" "0.05 5"; do
    set -- $case
    name="jitter=$1-seeds=$2"
    cat >"$out/$name.toml" <<TOML
kernels = ["monaghan"]
[classes]
linf_bound = 0.05
eps_margin = 0.01
[scene]
initial = "rest"
decay_tol = 0.01
[speed]
n = [6]
re = [1.0]
alpha = 0.1
c0 = ["rule10"]
[maps]
n = 10
alpha = 0.1
re = [1.0, 30.0]
c0_over_u = [0.01, 0.03, 0.1, 0.3, 1.0, 3.0, 10.0, 20.0]
[empirical]
re = [1.0, 30.0]
rel_tol = 0.1
max_extend = 1
[perturbed]
jitter = $1
seeds = $2
re = [1.0, 30.0]
[[case]]
id = "paper"
lattice = "triangular"
h_over_d = 1
[figure4]
n = 6
samples = 20
TOML
    "$bin" report --config "$out/$name.toml" --out "$out/$name" --force --quiet >/dev/null
    echo "== $name"
    jq -r '.[] | .kernel as $k | .answer[] | "Re = \(.re): empirical perfect \(.empirical_perfect), perturbed \(.empirical_perturbed); sufficient: \(.sufficient | join(", ")); perfect only: \(.perfect_only | join(", "))"' "$out/$name/answer.json"
done
