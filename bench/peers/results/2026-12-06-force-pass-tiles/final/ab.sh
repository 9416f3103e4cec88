#!/bin/bash
# main (A) against this build (B) at 1e6, 1 and 2 threads, alternating, 2 rounds.
#   A=path/to/main B=path/to/this ./ab.sh
set -eu
: "${A:?} ${B:?}"
for r in 1 2; do
  for t in a b; do
    bin=$A; [ $t = b ] && bin=$B
    $bin bench --disordered --particles 1e6 --threads 1,2 --repeats 1 --no-bandwidth > final-$t-$r.txt 2>&1
  done
done
