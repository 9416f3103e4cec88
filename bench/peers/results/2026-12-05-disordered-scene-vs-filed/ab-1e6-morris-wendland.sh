#!/bin/bash
# Morris's and Wendland C2's rows at 1e6 (ab.sh times Monaghan's and the
# composite kernel's): FILED against NOW, alternating round by round, 1 thread.
#   FILED=path/to/shearsph-filed NOW=path/to/shearsph OUT=folder ./ab-1e6-morris-wendland.sh
set -eu
: "${FILED:?} ${NOW:?} ${OUT:=.}"
for r in 1 2; do
  for t in filed now; do
    bin=$FILED; [ $t = now ] && bin=$NOW
    /usr/bin/time -f "%e s %M KB" -o "$OUT/bench-1e6-mw-$t-$r.time.txt" \
      $bin bench --disordered --kernels morris,wendland_c2 --particles 1e3,1e6 --threads 1 --repeats 1 --no-bandwidth > "$OUT/bench-1e6-mw-$t-$r.txt" 2>&1
  done
done
