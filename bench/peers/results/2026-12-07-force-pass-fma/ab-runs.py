#!/usr/bin/env python3
"""Whole runs of two shearsph binaries in turn (A B A B ...), one thread,
the wall time of each and A/B pair by pair: medians and ranges.

    ab-runs.py A_BIN B_BIN PAIRS KERNEL [KERNEL ..]

Each run: a jittered start (0.05 d, seed 1) on a strip as wide as the
channel, Monaghan's search scene at Re = 1 and 28 U, to t = 1200.
"""
import os
import statistics
import subprocess
import sys
import tempfile
import time


def run(binary, kernel, out):
    cmd = [binary, "run", "--kernel", kernel, "--n", "10", "--re", "1",
           "--c0", "28", "--jitter", "0.05", "--jitter-seed", "1",
           "--columns", "18", "--t-end", "1200", "--out", out, "--force",
           "--quiet", "--no-particles"]
    env = dict(os.environ, RAYON_NUM_THREADS="1")
    t0 = time.perf_counter()
    # The exit status is the run's class (5: not ok), not an error.
    subprocess.run(cmd, check=False, env=env, stdout=subprocess.DEVNULL)
    return time.perf_counter() - t0


def main():
    a, b, pairs, kernels = sys.argv[1], sys.argv[2], int(sys.argv[3]), sys.argv[4:]
    with tempfile.TemporaryDirectory() as tmp:
        for kernel in kernels:
            ta, tb = [], []
            run(a, kernel, os.path.join(tmp, "a"))  # warm-up
            for _ in range(pairs):
                ta.append(run(a, kernel, os.path.join(tmp, "a")))
                tb.append(run(b, kernel, os.path.join(tmp, "b")))
            ratios = [x / y for x, y in zip(ta, tb)]
            print(f"{kernel}: A {statistics.median(ta):.3f} s "
                  f"({min(ta):.3f}-{max(ta):.3f}), B {statistics.median(tb):.3f} s "
                  f"({min(tb):.3f}-{max(tb):.3f}), A/B median {statistics.median(ratios):.3f} "
                  f"({min(ratios):.3f}-{max(ratios):.3f}), {pairs} pairs", flush=True)


main()
