#!/bin/bash
# main (A) against the allocator advising large blocks onto huge pages (B),
# alternating round by round.
#   A=path/to/main B=path/to/huge-pages ./ab.sh
set -eu
: "${A:?} ${B:?}"
for r in 1 2 3; do
  for t in a b; do
    bin=$A; [ $t = b ] && bin=$B
    /usr/bin/time -v $bin bench --disordered --particles 1e4,1e5,1e6 --threads 1 --repeats 1 --no-bandwidth > disordered-$t-$r.txt 2> disordered-$t-$r.time.txt
  done
done
for r in 1 2; do
  for t in a b; do
    bin=$A; [ $t = b ] && bin=$B
    $bin bench --disordered --particles 1e6 --threads 2 --repeats 1 --no-bandwidth > two-threads-$t-$r.txt 2>&1
    $bin bench --kernels monaghan,wendland_c2 --particles 1e5,1e6 --threads 1 --repeats 1 --no-bandwidth > ordered-$t-$r.txt 2>&1
  done
done
