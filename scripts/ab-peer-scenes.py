#!/usr/bin/env python3
"""Alternating A/B of shearsph binaries on the peers' matched scenes.

The machines here are noisy (whole runs move by 30-40 % from minute to
minute), so a speed-up counts only as the ratio of runs made side by side:
each round runs every binary once per scene, in an order that alternates
from round to round, and the ratios to the first binary are taken within
each round. Prints each round's ratios, then per scene and binary the
median particle-steps/s, the median of the per-round ratios with their
range, and the L_inf error each binary reached (a change that only moves
code keeps it to the last digit).

usage: scripts/ab-peer-scenes.py [--rounds N] [--threads T] [--scenes S,S] BASE NEW [NEW...]

  BASE, NEW   shearsph binaries (e.g. one built in a worktree of the old
              commit: `git worktree add /tmp/old REV && cargo build
              --release --target-dir /tmp/old-target` there)
  --rounds    rounds (default 7)
  --threads   the solver's threads (default 1)
  --scenes    pysph (`bench --pysph-match --steps 2000`: PySPH's example
              scene, 1690 particles), sphinxsys (`bench --sphinxsys-match
              --tau 0.5 --columns 120`: SPHinXsys's channel, 2760
              particles); default both
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import time

SCENES = {
    "pysph": ["bench", "--pysph-match", "--steps", "2000"],
    "sphinxsys": ["bench", "--sphinxsys-match", "--tau", "0.5", "--columns", "120"],
}


def run(binary, scene, threads):
    cmd = [binary] + SCENES[scene] + ["--threads", str(threads)]
    done = subprocess.run(cmd, capture_output=True, text=True)
    if done.returncode != 0:
        sys.exit(f"ab-peer-scenes: `{' '.join(cmd)}` failed (exit {done.returncode}): {done.stderr.strip()}")
    lines = done.stdout.strip().splitlines()
    try:
        d = json.loads(lines[-1])
        return d["particle_steps_per_s"], d["linf_rel_err"]
    except (IndexError, ValueError, KeyError) as e:
        sys.exit(f"ab-peer-scenes: `{' '.join(cmd)}` printed no JSON line with particle_steps_per_s and linf_rel_err ({e})")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=7)
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--scenes", default="pysph,sphinxsys")
    ap.add_argument("bins", nargs="+", metavar="BIN")
    a = ap.parse_args()
    scenes = a.scenes.split(",")
    for s in scenes:
        if s not in SCENES:
            sys.exit(f"ab-peer-scenes: --scenes: unknown scene {s!r} (known: {', '.join(SCENES)})")
    if len(a.bins) < 2:
        sys.exit("ab-peer-scenes: give a base binary and at least one other")
    if a.rounds < 1 or a.threads < 1:
        sys.exit("ab-peer-scenes: --rounds and --threads must be at least 1")
    for b in a.bins:
        if not (os.path.isfile(b) and os.access(b, os.X_OK)):
            sys.exit(f"ab-peer-scenes: {b}: not an executable file")
    bins = a.bins
    names = [os.path.basename(b) for b in bins]
    res = {s: {b: [] for b in bins} for s in scenes}
    print(f"{a.rounds} rounds, {a.threads} thread(s), ratios to {names[0]} ({', '.join(names[1:])})", flush=True)
    for r in range(a.rounds):
        order = bins if r % 2 == 0 else bins[::-1]
        for s in scenes:
            for b in order:
                res[s][b].append(run(b, s, a.threads))
        cells = "  ".join(
            f"{s} " + " ".join(f"{res[s][b][-1][0] / res[s][bins[0]][-1][0]:.3f}" for b in bins[1:]) for s in scenes
        )
        print(f"round {r + 1} {time.strftime('%H:%M:%S', time.gmtime())} UTC: {cells}", flush=True)
    for s in scenes:
        base = [v for v, _ in res[s][bins[0]]]
        print(f"{s}, {a.threads} thread(s): {names[0]} {statistics.median(base):.4g} p-steps/s (median), "
              f"L_inf {res[s][bins[0]][0][1]!r}")
        for b, name in zip(bins[1:], names[1:]):
            new = [v for v, _ in res[s][b]]
            ratios = [y / x for x, y in zip(base, new)]
            errs = sorted({e for _, e in res[s][b]})
            print(f"  {name}: {statistics.median(new):.4g} p-steps/s; per-round ratio median "
                  f"{statistics.median(ratios):.3f} ({min(ratios):.3f}-{max(ratios):.3f}); L_inf "
                  + ", ".join(repr(e) for e in errs))


if __name__ == "__main__":
    main()
