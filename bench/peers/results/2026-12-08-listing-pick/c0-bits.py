#!/usr/bin/env python3
"""Compare `c0 --empirical --json` of two builds, field by field, the wall
times left out: for each KERNEL-RE, whether the answer (every field but the
trials and the rules' runs) is the same, and each trial run that differs.

    c0-bits.py DIR composite-10 wendland_c2-1 ...

reads DIR/KERNEL-RE-before.json and DIR/KERNEL-RE-after.json."""
import json
import sys

WALL = {"wall_s"}


def strip(o):
    if isinstance(o, dict):
        return {k: strip(v) for k, v in o.items() if k not in WALL}
    if isinstance(o, list):
        return [strip(v) for v in o]
    return o


def runs(t):
    out = [("perfect", t["perfect"])] if t.get("perfect") else []
    return out + [(f"seed {i + 1}", s) for i, s in enumerate(t.get("seeds") or [])]


folder = sys.argv[1]
for name in sys.argv[2:]:
    a = strip(json.load(open(f"{folder}/{name}-before.json")))
    b = strip(json.load(open(f"{folder}/{name}-after.json")))
    answer = [k for k in a if k not in ("trials", "rules") and a[k] != b.get(k)]
    differing = [(ta, tb) for ta, tb in zip(a["trials"], b["trials"]) if ta != tb]
    print(f"{name}: {'identical' if a == b else 'differs'}; the answer's fields "
          f"{'the same' if not answer else 'differ: ' + ', '.join(answer)}; "
          f"{len(differing)} of {len(a['trials'])} trials differ")
    for ta, tb in differing:
        for (n, ra), (_, rb) in zip(runs(ta), runs(tb)):
            if ra == rb:
                continue
            moved = []
            for f in ("class", "regime", "steps", "t", "eps_stat", "linf_stat", "dy_rms"):
                x, y = ra.get(f), rb.get(f)
                if x == y:
                    continue
                if isinstance(x, float) and isinstance(y, float) and x != 0:
                    moved.append(f"{f} {x:.6g} -> {y:.6g} ({(y - x) / abs(x):+.1e})")
                else:
                    moved.append(f"{f} {x} -> {y}")
            print(f"  c0 = {ta['c0_over_u']:.4g} U, {n}: " + "; ".join(moved))
    for ra, rb in zip(a["rules"], b["rules"]):
        if ra != rb:
            print(f"  rule {ra['name']}: its trial's pooled statistics moved with it")
