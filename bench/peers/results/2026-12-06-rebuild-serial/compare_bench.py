#!/usr/bin/env python3
"""Per-round ratios of two builds' `bench --disordered` tables: ns a
particle-step (the first table) and the list's share (list%), row by row.
usage: compare_bench.py BASE-1.txt NEW-1.txt [BASE-2.txt NEW-2.txt ...]"""
import sys
K = ('composite', 'monaghan', 'morris', 'wendland_c2')
def load(f):
    steps, lists = {}, {}
    for line in open(f):
        p = line.split()
        if not p or p[0] not in K:
            continue
        if p[-1] == 'ok' and len(p) == 15:
            steps[tuple(p[:3])] = float(p[8])
        elif p[-2] in ('lanes', 'pairs'):
            lists[tuple(p[:3])] = p[-4]
    return steps, lists
rows = {}
args = sys.argv[1:]
for base, new in zip(args[::2], args[1::2]):
    (b, bl), (n, nl) = load(base), load(new)
    for k in b:
        rows.setdefault(k, []).append(f'{b[k]:.1f} -> {n[k]:.1f} ({b[k] / n[k]:.3f}), list% {bl.get(k)} -> {nl.get(k)}')
print('kernel particles threads: ns a particle-step base -> new (ratio), per round')
for k, v in rows.items():
    print(' '.join(k) + ': ' + '; '.join(v))
