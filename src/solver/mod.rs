//! The 2D SPH solver for plane shear (Poiseuille) flow, generic over the
//! kernel. No I/O: [`simulate`] takes a scene and an observer and returns a
//! [`RunResult`]; `crate::output` writes it.
//!
//! One step (symplectic kick-drift-kick leapfrog):
//! 1. kick and drift: v += dt/2 a, x += dt v;
//! 2. rebuild the neighbour list if the displacements allow a missed pair;
//! 3. density by summation at the drifted positions, then the EOS;
//! 4. accelerations, with the velocities predicted at the step's end, then
//!    the closing kick v += dt/2 a;
//! 5. the checks for blow-up, every step.

mod diagnostics;
pub mod ideal_shear;
pub mod lattice;
pub mod neighbours;
mod step;

use std::time::Instant;

use serde::Serialize;

use crate::kernel::Kernel;
use crate::scene::{Problem, Scene, SceneError};
use neighbours::{Displacements, NeighbourList};
use step::{Params, State};

pub use diagnostics::{LayerProfile, Sample};

/// Receives progress from a running simulation.
pub trait Observer: Send {
    /// After every step.
    fn step(&mut self, _t: f64, _steps: u64) {}
    /// At every output time (t = 0 included), and at a failure.
    fn output(&mut self, _sample: &Sample) {}
}

/// An observer that ignores everything.
pub struct Quiet;
impl Observer for Quiet {}

/// The time-step limit that bound a step.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum DtLimit {
    /// 0.25 h / (c0 + |v|max).
    Cfl,
    /// 0.125 h^2 / nu.
    Viscous,
    /// 0.25 sqrt(h / |a|max).
    Force,
}

impl DtLimit {
    pub fn name(self) -> &'static str {
        match self {
            DtLimit::Cfl => "cfl",
            DtLimit::Viscous => "viscous",
            DtLimit::Force => "force",
        }
    }
}

/// The three limits for a state with speeds up to `v_max` and accelerations
/// up to `a_max`, and which binds.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct TimeStep {
    pub cfl: f64,
    pub viscous: f64,
    pub force: f64,
    pub dt: f64,
    pub limit: DtLimit,
}

impl TimeStep {
    pub fn new(h: f64, c0: f64, nu: f64, v_max: f64, a_max: f64) -> TimeStep {
        let cfl = 0.25 * h / (c0 + v_max);
        let viscous = 0.125 * h * h / nu;
        let force = if a_max > 0.0 {
            0.25 * (h / a_max).sqrt()
        } else {
            f64::INFINITY
        };
        let (dt, limit) = [
            (cfl, DtLimit::Cfl),
            (viscous, DtLimit::Viscous),
            (force, DtLimit::Force),
        ]
        .into_iter()
        .fold((f64::INFINITY, DtLimit::Cfl), |best, c| {
            if c.0 < best.0 {
                c
            } else {
                best
            }
        });
        TimeStep {
            cfl,
            viscous,
            force,
            dt,
            limit,
        }
    }
}

/// Why a run failed.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Failure {
    /// A velocity or acceleration became NaN or infinite.
    NotFinite,
    /// A fluid speed exceeded the bound 10 U + c0.
    Speed { v: f64, limit: f64 },
    /// A fluid particle reached a wall layer (|y| >= B).
    ThroughWall { y: f64, b: f64 },
    /// The fluid's compaction exceeded the scene's `eps_limit`.
    Compaction { eps: f64, limit: f64 },
}

impl std::fmt::Display for Failure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Failure::NotFinite => write!(
                f,
                "a velocity or acceleration is not finite (NaN or infinite)"
            ),
            Failure::Speed { v, limit } => write!(
                f,
                "a fluid speed {v:.4} exceeds the bound 10 U + c0 = {limit:.4}"
            ),
            Failure::ThroughWall { y, b } => {
                write!(
                    f,
                    "a fluid particle reached a wall: |y| = {y:.4} >= B = {b:.4}"
                )
            }
            Failure::Compaction { eps, limit } => {
                write!(f, "the compaction eps = {eps:.4} exceeds the limit {limit}")
            }
        }
    }
}

/// How a run ended.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "status", rename_all = "lowercase")]
pub enum Outcome {
    Ok,
    Failed { failure: Failure, t: f64, step: u64 },
}

impl Outcome {
    pub fn is_ok(&self) -> bool {
        matches!(self, Outcome::Ok)
    }
}

/// Time-step statistics over the steps not shortened to land on an output
/// time.
#[derive(Debug, Clone, Serialize)]
pub struct DtStats {
    /// The last step's dt and the limit that bound it.
    pub last: f64,
    pub last_limit: DtLimit,
    pub min: f64,
    pub max: f64,
    /// Steps bound by each limit: cfl, viscous, force.
    pub cfl_steps: u64,
    pub viscous_steps: u64,
    pub force_steps: u64,
}

impl DtStats {
    fn new(first: &TimeStep) -> Self {
        DtStats {
            last: first.dt,
            last_limit: first.limit,
            min: f64::INFINITY,
            max: 0.0,
            cfl_steps: 0,
            viscous_steps: 0,
            force_steps: 0,
        }
    }

    fn record(&mut self, ts: &TimeStep) {
        self.last = ts.dt;
        self.last_limit = ts.limit;
        self.min = self.min.min(ts.dt);
        self.max = self.max.max(ts.dt);
        match ts.limit {
            DtLimit::Cfl => self.cfl_steps += 1,
            DtLimit::Viscous => self.viscous_steps += 1,
            DtLimit::Force => self.force_steps += 1,
        }
    }

    /// The limit that bound the most steps.
    pub fn dominant(&self) -> DtLimit {
        let counts = [
            (self.cfl_steps, DtLimit::Cfl),
            (self.viscous_steps, DtLimit::Viscous),
            (self.force_steps, DtLimit::Force),
        ];
        counts
            .iter()
            .max_by_key(|c| c.0)
            .map(|c| c.1)
            .unwrap_or(self.last_limit)
    }
}

/// Everything a run produced.
#[derive(Debug, Clone, Serialize)]
pub struct RunResult {
    pub problem: Problem,
    pub kernel: &'static str,
    pub n_fluid: usize,
    pub n_wall: usize,
    pub steps: u64,
    /// Time reached (t_end unless the run failed).
    pub t: f64,
    pub dt: DtStats,
    pub outcome: Outcome,
    /// Diagnostics at t = 0, every output time, and at a failure.
    pub samples: Vec<Sample>,
    /// Largest fluid compaction over every step.
    pub max_eps_run: f64,
    pub neighbour_rebuilds: u64,
    /// Mean listed neighbours per particle (R h + skin).
    pub mean_neighbours: f64,
    /// Wall-clock seconds of the simulation.
    pub wall_s: f64,
}

impl RunResult {
    /// The last diagnostics sample.
    pub fn last(&self) -> &Sample {
        self.samples.last().expect("a run has its t = 0 sample")
    }
}

/// Resolve `scene` for kernel `K` and run it.
pub fn simulate<K: Kernel>(
    scene: &Scene,
    observer: &mut dyn Observer,
) -> Result<RunResult, SceneError> {
    if scene.kernel != K::NAME {
        return Err(SceneError::KernelMismatch {
            scene: scene.kernel.clone(),
            solver: K::NAME,
        });
    }
    let problem = Problem::new(scene, K::INFO)?;
    Ok(run::<K>(&problem, observer))
}

/// Run a resolved problem with kernel `K` on the current rayon pool.
pub fn run<K: Kernel>(problem: &Problem, observer: &mut dyn Observer) -> RunResult {
    // Drive the loop from a worker thread, so each parallel pass is a cheap
    // fork inside the pool rather than a hand-off from outside it.
    rayon::scope(|_| run_here::<K>(problem, observer))
}

fn run_here<K: Kernel>(problem: &Problem, observer: &mut dyn Observer) -> RunResult {
    let start = Instant::now();
    let lat = problem.lattice;
    let h = lat.h;
    let mut s = State::new(&lat, problem);
    let prm = Params::new(problem);
    let skin = problem.scene.skin * h;
    let cutoff = K::SUPPORT2_CLOSED.sqrt() * h + skin;
    // Blocks for the rebuild rule: the lattice layers, stored in turn.
    let block = lat.columns as usize;
    let mut motion = Vec::with_capacity(lat.fluid_layers() as usize);
    let mut list = NeighbourList::default();
    s.wrap(lat.width);
    list.build(&s.x, &s.y, lat.width, cutoff, block);
    let mean_neighbours = list.pairs() as f64 / s.x.len() as f64;

    let mut max_eps = step::density::<K>(&mut s, &list, &prm);
    let mut max_eps_run = max_eps;
    let mut forces = step::forces::<K>(&mut s, &list, &prm, 0.0);
    let nu = problem.flow.nu;
    let mut dt_stats = DtStats::new(&TimeStep::new(
        h,
        problem.c0,
        nu,
        forces.v_max,
        forces.a_max,
    ));

    let sample =
        |s: &State, t: f64, steps: u64, dt: f64| diagnostics::sample(problem, s, t, steps, dt);
    let first = sample(&s, 0.0, 0, dt_stats.last);
    observer.output(&first);
    let mut samples = vec![first];

    let t_end = problem.t_end;
    let mut t = 0.0;
    let mut steps = 0u64;
    let mut outputs_done = 0u64;
    // Output k (from 0) at (k + 1) intervals; the last one at t_end exactly,
    // also when t_end is a multiple of the interval up to round-off.
    let next_output = |k: u64| {
        let t = (k + 1) as f64 * problem.output_interval;
        if t >= t_end * (1.0 - 1e-9) {
            t_end
        } else {
            t
        }
    };
    let mut outcome = Outcome::Ok;
    while t < t_end {
        let ts = TimeStep::new(h, problem.c0, nu, forces.v_max, forces.a_max);
        let target = next_output(outputs_done);
        let landing = t + ts.dt >= target;
        let dt = if landing { target - t } else { ts.dt };
        if !landing {
            dt_stats.record(&ts);
        }

        step::kick_drift(&mut s, dt, block, &mut motion);
        let max_abs_y = motion.iter().fold(0.0f64, |m, b| m.max(b.1));
        if list.stale(|b| motion.get(b).map_or(Displacements::ZERO, |m| m.0), skin) {
            s.wrap(lat.width);
            list.build(&s.x, &s.y, lat.width, cutoff, block);
        }
        max_eps = step::density::<K>(&mut s, &list, &prm);
        max_eps_run = max_eps_run.max(max_eps);
        forces = step::forces::<K>(&mut s, &list, &prm, 0.5 * dt);
        t = if landing { target } else { t + dt };
        steps += 1;
        observer.step(t, steps);

        let failure = if !forces.finite {
            Some(Failure::NotFinite)
        } else if forces.v_max > problem.v_limit {
            Some(Failure::Speed {
                v: forces.v_max,
                limit: problem.v_limit,
            })
        } else if max_abs_y >= lat.b() {
            Some(Failure::ThroughWall {
                y: max_abs_y,
                b: lat.b(),
            })
        } else if max_eps > problem.scene.eps_limit {
            Some(Failure::Compaction {
                eps: max_eps,
                limit: problem.scene.eps_limit,
            })
        } else {
            None
        };
        if let Some(failure) = failure {
            let last = sample(&s, t, steps, dt);
            observer.output(&last);
            samples.push(last);
            outcome = Outcome::Failed {
                failure,
                t,
                step: steps,
            };
            break;
        }
        if landing {
            outputs_done += 1;
            let out = sample(&s, t, steps, dt_stats.last);
            observer.output(&out);
            samples.push(out);
        }
    }

    RunResult {
        problem: problem.clone(),
        kernel: K::NAME,
        n_fluid: s.n_fluid,
        n_wall: s.x.len() - s.n_fluid,
        steps,
        t,
        dt: dt_stats,
        outcome,
        samples,
        max_eps_run,
        neighbour_rebuilds: list.rebuilds,
        mean_neighbours,
        wall_s: start.elapsed().as_secs_f64(),
    }
}
