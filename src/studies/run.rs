//! Simulate a scene by kernel name: resolve it into a [`Problem`] and
//! dispatch to the solver compiled for that kernel. The one visitor `shearsph
//! run`, the sweep, the report and the tests go through.
//!
//! A process-wide stop ([`stop_all`]): once set (by a signal, in the CLI)
//! every run started through [`run_scene`] or [`run_problem`] ends at its
//! next step as interrupted, whatever its own observer says, so a command
//! whose runs are deep inside a search (the law's bisections) stops as
//! promptly as one that watches its own flag.

use std::sync::atomic::{AtomicBool, Ordering};

use crate::config::{Scene, SceneError};
use crate::kernel::{Kernel, KernelVisitor};
use crate::kernels;
use crate::problem::Problem;
use crate::solver::{self, Observer, ParticleFrame, RunResult, Sample};

/// The process-wide stop: set, every run ends at its next step as
/// interrupted. Never cleared (a signal ends the process's work).
pub fn stop_all() -> &'static AtomicBool {
    static STOP: AtomicBool = AtomicBool::new(false);
    &STOP
}

/// `inner`, and stop when [`stop_all`] is set.
struct OrStopAll<'a> {
    inner: &'a mut dyn Observer,
}

impl Observer for OrStopAll<'_> {
    fn step(&mut self, t: f64, steps: u64) {
        self.inner.step(t, steps)
    }
    fn output(&mut self, sample: &Sample) {
        self.inner.output(sample)
    }
    fn should_stop(&self) -> bool {
        stop_all().load(Ordering::Relaxed) || self.inner.should_stop()
    }
    fn wants_particles(&self) -> bool {
        self.inner.wants_particles()
    }
    fn particles(&mut self, frame: &ParticleFrame) {
        self.inner.particles(frame)
    }
}

/// Run a resolved problem with the kernel it was resolved for.
pub fn run_problem(problem: &Problem, observer: &mut dyn Observer) -> RunResult {
    struct Visit<'a> {
        problem: &'a Problem,
        observer: &'a mut dyn Observer,
    }
    impl KernelVisitor for Visit<'_> {
        type Output = RunResult;
        fn visit<K: Kernel>(self) -> RunResult {
            solver::run::<K>(self.problem, self.observer)
        }
    }
    let mut observer = OrStopAll { inner: observer };
    kernels::with_kernel(
        problem.kernel.name,
        Visit {
            problem,
            observer: &mut observer,
        },
    )
    .expect("the registry has a solver for every kernel it lists")
}

/// Resolve `scene` against the kernel it names and run it (to its t_end,
/// which must be at least one time step: [`Problem::check_duration`]).
pub fn run_scene(scene: &Scene, observer: &mut dyn Observer) -> Result<RunResult, SceneError> {
    let problem = Problem::resolve(scene, scene.kernel_info()?)?;
    problem.check_duration()?;
    Ok(run_problem(&problem, observer))
}
