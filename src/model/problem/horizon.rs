//! How long a run goes on and which of its frames it is judged by
//! (docs/stationary.md). A `fixed` horizon runs to t_end; a `stationary`
//! one runs past the laminar start-up until the disorder's statistics are
//! stationary, checking at checkpoints t_su + W0 2^k, up to a cap. Either
//! way the run is judged on the later half of its time after the start-up.

use serde::Serialize;

pub use crate::config::HorizonKind;

/// The first checkpoint's span after the start-up is the scene's
/// `horizon_span` shear times t_s = B / U, 64 by default: a 0.001 d jitter
/// disorders in about 20-25 t_s at N = 6, 10 and 20 (Monaghan, Re = 1,
/// 10 U), so the span holds the onset and a window of 32 t_s after it.
/// The span is kept between these bounds (shear times).
pub const SPAN_RANGE: (f64, f64) = (8.0, 4096.0);
/// Doublings of the span before the cap: t_su + 4 x 64 t_s by default.
/// The cost of a run to the cap is what bounds it: a 10 U run at N = 10,
/// Re = 1 takes about 155,000 steps to there.
pub const DOUBLINGS: u32 = 2;
/// Frames per shear time in a stationary horizon (unless the scene sets the
/// output interval): 128 frames in the first window.
pub const FRAMES_PER_SHEAR_TIME: f64 = 4.0;

/// A problem's horizon, resolved: every time the solver and the judge need.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Horizon {
    pub kind: HorizonKind,
    /// The start-up allowance t_su: the decay time of the start-up's slowest
    /// mode to `decay_tol` U (0 from the steady profile); in a stationary
    /// horizon rounded up to a whole number of output intervals.
    pub t_startup: f64,
    /// B / U.
    pub shear_time: f64,
    /// Where the run may stop to be judged: t_end alone (fixed), or
    /// t_su + W0 2^k, k = 0..=DOUBLINGS (stationary), each a whole number
    /// of output intervals. The last is the problem's t_end.
    pub checkpoints: Vec<f64>,
}

impl Horizon {
    /// A fixed horizon ending at `t_end`.
    pub fn fixed(t_startup: f64, shear_time: f64, t_end: f64) -> Horizon {
        Horizon {
            kind: HorizonKind::Fixed,
            t_startup,
            shear_time,
            checkpoints: vec![t_end],
        }
    }

    /// A stationary horizon whose first span is `span` shear times, with
    /// frames every `interval`.
    pub fn stationary(t_startup: f64, shear_time: f64, span: f64, interval: f64) -> Horizon {
        let t_su = (t_startup / interval).ceil() * interval;
        let w0 = (span * shear_time / interval).round().max(16.0) * interval;
        Horizon {
            kind: HorizonKind::Stationary,
            t_startup: t_su,
            shear_time,
            checkpoints: (0..=DOUBLINGS)
                .map(|k| t_su + w0 * f64::from(1u32 << k))
                .collect(),
        }
    }

    /// The run's last possible time.
    pub fn cap(&self) -> f64 {
        *self.checkpoints.last().expect("a horizon has a checkpoint")
    }

    /// The window a run that reached `t` is judged on: the later half of its
    /// time after the start-up, (t_su + (t - t_su) / 2, t]; a run that did
    /// not get past the start-up, the later half of its time.
    pub fn window(&self, t: f64) -> (f64, f64) {
        if t > self.t_startup {
            (self.t_startup + 0.5 * (t - self.t_startup), t)
        } else {
            (0.5 * t, t)
        }
    }

    /// Whether `t` is a checkpoint before the cap, where a stationary run
    /// may stop.
    pub fn may_stop_at(&self, t: f64) -> bool {
        self.kind == HorizonKind::Stationary
            && self.checkpoints[..self.checkpoints.len() - 1]
                .iter()
                .any(|&c| (t - c).abs() <= 1e-9 * c.max(1.0))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn checkpoints_double_after_the_startup() {
        let h = Horizon::stationary(24.3, 8.0, 64.0, 2.0);
        assert_eq!(h.t_startup, 26.0);
        assert_eq!(h.checkpoints, vec![538.0, 1050.0, 2074.0]);
        assert_eq!(h.window(538.0), (282.0, 538.0));
        assert!(h.may_stop_at(1050.0) && !h.may_stop_at(2074.0) && !h.may_stop_at(1000.0));
        let f = Horizon::fixed(24.3, 8.0, 24.3);
        assert_eq!(f.window(24.3), (12.15, 24.3));
        assert!(!f.may_stop_at(24.3));
    }
}
