//! Diagnostics at an output time: the velocity profile by layer against the
//! analytic solutions, its errors relative to U, compaction, transverse
//! pulsation and kinetic energy. Sequential: it runs only at output times.

use serde::Serialize;

use super::step::State;
use crate::format::nan_max;
use crate::problem::{Initial, Problem};

/// One fluid layer (the particles that started in it).
#[derive(Debug, Clone, Serialize)]
pub struct LayerProfile {
    /// Layer index n (starting layer).
    pub layer: i32,
    /// Mean y of the layer's particles now.
    pub y: f64,
    /// Mean u (x velocity) of the layer.
    pub u: f64,
    /// RMS of the transverse velocity v in the layer.
    pub v_rms: f64,
    /// The reference: the start-up series at this time when started from
    /// rest, the steady profile (7) when started steady; at the mean y.
    pub u_analytic: f64,
    /// The steady profile (7) at the mean y.
    pub u_steady: f64,
}

/// Diagnostics at one time.
#[derive(Debug, Clone, Serialize)]
pub struct Sample {
    pub t: f64,
    pub step: u64,
    /// The time step in force at this time.
    pub dt: f64,
    /// max and RMS over layers of |u - u_analytic| / U.
    pub linf_rel_err: f64,
    pub l2_rel_err: f64,
    /// Compaction eps = rho / rho0 - 1 over the fluid.
    pub max_eps: f64,
    pub mean_eps: f64,
    /// RMS transverse velocity of the fluid.
    pub rms_v: f64,
    /// Kinetic energy of the fluid, (1/2) m sum |v|^2.
    pub kinetic_energy: f64,
    pub profile: Vec<LayerProfile>,
}

pub(crate) fn sample(problem: &Problem, s: &State, t: f64, step: u64, dt: f64) -> Sample {
    let n_layers = problem.lattice.fluid_layers() as usize;
    let first = 1 - problem.lattice.n_layers as i32;
    // Per layer: count, sum y, sum u, sum v^2.
    let mut acc = vec![(0usize, 0.0, 0.0, 0.0); n_layers];
    let (mut eps_max, mut eps_sum, mut v2_sum, mut ke) = (f64::NEG_INFINITY, 0.0, 0.0, 0.0);
    for i in 0..s.n_fluid {
        let a = &mut acc[(s.layer[i] - first) as usize];
        a.0 += 1;
        a.1 += s.y[i];
        a.2 += s.vx[i];
        a.3 += s.vy[i] * s.vy[i];
        let eps = s.rho[i] / problem.rho0 - 1.0;
        eps_max = nan_max(eps_max, eps);
        eps_sum += eps;
        v2_sum += s.vy[i] * s.vy[i];
        ke += s.vx[i] * s.vx[i] + s.vy[i] * s.vy[i];
    }
    let flow = &problem.flow;
    let profile: Vec<LayerProfile> = acc
        .iter()
        .enumerate()
        .map(|(k, &(n, sy, su, sv2))| {
            let n = n as f64;
            let y = sy / n;
            let u_steady = flow.steady(y);
            LayerProfile {
                layer: first + k as i32,
                y,
                u: su / n,
                v_rms: (sv2 / n).sqrt(),
                u_analytic: match problem.initial {
                    Initial::Rest => flow.startup(y, t),
                    Initial::Steady => u_steady,
                },
                u_steady,
            }
        })
        .collect();
    let (mut linf, mut l2) = (0.0f64, 0.0);
    for l in &profile {
        let e = (l.u - l.u_analytic).abs() / flow.u;
        linf = nan_max(linf, e);
        l2 += e * e;
    }
    let nf = s.n_fluid as f64;
    Sample {
        t,
        step,
        dt,
        linf_rel_err: linf,
        l2_rel_err: (l2 / profile.len() as f64).sqrt(),
        max_eps: eps_max,
        mean_eps: eps_sum / nf,
        rms_v: (v2_sum / nf).sqrt(),
        kinetic_energy: 0.5 * problem.mass * ke,
        profile,
    }
}
