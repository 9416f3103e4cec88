//! The disordered scene of `bench --disordered`: the state a user's long
//! run is in, at every size. A jittered start of the empirical answer's
//! size (N = [`LAYERS`], the strip as wide as the channel) is run into its
//! disordered, stationary state once per kernel ([`base`]); each particle
//! count is then that state tiled along x ([`solver::run_steps_tiled`]), so
//! every size times the same state: the same neighbours per particle, the
//! same scatter of their indices and the same rebuilds per step. (Running
//! each size from its own jittered start cannot reach that state at 1e5
//! particles and more within a bench, and leaves the sizes in different
//! states: `results/2026-12-05-bench-disordered-1e6/`.)

use anyhow::{Context, Result};

use super::scene;
use crate::config::Scene;
use crate::kernel::{Kernel, KernelVisitor};
use crate::kernels;
use crate::problem::Problem;
use crate::solver::{self, FluidState};

/// Layers in the half-width of the base: the empirical answer's scene.
pub const LAYERS: u32 = 10;
/// The base's start: jittered by this much (the empirical search's), seed 1.
pub const JITTER: f64 = 0.05;
/// How long the base runs before it is tiled, in units of d / U: past the
/// start of the window the stationary horizon judges a jittered run at
/// Re = 10 and 10 U by (t = 602.5 on the square lattice at N = 10,
/// docs/validation.md). Whether the base is disordered by then is measured,
/// not assumed: the bench prints its dy_rms (>= 0.1 d: disordered).
pub const UNTIL_T: f64 = 640.0;
/// Fewest timed steps of the disordered scene: several rebuilds (one every
/// 12-30 steps in the disordered state) at every size.
pub const MIN_STEPS: u64 = 100;

/// The base scene of a kernel: the bench scene at N = [`LAYERS`], jittered.
pub fn base_scene(kernel: &str) -> Scene {
    let mut s = scene(kernel);
    s.n_layers = LAYERS;
    s.jitter = JITTER;
    s.jitter_seed = 1;
    s
}

/// The base tiled to at least `target` particles: its scene on a strip of
/// the fewest whole copies of the base's strip that hold them.
pub fn tiled(base: &Problem, target: usize) -> Result<Problem> {
    let copies = target.div_ceil(base.lattice.n_particles()).max(1);
    let mut s = base.scene.clone();
    s.columns = Some(base.lattice.columns * copies as u32);
    Problem::resolve(&s, s.kernel_info()?)
        .with_context(|| format!("the disordered scene tiled {copies} times"))
}

/// The base's state, run on a pool of every core (the solver's result does
/// not depend on the thread count).
pub fn base(problem: &Problem) -> Result<FluidState> {
    struct Base<'a>(&'a Problem);
    impl KernelVisitor for Base<'_> {
        type Output = FluidState;
        fn visit<K: Kernel>(self) -> FluidState {
            solver::disordered_state::<K>(self.0, UNTIL_T)
        }
    }
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(super::cores())
        .build()
        .context("building the thread pool")?;
    pool.install(|| {
        kernels::with_kernel(&problem.scene.kernel, Base(problem))
            .with_context(|| format!("unknown kernel {}", problem.scene.kernel))
    })
}
