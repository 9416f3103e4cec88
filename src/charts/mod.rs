//! Every chart (SVG, plotters): one run's ([`run`]: profile, time series)
//! and the sweep's and report's ([`sweep`]: speed against accuracy,
//! stability maps, Figure 4).

pub mod figure4;
pub mod run;
pub mod sweep;

pub use figure4::*;
pub use sweep::*;

use plotters::prelude::DrawingAreaErrorKind;

/// A plotters error as an error of ours.
fn chart_err<E: std::error::Error + Send + Sync + 'static>(
    e: DrawingAreaErrorKind<E>,
) -> anyhow::Error {
    anyhow::anyhow!("drawing a chart: {e}")
}
