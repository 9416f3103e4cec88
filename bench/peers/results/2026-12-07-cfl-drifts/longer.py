#!/usr/bin/env python3
"""longer.sh's runs: each run's statistics at the longer horizon beside the
default horizon's (Morris's seeds, from runs.csv and the grid's CSV at
cfl 0.5), and its trajectory: the means of eps_p99 (x 1e3) and rms_v over
bins of 320 t (Morris) or of a twelfth of the run (Monaghan), from its
timeseries.csv.

usage: longer.py OUT runs.csv ../2026-12-07-cfl-factor/grid-runs.csv > longer.md
"""
import csv
import json
import os
import sys

out, csvs = sys.argv[1], sys.argv[2:]
default = {}
for path in csvs:
    with open(path) as fh:
        for r in csv.DictReader(fh):
            if "-cfl0.5-" in r["run"]:
                default[r["run"].replace("-cfl0.5", "")] = r


def mean(xs):
    return sum(xs) / len(xs)


print("| run | default horizon: t, eps_stat x 1e3, L_inf | longer: t, stationary, eps_stat x 1e3, L_inf, rms_v |")
print("|---|---|---|")
trajectories = []
for name in sorted(os.listdir(out)):
    path = os.path.join(out, name, "run.json")
    if not os.path.exists(path):
        continue
    with open(path) as fh:
        d = json.load(fh)
    dflt = default.get(name)
    dcol = (f"{float(dflt['t']):.0f}, {float(dflt['eps_stat']) * 1e3:.2f}, {float(dflt['linf_stat']):.3f}"
            if dflt else "-")
    print(f"| {name} | {dcol} | {d['t']:.0f}, {'yes' if d['stationary'] else 'no'}, "
          f"{d['eps_stat'] * 1e3:.2f}, {d['linf_stat']:.3f}, {d['rms_v_stat']:.4f} |")
    with open(os.path.join(out, name, "timeseries.csv")) as fh:
        ts = list(csv.DictReader(fh))
    t_end = float(ts[-1]["t"])
    width = 320.0 if name.startswith("morris") else t_end / 12
    bins = {}
    for x in ts:
        t = float(x["t"])
        if t > 0:
            bins.setdefault(int((t - 1e-9) // width), []).append(x)
    cells = []
    for b in sorted(bins):
        xs = bins[b]
        cells.append(f"{(b + 1) * width:.0f}: {mean([float(x['eps_p99']) for x in xs]) * 1e3:.2f} / "
                     f"{mean([float(x['rms_v']) for x in xs]):.4f}")
    trajectories.append(f"- {name}: " + "; ".join(cells))
print()
print("Trajectories (bin end: eps_p99 x 1e3 / rms_v, bin means):")
print()
print("\n".join(trajectories))
