//! The statistics of a run's window (docs/stationary.md): what a run is
//! judged by, and whether it is stationary. Pure functions of the samples.

use serde::{Deserialize, Serialize};

use super::Sample;

/// Halves of a stationary window may differ by this share of their
/// average (plus a floor) in `eps_p99` and `rms_v`.
pub const STATIONARY_TOL: f64 = 0.15;
/// Floors of that test: a compaction of 1e-4 and a transverse velocity of
/// 1e-4 U are far below any tolerance a run is judged by.
pub const EPS_FLOOR: f64 = 1e-4;
pub const V_FLOOR: f64 = 1e-4;
/// A run whose `dy_rms` (in d) is at least this has left its lattice.
pub const DISORDER_DY: f64 = 0.1;
/// Below this `dy_rms` (in d) a perturbation is round-off: the perfect
/// lattice's own.
pub const ROUNDOFF_DY: f64 = 1e-4;
/// Within a window, an ordered perturbation growing by more than this
/// factor is still growing: not stationary.
pub const GROWTH_FACTOR: f64 = 1.1;

/// Ordered: the particles still near their lattice rows; disordered: they
/// have left them (dy_rms >= [`DISORDER_DY`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Regime {
    #[default]
    Ordered,
    Disordered,
}

impl std::fmt::Display for Regime {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Regime::Ordered => "ordered",
            Regime::Disordered => "disordered",
        })
    }
}

/// A window's statistics.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Window {
    /// The window (from, to]: the frames with from < t <= to.
    pub from: f64,
    pub to: f64,
    pub frames: usize,
    /// Mean over the frames of the 99th percentile of eps (judged).
    pub eps_stat: f64,
    /// Mean of the per-frame largest eps, and the largest.
    pub eps_max_mean: f64,
    pub eps_max: f64,
    /// The mean flow's error: per band, the mean over the frames of
    /// (u - u_analytic) / U; the largest magnitude over the bands (judged)
    /// and their RMS.
    pub linf_stat: f64,
    pub l2_stat: f64,
    /// The per-frame L_inf error's mean (it carries the fluctuations).
    pub linf_frame_mean: f64,
    pub rms_v_stat: f64,
    /// dy_rms (in d) at the window's start and end.
    pub dy_rms_start: f64,
    pub dy_rms: f64,
    pub regime: Regime,
    /// Means of `eps_p99` and of `rms_v` over the window's first and second
    /// halves, and whether the window passes the stationarity test.
    pub eps_halves: [f64; 2],
    pub rms_v_halves: [f64; 2],
    pub stationary: bool,
    /// Why not, in words (None when stationary).
    pub unsteady: Option<String>,
    /// The mean flow band by band (bands empty in more than half the frames
    /// left out).
    pub profile: Vec<BandMean>,
}

/// One band's mean over a window's frames (those it held particles in).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BandMean {
    pub layer: i32,
    /// Mean y and u of the band's particles.
    pub y: f64,
    pub u: f64,
    /// Mean of (u - u_analytic) / U.
    pub err: f64,
}

fn mean(v: impl Iterator<Item = f64>) -> f64 {
    let (s, n) = v.fold((0.0, 0usize), |(s, n), x| (s + x, n + 1));
    s / n as f64
}

/// The statistics of the samples with `from < t <= to`, velocities
/// relative to `u`. The frame before the window (or the first) gives
/// `dy_rms_start`.
pub fn window(samples: &[Sample], from: f64, to: f64, u: f64) -> Window {
    let tol = 1e-9 * to.abs().max(1.0);
    let first = samples.partition_point(|s| s.t <= from + tol);
    let end = samples.partition_point(|s| s.t <= to + tol);
    let frames = &samples[first.min(end)..end];
    let before = samples.get(first.saturating_sub(1)).or(samples.first());
    let n = frames.len();
    let eps_stat = mean(frames.iter().map(|s| s.eps_p99));
    let eps_max_mean = mean(frames.iter().map(|s| s.max_eps));
    let eps_max = frames
        .iter()
        .map(|s| s.max_eps)
        .fold(f64::NEG_INFINITY, crate::format::nan_max);
    let rms_v_stat = mean(frames.iter().map(|s| s.rms_v));
    let linf_frame_mean = mean(frames.iter().map(|s| s.linf_rel_err));
    // The mean flow: each band's error averaged over the frames it held
    // particles in; bands empty in more than half the frames are left out.
    let bands = frames.first().map_or(0, |s| s.profile.len());
    let mut sum = vec![(0.0, 0.0, 0.0, 0usize); bands];
    for s in frames {
        for (acc, l) in sum.iter_mut().zip(&s.profile) {
            if l.count > 0 {
                acc.0 += (l.u - l.u_analytic) / u;
                acc.1 += l.y;
                acc.2 += l.u;
                acc.3 += 1;
            }
        }
    }
    let first_layer = frames
        .first()
        .and_then(|s| s.profile.first())
        .map_or(0, |l| l.layer);
    let profile: Vec<BandMean> = sum
        .iter()
        .enumerate()
        .filter(|(_, a)| 2 * a.3 >= n && a.3 > 0)
        .map(|(k, a)| {
            let m = a.3 as f64;
            BandMean {
                layer: first_layer + k as i32,
                y: a.1 / m,
                u: a.2 / m,
                err: a.0 / m,
            }
        })
        .collect();
    let errs: Vec<f64> = profile.iter().map(|b| b.err).collect();
    let linf_stat = errs.iter().map(|e| e.abs()).fold(
        if errs.is_empty() { f64::NAN } else { 0.0 },
        crate::format::nan_max,
    );
    let l2_stat = mean(errs.iter().map(|e| e * e)).sqrt();
    let half = n / 2;
    let halves = |f: &dyn Fn(&Sample) -> f64| {
        [
            mean(frames[..half].iter().map(f)),
            mean(frames[half..].iter().map(f)),
        ]
    };
    let eps_halves = halves(&|s| s.eps_p99);
    let rms_v_halves = halves(&|s| s.rms_v / u);
    let dy_rms_start = before.map_or(f64::NAN, |s| s.dy_rms);
    let dy_rms = frames.last().map_or(f64::NAN, |s| s.dy_rms);
    let mut unsteady = Vec::new();
    if n < 4 {
        unsteady.push(format!("{n} frames in the window: too few to tell"));
    }
    for (name, [a, b], floor) in [
        ("eps_p99", eps_halves, EPS_FLOOR),
        ("rms_v", rms_v_halves, V_FLOOR),
    ] {
        let differ = (a - b).abs() > STATIONARY_TOL * 0.5 * (a + b).abs() + floor;
        if differ || !(a.is_finite() && b.is_finite()) {
            unsteady.push(format!(
                "the window's halves differ in {name}: {} against {}",
                crate::format::fmt_num(a),
                crate::format::fmt_num(b)
            ));
        }
    }
    if dy_rms < DISORDER_DY && dy_rms > ROUNDOFF_DY && dy_rms > GROWTH_FACTOR * dy_rms_start {
        unsteady.push(format!(
            "the perturbation is still growing: dy_rms {} d to {} d over the window",
            crate::format::fmt_num(dy_rms_start),
            crate::format::fmt_num(dy_rms)
        ));
    }
    Window {
        from,
        to,
        frames: n,
        eps_stat,
        eps_max_mean,
        eps_max,
        linf_stat,
        l2_stat,
        linf_frame_mean,
        rms_v_stat,
        dy_rms_start,
        dy_rms,
        regime: if dy_rms >= DISORDER_DY {
            Regime::Disordered
        } else {
            Regime::Ordered
        },
        eps_halves,
        rms_v_halves,
        stationary: unsteady.is_empty(),
        unsteady: (!unsteady.is_empty()).then(|| unsteady.join("; ")),
        profile,
    }
}

/// The first sample time at which dy_rms reached [`DISORDER_DY`]: the time
/// to disorder (None: the run stayed ordered).
pub fn t_disorder(samples: &[Sample]) -> Option<f64> {
    samples
        .iter()
        .find(|s| s.dy_rms >= DISORDER_DY)
        .map(|s| s.t)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::solver::LayerProfile;

    fn sample(t: f64, eps: f64, v: f64, dy: f64, err: f64) -> Sample {
        Sample {
            t,
            step: 0,
            dt: 0.1,
            linf_rel_err: err.abs(),
            l2_rel_err: err.abs(),
            max_eps: eps * 1.1,
            eps_p99: eps,
            mean_eps: 0.0,
            rms_v: v,
            dy_rms: dy,
            kinetic_energy: 0.0,
            profile: vec![LayerProfile {
                layer: 0,
                count: 5,
                y: 0.0,
                u: 1.0 + err,
                v_rms: v,
                u_analytic: 1.0,
                u_steady: 1.0,
            }],
        }
    }

    #[test]
    fn a_steady_window_is_stationary_and_a_trend_is_not() {
        // Alternating noise of +-10 % about a constant: stationary, and the
        // mean flow's error cancels where the per-frame one does not.
        let s: Vec<Sample> = (0..=40)
            .map(|i| {
                let sign = if i % 2 == 0 { 1.0 } else { -1.0 };
                sample(
                    f64::from(i),
                    0.02 * (1.0 + 0.1 * sign),
                    0.01,
                    0.5,
                    0.03 * sign,
                )
            })
            .collect();
        let w = window(&s, 20.0, 40.0, 1.0);
        assert_eq!(w.frames, 20);
        assert!(w.stationary, "{:?}", w.unsteady);
        assert!((w.eps_stat - 0.02).abs() < 1e-12);
        assert!(w.linf_stat < 1e-12 && (w.linf_frame_mean - 0.03).abs() < 1e-12);
        assert_eq!(w.regime, Regime::Disordered);
        // A compaction that grows by a third across the window is not.
        let s: Vec<Sample> = (0..=40)
            .map(|i| {
                sample(
                    f64::from(i),
                    0.02 * (1.0 + f64::from(i) / 10.0),
                    0.01,
                    0.5,
                    0.0,
                )
            })
            .collect();
        let w = window(&s, 20.0, 40.0, 1.0);
        assert!(!w.stationary && w.unsteady.unwrap().contains("eps_p99"));
    }

    #[test]
    fn a_growing_perturbation_is_not_stationary_and_round_off_is() {
        let grow: Vec<Sample> = (0..=40)
            .map(|i| {
                sample(
                    f64::from(i),
                    1e-3,
                    1e-3,
                    1e-3 * (0.05 * f64::from(i)).exp(),
                    0.0,
                )
            })
            .collect();
        let w = window(&grow, 20.0, 40.0, 1.0);
        assert!(!w.stationary && w.unsteady.unwrap().contains("growing"));
        assert_eq!(w.regime, Regime::Ordered);
        let roundoff: Vec<Sample> = (0..=40)
            .map(|i| {
                sample(
                    f64::from(i),
                    1e-3,
                    1e-3,
                    1e-12 * (0.05 * f64::from(i)).exp(),
                    0.0,
                )
            })
            .collect();
        assert!(window(&roundoff, 20.0, 40.0, 1.0).stationary);
        assert_eq!(t_disorder(&grow), None);
        let jump: Vec<Sample> = (0..=40)
            .map(|i| {
                sample(
                    f64::from(i),
                    1e-3,
                    1e-3,
                    if i >= 30 { 0.2 } else { 0.01 },
                    0.0,
                )
            })
            .collect();
        assert_eq!(t_disorder(&jump), Some(30.0));
    }
}
