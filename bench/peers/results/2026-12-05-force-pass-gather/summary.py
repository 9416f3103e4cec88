#!/usr/bin/env python3
"""One comparison of ab.sh as a table: `summary.py TAG` reads
round-R-{a,b}-TAG.txt and prints, per kernel and particle count, the ns per
particle-step of each round's two binaries (1 thread), the per-round ratio
a/b (above 1: b is faster) and its median, and of the last round the
kernel pass's ns per pair, the force pass's ns per lane, list% and where
the force pass read (dW/dq)/q (g) for each binary."""
import glob
import re
import statistics
import sys
from collections import defaultdict


def tables(path):
    """{(kernel, particles): {"ns": .., "kern": .., "lane": .., "list": .., "g": ..}}"""
    rows = defaultdict(dict)
    section = None
    for line in open(path):
        if line.startswith("kernel     particles thr  steps"):
            section = "main"
            continue
        if line.startswith("kernel     particles thr  kern%"):
            section = "pass"
            continue
        if not line.strip():
            section = None
            continue
        f = line.split()
        if section == "main" and len(f) > 9:
            rows[(f[0], int(f[1]))]["ns"] = float(f[8])
        elif section == "pass" and len(f) >= 15:
            rows[(f[0], int(f[1]))].update(
                kern=float(f[6]),
                lane=float(f[9]),
                list=float(f[13]),
                g=f[15] if len(f) > 15 else "lanes",
            )
    return rows


tag = sys.argv[1]
runs = defaultdict(dict)  # round -> variant -> rows
for path in sorted(glob.glob(f"round-*-*-{tag}.txt")):
    m = re.match(rf"round-(\d+)-(a|b)-{re.escape(tag)}\.txt", path)
    r, v = int(m.group(1)), m.group(2)
    runs[r][v] = tables(path)

keys = sorted({k for r in runs.values() for v in r.values() for k in v})
print(f"{'kernel':<11}{'particles':>9}  {'ns/p-step a':>15}  {'b':>15}  {'a/b':>11} {'median':>6}"
      f"  {'kern ns a -> b':>15}  {'ns/lane a -> b':>15}  {'list% a -> b':>13}  g a -> b")
for k in keys:
    done = [r for r in sorted(runs) if k in runs[r].get("a", {}) and k in runs[r].get("b", {})]
    if not done:
        continue
    a = [runs[r]["a"][k]["ns"] for r in done]
    b = [runs[r]["b"][k]["ns"] for r in done]
    ratios = [x / y for x, y in zip(a, b)]
    la, lb = runs[done[-1]]["a"][k], runs[done[-1]]["b"][k]
    print(f"{k[0]:<11}{k[1]:>9}  {' '.join(f'{x:7.1f}' for x in a):>15}  "
          f"{' '.join(f'{x:7.1f}' for x in b):>15}  "
          f"{' '.join(f'{x:5.2f}' for x in ratios):>11} {statistics.median(ratios):6.2f}"
          f"  {la['kern']:6.2f} -> {lb['kern']:5.2f}  {la['lane']:6.3f} -> {lb['lane']:5.3f}"
          f"  {la['list']:5.1f} -> {lb['list']:4.1f}  {la['g']} -> {lb['g']}")
