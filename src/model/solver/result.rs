//! What a run produced: its outcome (and why it failed), its time-step
//! statistics, its samples; the one result type that `output`, the sweep's
//! rows and the report read.

use std::fmt;

use serde::{Deserialize, Serialize};

use super::{Sample, Window};
use crate::problem::cost::{DtLimit, TimeStep};
use crate::problem::ClassRules;
use crate::problem::Problem;

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

impl Failure {
    /// The kind alone, as in JSON's `kind`.
    pub fn kind(&self) -> FailureKind {
        match self {
            Failure::NotFinite => FailureKind::NotFinite,
            Failure::Speed { .. } => FailureKind::Speed,
            Failure::ThroughWall { .. } => FailureKind::ThroughWall,
            Failure::Compaction { .. } => FailureKind::Compaction,
        }
    }
}

/// Why a run, or a point of a sweep, has no result: the solver's
/// [`Failure`]s by kind, and what stops a point before or outside the
/// solver. Written as snake_case (`no_c0`, `through_wall`, ...).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FailureKind {
    /// The rule gives no positive c0 for the scene.
    NoC0,
    /// The scene is invalid.
    Scene,
    /// The solver panicked (a bug; it costs the point, not the sweep).
    Panic,
    /// Stopped before the end.
    Interrupted,
    NotFinite,
    Speed,
    ThroughWall,
    Compaction,
}

impl FailureKind {
    pub fn name(self) -> &'static str {
        match self {
            FailureKind::NoC0 => "no_c0",
            FailureKind::Scene => "scene",
            FailureKind::Panic => "panic",
            FailureKind::Interrupted => "interrupted",
            FailureKind::NotFinite => "not_finite",
            FailureKind::Speed => "speed",
            FailureKind::ThroughWall => "through_wall",
            FailureKind::Compaction => "compaction",
        }
    }
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

/// The fluid particle that triggered a failure, as it was when the failure
/// was seen: the first with a non-finite value ([`Failure::NotFinite`]),
/// the fastest ([`Failure::Speed`]), the one of largest |y|
/// ([`Failure::ThroughWall`]) or the densest ([`Failure::Compaction`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Particle {
    /// Index among the particles at the start (fluid first), whatever
    /// order the solver stores them in since.
    pub index: usize,
    /// The lattice layer n it started in (0 on the centre line).
    pub layer: i32,
    pub x: f64,
    pub y: f64,
    pub vx: f64,
    pub vy: f64,
}

impl std::fmt::Display for Particle {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "fluid particle {} (started in layer {}) at x = {:.4}, y = {:.4}, velocity ({:.4}, {:.4})",
            self.index, self.layer, self.x, self.y, self.vx, self.vy
        )
    }
}

/// How a run ended.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "status", rename_all = "lowercase")]
pub enum Outcome {
    Ok,
    Failed {
        failure: Failure,
        t: f64,
        step: u64,
        particle: Particle,
    },
    /// The observer asked to stop ([`Observer::should_stop`]) after `step`.
    Interrupted {
        t: f64,
        step: u64,
    },
}

impl Outcome {
    pub fn is_ok(&self) -> bool {
        matches!(self, Outcome::Ok)
    }

    /// `ok`, `failed` or `interrupted`: the serialised `status`.
    pub fn status(&self) -> &'static str {
        match self {
            Outcome::Ok => "ok",
            Outcome::Failed { .. } => "failed",
            Outcome::Interrupted { .. } => "interrupted",
        }
    }
}

impl std::fmt::Display for Outcome {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Outcome::Ok => write!(f, "ok"),
            Outcome::Failed {
                failure,
                t,
                step,
                particle,
            } => write!(
                f,
                "failed at t = {t:.6}, step {step}: {failure}; {particle}"
            ),
            Outcome::Interrupted { t, step } => write!(f, "interrupted at t = {t:.6}, step {step}"),
        }
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
    /// Steps bound by each limit.
    pub steps: DtLimitSteps,
}

/// Steps bound by each time-step limit (`dt_limit_steps` in summary.json).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(default)]
pub struct DtLimitSteps {
    pub cfl: u64,
    pub viscous: u64,
    pub force: u64,
}

impl DtStats {
    pub(super) fn new(first: &TimeStep) -> Self {
        DtStats {
            last: first.dt,
            last_limit: first.limit,
            min: f64::INFINITY,
            max: 0.0,
            steps: DtLimitSteps::default(),
        }
    }

    pub(super) fn record(&mut self, ts: &TimeStep) {
        self.last = ts.dt;
        self.last_limit = ts.limit;
        self.min = self.min.min(ts.dt);
        self.max = self.max.max(ts.dt);
        match ts.limit {
            DtLimit::Cfl => self.steps.cfl += 1,
            DtLimit::Viscous => self.steps.viscous += 1,
            DtLimit::Force => self.steps.force += 1,
        }
    }

    /// The limit that bound the most steps.
    pub fn dominant(&self) -> DtLimit {
        let counts = [
            (self.steps.cfl, DtLimit::Cfl),
            (self.steps.viscous, DtLimit::Viscous),
            (self.steps.force, DtLimit::Force),
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
    /// Time reached (t_end unless the run failed or was stopped).
    pub t: f64,
    pub dt: DtStats,
    pub outcome: Outcome,
    /// Diagnostics at t = 0, every output time, and at a failure.
    pub samples: Vec<Sample>,
    /// The window the run is judged on (the later half of its time after
    /// the start-up, see [`crate::problem::horizon::Horizon::window`]).
    pub window: Window,
    /// The first output time with dy_rms >= 0.1 d (None: stayed ordered).
    pub t_disorder: Option<f64>,
    /// Largest fluid compaction over every step.
    pub max_eps_run: f64,
    pub neighbour_rebuilds: u64,
    /// Mean listed neighbours per particle (R h + skin).
    pub mean_neighbours: f64,
    /// Wall-clock seconds of the simulation.
    pub wall_s: f64,
}

impl RunResult {
    /// The compaction above which this run's window is over-compressed:
    /// the kernel's ordered-lattice pulsation eps0 (if positive) plus the
    /// margin, whatever the start ([`ClassRules::eps_bound`]).
    pub fn eps_bound(&self, rules: &ClassRules) -> f64 {
        rules.eps_bound(self.problem.discretisation)
    }

    /// The run's class under `rules`: `failed` when the run failed,
    /// `interrupted` when it was stopped before its end (no verdict), else
    /// by its window's mean-flow error and compaction, see [`classify`].
    pub fn class(&self, rules: &ClassRules) -> Class {
        match self.outcome {
            Outcome::Ok => classify(
                self.window.linf_stat,
                self.window.eps_stat,
                rules.linf_bound,
                self.eps_bound(rules),
            ),
            Outcome::Failed { .. } => Class::Failed,
            Outcome::Interrupted { .. } => Class::Interrupted,
        }
    }

    /// Fluid and wall particles.
    pub fn particles(&self) -> usize {
        self.n_fluid + self.n_wall
    }

    /// The largest L_inf error over the output times (NaN if any is).
    pub fn linf_rel_err_max(&self) -> f64 {
        self.samples
            .iter()
            .map(|s| s.linf_rel_err)
            .fold(0.0, crate::format::nan_max)
    }

    /// The last diagnostics sample.
    pub fn last(&self) -> &Sample {
        self.samples.last().expect("a run has its t = 0 sample")
    }
}

/// The outcome class of a run: one definition for `run`, the sweep and
/// the report.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Class {
    Ok,
    Inaccurate,
    OverCompressed,
    Failed,
    /// Stopped before t_end (a signal): no verdict. Never a stored row.
    Interrupted,
}

impl Class {
    /// The classes of a run that ended (every verdict; not `Interrupted`).
    pub const ALL: [Class; 4] = [
        Class::Ok,
        Class::Inaccurate,
        Class::OverCompressed,
        Class::Failed,
    ];
    pub fn name(self) -> &'static str {
        match self {
            Class::Ok => "ok",
            Class::Inaccurate => "inaccurate",
            Class::OverCompressed => "over-compressed",
            Class::Failed => "failed",
            Class::Interrupted => "interrupted",
        }
    }
    /// Parse a class name as written in rows.
    pub fn parse(s: &str) -> Option<Class> {
        Class::ALL
            .into_iter()
            .chain([Class::Interrupted])
            .find(|c| c.name() == s)
    }
}

impl fmt::Display for Class {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// The class of a run that did not fail: over-compressed before inaccurate
/// (a compacted lattice is the worse fault), NaN errors count as failed.
pub fn classify(linf_max: f64, max_eps: f64, linf_bound: f64, eps_bound: f64) -> Class {
    if !(linf_max.is_finite() && max_eps.is_finite()) {
        Class::Failed
    } else if max_eps > eps_bound {
        Class::OverCompressed
    } else if linf_max > linf_bound {
        Class::Inaccurate
    } else {
        Class::Ok
    }
}
