//! shearsph: model sound speed c0 for SPH plane shear flow. The library holds
//! the solver and the CLI's commands; the kernels come from `generated/`
//! (made by `cargo run -p shearsph-codegen -- generate`).

pub mod kernel;

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
pub mod analytic;
pub mod bench;
pub mod charts;
pub mod cli;
pub mod config;
pub mod empirical;
pub mod format;
pub mod law;
pub mod output;
pub mod particles;
pub mod problem;
pub mod report;
pub mod run;
pub mod solver;
pub mod stability;
pub mod sweep;
