//! Diagnostics at an output time: the velocity profile by position against
//! the analytic solutions, its errors relative to U, compaction, transverse
//! pulsation, how far the particles have left their lattice, and kinetic
//! energy. Sequential: it runs only at output times.

use serde::Serialize;

use super::step::State;
use crate::format::nan_max;
use crate::problem::{Initial, Problem};

/// One band of the channel: the fluid particles whose y is now nearest to
/// lattice layer n's (|y - n dy| <= dy / 2; the outermost bands take every
/// particle beyond them). On a lattice that keeps its order a band is the
/// layer that started there; in a disordered flow particles leave their
/// starting layers, and the profile is taken where they are.
#[derive(Debug, Clone, Serialize)]
pub struct LayerProfile {
    /// The band's lattice layer index n.
    pub layer: i32,
    /// Fluid particles in the band now (0: the band is empty, its figures
    /// NaN and left out of the errors).
    pub count: usize,
    /// Mean y of the band's particles now.
    pub y: f64,
    /// Mean u (x velocity) of the band.
    pub u: f64,
    /// RMS of the transverse velocity v in the band.
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
    /// max and RMS over bands of |u - u_analytic| / U.
    pub linf_rel_err: f64,
    pub l2_rel_err: f64,
    /// Compaction eps = rho / rho0 - 1 over the fluid: the largest, the
    /// 99th percentile (linear between order statistics) and the mean.
    pub max_eps: f64,
    pub eps_p99: f64,
    pub mean_eps: f64,
    /// RMS transverse velocity of the fluid.
    pub rms_v: f64,
    /// RMS over the fluid of y - n dy (n the layer each particle started
    /// in), in units of d: how far the particles have left their lattice
    /// across the flow. A jittered start begins at amplitude / sqrt 3; an
    /// ordered lattice keeps it, a disordered flow grows it.
    pub dy_rms: f64,
    /// Kinetic energy of the fluid, (1/2) m sum |v|^2.
    pub kinetic_energy: f64,
    pub profile: Vec<LayerProfile>,
}

/// The q-quantile of `v` (0 <= q <= 1), linear between order statistics;
/// NaN for an empty slice or one holding a NaN. Reorders `v`.
pub fn quantile(v: &mut [f64], q: f64) -> f64 {
    if v.is_empty() || v.iter().any(|x| x.is_nan()) {
        return f64::NAN;
    }
    let pos = q * (v.len() - 1) as f64;
    let lo = pos.floor() as usize;
    let frac = pos - lo as f64;
    let (_, &mut a, rest) = v.select_nth_unstable_by(lo, f64::total_cmp);
    if frac == 0.0 || rest.is_empty() {
        return a;
    }
    let b = rest.iter().copied().fold(f64::INFINITY, f64::min);
    a + frac * (b - a)
}

pub(crate) fn sample(problem: &Problem, s: &State, t: f64, step: u64, dt: f64) -> Sample {
    let lattice = &problem.lattice;
    let n_bands = lattice.fluid_layers() as usize;
    let first = 1 - lattice.n_layers as i32;
    let dy = lattice.dy;
    // Per band: count, sum y, sum u, sum v^2.
    let mut acc = vec![(0usize, 0.0, 0.0, 0.0); n_bands];
    let (mut eps_max, mut eps_sum, mut v2_sum, mut ke, mut off2) =
        (f64::NEG_INFINITY, 0.0, 0.0, 0.0, 0.0);
    let mut eps = Vec::with_capacity(s.n_fluid);
    for i in 0..s.n_fluid {
        let y = s.y[i];
        // The nearest band; a NaN y (a failed run's last sample) lands in
        // the first, whose figures then show the NaN.
        let band = ((y / dy).round() as i64 - i64::from(first)).clamp(0, n_bands as i64 - 1);
        let a = &mut acc[band as usize];
        a.0 += 1;
        a.1 += y;
        a.2 += s.vx[i];
        a.3 += s.vy[i] * s.vy[i];
        let e = s.rho[i] / problem.rho0 - 1.0;
        eps.push(e);
        eps_max = nan_max(eps_max, e);
        eps_sum += e;
        v2_sum += s.vy[i] * s.vy[i];
        ke += s.vx[i] * s.vx[i] + s.vy[i] * s.vy[i];
        let off = y - f64::from(s.layer[i]) * dy;
        off2 += off * off;
    }
    let flow = &problem.flow;
    let profile: Vec<LayerProfile> = acc
        .iter()
        .enumerate()
        .map(|(k, &(count, sy, su, sv2))| {
            let n = count as f64;
            let y = sy / n;
            let u_steady = flow.steady(y);
            LayerProfile {
                layer: first + k as i32,
                count,
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
    let (mut linf, mut l2, mut bands) = (0.0f64, 0.0, 0usize);
    for l in profile.iter().filter(|l| l.count > 0) {
        let e = (l.u - l.u_analytic).abs() / flow.u;
        linf = nan_max(linf, e);
        l2 += e * e;
        bands += 1;
    }
    let nf = s.n_fluid as f64;
    Sample {
        t,
        step,
        dt,
        linf_rel_err: linf,
        l2_rel_err: (l2 / bands as f64).sqrt(),
        max_eps: eps_max,
        eps_p99: quantile(&mut eps, 0.99),
        mean_eps: eps_sum / nf,
        rms_v: (v2_sum / nf).sqrt(),
        dy_rms: (off2 / nf).sqrt() / lattice.d,
        kinetic_energy: 0.5 * problem.mass * ke,
        profile,
    }
}

#[cfg(test)]
mod tests {
    use super::quantile;

    #[test]
    fn quantile_interpolates_between_order_statistics() {
        let mut v: Vec<f64> = (0..101).rev().map(f64::from).collect();
        assert_eq!(quantile(&mut v, 0.99), 99.0);
        let mut v = vec![3.0, 1.0, 2.0, 4.0];
        // position 0.99 * 3 = 2.97: between 3 and 4
        assert!((quantile(&mut v, 0.99) - 3.97).abs() < 1e-12);
        assert_eq!(quantile(&mut [5.0], 0.99), 5.0);
        assert!(quantile(&mut [], 0.5).is_nan());
        assert!(quantile(&mut [1.0, f64::NAN], 0.5).is_nan());
    }
}
