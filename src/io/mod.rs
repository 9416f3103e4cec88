//! What the model and the studies write: a run's summary and CSVs and the
//! write path ([`output`]), the charts ([`charts`]: a run's, and the
//! sweep's, report's and law's, drawn from their rows) and the particle
//! snapshots and picture ([`particles`]). The charts read the studies'
//! rows, so this folder sits beside the studies, not beneath them; the
//! crate root re-exports each module (`crate::charts` is
//! `crate::io::charts`).

pub mod charts;
pub mod output;
pub mod particles;
