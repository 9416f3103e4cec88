//! A run's outputs in one folder: `summary.json`, `profile.csv`,
//! `timeseries.csv`, `scene.toml` (the scene as run), beside the charts
//! (`crate::charts::run`) and the particles (`crate::particles`). The write
//! path is [`atomic`]: a run's files are staged and swapped in as one set, so
//! a reader never sees half a file nor a new file beside an old one; an
//! existing non-empty folder is not touched without `force`.

use std::fmt::Write as _;

use anyhow::Result;
use serde::Serialize;

pub mod atomic;
pub use atomic::{prepare_dir, write_atomic, StagedSet};

use crate::solver::{Class, DtLimitSteps, Outcome, Particle, RunResult, Sample};

/// The figures of one run, as `summary.json` and `shearsph run --json`.
#[derive(Debug, Clone, Serialize)]
pub struct Summary {
    pub kernel: String,
    pub n_layers: u32,
    /// All particles, fluid and wall.
    pub particles: usize,
    pub fluid_particles: usize,
    pub wall_particles: usize,
    pub d: f64,
    pub h: f64,
    /// Half-width B = N dy.
    pub b: f64,
    pub u: f64,
    pub re: f64,
    pub nu: f64,
    pub p: f64,
    pub alpha: f64,
    pub initial: crate::config::Initial,
    pub t_end: f64,
    /// Time reached (below t_end when the run failed or was interrupted).
    pub t: f64,
    pub steps: u64,
    /// The last full step's dt and the limit that bound it (the limit that
    /// bound the most steps is results.csv's `dt_limit_dominant`).
    pub dt: f64,
    pub dt_limit: crate::problem::cost::DtLimit,
    pub dt_min: f64,
    pub dt_max: f64,
    /// Steps bound by each limit.
    pub dt_limit_steps: DtLimitSteps,
    pub c0: f64,
    pub c0_rule: String,
    pub wall_s: f64,
    /// Particles (fluid and wall) times steps per wall-clock second.
    pub particle_steps_per_s: f64,
    /// Errors of the layer-mean velocity relative to U at the end, against
    /// the start-up series (from rest) or (7) (from the steady profile).
    pub linf_rel_err: f64,
    pub l2_rel_err: f64,
    /// Largest L_inf error over the output times.
    pub linf_rel_err_max: f64,
    /// Largest fluid compaction over every step of the run.
    pub max_eps: f64,
    /// Mean fluid compaction at the end.
    pub mean_eps: f64,
    /// RMS transverse velocity of the fluid at the end.
    pub rms_v: f64,
    pub kinetic_energy: f64,
    pub neighbour_rebuilds: u64,
    /// Mean neighbour-list length (R h + skin) per particle, at the start.
    pub mean_neighbours: f64,
    /// `ok`, `failed` or `interrupted` (stopped early, e.g. by Ctrl-C; `t`
    /// and `steps` say where).
    pub outcome: &'static str,
    /// The class the sweep gives the same run: `ok`, `inaccurate`,
    /// `over-compressed` or `failed`, by the scene's bounds below.
    pub class: Class,
    /// Inaccurate above this L_inf error (relative to U) over the outputs.
    pub linf_bound: f64,
    /// Over-compressed above this compaction (the kernel's eps0 plus the
    /// scene's eps_margin).
    pub eps_bound: f64,
    pub failure_reason: Option<String>,
    pub failure_t: Option<f64>,
    pub failure_step: Option<u64>,
    /// The fluid particle that triggered the failure.
    pub failure_particle: Option<Particle>,
}

impl Summary {
    pub fn new(r: &RunResult) -> Summary {
        let pr = &r.problem;
        let last = r.last();
        let (failure_reason, failure_t, failure_step, failure_particle) = match &r.outcome {
            Outcome::Ok | Outcome::Interrupted { .. } => (None, None, None, None),
            Outcome::Failed {
                failure,
                t,
                step,
                particle,
            } => (
                Some(failure.to_string()),
                Some(*t),
                Some(*step),
                Some(*particle),
            ),
        };
        let particles = r.particles();
        let rules = pr.scene.classes();
        Summary {
            kernel: r.kernel.to_string(),
            n_layers: pr.lattice.n_layers,
            particles,
            fluid_particles: r.n_fluid,
            wall_particles: r.n_wall,
            d: pr.lattice.d,
            h: pr.lattice.h,
            b: pr.flow.b,
            u: pr.flow.u,
            re: pr.re,
            nu: pr.flow.nu,
            p: pr.flow.p,
            alpha: pr.alpha,
            initial: pr.initial,
            t_end: pr.t_end,
            t: r.t,
            steps: r.steps,
            dt: r.dt.last,
            dt_limit: r.dt.last_limit,
            dt_min: r.dt.min.min(r.dt.last),
            dt_max: r.dt.max.max(r.dt.last),
            dt_limit_steps: r.dt.steps,
            c0: pr.c0,
            c0_rule: pr.c0_rule.clone(),
            wall_s: r.wall_s,
            particle_steps_per_s: particles as f64 * r.steps as f64 / r.wall_s.max(1e-9),
            linf_rel_err: last.linf_rel_err,
            l2_rel_err: last.l2_rel_err,
            linf_rel_err_max: r.linf_rel_err_max(),
            max_eps: r.max_eps_run,
            mean_eps: last.mean_eps,
            rms_v: last.rms_v,
            kinetic_energy: last.kinetic_energy,
            neighbour_rebuilds: r.neighbour_rebuilds,
            mean_neighbours: r.mean_neighbours,
            outcome: r.outcome.status(),
            class: r.class(&rules),
            linf_bound: rules.linf_bound,
            eps_bound: r.eps_bound(&rules),
            failure_reason,
            failure_t,
            failure_step,
            failure_particle,
        }
    }

    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).expect("a summary serialises")
    }
}

/// Stage the run's text outputs in `set` (see [`StagedSet`]): the summary,
/// the scene as run, the profile and the time series. Its charts are
/// [`crate::charts::run::stage_charts`], its particles
/// [`crate::particles::series`].
pub fn write_outputs(set: &StagedSet, result: &RunResult) -> Result<()> {
    set.put("summary.json", Summary::new(result).to_json().as_bytes())?;
    set.put("scene.toml", result.problem.scene.to_toml().as_bytes())?;
    set.put("profile.csv", profile_csv(result.last()).as_bytes())?;
    set.put("timeseries.csv", timeseries_csv(&result.samples).as_bytes())
}

/// The layer profile of one sample.
pub fn profile_csv(s: &Sample) -> String {
    let mut out = String::from("layer,y,u,u_analytic,u_steady,v_rms\n");
    for l in &s.profile {
        let _ = writeln!(
            out,
            "{},{},{},{},{},{}",
            l.layer, l.y, l.u, l.u_analytic, l.u_steady, l.v_rms
        );
    }
    out
}

pub fn timeseries_csv(samples: &[Sample]) -> String {
    let mut out =
        String::from("t,step,dt,linf_rel_err,l2_rel_err,max_eps,mean_eps,rms_v,kinetic_energy\n");
    for s in samples {
        let _ = writeln!(
            out,
            "{},{},{},{},{},{},{},{},{}",
            s.t,
            s.step,
            s.dt,
            s.linf_rel_err,
            s.l2_rel_err,
            s.max_eps,
            s.mean_eps,
            s.rms_v,
            s.kinetic_energy
        );
    }
    out
}
