#!/usr/bin/env bash
# The two drifts of the CFL factor's grid (../2026-12-07-cfl-factor/), with
# more seeds: are they the factor's, or the seeds' spread? Monaghan's kernel
# on the triangular lattice at h = d, Re = 1, c0 = 100 U, and Morris's on the
# square lattice at h = 17/10 d, Re = 30, c0 = 10 U, each from a 0.05 d
# jitter to its stationary window, at factors 0.25, 0.5 and 1.0, seeds
# FIRST-LAST (4-40 here; the grid ran seeds 1-3, which are not rerun: the
# same command gives the same bits). One JSON a run in OUT/runs.
#
# usage: seeds.sh SHEARSPH OUT [JOBS [FIRST [LAST]]]   (one thread a run)
set -euo pipefail
bin=$1 out=$2 jobs=${3:-2} first=${4:-4} last=${5:-40}
{
  for s in $(seq "$first" "$last"); do
    for f in 0.25 0.5 1.0; do
      echo "morris square 17/10 30 10 $f $s"
      echo "monaghan triangular 1 1 100 $f $s"
    done
  done
} | "$(dirname "$0")/../2026-12-07-cfl-factor/run-cases.sh" "$bin" "$out" "$jobs"
