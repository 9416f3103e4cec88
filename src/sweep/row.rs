//! One finished point of a sweep as a row: what was run, how it was
//! classified and what it cost, as `results.jsonl` and `results.csv` hold it.

use serde::{Deserialize, Serialize};

use super::axes::{At, HOverD, Start};
use super::{Class, ClassRules, Point};
use crate::kernel::Lattice;
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
    /// The discretisation (rows written before it was an axis: the paper's).
    #[serde(default)]
    pub lattice: Lattice,
    #[serde(default = "h_one")]
    pub h_over_d: HOverD,
    /// The start: jitter amplitude in d (0: the perfect lattice) and seed
    /// (0 for the perfect lattice, else 1..=seeds).
    #[serde(default)]
    pub jitter: f64,
    #[serde(default)]
    pub seed: u32,
    /// The point's position on the grid's axes: the key to join rows by.
    /// Not stored: given by the run, or on reading by the point of the
    /// grid with this row's id.
    #[serde(skip)]
    pub at: At,
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

fn h_one() -> HOverD {
    HOverD::ONE
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
            lattice: point.disc.lattice,
            h_over_d: point.disc.h_over_d,
            jitter: point.start.jitter().0,
            seed: point.start.jitter().1,
            at: point.at,
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
            lattice: point.disc.lattice,
            h_over_d: point.disc.h_over_d,
            jitter: point.start.jitter().0,
            seed: point.start.jitter().1,
            at: point.at,
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

    /// The row's start.
    pub fn start(&self) -> Start {
        if self.jitter == 0.0 {
            Start::Perfect
        } else {
            Start::Jittered {
                amplitude: self.jitter,
                seed: self.seed,
            }
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

/// A point's outcome over its starts' seeds (rows that share
/// [`At::without_seed`]): the perfect start is a group of one.
#[derive(Debug, Clone)]
pub struct OverSeeds<'a> {
    /// The rows' common position, with seed 0.
    pub at: At,
    /// The worst class over the seeds: failed > over-compressed >
    /// inaccurate > ok.
    pub class: Class,
    /// The row that had it: its failure kind and reason, its errors. Among
    /// seeds of the same class, the one with the larger worst L_inf error
    /// (NaN the largest), then the lower seed.
    pub worst: &'a Row,
    /// Every seed's row, in the order given.
    pub rows: Vec<&'a Row>,
}

/// Fold `rows` over seeds: one [`OverSeeds`] per point without its seed,
/// in the order of each group's first row.
pub fn worst_over_seeds(rows: &[Row]) -> Vec<OverSeeds<'_>> {
    fn worse(a: &Row, b: &Row) -> bool {
        let err = |r: &Row| {
            if r.linf_max.is_nan() {
                f64::INFINITY
            } else {
                r.linf_max
            }
        };
        (a.class, err(a), std::cmp::Reverse(a.seed)) > (b.class, err(b), std::cmp::Reverse(b.seed))
    }
    let mut out: Vec<OverSeeds> = Vec::new();
    let mut group: std::collections::HashMap<At, usize> = std::collections::HashMap::new();
    for r in rows {
        let at = r.at.without_seed();
        match group.get(&at) {
            Some(&i) => {
                let g = &mut out[i];
                g.rows.push(r);
                if worse(r, g.worst) {
                    g.worst = r;
                    g.class = r.class;
                }
            }
            None => {
                group.insert(at, out.len());
                out.push(OverSeeds {
                    at,
                    class: r.class,
                    worst: r,
                    rows: vec![r],
                });
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sweep::{Discretisation, PointC0};

    #[test]
    fn a_perturbed_point_is_its_worst_seed() {
        let row = |seed: u32, class: Class, linf_max: f64, reason: &str| {
            let mut p = Point::paper(0, "monaghan", 10, 1.0, 0.1, PointC0::OverU(1.0));
            p.disc = Discretisation::PAPER;
            if seed > 0 {
                p.start = Start::Jittered {
                    amplitude: 0.05,
                    seed,
                };
                p.at.jitter = 1;
                p.at.seed = seed;
            }
            let mut r = Row::not_run(&p, FailureKind::Scene, reason.into(), 1.0, "value".into());
            r.class = class;
            r.linf_max = linf_max;
            r
        };
        let rows = vec![
            row(0, Class::Ok, 0.01, "perfect"),
            row(1, Class::Inaccurate, 0.07, "one"),
            row(2, Class::OverCompressed, 0.02, "two"),
            row(3, Class::Inaccurate, 0.09, "three"),
            row(4, Class::OverCompressed, 0.03, "four"),
        ];
        let folded = worst_over_seeds(&rows);
        assert_eq!(folded.len(), 2);
        assert_eq!((folded[0].class, folded[0].rows.len()), (Class::Ok, 1));
        let p = &folded[1];
        assert_eq!(
            (p.class, p.rows.len(), p.at.seed),
            (Class::OverCompressed, 4, 0)
        );
        assert_eq!(
            p.worst.failure_reason.as_deref(),
            Some("four"),
            "ties: the larger error"
        );
        // failed beats every other class, whatever the errors
        let mut rows = rows;
        rows.push(row(5, Class::Failed, f64::NAN, "five"));
        rows[1].linf_max = 10.0;
        let folded = worst_over_seeds(&rows);
        assert_eq!(folded[1].class, Class::Failed);
        assert_eq!(folded[1].worst.failure_reason.as_deref(), Some("five"));
        // inaccurate only over ok
        let folded = worst_over_seeds(&rows[..2]);
        assert_eq!(
            folded.iter().map(|g| g.class).collect::<Vec<_>>(),
            [Class::Ok, Class::Inaccurate]
        );
    }
}
