//! One finished point of a sweep as a row: the point's key (its id, grid
//! position, discretisation, start and c0 as gridded) and the run's
//! [`Summary`], the same figures `summary.json` holds, flattened into one
//! JSON object per line of `results.jsonl` (and a column each in
//! `results.csv`).

use std::ops::{Deref, DerefMut};

use serde::{Deserialize, Serialize};

use super::axes::{GridPosition, HOverD, Start};
use super::{Class, Point};
use crate::kernel::Lattice;
use crate::output::{nan_null, Summary};
use crate::solver::{FailureKind, RunResult};

/// One finished point: what was run (the key) and what came of it (the
/// run's summary, classified by the scene's bounds, which the sweep's
/// `[classes]` set). The summary's fields read through the row
/// (`row.class`, `row.linf_max`).
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Row {
    /// Position in the whole grid.
    pub index: usize,
    pub id: String,
    /// The discretisation (rows written before it was an axis: the paper's).
    #[serde(default)]
    pub lattice: Lattice,
    #[serde(default = "h_one")]
    pub h_over_d: HOverD,
    /// The start: jitter amplitude in d (0: the perfect lattice) and seed
    /// (0 for the perfect lattice, else 1..=seeds).
    #[serde(default, with = "nan_null")]
    pub jitter: f64,
    #[serde(default)]
    pub seed: u32,
    /// The c0 as gridded: a rule (`derived`, `rule10`, `0.5*table2`), a
    /// number, or a multiple of U (`3U`).
    pub c0_spec: String,
    /// The point's position on the grid's axes: the key to join rows by.
    /// Not stored: given by the run, or on reading by the point of the
    /// grid with this row's id ([`super::store::on_grid`]).
    #[serde(skip)]
    pub at: GridPosition,
    /// What the run gave; for a point that did not reach the solver, its
    /// kernel, N, Re, alpha, c0 if any, and why (`failure_kind`,
    /// `failure_reason`), the rest NaN or 0.
    #[serde(flatten)]
    pub summary: Summary,
}

impl Deref for Row {
    type Target = Summary;
    fn deref(&self) -> &Summary {
        &self.summary
    }
}

impl DerefMut for Row {
    fn deref_mut(&mut self) -> &mut Summary {
        &mut self.summary
    }
}

fn h_one() -> HOverD {
    HOverD::ONE
}

impl Row {
    fn keyed(point: &Point, summary: Summary) -> Row {
        let (jitter, seed) = point.start.jitter();
        Row {
            index: point.index,
            id: point.id(),
            lattice: point.disc.lattice,
            h_over_d: point.disc.h_over_d,
            jitter,
            seed,
            c0_spec: point.c0.to_string(),
            at: point.at,
            summary,
        }
    }

    /// A row for a point that did not run (no c0, invalid scene, panic).
    pub(super) fn not_run(
        point: &Point,
        kind: FailureKind,
        reason: String,
        c0: f64,
        c0_rule: String,
    ) -> Row {
        Row::keyed(
            point,
            Summary {
                kernel: point.kernel.clone(),
                n: point.n,
                re: point.re,
                alpha: point.alpha,
                c0,
                c0_rule,
                class: Class::Failed,
                failure_kind: Some(kind),
                failure_reason: Some(reason),
                ..Summary::default()
            },
        )
    }

    /// The row of a finished run: its summary, classified by its scene's
    /// bounds (as `run` classifies it).
    pub fn from_run(point: &Point, r: &RunResult) -> Row {
        Row::keyed(point, Summary::new(r))
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

    /// The fields of a row that are wall-clock measurements (they differ
    /// between any two runs of one point; `bench/slurm/run_array.sh` leaves
    /// the same ones out of its comparison).
    pub const TIMING_FIELDS: &'static [&'static str] = &["wall_s", "particle_steps_per_s"];

    /// The row as JSON with the wall-clock figures ([`Row::TIMING_FIELDS`])
    /// left out: what two runs of the same point agree on.
    pub fn without_timing(&self) -> serde_json::Value {
        let mut v = serde_json::to_value(self).expect("a row serialises");
        let o = v.as_object_mut().expect("a row is an object");
        for f in Row::TIMING_FIELDS {
            o.remove(*f);
        }
        v
    }

    /// A row from one line of `results.jsonl`, in this format or in the
    /// one rows had before they were summaries (see [`migrate_flat_row`]).
    pub fn from_json(line: &str) -> serde_json::Result<Row> {
        let mut v: serde_json::Value = serde_json::from_str(line)?;
        if let Some(o) = v.as_object_mut() {
            if !o.contains_key("outcome") {
                migrate_flat_row(o);
            }
        }
        serde_json::from_value(v)
    }
}

/// A row as written before rows were summaries (no `outcome`): `n`, `linf`,
/// `l2` and `linf_max` are read as aliases; what changed meaning is
/// translated here. `rms_v` was relative to U (now the summary's own), with
/// U = c0 / c0_over_u, the row's own figures; `dt_limit` (in the oldest rows)
/// was the dominant limit; the outcome follows from the failure kind.
fn migrate_flat_row(o: &mut serde_json::Map<String, serde_json::Value>) {
    use serde_json::Value;
    let num = |o: &serde_json::Map<String, Value>, k: &str| o.get(k).and_then(Value::as_f64);
    let u = match (num(o, "c0"), num(o, "c0_over_u")) {
        (Some(c0), Some(x)) if c0 / x > 0.0 && (c0 / x).is_finite() => Some(c0 / x),
        _ => None,
    };
    if let Some(u) = u {
        o.insert("u".into(), Value::from(u));
        if let Some(rms) = num(o, "rms_v") {
            o.insert("rms_v".into(), Value::from(rms * u));
        }
    } else {
        o.insert("rms_v".into(), Value::Null);
    }
    if let Some(limit) = o.remove("dt_limit") {
        o.entry("dt_limit_dominant").or_insert(limit);
    }
    let kind = o.get("failure_kind").and_then(Value::as_str);
    let outcome = match kind {
        None => "ok",
        Some("no_c0" | "scene" | "panic") => "not_run",
        Some("interrupted") => "interrupted",
        Some(_) => "failed",
    };
    o.insert("outcome".into(), Value::from(outcome));
}

/// A point's outcome over its starts' seeds (rows that share
/// [`GridPosition::without_seed`]): the perfect start is a group of one.
#[derive(Debug, Clone)]
pub struct OverSeeds<'a> {
    /// The rows' common position, with seed 0.
    pub at: GridPosition,
    /// The seeds pooled as `empirical::trial::pool` pools them
    /// (docs/stationary.md): failed when any seed failed (that seed's row,
    /// its failure kind and reason); else the first seed's row with the
    /// means over the seeds of `eps_stat` and `linf_stat`, classified by the
    /// rows' own bounds, and `stationary` only if every seed was.
    pub pooled: Row,
    /// Every seed's row, in the order given.
    pub rows: Vec<&'a Row>,
}

impl OverSeeds<'_> {
    pub fn class(&self) -> Class {
        self.pooled.class
    }
}

/// The pooled row of one point's seeds (see [`OverSeeds::pooled`]).
pub fn pool_rows(rows: &[&Row]) -> Row {
    if let Some(failed) = rows.iter().find(|r| r.class == Class::Failed) {
        return (*failed).clone();
    }
    let first = rows.first().expect("a point has a row");
    let n = rows.len() as f64;
    let mean = |f: &dyn Fn(&Row) -> f64| rows.iter().map(|r| f(r)).sum::<f64>() / n;
    let mut r = (*first).clone();
    r.eps_stat = mean(&|r| r.eps_stat);
    r.linf_stat = mean(&|r| r.linf_stat);
    r.stationary = rows.iter().all(|r| r.stationary);
    r.class = super::classify(r.linf_stat, r.eps_stat, r.linf_bound, r.eps_bound);
    r
}

/// Fold `rows` over seeds: one [`OverSeeds`] per point without its seed,
/// in the order of each group's first row.
pub fn pool_over_seeds(rows: &[Row]) -> Vec<OverSeeds<'_>> {
    let mut groups: Vec<(GridPosition, Vec<&Row>)> = Vec::new();
    let mut index: std::collections::HashMap<GridPosition, usize> =
        std::collections::HashMap::new();
    for r in rows {
        let at = r.at.without_seed();
        match index.get(&at) {
            Some(&i) => groups[i].1.push(r),
            None => {
                index.insert(at, groups.len());
                groups.push((at, vec![r]));
            }
        }
    }
    groups
        .into_iter()
        .map(|(at, rows)| OverSeeds {
            at,
            pooled: pool_rows(&rows),
            rows,
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sweep::{Discretisation, PointC0};

    #[test]
    fn a_perturbed_point_pools_its_seeds() {
        let row = |seed: u32, class: Class, eps: f64, linf: f64, reason: &str| {
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
            r.eps_stat = eps;
            r.linf_stat = linf;
            r.eps_bound = 0.012;
            r.linf_bound = 0.05;
            r.stationary = true;
            r
        };
        // Two seeds over-compressed and two ok by their own windows pool
        // to the mean compaction 0.011: ok.
        let rows = vec![
            row(0, Class::Ok, 0.001, 0.01, "perfect"),
            row(1, Class::OverCompressed, 0.014, 0.01, "one"),
            row(2, Class::Ok, 0.008, 0.02, "two"),
            row(3, Class::OverCompressed, 0.013, 0.03, "three"),
            row(4, Class::Ok, 0.009, 0.02, "four"),
        ];
        let folded = pool_over_seeds(&rows);
        assert_eq!(folded.len(), 2);
        assert_eq!((folded[0].class(), folded[0].rows.len()), (Class::Ok, 1));
        let p = &folded[1];
        assert_eq!((p.class(), p.rows.len(), p.at.seed), (Class::Ok, 4, 0));
        assert!((p.pooled.eps_stat - 0.011).abs() < 1e-15);
        assert!((p.pooled.linf_stat - 0.02).abs() < 1e-15);
        // One seed failed: the point failed, with that seed's reason.
        let mut rows = rows;
        rows.push(row(5, Class::Failed, f64::NAN, f64::NAN, "five"));
        let folded = pool_over_seeds(&rows);
        assert_eq!(folded[1].class(), Class::Failed);
        assert_eq!(folded[1].pooled.failure_reason.as_deref(), Some("five"));
        // The mean over the bound: over-compressed.
        let two = vec![rows[1].clone(), rows[3].clone()];
        let folded = pool_over_seeds(&two);
        assert_eq!(folded[0].class(), Class::OverCompressed);
    }
}
