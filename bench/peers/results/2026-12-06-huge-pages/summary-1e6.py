#!/usr/bin/env python3
"""ab-1e6.sh's rounds: ns per particle-step at 1e6 of main (A) and the
huge pages (B), kernel by kernel, the per-round ratios A/B and their
median."""
import glob
import re
import statistics
from collections import defaultdict

ns = defaultdict(dict)
for path in glob.glob("1e6-*-[ab]-[0-9].txt"):
    m = re.match(r"1e6-(.+)-([ab])-(\d+)\.txt", path)
    rows = [l.split() for l in open(path)]
    head = next(i for i, l in enumerate(rows) if l[:4] == ["kernel", "particles", "thr", "steps"])
    ns[(m.group(1), int(m.group(3)))][m.group(2)] = float(rows[head + 1][8])
for k in sorted({k for k, _ in ns}):
    rs = sorted(r for kk, r in ns if kk == k and len(ns[(kk, r)]) == 2)
    a = [ns[(k, r)]["a"] for r in rs]
    b = [ns[(k, r)]["b"] for r in rs]
    q = [x / y for x, y in zip(a, b)]
    print(f"{k:<12} A {' '.join(f'{x:6.1f}' for x in a)}  B {' '.join(f'{x:6.1f}' for x in b)}  "
          f"A/B {' '.join(f'{x:4.2f}' for x in q)}  median {statistics.median(q):4.2f}")
