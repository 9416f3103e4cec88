"""Summarise ab.sh's folder: per Re, each side's wall and CPU seconds, the
old / new ratio pair by pair, the runs and steps, and the answer.

    summarise.py OUT [OLD_LABEL NEW_LABEL]   (labels: what each build's default is)"""
import glob
import json
import os
import statistics
import sys

out = sys.argv[1]
labels = sys.argv[2:4] if len(sys.argv) >= 4 else ["old (0.125)", "new (0.85 F*)"]


def load(side, re):
    rows = []
    for t in sorted(glob.glob(f"{out}/{side}-re{re}-*.time")):
        i = t.rsplit("-", 1)[1].split(".")[0]
        wall, user, sys_ = (float(x) for x in open(t).read().split()[-3:])
        j = json.load(open(f"{out}/{side}-re{re}-{i}.json"))
        rows.append((int(i), wall, user + sys_, j))
    return sorted(rows, key=lambda r: r[0])


def answer(j):
    d = j["disordered"]
    nc = d.get("not_compressed")
    co = d.get("compressed")
    law = j.get("law") or {}
    steps = sum(
        r["steps"]
        for t in j["trials"]
        for r in ([t["perfect"]] if t.get("perfect") else []) + t.get("seeds", [])
    )
    return {
        "c0_min_ok": j["c0_min_ok"],
        "compaction needs": nc[0] if nc else None,
        "over-compressed at": co[0] if co else None,
        "ordered ok from": j["ordered"]["c0_min_ok"],
        "law k, m": (round(law["k"], 3), round(law["m"], 3)) if law else None,
        "runs": j["horizon"]["runs"],
        "steps": steps,
    }


res = sorted({os.path.basename(p).split("-")[1][2:] for p in glob.glob(f"{out}/*-re*-*.time")}, key=float)
for re in res:
    old, new = load("old", re), load("new", re)
    print(f"Re = {re}")
    for name, rows in ((labels[0], old), (labels[1], new)):
        walls = [r[1] for r in rows]
        cpus = [r[2] for r in rows]
        print(f"  {name:14} wall {', '.join(f'{w:.2f}' for w in walls)} s (median {statistics.median(walls):.2f}); "
              f"CPU {min(cpus):.2f}-{max(cpus):.2f} s")
    ratios = [o[1] / n[1] for o, n in zip(old, new)]
    print(f"  ratio old / new, pair by pair: {', '.join(f'{r:.3f}' for r in ratios)} (median {statistics.median(ratios):.3f})")
    for name, rows in (("old", old), ("new", new)):
        answers = [answer(r[3]) for r in rows]
        same = all(a == answers[0] for a in answers)
        print(f"  {name}: {answers[0]}; every repeat the same: {same}")
