#!/bin/bash
# One jittered start (0.05 d) at Re = 1, c0 = 10 U, to the stationary
# horizon: KERNEL LATTICE H_OVER_D FACTOR SEED -> its class, window
# statistics, steps and the limit the last step's dt came from.
# Usage: xargs -P 2 -L 1 bash disordered-run.sh < disordered-jobs.txt
set -u
B=${SHEARSPH:-shearsph}
k=$1; lat=$2; hd=$3; f=$4; s=$5
out=$(mktemp -d)
o=$($B run --kernel $k --lattice $lat --h-over-d $hd --re 1 --c0 10 --viscous-dt $f --jitter 0.05 --jitter-seed $s --horizon stationary --out "$out/run" --force 2>&1)
rm -rf "$out"
cls=$(echo "$o" | grep "^class" | awk '{print $2}' | tr -d ':')
eps=$(echo "$o" | grep -o "eps_stat (mean p99 eps) = [0-9.e+-]*" | awk '{print $NF}')
linf=$(echo "$o" | grep -o "mean-flow L_inf / U = [0-9.e+-]*" | awk '{print $NF}')
st=$(echo "$o" | grep -o "^t = .* steps" | head -1)
dtl=$(echo "$o" | grep -o "dt = [0-9.e+-]* ([a-z]*)" | head -1)
echo "$k $lat $hd F=$f seed=$s: $cls eps_stat=$eps linf=$linf | $st $dtl"
