#!/usr/bin/env python3
"""The two drifts with 40 seeds: each case's eps_stat and mean-flow L_inf by
CFL factor (mean, standard deviation, standard error of the mean over the
seeds), and each factor's difference from 0.25's in standard errors (the
two means' difference over the root sum of their squared standard errors).
Seeds 1-3 from the grid's CSV, 4-40 from this folder's runs.

usage: summarise.py RUNS GRID_CSV > summary.md  (RUNS: a directory of
run JSONs, or a CSV in the grid's columns such as runs.csv)
"""
import csv
import glob
import json
import math
import os
import re
import sys

runs_dir, grid_csv = sys.argv[1], sys.argv[2]
CASES = {
    "monaghan-triangular-1-re1-c0100": "Monaghan, triangular h = d, Re 1, 100 U",
    "morris-square-17_10-re30-c010": "Morris, square 17/10, Re 30, 10 U",
}
FACTORS = ["0.25", "0.5", "1.0"]
rows = {}  # (case, factor) -> list of (seed, eps, linf, stationary, class, t)


def add(name, cls, eps, linf, stationary, t):
    m = re.match(r"(.*)-cfl([0-9.]+)-seed(\d+)$", name)
    case, f, seed = m.group(1), m.group(2), int(m.group(3))
    if case in CASES and f in FACTORS and seed > 0:
        rows.setdefault((case, f), []).append((seed, eps, linf, stationary, cls, t))


def add_csv(path):
    with open(path) as fh:
        for r in csv.DictReader(fh):
            add(r["run"], r["class"], float(r["eps_stat"]), float(r["linf_stat"]),
                r["stationary"] == "True", float(r["t"]))


add_csv(grid_csv)
if runs_dir.endswith(".csv"):
    add_csv(runs_dir)
for path in sorted(glob.glob(os.path.join(runs_dir, "*.json"))):
    name = os.path.basename(path)[:-5]
    with open(path) as fh:
        d = json.load(fh)
    s = d["summary"] if "summary" in d else d
    add(name, s["class"], s["eps_stat"], s["linf_stat"], s["stationary"], s["t"])


def stats(xs):
    n = len(xs)
    m = sum(xs) / n
    sd = math.sqrt(sum((x - m) ** 2 for x in xs) / (n - 1))
    return m, sd, sd / math.sqrt(n)


print("| case | factor | seeds (stationary) | eps_stat x 1e3: mean, sd, se | vs 0.25 | mean-flow L_inf: mean, sd, se | vs 0.25 |")
print("|---|---|---|---|---|---|---|")
for case, label in CASES.items():
    base = None
    for f in FACTORS:
        rs = sorted(rows.get((case, f), []))
        if len(rs) < 2:
            continue
        eps = stats([r[1] * 1e3 for r in rs])
        linf = stats([r[2] for r in rs])
        if base is None:
            base = (eps, linf)
            de = dl = "-"
        else:
            de = "%+.1f %% (%+.1f se)" % (100 * (eps[0] / base[0][0] - 1),
                                          (eps[0] - base[0][0]) / math.hypot(eps[2], base[0][2]))
            dl = "%+.1f %% (%+.1f se)" % (100 * (linf[0] / base[1][0] - 1),
                                          (linf[0] - base[1][0]) / math.hypot(linf[2], base[1][2]))
        n_stat = sum(1 for r in rs if r[3])
        print(f"| {label} | {f} | {len(rs)} ({n_stat}) | {eps[0]:.2f}, {eps[1]:.2f}, {eps[2]:.2f} | {de} | {linf[0]:.3f}, {linf[1]:.3f}, {linf[2]:.3f} | {dl} |")
print()
print("Each run (seed: class, stationary, t, eps_stat x 1e3, L_inf):")
print()
for case, label in CASES.items():
    for f in FACTORS:
        rs = sorted(rows.get((case, f), []))
        print(f"- {label}, {f}: " + "; ".join(
            f"{r[0]}: {r[4]}{'' if r[3] else ' (not stationary)'}, t {r[5]:.0f}, {r[1]*1e3:.2f}, {r[2]:.3f}" for r in rs))
print()
print("By the checkpoint each run stopped at (the time, the runs there, their mean eps_stat x 1e3):")
print()
for case, label in CASES.items():
    for f in FACTORS:
        by = {}
        for r in rows.get((case, f), []):
            by.setdefault(round(r[5]), []).append(r[1] * 1e3)
        print(f"- {label}, {f}: " + "; ".join(
            f"t {t}: {len(v)} runs, {sum(v) / len(v):.2f}" for t, v in sorted(by.items())))
