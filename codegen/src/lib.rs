//! shearsph-codegen: exact derivation of how SPH particle density pulses
//! under plane shear, and of the model sound speed c0 (Reshetnikova 2024),
//! from kernel definitions in `kernels/*.toml`; emission of the specialised
//! Rust in `generated/`.
//!
//! Stages: [`kernel`] reads and validates a definition (exact polynomials,
//! [`poly`], over exact numbers, [`exact`]); [`discretisation`] reads the
//! set of discretisations, [`lattice`] enumerates their lattices; [`compaction`] computes eps(t, n); [`c0`] the terms of
//! (25)-(34); [`analysis`] gathers them; [`show`] prints them.

/// Re-exported so tests of the solver crate can use the exact numbers without
/// their own dependency on rug.
pub use rug;

pub mod analysis;
pub mod c0;
pub mod claims;
pub mod compaction;
pub mod discretisation;
pub mod emit;
pub mod exact;
pub mod kernel;
pub mod lattice;
pub mod poly;
pub mod show;
