//! shearsph: model sound speed c0 for SPH plane shear flow. The library holds
//! the solver and the CLI's commands; the kernels come from `generated/`
//! (made by `cargo run -p shearsph-codegen -- generate`).

pub mod kernel;
