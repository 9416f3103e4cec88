//! shearsph: model sound speed c0 for SPH plane shear flow. The library holds
//! the solver and the CLI's commands; the kernels come from `generated/`
//! (made by `cargo run -p shearsph-codegen -- generate`).
//!
//! The folders are the layers, each looking only down or beside itself:
//! [`model`] (config, problem, kernel, solver) <- [`studies`] (run,
//! empirical, law, sweep, report, stability, bench) and [`io`] (output,
//! charts, particles) <- [`cli`]. Every module is also at the root
//! (`crate::solver`, `crate::sweep`, `crate::charts`), the paths the code
//! uses.

pub mod cli;
pub mod io;
pub mod model;
pub mod studies;

pub use io::{charts, output, particles};
pub use model::{analytic, config, format, kernel, problem, solver};
pub use studies::{bench, empirical, law, report, run, stability, sweep};

/// The generated kernels: one unit struct per `kernels/*.toml` implementing
/// [`kernel::Kernel`], and the registry (`KERNELS`, `NAMES`, `kernel_info`,
/// `with_kernel`). `include!` keeps rustfmt out of `generated/`, whose
/// formatting is prettyplease's.
#[allow(
    clippy::approx_constant,
    clippy::excessive_precision,
    clippy::unreadable_literal
)]
pub mod kernels {
    include!("../generated/registry.rs");
}
