#!/bin/bash
# The build the disordered scene's speed work started from (FILED) against
# this build (NOW) at 1e6 particles, every kernel, alternating, 1 thread.
#   FILED=path/to/filed NOW=path/to/shearsph ./ab-filed.sh
set -eu
: "${FILED:?} ${NOW:?}"
for r in 1 2; do
  for t in filed now; do
    bin=$FILED; [ $t = now ] && bin=$NOW
    /usr/bin/time -f "%e s %M KB" -o "filed-1e6-$t-$r.time.txt" \
      $bin bench --disordered --particles 1e3,1e6 --threads 1 --repeats 1 --no-bandwidth > "filed-1e6-$t-$r.txt" 2>&1
  done
done
