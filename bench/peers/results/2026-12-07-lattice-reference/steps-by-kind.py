#!/usr/bin/env python3
"""Per step, the runs two `c0 --empirical --json` outputs share: for the
perfect lattice's runs and the seeds' apart, their steps, their run-seconds
(each run's own wall seconds, summed; three workers share two cores) and
the microseconds a step; then the c0s only one of them probed.

    python3 steps-by-kind.py OLD.json NEW.json
"""
import json
import sys


def runs(path):
    out = {}
    for t in json.load(open(path))["trials"]:
        c0 = round(t["c0_over_u"], 6)
        if t["perfect"]:
            out[(c0, "perfect")] = t["perfect"]
        for i, s in enumerate(t["seeds"]):
            out[(c0, f"seed {i + 1}")] = s
    return out


old, new = runs(sys.argv[1]), runs(sys.argv[2])
common = [k for k in old if k in new]
for kind in ("perfect", "seed"):
    keys = [k for k in common if k[1].startswith(kind)]
    so, sn = sum(old[k]["steps"] for k in keys), sum(new[k]["steps"] for k in keys)
    wo, wn = sum(old[k]["wall_s"] for k in keys), sum(new[k]["wall_s"] for k in keys)
    print(f"{kind}: {len(keys)} runs in both; steps {so} -> {sn}; run-s {wo:.1f} -> {wn:.1f}; "
          f"us a step {1e6 * wo / so:.2f} -> {1e6 * wn / sn:.2f} ({(wo / so) / (wn / sn):.2f}x)")
for name, a, b in (("old", old, new), ("new", new, old)):
    only = sorted({k[0] for k in a if k not in b})
    print(f"c0/U probed by {name} alone: {', '.join(f'{c:.3f}' for c in only) or '-'}")
