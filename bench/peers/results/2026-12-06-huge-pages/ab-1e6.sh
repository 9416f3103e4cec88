#!/bin/bash
# The 1e6 disordered scene alone, main (A) against huge pages (B), the two
# alternating kernel by kernel within each round, 1 thread.
#   A=path/to/main B=path/to/huge-pages ./ab-1e6.sh
set -eu
: "${A:?} ${B:?}"
for r in 1 2 3 4; do
  for k in monaghan composite morris wendland_c2; do
    for t in a b; do
      bin=$A; [ $t = b ] && bin=$B
      $bin bench --disordered --kernels $k --particles 1e6 --threads 1 --repeats 1 --no-bandwidth > 1e6-$k-$t-$r.txt 2>&1
    done
  done
done
