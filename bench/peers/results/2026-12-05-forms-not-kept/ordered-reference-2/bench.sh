#!/bin/bash
for r in 1 2; do
 for b in main patch; do
  $BIN_DIR/$b bench --disordered --kernels composite,wendland_c2 --particles 1e3,1e4,1e5 --threads 1 --repeats 3 --no-bandwidth --quiet > bench-disordered-$b-$r.txt 2>&1
 done
done
