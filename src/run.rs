//! Simulate a scene by kernel name: resolve it into a [`Problem`] and
//! dispatch to the solver compiled for that kernel. The one visitor `shearsph
//! run`, the sweep, the report and the tests go through.

use crate::config::{Scene, SceneError};
use crate::kernel::{Kernel, KernelVisitor};
use crate::kernels;
use crate::problem::Problem;
use crate::solver::{self, Observer, RunResult};

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
    kernels::with_kernel(problem.kernel.name, Visit { problem, observer })
        .expect("the registry has a solver for every kernel it lists")
}

/// Resolve `scene` against the kernel it names and run it.
pub fn run_scene(scene: &Scene, observer: &mut dyn Observer) -> Result<RunResult, SceneError> {
    let problem = Problem::resolve(scene, scene.kernel_info()?)?;
    Ok(run_problem(&problem, observer))
}
