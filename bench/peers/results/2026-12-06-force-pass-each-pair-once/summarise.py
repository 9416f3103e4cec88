#!/usr/bin/env python3
"""main against the prototype, round by round, from ab.sh's bench tables.

Usage: summarise.py RUNS_DIR ROUNDS. Per kernel and size: the medians of
the step (ns a particle-step) and of the per-round ratios main / prototype
of the step and of the force pass (its share times the step), with their
ranges. A ratio below 1: the prototype is slower.
"""
import re
import statistics as st
import sys


def parse(path):
    rows, passes, mode = {}, {}, None
    for line in open(path).read().splitlines():
        if re.match(r"^kernel +particles thr +steps", line):
            mode = "rows"
            continue
        if "kern%  sums%  forc%" in line:
            mode = "passes"
            continue
        if not line.strip():
            mode = None
            continue
        p = line.split()
        if mode == "rows":
            rows[(p[0], int(p[1]))] = float(p[8])
        elif mode == "passes":
            passes[(p[0], int(p[1]))] = float(p[5])
    return rows, passes


out, rounds = sys.argv[1], int(sys.argv[2])
res = {}
for r in range(1, rounds + 1):
    m, mf = parse(f"{out}/disordered-main-{r}.txt")
    p, pf = parse(f"{out}/disordered-proto-{r}.txt")
    for k in m:
        res.setdefault(k, []).append((m[k], p[k], m[k] * mf[k] / p[k] / pf[k]))
print("kernel       particles  main ns  proto ns  step main/proto     force pass main/proto")
for (kernel, n), v in sorted(res.items()):
    step = [a / b for a, b, _ in v]
    force = [f for _, _, f in v]
    print(
        f"{kernel:12s} {n:9d} {st.median(a for a, _, _ in v):8.1f} {st.median(b for _, b, _ in v):9.1f}"
        f"  {st.median(step):.2f} ({min(step):.2f}-{max(step):.2f})"
        f"     {st.median(force):.2f} ({min(force):.2f}-{max(force):.2f})"
    )
