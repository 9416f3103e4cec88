//! A run's outputs in one folder: `summary.json`, `profile.csv`,
//! `timeseries.csv`, `scene.toml` (the scene as run), beside the charts
//! (`crate::charts::run`) and the particles (`crate::particles`). The write
//! path is [`atomic`]: a run's files are staged and swapped in as one set, so
//! a reader never sees half a file nor a new file beside an old one; an
//! existing non-empty folder is not touched without `force`.

use std::fmt::Write as _;

use anyhow::Result;
use serde::{Deserialize, Serialize};

pub mod atomic;
pub use atomic::{prepare_dir, write_atomic, StagedSet};

use crate::problem::cost::DtLimit;
use crate::solver::{Class, DtLimitSteps, FailureKind, Outcome, Particle, RunResult, Sample};

/// The figures of one run, as `summary.json` and `shearsph run --json`, and
/// the part of a sweep's row that is not the point's key (a row is its point
/// plus this, flattened): one result type from the solver to the report.
/// Read back with every field optional (a row written before a field existed
/// gets the default written beside the field: NaN, 0 or none; the same
/// defaults are `Summary::default()`); non-finite numbers are written as JSON
/// `null` and read back as NaN. The JSON names are summary.json's; the names
/// rows had before they were summaries (`n`, `linf`, `l2`, `linf_max`) are
/// read as aliases.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Summary {
    #[serde(default)]
    pub kernel: String,
    #[serde(rename = "n_layers", alias = "n", default)]
    pub n: u32,
    /// All particles, fluid and wall.
    #[serde(default)]
    pub particles: usize,
    #[serde(default)]
    pub fluid_particles: usize,
    #[serde(default)]
    pub wall_particles: usize,
    #[serde(with = "nan_null", default = "nan")]
    pub d: f64,
    #[serde(with = "nan_null", default = "nan")]
    pub h: f64,
    /// Half-width B = N dy.
    #[serde(with = "nan_null", default = "nan")]
    pub b: f64,
    #[serde(with = "nan_null", default = "nan")]
    pub u: f64,
    /// The Reynolds number the scene gave (U B / nu when it gave p).
    #[serde(with = "nan_null", default = "nan")]
    pub re: f64,
    #[serde(with = "nan_null", default = "nan")]
    pub nu: f64,
    #[serde(with = "nan_null", default = "nan")]
    pub p: f64,
    #[serde(with = "nan_null", default = "nan")]
    pub alpha: f64,
    #[serde(default)]
    pub initial: crate::config::Initial,
    #[serde(with = "nan_null", default = "nan")]
    pub t_end: f64,
    /// Time reached (below t_end when the run failed or was interrupted).
    #[serde(with = "nan_null", default)]
    pub t: f64,
    #[serde(default)]
    pub steps: u64,
    /// The last full step's dt and the limit that bound it (the limit that
    /// bound the most steps is `dt_limit_dominant`).
    #[serde(with = "nan_null", default = "nan")]
    pub dt: f64,
    pub dt_limit: Option<DtLimit>,
    #[serde(with = "nan_null", default = "nan")]
    pub dt_min: f64,
    #[serde(with = "nan_null", default = "nan")]
    pub dt_max: f64,
    /// Steps bound by each limit.
    #[serde(default)]
    pub dt_limit_steps: DtLimitSteps,
    /// The limit that bound the most steps (`dt_limit` in rows written
    /// before the two were told apart).
    pub dt_limit_dominant: Option<DtLimit>,
    /// The time step's factors in use, the scene's or by default the
    /// kernel's own (docs/timestep.md): dt <= cfl h / (c0 + |v|max),
    /// viscous_dt h^2 / nu.
    #[serde(with = "nan_null", default = "nan")]
    pub cfl: f64,
    #[serde(with = "nan_null", default = "nan")]
    pub viscous_dt: f64,
    /// The sound speed (NaN when the rule gives none), its rule as resolved
    /// (`derived:field-av`, `rule10`, `value`) and c0 / U.
    #[serde(with = "nan_null", default = "nan")]
    pub c0: f64,
    #[serde(default)]
    pub c0_rule: String,
    #[serde(with = "nan_null", default = "nan")]
    pub c0_over_u: f64,
    #[serde(with = "nan_null", default)]
    pub wall_s: f64,
    /// Particles (fluid and wall) times steps per wall-clock second.
    #[serde(with = "nan_null", default)]
    pub particle_steps_per_s: f64,
    /// particles x steps: the work, independent of the machine.
    #[serde(default)]
    pub particle_steps: f64,
    /// Errors of the layer-mean velocity relative to U at the end, against
    /// the start-up series (from rest) or (7) (from the steady profile).
    #[serde(
        rename = "linf_rel_err",
        alias = "linf",
        with = "nan_null",
        default = "nan"
    )]
    pub linf: f64,
    #[serde(
        rename = "l2_rel_err",
        alias = "l2",
        with = "nan_null",
        default = "nan"
    )]
    pub l2: f64,
    /// Largest L_inf error over the output times (a diagnostic: the class
    /// judges the window's `linf_stat`).
    #[serde(
        rename = "linf_rel_err_max",
        alias = "linf_max",
        with = "nan_null",
        default = "nan"
    )]
    pub linf_max: f64,
    /// Largest fluid compaction over every step of the run (a diagnostic:
    /// the class judges the window's `eps_stat`).
    #[serde(with = "nan_null", default = "nan")]
    pub max_eps: f64,
    /// The horizon (`fixed` or `stationary`), the window the run is judged
    /// on (`window_from` < t <= `window_to`, `window_frames` frames) and
    /// whether it passed the stationarity test (`unsteady`: why not).
    #[serde(default)]
    pub horizon: crate::problem::horizon::HorizonKind,
    #[serde(with = "nan_null", default = "nan")]
    pub window_from: f64,
    #[serde(with = "nan_null", default = "nan")]
    pub window_to: f64,
    #[serde(default)]
    pub window_frames: usize,
    #[serde(default)]
    pub stationary: bool,
    pub unsteady: Option<String>,
    /// `ordered` or `disordered` (dy_rms at the window's end >= 0.1 d).
    #[serde(default)]
    pub regime: crate::solver::Regime,
    /// The window's compaction: mean of the per-frame 99th percentile of
    /// eps (judged), mean of the per-frame largest, the largest.
    #[serde(with = "nan_null", default = "nan")]
    pub eps_stat: f64,
    #[serde(with = "nan_null", default = "nan")]
    pub eps_max_mean: f64,
    #[serde(with = "nan_null", default = "nan")]
    pub eps_max_window: f64,
    /// The window's mean-flow error relative to U (judged), its RMS over
    /// the bands, and the per-frame L_inf's mean.
    #[serde(with = "nan_null", default = "nan")]
    pub linf_stat: f64,
    #[serde(with = "nan_null", default = "nan")]
    pub l2_stat: f64,
    #[serde(with = "nan_null", default = "nan")]
    pub linf_frame_mean: f64,
    /// The window's mean RMS transverse velocity, and dy_rms (in d) at its
    /// end.
    #[serde(with = "nan_null", default = "nan")]
    pub rms_v_stat: f64,
    #[serde(with = "nan_null", default = "nan")]
    pub dy_rms: f64,
    /// The first output time with dy_rms >= 0.1 d (none: stayed ordered).
    pub t_disorder: Option<f64>,
    /// Mean fluid compaction at the end.
    #[serde(with = "nan_null", default = "nan")]
    pub mean_eps: f64,
    /// RMS transverse velocity of the fluid at the end.
    #[serde(with = "nan_null", default = "nan")]
    pub rms_v: f64,
    #[serde(with = "nan_null", default = "nan")]
    pub kinetic_energy: f64,
    #[serde(default)]
    pub neighbour_rebuilds: u64,
    /// Mean neighbour-list length (R h + skin) per particle, at the start.
    #[serde(with = "nan_null", default = "nan")]
    pub mean_neighbours: f64,
    /// `ok`, `failed` or `interrupted` (stopped early, e.g. by Ctrl-C; `t`
    /// and `steps` say where); `not_run` for a sweep's point that did not
    /// reach the solver.
    #[serde(default = "not_run")]
    pub outcome: String,
    /// `ok`, `inaccurate`, `over-compressed` or `failed`, by the scene's
    /// bounds below: one class for `run`, the sweep and the report;
    /// `interrupted` for a run stopped before t_end (no verdict).
    #[serde(default = "failed")]
    pub class: Class,
    /// Inaccurate above this L_inf error (relative to U) over the outputs.
    #[serde(with = "nan_null", default = "nan")]
    pub linf_bound: f64,
    /// Over-compressed above this window compaction (the kernel's eps0, if
    /// positive, plus the scene's eps_margin).
    #[serde(with = "nan_null", default = "nan")]
    pub eps_bound: f64,
    /// For `failed`: `no_c0` (the rule gives no positive c0), `scene` (the
    /// scene is invalid), `panic`, `interrupted`, or the solver's failure
    /// (`not_finite`, `speed`, `through_wall`, `compaction`).
    pub failure_kind: Option<FailureKind>,
    pub failure_reason: Option<String>,
    pub failure_t: Option<f64>,
    pub failure_step: Option<u64>,
    /// The fluid particle that triggered the failure.
    pub failure_particle: Option<Particle>,
}

impl Default for Summary {
    /// Nothing run: every field's serde default (NaN numbers, no counts,
    /// class `failed`, outcome `not_run`), so that a field's default is
    /// written once, beside the field.
    fn default() -> Summary {
        serde_json::from_value(serde_json::Value::Object(Default::default()))
            .expect("every field of Summary has a serde default")
    }
}

fn nan() -> f64 {
    f64::NAN
}

fn not_run() -> String {
    "not_run".into()
}

fn failed() -> Class {
    Class::Failed
}

/// f64 fields in JSON: non-finite values as `null`, `null` read as NaN.
pub mod nan_null {
    use serde::{Deserialize, Deserializer, Serializer};
    pub fn serialize<S: Serializer>(v: &f64, s: S) -> Result<S::Ok, S::Error> {
        if v.is_finite() {
            s.serialize_f64(*v)
        } else {
            s.serialize_none()
        }
    }
    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
        Ok(Option::<f64>::deserialize(d)?.unwrap_or(f64::NAN))
    }
}

impl Summary {
    pub fn new(r: &RunResult) -> Summary {
        let pr = &r.problem;
        let last = r.last();
        let w = &r.window;
        let rules = pr.scene.classes();
        let class = r.class(&rules);
        let (failure_kind, failure_reason, failure_t, failure_step, failure_particle) =
            match &r.outcome {
                Outcome::Failed {
                    failure,
                    t,
                    step,
                    particle,
                } => (
                    Some(failure.kind()),
                    Some(failure.to_string()),
                    Some(*t),
                    Some(*step),
                    Some(*particle),
                ),
                Outcome::Interrupted { .. } => (
                    Some(FailureKind::Interrupted),
                    Some("stopped before the end".to_string()),
                    None,
                    None,
                    None,
                ),
                // failed by its numbers: an error or a compaction not finite
                Outcome::Ok if class == Class::Failed => (
                    Some(FailureKind::NotFinite),
                    Some("the velocity error is not finite".to_string()),
                    None,
                    None,
                    None,
                ),
                Outcome::Ok => (None, None, None, None, None),
            };
        let particles = r.particles();
        Summary {
            kernel: r.kernel.to_string(),
            n: pr.lattice.n_layers,
            particles,
            fluid_particles: r.n_fluid,
            wall_particles: r.n_wall,
            d: pr.lattice.d,
            h: pr.lattice.h,
            b: pr.flow.b,
            u: pr.flow.u,
            re: pr.scene.re.unwrap_or(pr.re),
            nu: pr.flow.nu,
            p: pr.flow.p,
            alpha: pr.alpha,
            initial: pr.initial,
            t_end: pr.t_end,
            t: r.t,
            steps: r.steps,
            dt: r.dt.last,
            dt_limit: Some(r.dt.last_limit),
            dt_min: r.dt.min.min(r.dt.last),
            dt_max: r.dt.max.max(r.dt.last),
            dt_limit_steps: r.dt.steps,
            dt_limit_dominant: Some(r.dt.dominant()),
            cfl: pr.dt_factors.cfl,
            viscous_dt: pr.dt_factors.viscous,
            c0: pr.c0,
            c0_rule: pr.c0_rule.clone(),
            c0_over_u: pr.c0 / pr.flow.u,
            wall_s: r.wall_s,
            particle_steps_per_s: particles as f64 * r.steps as f64 / r.wall_s.max(1e-9),
            particle_steps: particles as f64 * r.steps as f64,
            linf: last.linf_rel_err,
            l2: last.l2_rel_err,
            linf_max: r.linf_rel_err_max(),
            max_eps: r.max_eps_run,
            horizon: pr.horizon.kind,
            window_from: w.from,
            window_to: w.to,
            window_frames: w.frames,
            stationary: w.stationary,
            unsteady: w.unsteady.clone(),
            regime: w.regime,
            eps_stat: w.eps_stat,
            eps_max_mean: w.eps_max_mean,
            eps_max_window: w.eps_max,
            linf_stat: w.linf_stat,
            l2_stat: w.l2_stat,
            linf_frame_mean: w.linf_frame_mean,
            rms_v_stat: w.rms_v_stat,
            dy_rms: w.dy_rms,
            t_disorder: r.t_disorder,
            mean_eps: last.mean_eps,
            rms_v: last.rms_v,
            kinetic_energy: last.kinetic_energy,
            neighbour_rebuilds: r.neighbour_rebuilds,
            mean_neighbours: r.mean_neighbours,
            outcome: r.outcome.status().to_string(),
            class,
            linf_bound: rules.linf_bound,
            eps_bound: r.eps_bound(&rules),
            failure_kind,
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
    set.put(
        "window_profile.csv",
        window_profile_csv(&result.window).as_bytes(),
    )?;
    set.put("timeseries.csv", timeseries_csv(&result.samples).as_bytes())
}

/// The layer profile of one sample.
pub fn profile_csv(s: &Sample) -> String {
    let mut out = String::from("layer,y,u,u_analytic,u_steady,v_rms,count\n");
    for l in &s.profile {
        let _ = writeln!(
            out,
            "{},{},{},{},{},{},{}",
            l.layer, l.y, l.u, l.u_analytic, l.u_steady, l.v_rms, l.count
        );
    }
    out
}

/// The window's mean flow, band by band, against the steady profile (7)
/// at each band's mean y.
pub fn window_profile_csv(w: &crate::solver::Window) -> String {
    let mut out = String::from("layer,y,u_mean,err_mean\n");
    for b in &w.profile {
        let _ = writeln!(out, "{},{},{},{}", b.layer, b.y, b.u, b.err);
    }
    out
}

pub fn timeseries_csv(samples: &[Sample]) -> String {
    let mut out = String::from(
        "t,step,dt,linf_rel_err,l2_rel_err,max_eps,mean_eps,rms_v,kinetic_energy,eps_p99,dy_rms\n",
    );
    for s in samples {
        let _ = writeln!(
            out,
            "{},{},{},{},{},{},{},{},{},{},{}",
            s.t,
            s.step,
            s.dt,
            s.linf_rel_err,
            s.l2_rel_err,
            s.max_eps,
            s.mean_eps,
            s.rms_v,
            s.kinetic_energy,
            s.eps_p99,
            s.dy_rms
        );
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The defaults beside the fields are what a point that did not run
    /// writes: NaN (`null`) numbers but the times and speeds (0), no counts,
    /// outcome `not_run`, class `failed`.
    #[test]
    fn the_default_summary_is_nothing_run() {
        let s = Summary::default();
        assert_eq!(s.outcome, "not_run");
        assert_eq!(s.class, Class::Failed);
        assert!(s.d.is_nan() && s.c0.is_nan() && s.eps_bound.is_nan());
        assert_eq!((s.t, s.wall_s, s.particle_steps_per_s), (0.0, 0.0, 0.0));
        assert_eq!((s.n, s.steps, s.particles), (0, 0, 0));
        assert!(s.failure_kind.is_none() && s.dt_limit.is_none());
        let json: serde_json::Value = serde_json::from_str(&s.to_json()).unwrap();
        assert_eq!(json["linf_rel_err"], serde_json::Value::Null);
        assert_eq!(json["particle_steps"], 0.0);
    }
}
