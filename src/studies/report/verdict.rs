//! The verdict per kernel: plain sentences built from the runs (the derived
//! c0's run, the empirical c0, 10 U and Table 2 at each verdict Re), never
//! typed-in conclusions.

use serde::Serialize;

use super::config::ReportConfig;
use super::empirical::Empirical;
use super::plan::Case;
use super::tables::C0Compare;
use crate::config::C0Rule;
use crate::format::fmt_num;
use crate::kernel::KernelInfo;
use crate::problem::cost::DtLimit;
use crate::sweep::Class;

#[derive(Debug, Clone, Serialize)]
pub struct Verdict {
    pub kernel: String,
    /// One paragraph per verdict Re: the paper's discretisation, perfect
    /// lattice.
    pub at_re: Vec<VerdictAtRe>,
    /// One sentence over all of them.
    pub summary: String,
    /// The same for the other cases: the paper's discretisation perturbed,
    /// and the square discretisation perfect and perturbed.
    pub cases: Vec<CaseVerdict>,
}

/// The verdict of one case (a discretisation and a start).
#[derive(Debug, Clone, Serialize)]
pub struct CaseVerdict {
    pub discretisation: String,
    /// `perfect`, or `perturbed` (each run's outcome the worst of its seeds').
    pub start: &'static str,
    pub at_re: Vec<VerdictAtRe>,
    pub summary: String,
}

#[derive(Debug, Clone, Serialize)]
pub struct VerdictAtRe {
    pub re: f64,
    pub n: u32,
    pub alpha: f64,
    /// The derived (default model) c0 / U, None when it has no positive root.
    pub derived_c0_over_u: Option<f64>,
    pub derived_class: Option<Class>,
    pub empirical_c0_over_u: Option<f64>,
    /// `disordered` (the pooled seeds) or `ordered` (the perfect lattice).
    pub empirical_regime: String,
    pub rule10_class: Option<Class>,
    pub sentences: Vec<String>,
}

fn pct(v: f64) -> String {
    format!("{} %", fmt_num(100.0 * v))
}

/// "ran ok (L_inf 0.2 % of U, max eps 0.0015; 0.04 s, 1.7e5 particle-steps, dt bound by viscous)".
fn run_words(c: &C0Compare) -> String {
    match c.class {
        None => "did not run".into(),
        Some(Class::Failed) => format!(
            "failed ({})",
            c.reason
                .clone()
                .unwrap_or_default()
                .trim_start_matches("failed: ")
        ),
        Some(class) => format!(
            "ran {class} (mean-flow error {} of U, eps_stat {}; {} s, {} steps, dt bound by the {} limit)",
            pct(c.linf_stat),
            fmt_num(c.eps_stat),
            fmt_num(c.wall_s),
            c.steps,
            c.run_dt_limit_dominant.map_or("", DtLimit::name)
        ),
    }
}

/// The rows of one verdict: a kernel at one Re, by key.
struct AtRe<'a> {
    derived: Option<&'a C0Compare>,
    rule10: Option<&'a C0Compare>,
    table2: Option<&'a C0Compare>,
    /// The other derived models.
    others: Vec<&'a C0Compare>,
    emp: Option<&'a Empirical>,
}

impl<'a> AtRe<'a> {
    fn find(
        (kernel, case, re): (usize, Case, usize),
        compare: &'a [C0Compare],
        empirical: &'a [Empirical],
    ) -> Self {
        let here: Vec<&C0Compare> = compare
            .iter()
            .filter(|c| c.kernel_index == kernel && c.re_index == re && c.case == case)
            .collect();
        let rule = |r: C0Rule| here.iter().find(|c| c.rule == r).copied();
        AtRe {
            derived: here.iter().find(|c| c.default_model).copied(),
            rule10: rule(C0Rule::Code(&crate::config::RULE10)),
            table2: rule(C0Rule::Table2),
            others: here
                .iter()
                .filter(|c| matches!(c.rule, C0Rule::Derived(_)) && !c.default_model)
                .copied()
                .collect(),
            emp: empirical
                .iter()
                .find(|e| e.kernel_index == kernel && e.re_index == re && e.case == case),
        }
    }
}

pub fn verdicts(
    config: &ReportConfig,
    infos: &[&'static KernelInfo],
    empirical: &[Empirical],
    compare: &[C0Compare],
) -> Vec<Verdict> {
    let mut out = Vec::new();
    for (ki, &info) in infos.iter().enumerate() {
        let case_at = |case: Case| -> Vec<VerdictAtRe> {
            config
                .empirical
                .re
                .iter()
                .enumerate()
                .map(|(ri, &re)| {
                    verdict_at(config, re, &AtRe::find((ki, case, ri), compare, empirical))
                })
                .collect()
        };
        let at_re = case_at(Case::PAPER);
        let cases = config.cases()[1..]
            .iter()
            .filter_map(|&case| {
                let (_, on) = case.disc.of(info)?;
                let at_re = case_at(case);
                Some(CaseVerdict {
                    discretisation: on.label(),
                    start: case.start_name(),
                    summary: summary(info, &at_re),
                    at_re,
                })
            })
            .collect();
        out.push(Verdict {
            kernel: info.name.to_string(),
            summary: summary(info, &at_re),
            at_re,
            cases,
        });
    }
    out
}

/// The derived c0 of the default model, when it is a positive number.
fn derived_c0(at: &AtRe) -> Option<f64> {
    at.derived
        .map(|d| d.c0_over_u)
        .filter(|c| *c > 0.0 && c.is_finite())
}

fn verdict_at(config: &ReportConfig, re: f64, at: &AtRe) -> VerdictAtRe {
    let derived_c0 = derived_c0(at);
    let mut s = Vec::new();
    s.push(derived_sentence(at));
    // The other derived models, briefly.
    let others: Vec<String> = at
        .others
        .iter()
        .map(|c| {
            if c.c0_over_u > 0.0 && c.c0_over_u.is_finite() {
                format!(
                    "{} = {} U ({})",
                    c.rule,
                    fmt_num(c.c0_over_u),
                    c.class.map_or("not run".into(), |k| k.to_string())
                )
            } else {
                format!("{}: no positive root", c.rule)
            }
        })
        .collect();
    if !others.is_empty() {
        s.push(format!("Other models: {}.", others.join("; ")));
    }
    if let Some(e) = at.emp {
        s.push(format!("Empirically, {}.", e.describe()));
    }
    if let Some(r) = at.rule10 {
        s.push(format!("10 U: {}.", run_words(r)));
    }
    if let Some(t) = at.table2 {
        if t.c0_over_u > 0.0 && t.c0_over_u.is_finite() {
            s.push(format!(
                "Table 2 as printed: {} U, {}.",
                fmt_num(t.c0_over_u),
                run_words(t)
            ));
        }
    }
    s.push(match (at.derived, derived_c0) {
        (Some(d), Some(c)) => conclusion(config, at, d, c),
        _ => no_derived_conclusion(at),
    });
    let emp_c0 = at.emp.and_then(|e| e.c0_over_u);
    VerdictAtRe {
        re,
        n: config.maps.n,
        alpha: config.maps.alpha,
        derived_c0_over_u: derived_c0,
        derived_class: at
            .derived
            .and_then(|d| d.class)
            .filter(|_| derived_c0.is_some()),
        empirical_c0_over_u: emp_c0,
        empirical_regime: at.emp.map_or(String::new(), |e| {
            if e.case.perturbed {
                "disordered".to_string()
            } else {
                "ordered".to_string()
            }
        }),
        rule10_class: at.rule10.and_then(|r| r.class),
        sentences: s,
    }
}

/// The first sentence: the derived c0 and its run, or why there is none.
fn derived_sentence(at: &AtRe) -> String {
    match (at.derived, derived_c0(at)) {
        (Some(d), Some(c)) => format!(
            "derived c0 ({}) = {} U: {}.",
            d.rule,
            fmt_num(c),
            run_words(d)
        ),
        (Some(d), None) if d.c0_over_u.is_nan() => format!(
            "derived c0 ({}): the derivation has no positive root for this scene (P alpha^2 + Q A < 0), so there is no derived sound speed to run.",
            d.rule
        ),
        (Some(d), None) => format!(
            "derived c0 ({}): the derivation gives c0 = {} for this scene, no positive root, so there is no derived sound speed to run.",
            d.rule,
            fmt_num(d.c0_over_u)
        ),
        (None, _) => "no derived model for this kernel.".into(),
    }
}

/// The conclusion at one Re when the derived c0 is `c` (run `d`).
fn conclusion(config: &ReportConfig, at: &AtRe, d: &C0Compare, c: f64) -> String {
    let emp = at.emp;
    let emp_c0 = emp.and_then(|e| e.c0_over_u);
    let emp_ok = emp.is_some_and(|e| e.c0_over_u.is_some());
    let ok = d.class == Some(Class::Ok);
    let mut t = if ok {
        "So the derived c0 was sufficient here".to_string()
    } else {
        format!(
            "So the derived c0 was not sufficient here: its run was {}",
            d.class.map_or("not run".into(), |k| k.to_string())
        )
    };
    match (emp_c0, emp_ok) {
        (Some(e), true) if ok => {
            let tol = 1.0 + config.empirical.rel_tol;
            let open_below = emp.is_some_and(|x| x.below.is_none());
            if e * tol * tol < c || (open_below && e < c) {
                t.push_str(&format!(
                    ", but not necessary: runs were ok down to {} U, {} times the derived value",
                    fmt_num(e),
                    fmt_num(e / c)
                ));
            } else {
                t.push_str(", and about necessary: the smallest ok c0 is within the bisection's tolerance of it");
            }
        }
        (Some(e), true) => t.push_str(&format!(
            "; ok needed at least {} U, {} times the derived value",
            fmt_num(e),
            fmt_num(e / c)
        )),
        _ => t.push_str("; no c0 tried ran ok at all"),
    }
    if let Some(r) = at.rule10 {
        if d.class.is_some() && d.steps > 0 && r.steps > 0 {
            let ratio = r.steps as f64 / d.steps as f64;
            if ratio > 1.2 {
                t.push_str(&format!(
                    ". At the derived c0 the run took {} times fewer steps than at 10 U ({} s against {} s)",
                    fmt_num(ratio),
                    fmt_num(d.wall_s),
                    fmt_num(r.wall_s)
                ));
            } else {
                t.push_str(&format!(
                    ". It cost about the same as 10 U ({} against {} steps): the {} limit binds the time step at this Re",
                    d.steps, r.steps, d.run_dt_limit_dominant.map_or("", DtLimit::name)
                ));
            }
        }
    }
    t.push('.');
    t
}

/// The conclusion at one Re when the derivation gives no c0 to run.
fn no_derived_conclusion(at: &AtRe) -> String {
    let emp = at.emp;
    let emp_ok = emp.is_some_and(|e| e.c0_over_u.is_some());
    match (emp.and_then(|e| e.c0_over_u), emp_ok) {
        (Some(e), true) => format!(
            "So the derivation gives nothing to use here, while runs were ok from {} U{}.",
            fmt_num(e),
            match emp.and_then(|x| x.above.map(|a| (x.top, a))) {
                Some((Some(top), (_, class))) => format!(" to {} U (above: {class})", fmt_num(top)),
                _ => " up".to_string(),
            }
        ),
        _ => "So the derivation gives nothing to use here, and no c0 tried ran ok.".into(),
    }
}

/// One sentence over every Re of a kernel.
fn summary(info: &KernelInfo, at_re: &[VerdictAtRe]) -> String {
    let total = at_re.len();
    let count = |f: &dyn Fn(&VerdictAtRe) -> bool| at_re.iter().filter(|v| f(v)).count();
    let ok = count(&|v| v.derived_class == Some(Class::Ok));
    let none = count(&|v| v.derived_c0_over_u.is_none());
    let r10 = count(&|v| v.rule10_class == Some(Class::Ok));
    if none == total {
        format!(
            "{}: the derivation gives no positive c0 at any of the {total} scenes; 10 U ran ok at {r10} of {total}.",
            info.name
        )
    } else {
        format!(
            "{}: the derived c0 ran ok at {ok} of {total} scenes{}; 10 U ran ok at {r10} of {total}.",
            info.name,
            if none > 0 { format!(" (no positive root at {none})") } else { String::new() }
        )
    }
}
