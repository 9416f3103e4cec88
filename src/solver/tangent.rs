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
        self.max_eps = super::step::density::<K>(&mut self.s, &self.list, &self.prm);
        self.forces = super::step::forces(&mut self.s, &self.list, &self.prm, 0.0);
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
