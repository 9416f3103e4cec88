#!/bin/bash
# Alternating pairs of single runs of SPHinXsys's matched scene
# (`bench --sphinxsys-match --tau 1 --columns 120`), build A then build B,
# on THREADS threads: each pass's and the whole step's median us a step
# per build, and the median and range of the pairs' ratios A / B.
# usage: ab-pairs.sh A B THREADS PAIRS
A=$1; B=$2; T=$3; N=$4
for i in $(seq "$N"); do
  "$A" bench --sphinxsys-match --threads "$T" --tau 1 --columns 120 2>/dev/null
  "$B" bench --sphinxsys-match --threads "$T" --tau 1 --columns 120 2>/dev/null
done | python3 -c "
import json, sys, statistics as st
rows = [json.loads(l) for l in sys.stdin if l.strip()]
A, B = rows[0::2], rows[1::2]
for k in ['wall_s', 'kernel_s', 'sums_s', 'forces_s', 'rebuild_s']:
    r = [a[k] / b[k] for a, b in zip(A, B)]
    us = lambda x: st.median(d[k] * 1e6 / d['steps'] for d in x)
    print('%-10s A %.1f B %.1f us a step; A / B median %.3f (%.3f-%.3f)' % (k, us(A), us(B), st.median(r), min(r), max(r)))
"
