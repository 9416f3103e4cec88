#!/bin/bash
for r in 1 2; do
 for b in main patch; do
  for re in 1 10; do
   /usr/bin/time -f "%e s wall %U user" -o c0-re$re-$b-$r.time.txt $BIN_DIR/$b c0 --kernel monaghan --n 10 --re $re --empirical --json > c0-re$re-$b-$r.json 2>/dev/null
  done
 done
done
