#!/usr/bin/env bash
# Alternating rounds on the disordered scene, 1 thread: main's windows, the
# packed lanes gathered, the packed lanes from records, and windows of two
# 4-index halves. GATHERS is main built with full-lanes-gathers.patch (run
# without SHEARSPH_FULL_LANES=1 it takes main's windows: "main" here),
# RECORDS with full-lanes-records.patch, HALVES with
# half-windows-two-halves.patch. ROUNDS="1 2" by default. The rounds' files
# go to OUT (this folder by default); summary.py reads those of the folder
# it runs in.
#
#   GATHERS=... RECORDS=... HALVES=... ./ab.sh && ./summary.py > summary.txt
set -u
cd "${OUT:-$(dirname "$0")}"
for r in ${ROUNDS:-1 2}; do
  for v in main gathers records halves; do
    case $v in
      main) bin=$GATHERS; env=0 ;;
      gathers) bin=$GATHERS; env=1 ;;
      records) bin=$RECORDS; env=1 ;;
      halves) bin=$HALVES; env=0 ;;
    esac
    SHEARSPH_FULL_LANES=$env $bin bench --disordered --kernels monaghan,composite,wendland_c2 \
      --particles 1e3,1e4 --threads 1 --repeats 3 --no-bandwidth --quiet > round-$r-$v.txt 2>&1
  done
done
echo done
