#!/usr/bin/env python3
"""The filed build against main on the disordered scene (ab-filed.sh's
files in this folder): per kernel and particle count, ns a particle-step
of each build in each round, the rounds' means, and the rounds' ratios
filed / main (above 1: main is faster)."""
import collections, glob, re

ns = collections.defaultdict(dict)  # (kernel, size, build) -> round -> ns/p-step
for f in sorted(glob.glob("bench-*.txt")):
    m = re.match(r"bench-(?:1e6-)?(filed|now)-(\d)\.txt$", f)
    if not m:
        continue
    build, r = m.groups()
    section = False
    for line in open(f):
        if line.startswith("kernel     particles thr  steps"):
            section = True
            continue
        t = line.split()
        if not t:
            section = False
            continue
        if section and len(t) > 8 and t[2] == "1":
            ns[(t[0], int(t[1]), build)][r] = float(t[8])

print(f"{'kernel':<12}{'particles':>10}  {'filed, rounds':<18}{'main, rounds':<18}{'means':<18}filed / main")
for kernel, size in sorted({(k, s) for k, s, _ in ns}):
    f, n = ns.get((kernel, size, "filed"), {}), ns.get((kernel, size, "now"), {})
    rounds = sorted(set(f) & set(n))
    if not rounds:
        continue
    ratios = ", ".join(f"{f[r] / n[r]:.2f}" for r in rounds)
    mf = sum(f[r] for r in rounds) / len(rounds)
    mn = sum(n[r] for r in rounds) / len(rounds)
    print(f"{kernel:<12}{size:>10}  {', '.join(f'{f[r]:.1f}' for r in rounds):<18}"
          f"{', '.join(f'{n[r]:.1f}' for r in rounds):<18}{f'{mf:.1f} -> {mn:.1f}':<18}{ratios}")
