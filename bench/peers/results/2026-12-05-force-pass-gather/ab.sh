#!/usr/bin/env bash
# Alternating A/B of `bench --disordered` on 1 thread: binary B against
# binary A, ROUNDS rounds, each run's tables kept as round-R-{a,b}-TAG.txt.
#   A=... B=... TAG=... PARTICLES=1e4,5e4,1e5,1e6 KERNELS=monaghan,composite ROUNDS=2 ./ab.sh
set -euo pipefail
A=${A:?the first binary}
B=${B:?the second binary}
TAG=${TAG:?a name for this comparison}
PARTICLES=${PARTICLES:-1e4,5e4,1e5,1e6}
KERNELS=${KERNELS:-monaghan,composite}
ROUNDS=${ROUNDS:-2}
for r in $(seq 1 "$ROUNDS"); do
  for v in a b; do
    if [ $v = a ]; then bin=$A; else bin=$B; fi
    "$bin" bench --disordered --particles "$PARTICLES" --kernels "$KERNELS" \
      --threads 1 --repeats 3 --no-bandwidth > "round-$r-$v-$TAG.txt" 2>&1
  done
done
