//! The empirical c0: for a kernel and a scene, the smallest c0 from which
//! the runs are `ok`, found with the solver in the loop. The stability map's
//! row at that Re gives the bracket: of the block of consecutive ok values
//! that ends at the largest ok c0 on the grid, its lowest value, and the grid
//! value below it (which was not ok). Bisection on log c0 then narrows it to
//! `rel_tol`. Ok values further down, cut off from that block by runs that
//! were not ok, are isolated and listed apart: a c0 is no safe choice when a
//! larger one fails. (Ok-ness is not monotone in c0: too small a c0
//! over-compresses, too large a one adds artificial viscosity alpha c0 h,
//! which makes high-Re runs inaccurate.)
//!
//! When no c0 of the map ran ok (a kernel whose runs are inaccurate at every
//! c0), the criterion falls back to `stable` (ok or inaccurate: neither
//! failed nor over-compressed), and says so.

use std::fmt::Write as _;
use std::sync::atomic::AtomicBool;

use anyhow::Result;
use indicatif::ProgressBar;
use serde::Serialize;

use super::plan::{worst, Case, Config, Plan};
use crate::kernel::KernelInfo;
use crate::sweep::store::csv_field;
use crate::sweep::{run_point, Class, Discretisation, Parallel, Point, PointC0, Row};

/// The result for one kernel at one Re.
#[derive(Debug, Clone, Serialize)]
pub struct Empirical {
    pub kernel: String,
    /// The kernel's index in [`Config::kernel_infos`] and the Re's in
    /// `empirical.re`: the keys the report joins by.
    #[serde(skip)]
    pub kernel_index: usize,
    #[serde(skip)]
    pub re_index: usize,
    /// The discretisation and start; a perturbed case's outcome at a c0 is
    /// its worst over the seeds.
    #[serde(skip)]
    pub case: Case,
    /// The discretisation, and its label ("triangular, h = d").
    #[serde(skip)]
    pub disc: Discretisation,
    pub discretisation: String,
    pub n: u32,
    pub re: f64,
    pub alpha: f64,
    /// `ok`, or `stable` when no c0 tried ran ok.
    pub criterion: Criterion,
    /// The smallest c0 / U seen to meet the criterion (None: none did).
    pub c0_over_u: Option<f64>,
    /// The largest c0 / U below it seen not to meet it, and how that run
    /// ended (None: the answer is at or below the smallest c0 tried).
    pub below: Option<f64>,
    pub below_class: Option<Class>,
    pub below_reason: Option<String>,
    pub rel_tol: f64,
    /// The c0 / U range that was tried.
    pub tried_min: f64,
    pub tried_max: f64,
    /// The run at the answer.
    pub at: Option<Row>,
    /// The largest c0 / U of the block of ok runs, and the first grid value
    /// above it with its class (None: the block reaches the map's top).
    pub top: Option<f64>,
    pub above: Option<(f64, Class)>,
    /// Grid values below the block that also met the criterion (isolated).
    pub isolated_below: Vec<f64>,
    /// The bisection's own runs (the map's are in the map).
    #[serde(skip)]
    pub runs: Vec<Row>,
}

/// What the empirical c0 is the smallest value of.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Criterion {
    /// Runs `ok`.
    Ok,
    /// Runs neither failed nor over-compressed (none ran ok).
    Stable,
}

impl std::fmt::Display for Criterion {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Criterion::Ok => "ok",
            Criterion::Stable => "stable",
        })
    }
}

impl Criterion {
    fn meets(self, class: Class) -> bool {
        match self {
            Criterion::Ok => class == Class::Ok,
            Criterion::Stable => matches!(class, Class::Ok | Class::Inaccurate),
        }
    }
}

impl Empirical {
    /// Plain words for the table and the verdicts.
    /// Plain words: the answer, its bracket, how far up the ok runs reach,
    /// and any isolated ok values below.
    pub fn describe(&self) -> String {
        let crit = if self.criterion == Criterion::Ok {
            "ran ok"
        } else {
            "ran without failing or over-compressing (none ran ok)"
        };
        let mut t = match (self.c0_over_u, self.below) {
            (None, _) => {
                return format!(
                    "no c0 from {} U to {} U ran ok, or even without failing or over-compressing",
                    fmt(self.tried_min),
                    fmt(self.tried_max)
                )
            }
            (Some(c), Some(b)) => format!(
                "the smallest c0 that {crit} is {} U (bisection to {} %: at {} U the run was {})",
                fmt(c),
                fmt(100.0 * self.rel_tol),
                fmt(b),
                self.below_reason.clone().unwrap_or_default()
            ),
            (Some(c), None) => format!("every c0 tried down to {} U {crit}", fmt(c)),
        };
        if let Some(at) = &self.at {
            t.push_str(&format!(
                "; at {} U: {}, {} s",
                fmt(at.c0_over_u),
                reason(at),
                fmt(at.wall_s)
            ));
        }
        match &self.above {
            Some((c, class)) => t.push_str(&format!(
                "; runs {} up to {} U, and at {} U the run was {class}",
                if self.criterion == Criterion::Ok {
                    "stayed ok"
                } else {
                    "stayed stable"
                },
                fmt(self.top.unwrap_or(f64::NAN)),
                fmt(*c)
            )),
            None => t.push_str(&format!(
                "; every c0 above it on the map {} too, up to {} U",
                if self.criterion == Criterion::Ok {
                    "ran ok"
                } else {
                    "ran stably"
                },
                fmt(self.tried_max)
            )),
        }
        if !self.isolated_below.is_empty() {
            let iso: Vec<String> = self
                .isolated_below
                .iter()
                .map(|v| format!("{} U", fmt(*v)))
                .collect();
            t.push_str(&format!(
                "; below the bracket, {} also {} while values between did not (isolated, not counted)",
                iso.join(", "),
                if self.criterion == Criterion::Ok { "ran ok" } else { "ran stably" }
            ));
        }
        t
    }
}

fn fmt(v: f64) -> String {
    crate::format::fmt_num(v)
}

/// One target: a kernel at one Re, with the map's rows there.
struct Target<'a> {
    info: &'static KernelInfo,
    case: Case,
    kernel: usize,
    /// Index into `empirical.re`.
    re_index: usize,
    re: f64,
    map: Vec<&'a Row>,
}

/// The empirical c0 for every kernel at every `config.empirical.re`, the
/// targets in parallel. `None` when the stop flag cut it short.
pub fn find_all(
    config: &Config,
    plan: &Plan,
    infos: &[&'static KernelInfo],
    rows: &[Row],
    par: Parallel,
    stop: &AtomicBool,
    bar: &ProgressBar,
) -> Result<Option<Vec<Empirical>>> {
    let mut targets = Vec::new();
    for case in config.cases() {
        for (kernel, &info) in infos.iter().enumerate() {
            if case.disc.of(info).is_none() {
                continue;
            }
            for (re_index, &re) in config.empirical.re.iter().enumerate() {
                let at = Some(config.map_re_of_verdict(re_index));
                let mut map = plan.map_rows(rows, kernel, case, at);
                map.retain(|r| r.c0_over_u.is_finite());
                map.sort_by(|a, b| a.c0_over_u.total_cmp(&b.c0_over_u));
                targets.push(Target {
                    info,
                    case,
                    kernel,
                    re_index,
                    re,
                    map,
                });
            }
        }
    }
    // Bisection steps are not known ahead: the bar grows as they start.
    let results = par.map(
        &targets,
        stop,
        |t| {
            find_one(
                config,
                t,
                stop,
                &|| {
                    bar.inc_length(1);
                },
                &|| bar.inc(1),
            )
        },
        |_, _| {},
    )?;
    if results.iter().any(Option::is_none) {
        return Ok(None);
    }
    Ok(Some(results.into_iter().flatten().collect()))
}

fn find_one(
    config: &Config,
    t: &Target,
    stop: &AtomicBool,
    started: &dyn Fn(),
    finished: &dyn Fn(),
) -> Option<Empirical> {
    let e = &config.empirical;
    let tried_min = t.map.first().map_or(f64::NAN, |r| r.c0_over_u);
    let tried_max = t.map.last().map_or(f64::NAN, |r| r.c0_over_u);
    let mut result = Empirical {
        kernel: t.info.name.to_string(),
        kernel_index: t.kernel,
        re_index: t.re_index,
        case: t.case,
        disc: t
            .case
            .disc
            .of(t.info)
            .map_or_else(Default::default, |(d, _)| d),
        discretisation: t
            .case
            .disc
            .of(t.info)
            .map_or(String::new(), |(_, on)| on.label()),
        n: config.maps.n,
        re: t.re,
        alpha: config.maps.alpha,
        criterion: Criterion::Ok,
        c0_over_u: None,
        below: None,
        below_class: None,
        below_reason: None,
        rel_tol: e.rel_tol,
        tried_min,
        tried_max,
        at: None,
        top: None,
        above: None,
        isolated_below: Vec::new(),
        runs: Vec::new(),
    };
    let criterion = if t.map.iter().any(|r| Criterion::Ok.meets(r.class)) {
        Criterion::Ok
    } else if t.map.iter().any(|r| Criterion::Stable.meets(r.class)) {
        Criterion::Stable
    } else {
        return Some(result);
    };
    result.criterion = criterion;
    // The block of consecutive values meeting it that ends at the largest one.
    let top = t
        .map
        .iter()
        .rposition(|r| criterion.meets(r.class))
        .expect("one meets it");
    result.top = Some(t.map[top].c0_over_u);
    result.above = t.map.get(top + 1).map(|r| (r.c0_over_u, r.class));
    let mut k = top;
    while k > 0 && criterion.meets(t.map[k - 1].class) {
        k -= 1;
    }
    result.isolated_below = t.map[..k]
        .iter()
        .filter(|r| criterion.meets(r.class))
        .map(|r| r.c0_over_u)
        .collect();
    let mut hi: Row = t.map[k].clone();
    let mut lo: Option<Row> = k.checked_sub(1).map(|j| t.map[j].clone());

    let mut counter = 0usize;
    let (disc, _) = t.case.disc.of(t.info).expect("a target's discretisation");
    // One c0 on every start of the case: the worst row, every row kept.
    let mut run = |c0_over_u: f64, runs: &mut Vec<Row>| -> Option<Row> {
        let first = runs.len();
        for seed in config.seeds(t.case.perturbed) {
            started();
            let point = Point {
                disc,
                start: config.start(seed),
                ..Point::paper(
                    counter,
                    t.info.name,
                    config.maps.n,
                    t.re,
                    config.maps.alpha,
                    PointC0::OverU(c0_over_u),
                )
            };
            counter += 1;
            runs.push(run_point(&point, &config.scene, &config.classes, stop)?);
            finished();
        }
        Some(worst(runs[first..].iter().collect()).clone())
    };
    // Below the map's lowest value, when that one already met it.
    if lo.is_none() {
        for _ in 0..e.max_extend {
            let row = run(hi.c0_over_u / 3.0, &mut result.runs)?;
            result.tried_min = result.tried_min.min(row.c0_over_u);
            if criterion.meets(row.class) {
                hi = row;
            } else {
                lo = Some(row);
                break;
            }
        }
    }
    if let Some(mut below) = lo {
        while hi.c0_over_u / below.c0_over_u > 1.0 + e.rel_tol {
            let mid = (hi.c0_over_u * below.c0_over_u).sqrt();
            let row = run(mid, &mut result.runs)?;
            if criterion.meets(row.class) {
                hi = row;
            } else {
                below = row;
            }
        }
        result.below = Some(below.c0_over_u);
        result.below_class = Some(below.class);
        result.below_reason = Some(reason(&below));
    }
    result.c0_over_u = Some(hi.c0_over_u);
    result.at = Some(hi);
    Some(result)
}

/// A row's class with its reason or figures, in a few words.
pub fn reason(r: &Row) -> String {
    match r.class {
        Class::Failed | Class::Interrupted => format!(
            "{}: {}",
            r.class,
            r.failure_reason.clone().unwrap_or_default()
        ),
        Class::OverCompressed => format!(
            "over-compressed: max eps {} above {}",
            fmt(r.max_eps),
            fmt(r.eps_bound)
        ),
        Class::Inaccurate => format!("inaccurate: L_inf {} % of U", fmt(100.0 * r.linf_max)),
        Class::Ok => format!("ok: L_inf {} % of U", fmt(100.0 * r.linf_max)),
    }
}

pub fn csv(list: &[Empirical]) -> String {
    let mut out = String::from(
        "kernel,n,re,alpha,criterion,c0_over_u,below_c0_over_u,below_class,below_reason,rel_tol,tried_min,tried_max,linf_max_at,wall_s_at,bisection_runs,isolated_below,lattice,h_over_d,start\n",
    );
    let f = |v: Option<f64>| v.map_or(String::new(), |v| v.to_string());
    for e in list {
        let _ = writeln!(
            out,
            "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}",
            csv_field(&e.kernel),
            e.n,
            e.re,
            e.alpha,
            e.criterion,
            f(e.c0_over_u),
            f(e.below),
            e.below_class.map_or(String::new(), |c| c.to_string()),
            csv_field(&e.below_reason.clone().unwrap_or_default()),
            e.rel_tol,
            e.tried_min,
            e.tried_max,
            f(e.at.as_ref().map(|r| r.linf_max)),
            f(e.at.as_ref().map(|r| r.wall_s)),
            e.runs.len(),
            csv_field(
                &e.isolated_below
                    .iter()
                    .map(|v| v.to_string())
                    .collect::<Vec<_>>()
                    .join(" ")
            ),
            e.disc.lattice.name(),
            e.disc.h_over_d,
            e.case.start_name()
        );
    }
    out
}
