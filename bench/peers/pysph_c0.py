"""shearsph's `c0 --empirical` scene (square lattice h = d, N layers, a
jittered start) in PySPH 1.0b2, by one of two schemes, run to a given end
time; prints, as one JSON line, the statistics shearsph judges a stationary
window by (docs/stationary.md), computed the same way from PySPH's particles.

- `--scheme matched` (default): shearsph's solver rebuilt equation by
  equation (Monaghan cubic spline, walls at rest, below);
- `--scheme tvf`: PySPH's own transport-velocity scheme as its stock example
  `pysph.examples.poiseuille` sets it up (`pysph.sph.scheme.TVFScheme`,
  below), on the same fluid particles.

usage: python pysph_c0.py --re RE --c0 C0 --seed SEED --t-end T --window-from T0
                          [--scheme matched|tvf] [--n 10] [--alpha 0.1]
                          [--jitter 0.05] [--timeseries CSV]
                          [--tvf-kernel quintic|cubic] [--tvf-pb p0|0]
       (threads: OMP_NUM_THREADS; the script runs PySPH serial)

The scene (shearsph's defaults, `shearsph run --lattice square --h-over-d 1
--kernel monaghan --n N --re RE`): d = h = 1, U = 1, rho0 = 1, B = N d,
nu = U B / Re, body force p = 2 U nu / B^2, mass m = rho0 d^2, fluid layers
y = n d for |n| <= N - 1, wall layers at |n| = N, N + 1 (every layer within
the support 2h of the last fluid layer), 2B / d = 2N columns (the strip of a
jittered start), periodic in x.

The equations (each named as in the code below; shearsph's in
src/model/solver/step/):
- SummationDensity (PySPH's own): rho_i = sum_j m_j W_ij over fluid and wall
  neighbours, self included, for fluid and wall particles alike (shearsph's
  density.rs, (11)).
- ClippedLinearEOS: P = rho0 c0^2 (rho / rho0 - 1), negative pressures
  clipped to 0 (shearsph's EOS (13), gamma = 1, allow_negative_pressure
  false), on fluid and walls.
- MatchedMomentum, over fluid and wall neighbours, with the velocities
  predicted at the step's end (v + dt/2 a), as shearsph's forces.rs:
  - pressure (12), the paper's form: -(m_j / rho_i^2) (P_i + P_j) grad_i W_ij;
  - artificial viscosity (31): (alpha c0 h m_j / rho_i) min(v_ij . r_ij, 0)
    / r_ij^2 grad_i W_ij (no eta^2 in the denominator, rho_i not the mean);
  - viscosity, the Laplacian (14): (2 mu m_j / (rho_i rho_j)) v_ij
    (dW/dr) / r_ij, mu = rho0 nu, the walls' velocity zero;
  - the body force p along +x.
- KDKStep / KDKIntegrator: kick v += dt/2 a, drift x += dt v, predict
  v + dt/2 a, forces, kick v += dt/2 a (shearsph's leapfrog, one force
  evaluation per step); walls do not move.

Differences from shearsph's solver, all that are known:
- time step: fixed, dt = min(0.5 h / (c0 + U), 0.125 h^2 / nu); shearsph
  runs with PySPH's viscous factor, `--viscous-dt 0.125` (its default, 0.85
  of the kernel's stable factor, is 0.156 on this lattice); its CFL uses the current largest speed (0.5 h / (c0 + |v|max)) and a force
  limit 0.25 sqrt(h / |a|max), so at Re = 10 its dt varies by a few per cent
  (at Re = 1 both are the viscous 0.0125 throughout);
- frames: sampled at the first step at or after each multiple of B / (4 U)
  (shearsph lands a step on each frame time exactly);
- neighbours: PySPH's linked list, all pairs within 2h (shearsph: a Verlet
  list with a skin, the same pairs);
- the jitter: the same SplitMix64 stream and order as shearsph's
  (state.rs), so seed s is the same perturbed lattice in both codes, to
  round-off of the generator's float conversion;
- failure: shearsph's eps_limit (a run fails when eps passes 0.2, or on
  NaN) checked at each frame, not each step (`--eps-limit`); the run then
  stops and is judged, as shearsph judges a failed run, on the later half of
  its time (`outcome`, `failure_t`); shearsph's other checks (a speed past
  10 U + c0, a particle through a wall) are not made.

The TVF scheme (`--scheme tvf`): `TVFScheme(['fluid'], ['wall'], dim=2,
rho0, c0, nu, p0 = rho0 c0^2, pb = p0, h0 = h, gx = p)` with the stock
example's choices (its `configure_scheme`: pb = p0, no artificial viscosity
(TVFScheme's alpha 0), tdamp 0; its kernel, `QuinticSpline`, support 3h, at
h = dx; its integrator, `PECIntegrator` with `TransportVelocityStep`; its
time step min(0.25 h / (c0 + U), 0.125 h^2 / nu, 0.25 sqrt(h / p)), fixed;
its walls, `ghost_extent` = 5 layers of wall particles). The equations, as
`TVFScheme.get_equations` assembles them (pysph.sph.wc.transport_velocity):
- group 1: SummationDensity (TVF's: rho_i = m_i sum_j W_ij and the inverse
  volume V_i = sum_j W_ij) on the fluid, from fluid and wall;
- group 2: StateEquation, P = p0 (rho / rho0 - 1), not clipped (negative
  pressure kept); SetWallVelocity (wall from fluid): the wall's ghost
  velocity 2 u_wall - (Shepard average of the fluid's u), u_wall = 0;
- group 3: SolidWallPressureBC (wall from fluid): the wall's pressure
  extrapolated from the fluid's with the body force, and its density from it;
- group 4, on the fluid: MomentumEquationPressureGradient (fluid and wall:
  -(1/m_i) (V_i^-2 + V_j^-2) (rho_j P_i + rho_i P_j) / (rho_i + rho_j)
  grad W, the body force, and the background pressure pb's
  -(1/m_i) (V_i^-2 + V_j^-2) pb grad W into the transport acceleration);
  MomentumEquationViscosity (fluid: Morris's form with the particle volumes,
  (1/m_i) (V_i^-2 + V_j^-2) eta_ij (r . grad W) / (r^2 + eps) v_ij);
  SolidWallNoSlipBC (wall: the same with the wall's ghost velocity);
  MomentumEquationArtificialStress (fluid: the (u - uhat) stress of Adami
  2013).
- TransportVelocityStep: kick v += dt/2 a, transport velocity uhat = v +
  dt/2 ahat, drift x += dt uhat (the particles move with uhat, not v);
  forces; kick v += dt/2 a.
Every difference from shearsph's solver (and so from the matched scheme):
- walls and fluid rows (`--tvf-walls native`, the default): TVF's Adami
  walls put the wall's surface half a spacing in front of the first wall
  layer, so the same channel (|y| <= B) has 2N fluid rows at y = (k + 1/2) d,
  k = -N..N-1 (400 particles, jittered by the same SplitMix64 stream: the
  same numbers on other positions), and 5 wall layers from |y| = B + d/2;
  `--tvf-walls shearsph` keeps the matched scheme's 380 particles and puts
  the 5 layers at |n| = N .. N + 4 (TVF then sees a channel of half-width
  B - d/2); Adami's ghost velocity and extrapolated pressure instead of
  fixed particles at rest with the fluid's EOS; the wall's density is not
  summed;
- integrator: the transport-velocity leapfrog (particles advected by uhat);
- density: the same summation (mass times the kernel sum), fluid only;
- EOS: linear with negative pressure kept (shearsph clips it at 0);
- pressure: the inter-particle averaged pressure with volumes (Adami 2013
  (8)) instead of the paper's (P_i + P_j) / rho_i^2, and the background
  pressure pb = p0 = rho0 c0^2 on the transport velocity;
- viscous form: the volume-weighted Morris form with the harmonic mean of
  eta (equal here) and eps in the denominator, against shearsph's (14);
- no artificial viscosity (shearsph's scene: alpha 0.1);
- kernel: the quintic spline, support 3h (shearsph: Monaghan's cubic, 2h);
- time step: 0.25 h / (c0 + U) (the matched scheme and shearsph: 0.5).
`--tvf-kernel cubic` (the cubic spline instead), `--tvf-pb 0` (no
background pressure) and `--tvf-walls shearsph` switch one difference off
each.
"""
import argparse
import json
import math
import sys
import tempfile
import time

import numpy as np
from pysph.base.kernels import CubicSpline, QuinticSpline
from pysph.base.nnps import DomainManager
from pysph.base.utils import get_particle_array
from pysph.solver.application import Application
from pysph.solver.solver import Solver
from pysph.sph.basic_equations import SummationDensity
from pysph.sph.equation import Equation, Group
from pysph.sph.integrator import Integrator
from pysph.sph.integrator_step import IntegratorStep
from pysph.sph.scheme import TVFScheme

from peer_metric import startup

MASK = (1 << 64) - 1


def splitmix_symmetric(seed):
    """shearsph's jitter generator (src/model/solver/step/state.rs): uniform in
    [-1, 1), SplitMix64 seeded with 0x5eed5be5 ^ seed."""
    s = (0x5EED5BE5 ^ seed) & MASK
    while True:
        s = (s + 0x9E3779B97F4A7C15) & MASK
        z = s
        z = ((z ^ (z >> 30)) * 0xBF58476D1CE4E5B9) & MASK
        z = ((z ^ (z >> 27)) * 0x94D049BB133111EB) & MASK
        z ^= z >> 31
        yield 2.0 * ((z >> 11) / float(1 << 53)) - 1.0


class ClippedLinearEOS(Equation):
    """P = rho0 c0^2 (rho / rho0 - 1), clipped at 0 (shearsph's (13))."""

    def __init__(self, dest, sources, rho0, c0):
        self.rho0 = rho0
        self.c0 = c0
        super().__init__(dest, sources)

    def initialize(self, d_idx, d_rho, d_p):
        p = self.c0 * self.c0 * (d_rho[d_idx] - self.rho0)
        if p < 0.0:
            p = 0.0
        d_p[d_idx] = p


class MatchedMomentum(Equation):
    """Pressure (12, paper form), artificial viscosity (31), Laplacian
    viscosity (14) and the body force, with the predicted velocities
    (uhat, vhat), as shearsph's forces.rs."""

    def __init__(self, dest, sources, alpha, c0, h, mu, fx):
        self.alpha = alpha
        self.c0 = c0
        self.h = h
        self.mu = mu
        self.fx = fx
        super().__init__(dest, sources)

    def initialize(self, d_idx, d_au, d_av):
        d_au[d_idx] = self.fx
        d_av[d_idx] = 0.0

    def loop(self, d_idx, s_idx, d_rho, s_rho, d_p, s_p, s_m, d_au, d_av,
             d_uhat, d_vhat, s_uhat, s_vhat, DWIJ, XIJ, R2IJ):
        r2 = R2IJ
        if r2 > 1e-14:
            rhoi = d_rho[d_idx]
            mj = s_m[s_idx]
            pf = -mj * (d_p[d_idx] + s_p[s_idx]) / (rhoi * rhoi)
            uij = d_uhat[d_idx] - s_uhat[s_idx]
            vij = d_vhat[d_idx] - s_vhat[s_idx]
            g = (DWIJ[0] * XIJ[0] + DWIJ[1] * XIJ[1]) / r2
            vf = 2.0 * self.mu * mj / (rhoi * s_rho[s_idx]) * g
            vr = uij * XIJ[0] + vij * XIJ[1]
            af = 0.0
            if vr < 0.0:
                af = self.alpha * self.c0 * self.h * mj / rhoi * vr / r2
            d_au[d_idx] += (pf + af) * DWIJ[0] + vf * uij
            d_av[d_idx] += (pf + af) * DWIJ[1] + vf * vij


class KDKStep(IntegratorStep):
    """Kick, drift and the prediction (stage1); the closing kick (stage2)."""

    def stage1(self, d_idx, d_x, d_y, d_u, d_v, d_au, d_av, d_uhat, d_vhat, dt):
        d_u[d_idx] += 0.5 * dt * d_au[d_idx]
        d_v[d_idx] += 0.5 * dt * d_av[d_idx]
        d_x[d_idx] += dt * d_u[d_idx]
        d_y[d_idx] += dt * d_v[d_idx]
        d_uhat[d_idx] = d_u[d_idx] + 0.5 * dt * d_au[d_idx]
        d_vhat[d_idx] = d_v[d_idx] + 0.5 * dt * d_av[d_idx]

    def stage2(self, d_idx, d_u, d_v, d_au, d_av, dt):
        d_u[d_idx] += 0.5 * dt * d_au[d_idx]
        d_v[d_idx] += 0.5 * dt * d_av[d_idx]


class KDKIntegrator(Integrator):
    def one_timestep(self, t, dt):
        self.stage1()
        self.update_domain()
        self.do_post_stage(dt, 1)
        self.compute_accelerations()
        self.stage2()
        self.do_post_stage(dt, 2)


class Channel(Application):
    def __init__(self, a, **kw):
        self.a = a
        n = a.n
        self.d = self.h = 1.0
        self.u0 = 1.0
        self.rho0 = 1.0
        self.b = n * self.d
        self.nu = self.u0 * self.b / a.re
        self.fx = 2.0 * self.u0 * self.nu / self.b ** 2
        self.cols = 2 * n
        self.width = self.cols * self.d
        if a.scheme == "tvf":  # the stock example's time step
            self.dt = min(0.25 * self.h / (a.c0 + self.u0), 0.125 * self.h ** 2 / self.nu,
                          0.25 * math.sqrt(self.h / self.fx))
        else:
            self.dt = min(0.5 * self.h / (a.c0 + self.u0), 0.125 * self.h ** 2 / self.nu)
        self.tvf = None
        self.native = a.scheme == "tvf" and a.tvf_walls == "native"
        if a.scheme == "tvf":
            p0 = self.rho0 * a.c0 ** 2
            self.tvf = TVFScheme(["fluid"], ["wall"], dim=2, rho0=self.rho0, c0=a.c0, nu=self.nu,
                                 p0=p0, pb=p0 if a.tvf_pb == "p0" else 0.0, h0=self.h,
                                 gx=self.fx)
        self.frame_dt = self.b / self.u0 / 4.0
        self.frames = []
        self.next_frame = 0.0
        self.failed_t = None
        super().__init__(**kw)

    def create_domain(self):
        return DomainManager(xmin=0.0, xmax=self.width, periodic_in_x=True)

    def create_particles(self):
        n, d = self.a.n, self.d
        rng = splitmix_symmetric(self.a.seed)
        fx_, fy_, layer = [], [], []
        # the rows: shearsph's, y = k d for |k| <= N - 1; or, for TVF's own
        # wall convention (`--tvf-walls native`), 2N rows at y = (k + 1/2) d
        rows = ([k + 0.5 for k in range(-n, n)] if self.native
                else [float(k) for k in range(-(n - 1), n)])
        for k in rows:
            for c in range(self.cols):
                fx_.append(c * d)
                fy_.append(k * d)
                layer.append(k)
        amp = self.a.jitter * d
        if amp > 0.0:
            for i in range(len(fx_)):
                fx_[i] += amp * next(rng)
                fy_[i] += amp * next(rng)
        fx_ = np.mod(np.array(fx_), self.width)
        wx, wy = [], []
        # matched: shearsph's 2 wall layers a side (|n| = N, N + 1); tvf: the
        # stock example's 5 (its ghost_extent = 5 dx), from the same |n| = N
        # (native: from |y| = (N + 1/2) d, the wall's surface at |y| = B)
        depth = 5 if self.tvf else 2
        off = 0.5 if self.native else 0.0
        for k in sorted(sg * (n + off + i) for sg in (-1, 1) for i in range(depth)):
            for c in range(self.cols):
                wx.append(c * d)
                wy.append(k * d)
        m = self.rho0 * d * d
        extra = dict(h=self.h, m=m, rho=self.rho0)
        fluid = get_particle_array(name="fluid", x=fx_, y=np.array(fy_), **extra)
        wall = get_particle_array(name="wall", x=np.array(wx), y=np.array(wy), **extra)
        if self.tvf:  # the stock example's properties: TVF's arrays, V = 1 / dx^2
            self.tvf.setup_properties([fluid, wall])
            for pa in (fluid, wall):
                pa.m[:] = m
                pa.rho[:] = self.rho0
                pa.h[:] = self.h
                pa.V[:] = 1.0 / (d * d)
        else:
            for pa in (fluid, wall):
                for prop in ("uhat", "vhat"):
                    pa.add_property(prop)
        fluid.add_property("layer")
        fluid.layer[:] = np.array(layer, dtype=float)
        fluid.add_output_arrays(["layer"])
        self.n_fluid = len(fx_)
        self.n_wall = len(wx)
        return [fluid, wall]

    def create_equations(self):
        a = self.a
        if self.tvf:
            return self.tvf.get_equations()
        both = ["fluid", "wall"]
        return [
            Group(equations=[SummationDensity(dest="fluid", sources=both),
                             SummationDensity(dest="wall", sources=both)]),
            Group(equations=[ClippedLinearEOS(dest="fluid", sources=None, rho0=self.rho0, c0=a.c0),
                             ClippedLinearEOS(dest="wall", sources=None, rho0=self.rho0, c0=a.c0)]),
            Group(equations=[MatchedMomentum(dest="fluid", sources=both, alpha=a.alpha, c0=a.c0,
                                             h=self.h, mu=self.rho0 * self.nu, fx=self.fx)]),
        ]

    def create_solver(self):
        if self.tvf:
            kernel = QuinticSpline(dim=2) if self.a.tvf_kernel == "quintic" else CubicSpline(dim=2)
            self.tvf.configure_solver(kernel=kernel, dt=self.dt, tf=self.a.t_end,
                                      adaptive_timestep=False, pfreq=10 ** 9)
            return self.tvf.solver
        integrator = KDKIntegrator(fluid=KDKStep())
        return Solver(kernel=CubicSpline(dim=2), dim=2, integrator=integrator, dt=self.dt,
                      tf=self.a.t_end, adaptive_timestep=False, pfreq=10 ** 9)

    def post_step(self, solver):
        if solver.t + 1e-9 * self.dt >= self.next_frame:
            self.sample(solver.t)
            self.next_frame += self.frame_dt
            f = self.frames[-1]
            if self.failed_t is None and (not f["finite"] or f["max_eps"] > self.a.eps_limit):
                # shearsph's failure (eps past eps_limit, or NaN), checked per frame: stop
                self.failed_t = solver.t
                solver.tf = solver.t

    def sample(self, t):
        fl = next(p for p in self.particles if p.name == "fluid")
        nf = self.n_fluid
        eps = fl.rho[:nf] / self.rho0 - 1.0
        y, u, v = fl.y[:nf], fl.u[:nf], fl.v[:nf]
        n = self.a.n
        # the bands: |y - row| <= d/2 about each starting row, the outermost
        # taking everything beyond
        if self.native:
            band = np.clip(np.floor(y / self.d), -n, n - 1).astype(int)
            ks = range(-n, n)
        else:
            band = np.clip(np.rint(y / self.d), -(n - 1), n - 1).astype(int)
            ks = range(-(n - 1), n)
        ly = 2.0 * self.b
        err = np.full(len(ks), np.nan)
        for i, k in enumerate(ks):
            sel = band == k
            if sel.any():
                ua = startup(float(y[sel].mean() + self.b), t, ly, self.fx, self.nu)
                err[i] = (u[sel].mean() - ua) / self.u0
        self.frames.append(dict(
            t=t, eps_p99=float(np.percentile(eps, 99)), max_eps=float(eps.max()),
            mean_eps=float(eps.mean()), rms_v=float(math.sqrt(np.mean(v * v))),
            dy_rms=float(math.sqrt(np.mean((y - fl.layer[:nf] * self.d) ** 2))),
            finite=bool(np.isfinite(fl.u[:nf]).all() and np.isfinite(eps).all()), band_err=err))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--scheme", choices=("matched", "tvf"), default="matched")
    ap.add_argument("--tvf-kernel", choices=("quintic", "cubic"), default="quintic")
    ap.add_argument("--tvf-pb", choices=("p0", "0"), default="p0")
    ap.add_argument("--tvf-walls", choices=("native", "shearsph"), default="native")
    ap.add_argument("--n", type=int, default=10)
    ap.add_argument("--re", type=float, required=True)
    ap.add_argument("--c0", type=float, required=True)
    ap.add_argument("--alpha", type=float, default=0.1)
    ap.add_argument("--jitter", type=float, default=0.05)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--t-end", type=float, required=True)
    ap.add_argument("--window-from", type=float, required=True)
    ap.add_argument("--eps-limit", type=float, default=0.2)
    ap.add_argument("--timeseries")
    ap.add_argument("--out", help="PySPH's output folder (default: a new temporary one)")
    a = ap.parse_args()
    app = Channel(a, fname="c0", output_dir=a.out or tempfile.mkdtemp(prefix="pysph-c0-"))
    app.setup(["--disable-output", "-q"])
    start = time.perf_counter()
    app.solve()
    wall = time.perf_counter() - start
    frames = app.frames
    if app.failed_t is not None:  # as shearsph judges a failed run: the later half of its time
        win = [f for f in frames if app.failed_t / 2 < f["t"] <= app.failed_t + 1e-9]
    else:
        win = [f for f in frames if a.window_from < f["t"] <= a.t_end + 1e-9]
    band = np.nanmean(np.array([f["band_err"] for f in win]), axis=0)
    disorder = next((f["t"] for f in frames if f["dy_rms"] >= 0.1), None)
    if a.timeseries:
        with open(a.timeseries, "w") as fh:
            fh.write("t,eps_p99,max_eps,mean_eps,rms_v,dy_rms,linf_frame\n")
            for f in frames:
                fh.write("%g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g\n" % (
                    f["t"], f["eps_p99"], f["max_eps"], f["mean_eps"], f["rms_v"], f["dy_rms"],
                    np.nanmax(np.abs(f["band_err"]))))
    if a.scheme == "tvf":
        code = "pysph 1.0b2, TVFScheme as its stock Poiseuille example (bench/peers/pysph_c0.py)"
    else:
        code = "pysph 1.0b2, shearsph's scheme matched (bench/peers/pysph_c0.py)"
    print(json.dumps({
        "code": code, "scheme": a.scheme,
        "tvf_kernel": a.tvf_kernel if a.scheme == "tvf" else None,
        "tvf_pb": a.tvf_pb if a.scheme == "tvf" else None,
        "tvf_walls": a.tvf_walls if a.scheme == "tvf" else None,
        "n": a.n, "re": a.re, "c0_over_u": a.c0, "alpha": 0.0 if a.scheme == "tvf" else a.alpha, "jitter": a.jitter,
        "seed": a.seed, "n_fluid": app.n_fluid, "n_wall": app.n_wall, "dt": app.dt,
        "steps": app.solver.count, "t": app.solver.t, "wall_s": wall,
        "window_from": a.window_from, "window_to": a.t_end, "window_frames": len(win),
        "eps_stat": float(np.mean([f["eps_p99"] for f in win])),
        "eps_max_mean": float(np.mean([f["max_eps"] for f in win])),
        "linf_stat": float(np.nanmax(np.abs(band))),
        "rms_v_stat": float(np.mean([f["rms_v"] for f in win])),
        "dy_rms": frames[-1]["dy_rms"], "t_disorder": disorder,
        "finite": all(f["finite"] for f in frames),
        "outcome": "failed" if app.failed_t is not None else "ok", "failure_t": app.failed_t,
        "eps_limit": a.eps_limit,
    }))


if __name__ == "__main__":
    sys.exit(main())
