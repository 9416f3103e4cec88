"""Run PySPH's stock example pysph.examples.poiseuille (TVF scheme, quintic
spline, dx = 1/60, Re = 0.0125, c0 = 10 Vmax) for a fixed number of steps and
print, as one JSON line, its throughput and its accuracy: the L_inf error of
the fluid's mean u per row (dx high) against the start-up series of plane
Poiseuille flow at the time reached, as a fraction of Vmax.

Usage: python pysph_poiseuille.py STEPS OUTDIR   (threads: OMP_NUM_THREADS)

Only the solve is timed (PySPH's own "Run took"); the set-up, which compiles
the equations, is not, as shearsph's set-up is not.
"""
import json
import math
import os
import sys
import time

import numpy as np
from pysph.examples.poiseuille import PoiseuilleFlow, dx


def startup(y, t, ly, fx, nu, tol=1e-15):
    """u(y, t) from rest between walls at y = 0 and ly under the body force fx
    (Morris, Fox & Zhu 1997), the series summed until the rest is below tol."""
    amp = 4.0 * fx * ly * ly / (nu * math.pi ** 3)
    tau = math.pi ** 2 * nu * t / (ly * ly)
    u = fx / (2.0 * nu) * y * (ly - y)
    k = 1.0
    while True:
        term = amp / k ** 3 * math.exp(-k * k * tau)
        u -= term * np.sin(k * math.pi * y / ly)
        if term < tol * fx / (2.0 * nu) * ly * ly / 4.0 or k > 1e6:
            return u
        k += 2.0


def main():
    steps = int(sys.argv[1])
    out = sys.argv[2]
    threads = int(os.environ.get("OMP_NUM_THREADS", "1"))
    app = PoiseuilleFlow(fname="poiseuille", output_dir=out)
    argv = ["--max-steps", str(steps), "--disable-output", "-q"]
    if threads > 1:
        argv.append("--openmp")
    app.setup(argv)
    start = time.perf_counter()
    app.solve()
    wall = time.perf_counter() - start
    solver = app.solver
    fluid = next(p for p in app.particles if p.name == "fluid")
    channel = next(p for p in app.particles if p.name == "channel")
    n_fluid = fluid.get_number_of_particles(real=True)
    n_wall = channel.get_number_of_particles(real=True)
    y = fluid.y[:n_fluid]
    u = fluid.u[:n_fluid]
    t = solver.t
    ly, nu, fx, vmax = app.Ly, app.nu, app.fx, app.Vmax
    # Mean u per row of height dx (the rows the particles started in).
    rows = int(round(ly / dx))
    row = np.clip(np.floor(y / dx).astype(int), 0, rows - 1)
    linf = 0.0
    for r in range(rows):
        sel = row == r
        if not sel.any():
            continue
        ym = y[sel].mean()
        linf = max(linf, abs(u[sel].mean() - startup(ym, t, ly, fx, nu)) / vmax)
    particles = n_fluid + n_wall
    print(json.dumps({
        "code": "pysph 1.0b2, examples.poiseuille (TVF, quintic spline)",
        "particles": particles,
        "n_fluid": n_fluid,
        "n_wall": n_wall,
        "steps": solver.count,
        "threads": threads,
        "wall_s": wall,
        "particle_steps_per_s": particles * solver.count / wall,
        "t": t,
        # time in units of B^2 / nu, B the half-width
        "tau": t * nu / (ly / 2.0) ** 2,
        "linf_rel_err": linf,
    }))


if __name__ == "__main__":
    main()
