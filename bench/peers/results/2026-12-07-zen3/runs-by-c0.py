#!/usr/bin/env python3
"""Where `c0 --empirical --json` spent its runs: per c0 probed, the perfect
lattice's steps and the seeds', their run-seconds (each run's own wall
seconds, summed; three workers share two cores, so these add up to more
than the process's wall time) and share, and which rules asked for it.

    python3 runs-by-c0.py c0-re1.json
"""
import json
import sys

d = json.load(open(sys.argv[1]))
rules = {}
for r in d["rules"]:
    rules.setdefault(round(r["c0_over_u"], 9), []).append(r["name"])
rows = []
for t in d["trials"]:
    p, seeds = t["perfect"], t["seeds"]
    rows.append((
        t["c0_over_u"],
        p["steps"] if p else 0,
        sum(s["steps"] for s in seeds),
        (p["wall_s"] if p else 0.0) + sum(s["wall_s"] for s in seeds),
        p["class"] if p else "-",
        t["pooled"]["class"] if t["pooled"] else "-",
        ", ".join(rules.get(round(t["c0_over_u"], 9), [])) or "-",
    ))
total = sum(r[3] for r in rows)
print(f"{'c0/U':>8} {'perfect steps':>13} {'seeds steps':>11} {'run-s':>6} {'share':>6}  ordered / disordered  rules")
for c0, ps, ss, w, o, dis, names in rows:
    print(f"{c0:8.3f} {ps:13d} {ss:11d} {w:6.1f} {100 * w / total:5.1f}%  {o} / {dis}  {names}")
print(f"total: {sum(r[1] + r[2] for r in rows)} steps, {total:.1f} run-s")
