//! The model, the lowest layers: a scene's fields and rules as typed values
//! ([`config`]), every number a run needs, resolved once ([`problem`]), the
//! kernel's data types that `generated/` implements ([`kernel`]) and the
//! solver, generic over the kernel ([`solver`]); beneath them the series
//! and steady solutions ([`analytic`]) and short numbers ([`format`]).
//! Nothing here imports the studies, the outputs or the CLI; the crate
//! root re-exports each module (`crate::solver` is `crate::model::solver`).

pub mod analytic;
pub mod config;
pub mod format;
pub mod kernel;
pub mod problem;
pub mod solver;
