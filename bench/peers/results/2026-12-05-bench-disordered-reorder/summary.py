#!/usr/bin/env python3
"""The A/B of ab.sh as one table: per kernel and particle count, the ns per
particle-step of each round's two binaries (1 thread), the per-round ratio
before/after and its median, with lanes%, list% and rebuilds of the last
round."""
import glob
import re
import statistics
from collections import defaultdict


def tables(path):
    """{(kernel, particles): {"ns": .., "lanes": .., "list": .., "rebu": ..}}"""
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
                lanes=float(f[12]), list=float(f[13]), rebu=int(f[14])
            )
    return rows


runs = defaultdict(dict)  # round -> variant -> rows
for path in sorted(glob.glob("round-*-*-*.txt")):
    m = re.match(r"round-(\d+)-(after|before)-", path)
    r, v = int(m.group(1)), m.group(2)
    runs[r].setdefault(v, {}).update(tables(path))

keys = sorted({k for r in runs.values() for v in r.values() for k in v})
print(f"{'kernel':<12}{'particles':>10}  {'ns/p-step before':>24}  {'after':>20}  "
      f"{'before/after':>18} {'median':>7}  lanes% b->a  list% b->a  rebuilds b->a")
for k in keys:
    done = [r for r in sorted(runs) if k in runs[r].get("before", {}) and k in runs[r].get("after", {})]
    b = [runs[r]["before"][k]["ns"] for r in done]
    a = [runs[r]["after"][k]["ns"] for r in done]
    if not done:
        continue
    ratios = [x / y for x, y in zip(b, a)]
    both = [r for r in sorted(runs) if k in runs[r].get("before", {}) and k in runs[r].get("after", {})]
    if not both:
        continue
    lb, la = runs[both[-1]]["before"][k], runs[both[-1]]["after"][k]
    print(f"{k[0]:<12}{k[1]:>10}  {' '.join(f'{x:7.1f}' for x in b):>24}  "
          f"{' '.join(f'{x:7.1f}' for x in a):>20}  "
          f"{' '.join(f'{x:5.2f}' for x in ratios):>18} {statistics.median(ratios):7.2f}  "
          f"{lb['lanes']:5.1f} -> {la['lanes']:5.1f}  {lb['list']:4.1f} -> {la['list']:4.1f}  "
          f"{lb['rebu']:4d} -> {la['rebu']:4d}")
