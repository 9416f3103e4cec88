//! One finished point of a sweep as a row: what was run, how it was
//! classified and what it cost, as `results.jsonl` and `results.csv` hold it.

use serde::{Deserialize, Serialize};

use super::{Class, ClassRules, Point};
use crate::problem::cost::DtLimit;
use crate::solver::{self, FailureKind, RunResult};

/// One finished point: what was run and what came of it. Non-finite numbers
/// are written as JSON `null` and read back as NaN.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Row {
    /// Position in the whole grid.
    pub index: usize,
    pub id: String,
    pub kernel: String,
    pub n: u32,
    #[serde(with = "nan_null")]
    pub re: f64,
    #[serde(with = "nan_null")]
    pub alpha: f64,
    /// The c0 as gridded: a rule (`derived`, `rule10`, `0.5*table2`), a
    /// number, or a multiple of U (`3U`).
    pub c0_spec: String,
    /// The rule it resolved to (`derived:field-av`, `rule10`, `table2`,
    /// `value`), with the model named.
    pub c0_rule: String,
    /// The sound speed (NaN when the rule gives none).
    #[serde(with = "nan_null")]
    pub c0: f64,
    #[serde(with = "nan_null")]
    pub c0_over_u: f64,
    pub class: Class,
    /// For `failed`: `no_c0` (the rule gives no positive c0), `scene` (the
    /// scene is invalid), `panic`, or the solver's failure kind
    /// (`not_finite`, `speed`, `through_wall`, `compaction`).
    pub failure_kind: Option<FailureKind>,
    pub failure_reason: Option<String>,
    /// L_inf and L2 errors of the layer-mean velocity / U at t_end, and the
    /// worst L_inf over the output times (what `inaccurate` is judged by).
    #[serde(with = "nan_null")]
    pub linf: f64,
    #[serde(with = "nan_null")]
    pub linf_max: f64,
    #[serde(with = "nan_null")]
    pub l2: f64,
    /// Largest fluid compaction over the run, and the bound for `over-compressed`.
    #[serde(with = "nan_null")]
    pub max_eps: f64,
    #[serde(with = "nan_null")]
    pub eps_bound: f64,
    /// RMS transverse velocity / U at the end.
    #[serde(with = "nan_null")]
    pub rms_v: f64,
    pub steps: u64,
    /// The time-step limit that bound the most steps (`cfl`, `viscous`,
    /// `force`; `dt_limit` in files written before it was named apart from
    /// summary.json's last-step `dt_limit`), and the last full step.
    #[serde(alias = "dt_limit")]
    pub dt_limit_dominant: Option<DtLimit>,
    #[serde(with = "nan_null")]
    pub dt: f64,
    /// Fluid and wall particles.
    pub particles: usize,
    /// particles x steps: the work, independent of the machine.
    pub particle_steps: f64,
    #[serde(with = "nan_null")]
    pub t_end: f64,
    /// Time reached.
    #[serde(with = "nan_null")]
    pub t: f64,
    /// Wall-clock seconds of the simulation.
    #[serde(with = "nan_null")]
    pub wall_s: f64,
}

/// f64 fields in JSON: non-finite values as `null`, `null` read as NaN.
mod nan_null {
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

impl Row {
    /// A row for a point that did not run (no c0, invalid scene, panic).
    pub(super) fn not_run(
        point: &Point,
        kind: FailureKind,
        reason: String,
        c0: f64,
        c0_rule: String,
    ) -> Row {
        Row {
            index: point.index,
            id: point.id(),
            kernel: point.kernel.clone(),
            n: point.n,
            re: point.re,
            alpha: point.alpha,
            c0_spec: point.c0.to_string(),
            c0_rule,
            c0,
            c0_over_u: f64::NAN,
            class: Class::Failed,
            failure_kind: Some(kind),
            failure_reason: Some(reason),
            linf: f64::NAN,
            linf_max: f64::NAN,
            l2: f64::NAN,
            max_eps: f64::NAN,
            eps_bound: f64::NAN,
            rms_v: f64::NAN,
            steps: 0,
            dt_limit_dominant: None,
            dt: f64::NAN,
            particles: 0,
            particle_steps: 0.0,
            t_end: f64::NAN,
            t: 0.0,
            wall_s: 0.0,
        }
    }

    /// The row of a finished run, classified by `rules`.
    pub fn from_run(point: &Point, r: &RunResult, rules: &ClassRules) -> Row {
        let (pr, last) = (&r.problem, r.last());
        let linf_max = r.linf_rel_err_max();
        let eps_bound = r.eps_bound(rules);
        let class = r.class(rules);
        let failure_kind = match &r.outcome {
            solver::Outcome::Failed { failure, .. } => Some(failure.kind()),
            solver::Outcome::Ok => None,
            // [`run_point`] keeps no row of a stopped run (it is rerun on
            // resume); a row made of one anyway does not pass for a result.
            solver::Outcome::Interrupted { .. } => Some(FailureKind::Interrupted),
        };
        let failure_reason = match class {
            Class::Failed => Some(
                match &r.outcome {
                    solver::Outcome::Failed { failure, t, .. } => {
                        Some(format!("{failure} (t = {t:.4})"))
                    }
                    _ => None,
                }
                .unwrap_or_else(|| "the velocity error is not finite".into()),
            ),
            _ => None,
        };
        let failure_kind = match (class, failure_kind) {
            (Class::Failed, None) => Some(FailureKind::NotFinite),
            (_, k) => k,
        };
        Row {
            index: point.index,
            id: point.id(),
            kernel: r.kernel.to_string(),
            n: pr.lattice.n_layers,
            re: point.re,
            alpha: pr.alpha,
            c0_spec: point.c0.to_string(),
            c0_rule: pr.c0_rule.clone(),
            c0: pr.c0,
            c0_over_u: pr.c0 / pr.flow.u,
            class,
            failure_kind,
            failure_reason,
            linf: last.linf_rel_err,
            linf_max,
            l2: last.l2_rel_err,
            max_eps: r.max_eps_run,
            eps_bound,
            rms_v: last.rms_v / pr.flow.u,
            steps: r.steps,
            dt_limit_dominant: Some(r.dt.dominant()),
            dt: r.dt.last,
            particles: r.particles(),
            particle_steps: r.particles() as f64 * r.steps as f64,
            t_end: pr.t_end,
            t: r.t,
            wall_s: r.wall_s,
        }
    }

    /// The row as JSON with the wall-clock time left out: what two runs of
    /// the same point agree on.
    pub fn without_timing(&self) -> serde_json::Value {
        let mut v = serde_json::to_value(self).expect("a row serialises");
        v.as_object_mut()
            .expect("a row is an object")
            .remove("wall_s");
        v
    }
}
