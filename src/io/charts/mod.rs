//! Every chart (SVG, plotters): one run's ([`run`]: profile, time series)
//! and the sweep's and report's ([`sweep`]: speed against accuracy,
//! stability maps, Figure 4), and the clean log-axis ticks they share
//! ([`ticks`]).

pub mod figure4;
pub mod history;
pub mod law;
pub mod mode;
pub mod rules;
pub mod run;
pub mod sweep;
pub mod ticks;

pub use figure4::*;
pub use rules::*;
pub use sweep::*;

use plotters::prelude::DrawingAreaErrorKind;

/// A plotters error as an error of ours.
fn chart_err<E: std::error::Error + Send + Sync + 'static>(
    e: DrawingAreaErrorKind<E>,
) -> anyhow::Error {
    anyhow::anyhow!("drawing a chart: {e}")
}

use plotters::coord::combinators::{BindKeyPoints, WithKeyPoints};
use plotters::prelude::{IntoLogRange, LogCoord};

use ticks::{log_ticks, Tick};

/// A log axis over [lo, hi] with [`log_ticks`]: labelled decades (bold
/// mesh lines) and unlabelled 2..9 (light ones). Label the axis with
/// [`LogAxis::label`] as its label formatter.
pub struct LogAxis {
    ticks: Vec<Tick>,
}

impl LogAxis {
    /// At most `max_labels` labels.
    pub fn new(lo: f64, hi: f64, max_labels: usize) -> (WithKeyPoints<LogCoord<f64>>, LogAxis) {
        let mut ticks = log_ticks(lo, hi, max_labels);
        if ticks.iter().filter(|t| t.label.is_some()).count() == 0 {
            // narrower than any tick: the ends, labelled
            ticks = [lo, hi]
                .into_iter()
                .map(|v| Tick {
                    value: v,
                    label: Some(crate::format::fmt_num(v)),
                })
                .collect();
        }
        let bold: Vec<f64> = ticks
            .iter()
            .filter(|t| t.label.is_some())
            .map(|t| t.value)
            .collect();
        let light: Vec<f64> = ticks
            .iter()
            .filter(|t| t.label.is_none())
            .map(|t| t.value)
            .collect();
        let coord = (lo..hi)
            .log_scale()
            .with_key_points(bold)
            .with_light_points(light);
        (coord, LogAxis { ticks })
    }

    /// The label of the tick at `v` (empty for any other value).
    pub fn label(&self, v: &f64) -> String {
        self.ticks
            .iter()
            .find(|t| t.value == *v)
            .and_then(|t| t.label.clone())
            .unwrap_or_default()
    }
}
