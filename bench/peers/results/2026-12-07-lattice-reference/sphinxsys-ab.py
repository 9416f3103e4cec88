#!/usr/bin/env python3
"""SPHinXsys's matched scene against two shearsph builds, alternating.

Each round runs SPHinXsys's matched case (bench/peers/sphinxsys/, built by
bench/peers/sphinxsys_poiseuille.sh) and `bench --sphinxsys-match --tau TAU
--columns 120` of each shearsph binary, on THREADS threads, in an order that
rotates from round to round; each shearsph binary's particle-steps per
second over SPHinXsys's in the same round is that round's per-step ratio.
Prints every run and, per binary, the median and range of the rounds'
ratios, its rebuilds and its L_inf. CFL=F or CFL=default in the environment
runs shearsph at that CFL factor (`--cfl`; the matched scene's 0.5 without).

usage: sphinxsys-ab.py SPHINXSYS_CASE_BIN ROUNDS THREADS TAU NAME=BIN [NAME=BIN...]
"""
import json
import os
import statistics
import subprocess
import sys
import tempfile

case, rounds, threads, tau = sys.argv[1], int(sys.argv[2]), sys.argv[3], sys.argv[4]
bins = [a.split("=", 1) for a in sys.argv[5:]]
scratch = tempfile.mkdtemp()


def last_json(cmd, cwd=None):
    out = subprocess.run(cmd, capture_output=True, text=True, check=True, cwd=cwd).stdout
    return json.loads(out.strip().splitlines()[-1])


def sphinxsys():
    cmd = [case, "--layers", "10", "--re", "7.5", "--c0-factor", "10", "--tau", tau,
           "--columns", "120", "--threads", threads]
    return last_json(cmd, cwd=scratch)


def shearsph(binary):
    cmd = [binary, "bench", "--sphinxsys-match", "--tau", tau, "--columns", "120",
           "--threads", threads]
    if os.environ.get("CFL"):
        cmd += ["--cfl", os.environ["CFL"]]
    return last_json(cmd)


jobs = [("sphinxsys", None)] + [(n, b) for n, b in bins]
ratios = {n: [] for n, _ in bins}
runs = {n: [] for n, _ in jobs}
for r in range(rounds):
    k = r % len(jobs)
    order = jobs[k:] + jobs[:k]
    got = {}
    for name, binary in order:
        got[name] = sphinxsys() if binary is None else shearsph(binary)
        runs[name].append(got[name])
    sx = got["sphinxsys"]["particle_steps_per_s"]
    line = [f"round {r + 1}: sphinxsys {sx:.4g} p-steps/s"]
    for name, _ in bins:
        run = got[name]
        ratios[name].append(run["particle_steps_per_s"] / sx)
        line.append(f"{name} {run['particle_steps_per_s']:.4g} ({ratios[name][-1]:.2f}x, "
                    f"{run.get('neighbour_rebuilds')} rebuilds, {run['wall_s']:.3f} s)")
    print("; ".join(line), flush=True)
print(f"{rounds} rounds, {threads} thread(s), tau {tau}, CFL {os.environ.get('CFL') or 0.5}:")
for name, _ in bins:
    q = ratios[name]
    last = runs[name][-1]
    print(f"  {name}: per-step ratio to SPHinXsys median {statistics.median(q):.2f} "
          f"({min(q):.2f}-{max(q):.2f}); {last.get('neighbour_rebuilds')} rebuilds in "
          f"{last['steps']} steps; L_inf {last['linf_rel_err']!r}")
