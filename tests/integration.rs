//! The shearsph crate's integration tests, one test binary: each file of
//! tests/ is a module of it. One binary is compiled and linked once
//! (seventeen, each linking the library, took about 30 s of a 2-core
//! machine's wall from scratch), and its tests are scheduled together
//! over the cores rather than binary after binary.

mod common;

mod bench;
mod bounds_and_signals;
mod cfl_time_step;
mod classes;
mod cli;
mod cli_kernels;
mod empirical;
mod generated_kernels;
mod input_guards;
mod particles_vtk;
mod report;
mod solver;
mod stability;
mod sweep;
mod sweep_axes;
mod viscous_normalisation;
mod viscous_time_step;
