//! The growth a nonlinear run measures: the scene's base state (perfect
//! lattice, steady profile) jittered by a small amplitude, run by the
//! ordinary solver, its rms transverse displacement from the lattice
//! `dy_rms` sampled, and the slope of ln dy_rms fitted over the
//! exponential phase: from the first sample at twice the floor to the
//! first at half `DISORDER_DY_RMS` (0.05 d), before the growth saturates.
//! The floor is the largest dy_rms the perfect lattice itself reaches over
//! the same run (its layers pulse in y as they slide, about 0.005 d at
//! N = 10): below it the jitter's growth is hidden. That is the check of the linear analysis against the solver,
//! not against itself: another code path (the run, its jitter, its
//! diagnostics), finite amplitude, every sector at once.

use anyhow::Result;
use serde::Serialize;

use super::{base_scene, DISORDER_DY_RMS};
use crate::config::{HorizonKind, Scene};
use crate::law::fit::least_squares;
use crate::run::run_scene;
use crate::solver::{Observer, Sample};

/// What the run measured.
#[derive(Debug, Clone, Serialize)]
pub struct Measured {
    pub amplitude: f64,
    /// The fitted slope of ln dy_rms over the exponential phase, per unit
    /// time; none when the phase was not reached.
    pub growth_rate: Option<f64>,
    /// The phase fitted: [t_from, t_to] and the samples in it.
    pub fit_from: Option<f64>,
    pub fit_to: Option<f64>,
    pub samples: usize,
    /// The first sample with dy_rms >= 0.1 d.
    pub t_disorder: Option<f64>,
    /// The mean rate to disorder, ln(0.1 sqrt 3 / a) / t_disorder: what the
    /// prediction's time to disorder is compared with.
    pub mean_rate: Option<f64>,
    /// The perfect lattice's largest dy_rms over the run (d).
    pub floor: f64,
    pub t_end: f64,
}

struct Record(Vec<(f64, f64)>);
impl Observer for Record {
    fn output(&mut self, s: &Sample) {
        self.0.push((s.t, s.dy_rms));
    }
}

/// Run the base state of `scene` at `c0` from a jitter of `amplitude` d
/// (seed `seed`) to `t_end`, sampling every `interval`, and fit the growth.
pub fn measure(
    scene: &Scene,
    c0: f64,
    amplitude: f64,
    seed: u32,
    t_end: f64,
    interval: f64,
) -> Result<Measured> {
    let series = |jitter: f64| -> Result<Vec<(f64, f64)>> {
        let mut s = base_scene(scene, c0)?;
        s.jitter = jitter;
        s.jitter_seed = seed;
        s.horizon = HorizonKind::Fixed;
        s.t_end = Some(t_end);
        s.output_interval = Some(interval);
        let mut rec = Record(Vec::new());
        run_scene(&s, &mut rec)?;
        Ok(rec.0)
    };
    let floor = series(0.0)?.iter().fold(0.0f64, |m, p| m.max(p.1));
    let series = series(amplitude)?;
    let from = series.iter().position(|p| p.1 >= 2.0 * floor);
    let to = series.iter().position(|p| p.1 >= DISORDER_DY_RMS / 2.0);
    let t_disorder = series.iter().find(|p| p.1 >= DISORDER_DY_RMS).map(|p| p.0);
    let (rate, fit_from, fit_to, samples) = match (from, to) {
        (Some(a), Some(b)) if b >= a + 2 => {
            let pts = &series[a..=b];
            (
                Some(slope(pts)),
                Some(pts[0].0),
                Some(pts[pts.len() - 1].0),
                pts.len(),
            )
        }
        _ => (None, None, None, 0),
    };
    Ok(Measured {
        amplitude,
        growth_rate: rate,
        fit_from,
        fit_to,
        samples,
        t_disorder,
        mean_rate: t_disorder.map(|t| (DISORDER_DY_RMS * 3f64.sqrt() / amplitude).ln() / t),
        floor,
        t_end,
    })
}

/// The least-squares slope of ln v against t ([`least_squares`]); NaN
/// when the points cannot fit a line.
fn slope(pts: &[(f64, f64)]) -> f64 {
    let t: Vec<f64> = pts.iter().map(|p| p.0).collect();
    let ln: Vec<f64> = pts.iter().map(|p| p.1.ln()).collect();
    least_squares(&["ln v0", "rate"], &[vec![1.0; t.len()], t], &ln).map_or(f64::NAN, |f| f.coef[1])
}
