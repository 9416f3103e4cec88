#!/usr/bin/env bash
# The CFL factor against the disordered state's statistics: every kernel and
# discretisation at Re = 30, c0 = 10 U (the CFL limit binds at every c0
# there), and every kernel on the triangular lattice at h = d at Re = 1,
# c0 = 100 U (trixi's rule, where `c0 --empirical`'s rules spend its steps),
# each from a 0.05 d jitter (seeds 1-3) to its stationary window, and the
# perfect lattice beside the latter (seed 0). One JSON a run in OUT/runs.
#
# usage: cfl-grid.sh SHEARSPH OUT [JOBS]   (each run on one thread)
set -euo pipefail
bin=$1 out=$2 jobs=${3:-2}
{
  for k in monaghan morris wendland_c2 composite; do
    for disc in "triangular 1" "triangular 13/10" "square 1" "square 13/10" "square 17/10"; do
      for f in 0.25 0.5 0.75 1.0; do
        for s in 1 2 3; do echo "$k $disc 30 10 $f $s"; done
      done
    done
    for f in 0.25 0.5 0.75 1.0; do
      for s in 0 1 2 3; do echo "$k triangular 1 1 100 $f $s"; done
    done
  done
} | "$(dirname "$0")/run-cases.sh" "$bin" "$out" "$jobs"
