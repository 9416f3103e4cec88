"""Run PySPH's stock example pysph.examples.poiseuille (TVF scheme, quintic
spline, dx = 1/60, Re = 0.0125, c0 = 10 Vmax) for a fixed number of steps and
print, as one JSON line, its throughput and its accuracy: the L_inf error of
the fluid's mean u per row (dx high) against the start-up series of plane
Poiseuille flow at the time reached, as a fraction of Vmax.

Usage: python pysph_poiseuille.py STEPS OUTDIR [ROWS]   (threads: OMP_NUM_THREADS)

ROWS (default 60, the example's dx = 1/60) runs the same flow at another
resolution: dx = Ly / ROWS (so h = dx, the ghost layers 5 dx deep) and the
channel 0.4 Ly long rounded to whole columns (24 at the example's dx, where it
is the example's 0.4 exactly). STEPS is then scaled by (ROWS / 60)^2, the
viscous limit 0.125 h^2 / nu binding at every ROWS, so every resolution
reaches the same t nu / B^2 (as `shearsph bench --pysph-match --layers N`
scales its steps by (N / 35)^2).

Only the solve is timed (PySPH's own "Run took"); the set-up, which compiles
the equations, is not, as shearsph's set-up is not.
"""
import json
import os
import sys
import time

import numpy as np
from pysph.examples import poiseuille

from peer_metric import startup

# The example's resolution: dx = Ly / 60 (Ly = 1).
EXAMPLE_ROWS = 60


def resolution(rows):
    """Set the example's module-level resolution (its dx, h0 = hdx dx and the
    ghost layers' depth, which its methods read) to Ly / rows; return dx."""
    dx = 1.0 / rows
    poiseuille.dx = dx
    poiseuille.h0 = poiseuille.hdx * dx
    poiseuille.ghost_extent = 5 * dx
    return dx


class Flow(poiseuille.PoiseuilleFlow):
    """The example, its channel length 0.4 Ly rounded to whole columns of the
    current dx (periodic in x: a fraction of a column would leave a seam)."""

    def initialize(self):
        super().initialize()
        dx = poiseuille.dx
        self.Lx = max(1, round(0.4 * self.Ly / dx)) * dx


def main():
    steps = int(sys.argv[1])
    out = sys.argv[2]
    rows = int(sys.argv[3]) if len(sys.argv) > 3 else EXAMPLE_ROWS
    if rows < 6:
        sys.exit(f"pysph_poiseuille.py: ROWS {rows}: need at least 6 rows across the channel")
    dx = resolution(rows)
    steps = max(1, round(steps * (rows / EXAMPLE_ROWS) ** 2))
    threads = int(os.environ.get("OMP_NUM_THREADS", "1"))
    app = Flow(fname="poiseuille", output_dir=out)
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
    # The periodic ghosts (copies near x = 0 and Lx) PySPH holds besides.
    n_ghost = (fluid.get_number_of_particles() - n_fluid
               + channel.get_number_of_particles() - n_wall)
    y = fluid.y[:n_fluid]
    u = fluid.u[:n_fluid]
    t = solver.t
    ly, nu, fx, vmax = app.Ly, app.nu, app.fx, app.Vmax
    # Mean u per row of height dx (the rows the particles started in).
    row = np.clip(np.floor(y / dx).astype(int), 0, rows - 1)
    linf = 0.0
    for r in range(rows):
        sel = row == r
        if not sel.any():
            continue
        ym = y[sel].mean()
        linf = max(linf, abs(u[sel].mean() - startup(float(ym), t, ly, fx, nu)) / vmax)
    particles = n_fluid + n_wall
    print(json.dumps({
        "code": "pysph 1.0b2, examples.poiseuille (TVF, quintic spline)",
        "rows": rows,
        "particles": particles,
        "n_fluid": n_fluid,
        "n_wall": n_wall,
        "n_ghost": n_ghost,
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
