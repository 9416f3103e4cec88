#!/bin/bash
# main (A) against the force pass in tiles (B), alternating round by round, 1 thread.
#   A=path/to/main B=path/to/tiles ./ab.sh
set -eu
: "${A:?} ${B:?}"
for r in 1 2 3; do
  for t in a b; do
    bin=$A; [ $t = b ] && bin=$B
    $bin bench --disordered --particles 1e5,1e6 --threads 1 --repeats 1 --no-bandwidth > disordered-$t-$r.txt 2>&1
  done
done
for r in 1 2; do
  for t in a b; do
    bin=$A; [ $t = b ] && bin=$B
    $bin bench --kernels monaghan,wendland_c2 --particles 1e5,1e6 --threads 1 --repeats 1 --no-bandwidth > ordered-$t-$r.txt 2>&1
  done
done
