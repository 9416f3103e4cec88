#!/bin/bash
# The filed build against this build on the disordered scene, alternating,
# 1 thread: 1e3-1e5 (2 rounds, 3 repeats) and 1e6 (2 rounds, 1 repeat).
#   FILED=path/to/filed NOW=path/to/shearsph ./ab-filed.sh
set -eu
: "${FILED:?} ${NOW:?}"
for r in 1 2; do
  for t in filed now; do
    bin=$FILED; [ $t = now ] && bin=$NOW
    $bin bench --disordered --particles 1e3,1e4,1e5 --threads 1 --repeats 3 --no-bandwidth > "bench-$t-$r.txt" 2>&1
  done
done
for r in 1 2; do
  for t in filed now; do
    bin=$FILED; [ $t = now ] && bin=$NOW
    /usr/bin/time -f "%e s %M KB" -o "bench-1e6-$t-$r.time.txt" \
      $bin bench --disordered --particles 1e6 --threads 1 --repeats 1 --no-bandwidth > "bench-1e6-$t-$r.txt" 2>&1
  done
done
