#!/usr/bin/env python3
"""ab.sh's runs as one table: per scene, kernel, particle count and
threads, the ns per particle-step of each round's two builds (A = main,
B = large blocks advised onto huge pages), the per-round ratios A/B and
their median, and each pass's share of the step (kernel pass, sums, force
pass, list) in the last round, A -> B."""
import glob
import re
import statistics
from collections import defaultdict


def tables(path):
    """{(kernel, particles, threads): {"ns": .., "kern": .., ...}}"""
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
            rows[(f[0], int(f[1]), int(f[2]))]["ns"] = float(f[8])
        elif section == "pass" and len(f) >= 15:
            rows[(f[0], int(f[1]), int(f[2]))].update(
                kern=float(f[3]), sums=float(f[4]), forc=float(f[5]), list=float(f[13])
            )
    return rows


runs = defaultdict(lambda: defaultdict(dict))  # (scene, round) -> variant -> rows
for path in sorted(glob.glob("*-[ab]-[0-9].txt")):
    m = re.match(r"(disordered|two-threads|ordered)-([ab])-(\d+)\.txt", path)
    if not m:
        continue
    scene = "ordered" if m.group(1) == "ordered" else "disordered"
    runs[(scene, int(m.group(3)))][m.group(2)].update(tables(path))

keys = sorted({(s, k) for (s, _), r in runs.items() for v in r.values() for k in v})
print(f"{'scene':<11}{'kernel':<12}{'particles':>10}{'thr':>4}  {'ns/p-step A':>22}  {'B':>22}  "
      f"{'A/B':>16} {'median':>6}  kern/sums/forc/list % A -> B (last round)")
for s, k in keys:
    done = [r for (sc, r) in sorted(runs) if sc == s and k in runs[(s, r)]["a"] and k in runs[(s, r)]["b"]]
    if not done:
        continue
    a = [runs[(s, r)]["a"][k]["ns"] for r in done]
    b = [runs[(s, r)]["b"][k]["ns"] for r in done]
    ratios = [x / y for x, y in zip(a, b)]
    la, lb = runs[(s, done[-1])]["a"][k], runs[(s, done[-1])]["b"][k]
    shares = lambda d: "/".join(f"{d.get(x, float('nan')):.0f}" for x in ("kern", "sums", "forc", "list"))
    print(f"{s:<11}{k[0]:<12}{k[1]:>10}{k[2]:>4}  {' '.join(f'{x:6.1f}' for x in a):>22}  "
          f"{' '.join(f'{x:6.1f}' for x in b):>22}  {' '.join(f'{x:4.2f}' for x in ratios):>16} "
          f"{statistics.median(ratios):6.2f}  {shares(la)} -> {shares(lb)}")
