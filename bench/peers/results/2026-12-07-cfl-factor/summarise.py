#!/usr/bin/env python3
"""The runs of cfl-grid.sh and threshold.sh, as tables.

  summarise.py csv RUNS_DIR > runs.csv     one line a run from its JSON
  summarise.py grid grid-runs.csv          by kernel, discretisation, scene
                                           and factor: the seeds' eps_stat
                                           and linf_stat as mean (range) and
                                           mean over the same at 0.25, the
                                           classes, the mean steps and
                                           stationary (y/n a run); the
                                           perfect lattice on its own row
  summarise.py threshold threshold-runs.csv
                                           the perfect lattice's largest
                                           compaction over the run (max_eps)
                                           at each multiple of the derived
                                           factor, FAIL where the run failed
"""
import collections
import csv
import json
import pathlib
import sys

FIELDS = ["class", "outcome", "steps", "t", "dt_limit_dominant", "eps_stat", "linf_stat",
          "stationary", "regime", "max_eps", "dy_rms", "failure_reason", "wall_s"]


def to_csv(runs_dir):
    w = csv.writer(sys.stdout)
    w.writerow(["run"] + FIELDS)
    for p in sorted(pathlib.Path(runs_dir).glob("*.json")):
        try:
            d = json.loads(p.read_text())
        except json.JSONDecodeError:
            d = {}
        w.writerow([p.stem] + [d.get(k) for k in FIELDS])


def rows(path):
    with open(path, newline="") as f:
        for r in csv.DictReader(f):
            for k in ["steps", "eps_stat", "linf_stat", "max_eps"]:
                r[k] = float(r[k]) if r[k] not in ("", "None") else None
            yield r


def stat(rs, k):
    v = [r[k] for r in rs if r["outcome"] == "ok" and r[k] is not None]
    if not v:
        return None
    return sum(v) / len(v), min(v), max(v)


def fmt(s, ref):
    if s is None:
        return "-"
    m, lo, hi = s
    x = f" x{m / ref[0]:.2f}" if ref and ref[0] > 0 else ""
    return f"{m:.3e} ({lo:.2e}-{hi:.2e}){x}"


def grid(path):
    runs = collections.defaultdict(list)
    for r in rows(path):
        kernel, lat, hd, re, c0, cfl, seed = r["run"].split("-")
        key = (kernel, lat, hd.replace("_", "/"), re[2:], c0[2:],
               "perfect" if seed == "seed0" else "seeds")
        runs[key, float(cfl[3:])].append(r)
    print("| kernel | lattice | h/d | Re | c0/U | start | CFL | eps_stat mean (range) x at 0.25 "
          "| linf_stat mean (range) x at 0.25 | classes | steps | stationary |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    keys = sorted({k for k, _ in runs}, key=lambda k: (k[0], k[3], k[1], k[2], k[5]))
    for key in keys:
        ref = runs.get((key, 0.25), [])
        ref_e, ref_l = stat(ref, "eps_stat"), stat(ref, "linf_stat")
        for f in sorted(f for k, f in runs if k == key):
            rs = runs[key, f]
            classes = ",".join(sorted(r["class"] for r in rs))
            steps = int(sum(r["steps"] or 0 for r in rs) / len(rs))
            st = "".join("y" if r["stationary"] == "True" else "n" for r in rs)
            print(f"| {' | '.join(key)} | {f} | {fmt(stat(rs, 'eps_stat'), ref_e)} | "
                  f"{fmt(stat(rs, 'linf_stat'), ref_l)} | {classes} | {steps} | {st} |")


def threshold(path):
    table = collections.defaultdict(dict)
    for r in rows(path):
        kernel, lat, hd, x, seed = r["run"].split("-")
        v = "FAIL" if r["class"] == "failed" else f"{r['max_eps']:.2g}"
        table[kernel, lat, hd.replace("_", "/"), seed][x[1:]] = v
    xs = ["0.9", "0.97", "1.03", "1.1"]
    print("| kernel | lattice | h/d | start | " + " | ".join(f"{x} x" for x in xs) + " |")
    print("|---|---|---|---|" + "---|" * len(xs))
    for (k, lat, hd, seed), v in sorted(table.items()):
        start = "perfect" if seed == "seed0" else "jitter 0.05, seed 1"
        print(f"| {k} | {lat} | {hd} | {start} | " + " | ".join(v.get(x, "") for x in xs) + " |")


{"csv": to_csv, "grid": grid, "threshold": threshold}[sys.argv[1]](sys.argv[2])
