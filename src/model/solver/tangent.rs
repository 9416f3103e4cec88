//! The growth of a small perturbation of a scene's start under the
//! solver's own step: the tangent-linear map by finite differences
//! (Benettin's method). Two copies of the solver run side by side with the
//! same time steps, the base from the scene's start and the other from the
//! base displaced by `eps` along a perturbation; every `block` steps the
//! difference of their fluid states (positions, across the periodic strip,
//! and velocities) is measured, its logarithmic growth summed, and the
//! perturbed copy reset to the base plus `eps` along the difference. At
//! `eps` small the difference follows the linearised equations (density by
//! summation, equation of state, pressure, viscous and artificial-viscous
//! forces, walls and integrator exactly as the solver has them, because it
//! is the solver), and the summed growth over the time is the leading
//! Lyapunov exponent of the perturbation's sector.

use nalgebra::DMatrix;

use super::{Kernel, Sim};
use crate::problem::Problem;

/// How the growth is measured.
#[derive(Debug, Clone, Copy)]
pub struct Options {
    /// The perturbation's size, in d (positions) and U (velocities).
    pub eps: f64,
    /// Steps between renormalisations.
    pub block: u64,
    /// The time measured over, after `warm`.
    pub horizon: f64,
    /// Time run (and renormalised) before the growth is summed: the
    /// perturbation turns into its fastest-growing form.
    pub warm: f64,
}

/// A perturbation of the fluid particles: displacements (in d) and
/// velocities (in U), each fluid particle's.
#[derive(Debug, Clone)]
pub struct Perturbation {
    pub dx: Vec<f64>,
    pub dy: Vec<f64>,
    pub dvx: Vec<f64>,
    pub dvy: Vec<f64>,
}

/// What the measurement found.
#[derive(Debug, Clone)]
pub struct Growth {
    /// The mean logarithmic growth rate over the horizon, per unit time.
    pub rate: f64,
    /// (t, ln of the perturbation's growth since the warm-up) at each
    /// renormalisation: its slope is the rate.
    pub history: Vec<(f64, f64)>,
    /// The perturbation at the end, normalised (the mode it grew into).
    pub mode: Perturbation,
    /// Fluid particles' positions of the base at the end.
    pub x: Vec<f64>,
    pub y: Vec<f64>,
    /// The run failed (not finite, a particle through a wall ...) before
    /// the horizon.
    pub failed: bool,
}

/// The fluid particles' start positions of `problem` (the lattice, and the
/// jitter if the scene has one), in the solver's order.
pub fn start_positions<K: Kernel>(problem: &Problem) -> (Vec<f64>, Vec<f64>) {
    let sim = Sim::new::<K>(problem);
    let n = sim.s.n_fluid;
    (sim.s.x[..n].to_vec(), sim.s.y[..n].to_vec())
}

impl Sim<'_> {
    /// The difference of this copy's fluid state from `base`'s, in units
    /// of d and U, x across the periodic strip.
    fn difference(&self, base: &Sim<'_>) -> Perturbation {
        let (d, u) = (self.problem.lattice.d, self.problem.flow.u);
        let w = self.problem.lattice.width;
        let n = self.s.n_fluid;
        let wrap = |dx: f64| dx - w * (dx / w).round();
        Perturbation {
            dx: (0..n)
                .map(|i| wrap(self.s.x[i] - base.s.x[i]) / d)
                .collect(),
            dy: (0..n).map(|i| (self.s.y[i] - base.s.y[i]) / d).collect(),
            dvx: (0..n).map(|i| (self.s.vx[i] - base.s.vx[i]) / u).collect(),
            dvy: (0..n).map(|i| (self.s.vy[i] - base.s.vy[i]) / u).collect(),
        }
    }

    /// This copy set to `base` plus `p` (in d and U), its neighbour list,
    /// density and forces recomputed as at a start.
    fn set_to<K: Kernel>(&mut self, base: &Sim<'_>, p: &Perturbation) {
        let (d, u) = (self.problem.lattice.d, self.problem.flow.u);
        let n = self.s.n_fluid;
        for i in 0..n {
            self.s.x[i] = base.s.x[i] + p.dx[i] * d;
            self.s.y[i] = base.s.y[i] + p.dy[i] * d;
            self.s.vx[i] = base.s.vx[i] + p.dvx[i] * u;
            self.s.vy[i] = base.s.vy[i] + p.dvy[i] * u;
        }
        self.refresh::<K>();
    }

    /// Neighbour list, density and forces from the current positions and
    /// velocities, as [`Sim::new`] makes them (the forces see v itself).
    fn refresh<K: Kernel>(&mut self) {
        let lat = &self.problem.lattice;
        self.s.wrap(lat.width);
        self.list
            .build(&self.s.x, &self.s.y, lat.width, self.cutoff, self.block);
        self.max_eps = super::step::density::<K>(&mut self.s, &self.list, &self.params);
        let isa = super::step::Isa::detect();
        self.forces = super::step::forces(&mut self.s, &self.list, &self.params, 0.0, isa);
    }
}

impl Perturbation {
    /// The Euclidean norm over every component.
    pub fn norm(&self) -> f64 {
        [&self.dx, &self.dy, &self.dvx, &self.dvy]
            .iter()
            .flat_map(|v| v.iter())
            .map(|v| v * v)
            .sum::<f64>()
            .sqrt()
    }

    /// This perturbation times `f`.
    pub fn scaled(&self, f: f64) -> Perturbation {
        let s = |v: &Vec<f64>| v.iter().map(|x| x * f).collect();
        Perturbation {
            dx: s(&self.dx),
            dy: s(&self.dy),
            dvx: s(&self.dvx),
            dvy: s(&self.dvy),
        }
    }
}

/// The growth rate of `seed` (any size: it is normalised to `eps`) about
/// the trajectory of `problem`'s start, by the solver's own step.
pub fn growth<K: Kernel>(problem: &Problem, seed: &Perturbation, opt: Options) -> Growth {
    let mut base = Sim::new::<K>(problem);
    let mut pert = Sim::new::<K>(problem);
    // The two copies are compared particle by particle: each keeps its
    // start's order.
    (base.reorder, pert.reorder) = (false, false);
    let n0 = seed.norm();
    assert!(n0 > 0.0 && n0.is_finite(), "a perturbation to follow");
    pert.set_to::<K>(&base, &seed.scaled(opt.eps / n0));
    // Both copies start from a refreshed state, so they differ only by the
    // perturbation.
    base.refresh::<K>();
    let (mut t, mut sum, mut steps) = (0.0, 0.0, 0u64);
    // The time of the last renormalisation before the growth is summed.
    let (mut origin, mut last) = (None, 0.0);
    let mut history = Vec::new();
    let mut failed = false;
    let end = opt.warm + opt.horizon;
    let mut mode = seed.scaled(1.0 / n0);
    while t < end {
        let dt = base.time_step().dt.min(end - t);
        let cb = base.advance::<K>(dt);
        let cp = pert.advance::<K>(dt);
        t += dt;
        steps += 1;
        if base.failure(&cb).is_some() || pert.failure(&cp).is_some() {
            failed = true;
            break;
        }
        if steps % opt.block == 0 || t >= end {
            let diff = pert.difference(&base);
            let norm = diff.norm();
            if !(norm > 0.0 && norm.is_finite()) {
                failed = true;
                break;
            }
            if t > opt.warm {
                let from = *origin.get_or_insert(last);
                sum += (norm / opt.eps).ln();
                history.push((t - from, sum));
            }
            last = t;
            mode = diff.scaled(1.0 / norm);
            base.refresh::<K>();
            pert.set_to::<K>(&base, &mode.scaled(opt.eps));
        }
    }
    let n = base.s.n_fluid;
    let measured = history.last().map_or(0.0, |h| h.0);
    Growth {
        rate: if measured > 0.0 {
            sum / measured
        } else {
            f64::NAN
        },
        history,
        mode,
        x: base.s.x[..n].to_vec(),
        y: base.s.y[..n].to_vec(),
        failed,
    }
}

/// The Jacobian of the solver's flow over the time `t` from `problem`'s
/// start (in the steps the unperturbed run takes, the last one shortened
/// to end at `t`), by central differences of size `eps`, with respect to
/// the fluid state ordered [dx; dy; dvx; dvy] (each fluid particle's, in d
/// and U) and in that ordering: column k is how the state at `t` moves per
/// unit displacement of the start's component k. Returns the matrix and
/// the steps taken. The columns are independent runs, spread over the
/// rayon pool.
pub fn flow_jacobian<K: Kernel>(problem: &Problem, t: f64, eps: f64) -> (DMatrix<f64>, usize) {
    use rayon::prelude::*;
    let start = Sim::new::<K>(problem);
    let mut end = Sim::new::<K>(problem);
    let mut dts = Vec::new();
    let mut now = 0.0;
    while now < t {
        let dt = end.time_step().dt.min(t - now);
        end.advance::<K>(dt);
        dts.push(dt);
        now += dt;
    }
    let n = start.s.n_fluid;
    let zero = Perturbation {
        dx: vec![0.0; n],
        dy: vec![0.0; n],
        dvx: vec![0.0; n],
        dvy: vec![0.0; n],
    };
    let after = |k: usize, sign: f64| -> Vec<f64> {
        let mut p = zero.clone();
        let (part, i) = (k / n, k % n);
        [&mut p.dx, &mut p.dy, &mut p.dvx, &mut p.dvy][part][i] = sign * eps;
        let mut sim = Sim::new::<K>(problem);
        sim.set_to::<K>(&start, &p);
        for &dt in &dts {
            sim.advance::<K>(dt);
        }
        let d = sim.difference(&end);
        [d.dx, d.dy, d.dvx, d.dvy].concat()
    };
    let columns: Vec<Vec<f64>> = (0..4 * n)
        .into_par_iter()
        .map(|k| {
            let (plus, minus) = (after(k, 1.0), after(k, -1.0));
            plus.iter()
                .zip(&minus)
                .map(|(a, b)| (a - b) / (2.0 * eps))
                .collect()
        })
        .collect();
    let m = DMatrix::from_fn(4 * n, 4 * n, |r, c| columns[c][r]);
    (m, dts.len())
}

#[cfg(test)]
mod tests {
    use nalgebra::DMatrix;

    use super::*;
    use crate::config::{C0Spec, Initial, Scene};
    use crate::kernels::Monaghan;

    /// The scene at rest without forces but pressure: no body force, no
    /// viscosity, no artificial viscosity, negative pressures kept (the
    /// EOS smooth), so the step's linearisation is the pressure term's
    /// alone and can be written out by hand.
    fn at_rest(lattice: &str) -> Problem {
        let mut s = Scene::builtin();
        s.n_layers = 4;
        s.alpha = 0.0;
        s.allow_negative_pressure = true;
        s.initial = Initial::Rest;
        s.c0 = C0Spec::Value(10.0);
        s.lattice = lattice.parse().expect("a lattice kind");
        let mut p = Problem::resolve(&s, s.kernel_info().expect("monaghan")).expect("a scene");
        p.flow.p = 0.0;
        p.mu = 0.0;
        p
    }

    /// d(a_i)/d(x_j) of the pressure term (12), -(m / rho_i^2) sum_j
    /// (P_i + P_j) grad_i W_ij with rho by summation and P = B (rho/rho0 - 1),
    /// differentiated by hand: over the fluid's positions [x; y], at the
    /// positions `x`, `y` (fluid first, then the walls, which do not move).
    fn pressure_jacobian<K: Kernel>(sim: &Sim, x: &[f64], y: &[f64]) -> DMatrix<f64> {
        let params = &sim.params;
        let (n, all) = (sim.s.n_fluid, x.len());
        let h = sim.problem.lattice.h;
        let w = sim.problem.lattice.width;
        let (m, h2) = (params.mass, h * h);
        // g(r^2) with grad_i W_ij = g r_ij, and dg/d(r^2) by a central
        // difference of the kernel's (dW/dq)/q in q^2.
        let g = |q2: f64| K::w_dw_over_q_lanes(q2).1 / (h2 * h2);
        let dg = |q2: f64| {
            let d = 1e-6 * q2.max(1e-3);
            (g(q2 + d) - g(q2 - d)) / (2.0 * d * h2)
        };
        let sep = |i: usize, j: usize| {
            let dx = x[i] - x[j];
            (dx - w * (dx / w).round(), y[i] - y[j])
        };
        let inside = |q2: f64| q2 <= K::SUPPORT2_CLOSED;
        // Densities and their gradients with respect to the fluid positions.
        let mut rho = vec![0.0; all];
        let mut drho = vec![vec![0.0; 2 * n]; all];
        for k in 0..all {
            rho[k] = m / h2 * K::w(0.0);
            for l in 0..all {
                let (rx, ry) = sep(k, l);
                let q2 = (rx * rx + ry * ry) / h2;
                if l == k || !inside(q2) {
                    continue;
                }
                rho[k] += m / h2 * K::w(q2);
                let (gx, gy) = (m * g(q2) * rx, m * g(q2) * ry);
                if k < n {
                    drho[k][k] += gx;
                    drho[k][n + k] += gy;
                }
                if l < n {
                    drho[k][l] -= gx;
                    drho[k][n + l] -= gy;
                }
            }
        }
        let slope = params.b_eos / params.rho0;
        let p: Vec<f64> = rho
            .iter()
            .map(|r| params.b_eos * (r / params.rho0 - 1.0))
            .collect();
        let mut a = DMatrix::zeros(2 * n, 2 * n);
        for i in 0..n {
            let mut sum = [0.0; 2];
            for j in 0..all {
                let (rx, ry) = sep(i, j);
                let r2 = rx * rx + ry * ry;
                let q2 = r2 / h2;
                if j == i || !inside(q2) {
                    continue;
                }
                let (gij, dgij) = (g(q2), dg(q2));
                let r = [rx, ry];
                let pp = p[i] + p[j];
                sum[0] += pp * gij * rx;
                sum[1] += pp * gij * ry;
                for c in 0..2 {
                    for v in 0..2 * n {
                        // (dP_i + dP_j) g r_ij
                        a[(c * n + i, v)] -=
                            m / (rho[i] * rho[i]) * slope * (drho[i][v] + drho[j][v]) * gij * r[c];
                    }
                    for e in 0..2 {
                        // (P_i + P_j) d(g r_ij)/d r_ij, r_ij = x_i - x_j.
                        let d = pp * (gij * f64::from(u8::from(c == e)) + 2.0 * dgij * r[c] * r[e]);
                        a[(c * n + i, e * n + i)] -= m / (rho[i] * rho[i]) * d;
                        if j < n {
                            a[(c * n + i, e * n + j)] += m / (rho[i] * rho[i]) * d;
                        }
                    }
                }
            }
            // The 1 / rho_i^2 factor's own change.
            for c in 0..2 {
                for v in 0..2 * n {
                    a[(c * n + i, v)] += 2.0 * m / rho[i].powi(3) * drho[i][v] * sum[c];
                }
            }
        }
        a
    }

    /// The kick-drift-kick step's Jacobian from the accelerations' at its
    /// start (`a0`) and end (`a1`): v' = v + dt/2 (a(x) + a(x')),
    /// x' = x + dt v + dt^2/2 a(x).
    fn kdk(a0: &DMatrix<f64>, a1: &DMatrix<f64>, dt: f64) -> DMatrix<f64> {
        let m = a0.nrows();
        let id = DMatrix::<f64>::identity(m, m);
        let xx = &id + a0 * (0.5 * dt * dt);
        let xv = &id * dt;
        let vx = a0 * (0.5 * dt) + a1 * &xx * (0.5 * dt);
        let vv = &id + a1 * &xv * (0.5 * dt);
        let mut j = DMatrix::zeros(2 * m, 2 * m);
        j.view_mut((0, 0), (m, m)).copy_from(&xx);
        j.view_mut((0, m), (m, m)).copy_from(&xv);
        j.view_mut((m, 0), (m, m)).copy_from(&vx);
        j.view_mut((m, m), (m, m)).copy_from(&vv);
        j
    }

    /// The solver's step, differentiated by finite differences
    /// ([`flow_jacobian`]), against the linearisation written out by hand,
    /// on every lattice kind: entry by entry, and the multipliers (eigenvalues,
    /// nalgebra's) in modulus and argument.
    #[test]
    fn the_steps_jacobian_is_the_hand_linearisation_at_rest() {
        for lattice in crate::kernel::Lattice::ALL.iter().map(|l| l.name()) {
            let problem = at_rest(lattice);
            let start = Sim::new::<Monaghan>(&problem);
            let t = start.time_step().dt;
            let (fd, steps) = flow_jacobian::<Monaghan>(&problem, t, 1e-6);
            assert_eq!(steps, 1);
            let mut end = Sim::new::<Monaghan>(&problem);
            end.advance::<Monaghan>(t);
            let a0 = pressure_jacobian::<Monaghan>(&start, &start.s.x, &start.s.y);
            let a1 = pressure_jacobian::<Monaghan>(&end, &end.s.x, &end.s.y);
            let hand = kdk(&a0, &a1, t);
            let scale = hand.abs().max();
            let worst = (&fd - &hand).abs().max();
            assert!(
                worst <= 1e-6 * scale,
                "{lattice}: the step's Jacobian differs from the hand linearisation by {worst:e} (entries up to {scale:e})"
            );
            // The multipliers (nalgebra's eigenvalues): each of the hand's
            // has one of the finite differences' beside it.
            let mu_fd = fd.complex_eigenvalues();
            let mu_hand = hand.complex_eigenvalues();
            let mut worst_mu = 0.0f64;
            for z in mu_hand.iter() {
                let near = mu_fd
                    .iter()
                    .map(|f| (f - z).norm())
                    .fold(f64::INFINITY, f64::min);
                worst_mu = worst_mu.max(near);
            }
            assert!(
                worst_mu < 1e-5,
                "{lattice}: a multiplier {worst_mu:e} from the hand's"
            );
            let top = mu_hand.iter().map(|z| z.arg().abs()).fold(0.0, f64::max);
            assert!(top > 0.0, "{lattice}: the pressure term moves the lattice");
            let largest = mu_hand.iter().map(|z| z.norm()).fold(0.0, f64::max);
            eprintln!("{lattice}: {} multipliers, largest argument {top:.4e} and modulus {largest:.6} per step of {t:.4e}", mu_fd.len());
        }
    }
}
