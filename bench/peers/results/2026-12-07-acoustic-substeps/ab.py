#!/usr/bin/env python3
"""The step with and without the viscous term, alternating: the upper bound
of what acoustic substeps could spare (README.md).

    MAIN=<main's shearsph> PATCHED=<build with no-viscous-term.patch> \
        ./ab.py [ROUNDS] > ab.txt

Each round runs `bench` for each kernel on the ordered bench scene at 1e3
and 1e4 particles on one thread, main first then the patch, and keeps the
bench's own seconds a step (the steps alone, the set-up left out), the
force pass's ns a lane and the list's rebuilds. Without the viscous term
the flow is not the same (nothing balances the body force), so a count
whose rebuilds differ between the two builds compares the force pass
alone. Prints every round's figures and the patched over main ratios, then
per kernel and count the median ratios and their ranges.
"""
import os
import statistics
import subprocess
import sys

ROUNDS = int(sys.argv[1]) if len(sys.argv) > 1 else 10
KERNELS = ["monaghan", "morris", "wendland_c2", "composite"]
ARGS = ["bench", "--particles", "1e3,1e4", "--threads", "1", "--steps", "1500",
        "--repeats", "1", "--no-bandwidth", "--quiet"]


def s_per_step(binary, kernel):
    out = subprocess.run([binary, *ARGS, "--kernels", kernel], check=True,
                         capture_output=True, text=True,
                         env={**os.environ, "RAYON_NUM_THREADS": "1"}).stdout
    step, lane = {}, {}
    for line in out.splitlines():
        f = line.split()
        if len(f) < 5 or f[0] != kernel or f[2] != "1":
            continue
        if f[1] not in step:
            # The first table: kernel particles thr steps s/step ...
            step[f[1]] = float(f[4])
        elif len(f) == 17 and f[-2] in ("pairs", "lanes") and f[1] not in lane:
            # The pass-by-pass table: ... ns/lane (10th), ..., list% rebu g vec
            lane[f[1]] = (float(f[9]), int(f[-3]))
    return {n: (step[n], *lane[n]) for n in step}


ratios = {}
for r in range(1, ROUNDS + 1):
    for k in KERNELS:
        main = s_per_step(os.environ["MAIN"], k)
        patched = s_per_step(os.environ["PATCHED"], k)
        for n in main:
            (sm, lm, rm), (sp, lp, rp) = main[n], patched[n]
            q = (sp / sm, lp / lm, rm == rp)
            ratios.setdefault((k, n), []).append(q)
            print(f"round {r} {k} {n}: s/step {sm:.4e} -> {sp:.4e} ({q[0]:.3f}), force pass "
                  f"ns/lane {lm:.3f} -> {lp:.3f} ({q[1]:.3f}), rebuilds {rm} -> {rp}", flush=True)
print()
print("kernel particles: the patch over main, median (range) over", ROUNDS, "rounds:")
print("the step (where every round rebuilt as often), the force pass a lane")
for (k, n), qs in ratios.items():
    step = [q[0] for q in qs]
    lane = [q[1] for q in qs]
    same = all(q[2] for q in qs)
    st = f"{statistics.median(step):.3f} ({min(step):.3f}-{max(step):.3f})" if same else "rebuilds differ"
    print(f"{k} {n}: step {st}; force pass {statistics.median(lane):.3f} ({min(lane):.3f}-{max(lane):.3f})")
