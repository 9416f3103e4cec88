//! The verdict per kernel: plain sentences built from the runs (the derived
//! c0's run, the empirical c0, 10 U and Table 2 at each verdict Re), never
//! typed-in conclusions.

use serde::Serialize;

use super::empirical::Empirical;
use super::tables::C0Compare;
use super::Config;
use crate::format::fmt_num;
use crate::kernel::KernelInfo;
use crate::problem::cost::DtLimit;
use crate::sweep::{Class, Row};

#[derive(Debug, Clone, Serialize)]
pub struct Verdict {
    pub kernel: String,
    /// One paragraph per verdict Re.
    pub at_re: Vec<VerdictAtRe>,
    /// One sentence over all of them.
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
    pub empirical_criterion: String,
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
            "ran {class} (L_inf {} of U, max eps {}; {} s, {} steps, dt bound by the {} limit)",
            pct(c.linf_max),
            fmt_num(c.max_eps),
            fmt_num(c.wall_s),
            c.steps,
            c.run_dt_limit_dominant.map_or("", DtLimit::name)
        ),
    }
}

pub fn verdicts(
    config: &Config,
    infos: &[&'static KernelInfo],
    _rows: &[Row],
    empirical: &[Empirical],
    compare: &[C0Compare],
) -> Vec<Verdict> {
    let mut out = Vec::new();
    for info in infos {
        let mut at_re = Vec::new();
        for &re in &config.empirical.re {
            let here: Vec<&C0Compare> = compare
                .iter()
                .filter(|c| c.kernel == info.name && c.re == re)
                .collect();
            let derived = here.iter().find(|c| c.default_model).copied();
            let rule10 = here.iter().find(|c| c.rule == "rule10").copied();
            let table2 = here.iter().find(|c| c.rule == "table2").copied();
            let emp = empirical
                .iter()
                .find(|e| e.kernel == info.name && e.re == re);
            let mut s = Vec::new();
            let derived_c0 = derived
                .map(|d| d.c0_over_u)
                .filter(|c| *c > 0.0 && c.is_finite());
            match (derived, derived_c0) {
                (Some(d), Some(c)) => s.push(format!(
                    "derived c0 ({}) = {} U: {}.",
                    d.rule,
                    fmt_num(c),
                    run_words(d)
                )),
                (Some(d), None) if d.c0_over_u.is_nan() => s.push(format!(
                    "derived c0 ({}): the derivation has no positive root for this scene (P alpha^2 + Q A < 0), so there is no derived sound speed to run.",
                    d.rule
                )),
                (Some(d), None) => s.push(format!(
                    "derived c0 ({}): the derivation gives c0 = {} for this scene, no positive root, so there is no derived sound speed to run.",
                    d.rule,
                    fmt_num(d.c0_over_u)
                )),
                (None, _) => s.push("no derived model for this kernel.".into()),
            }
            // The other derived models, briefly.
            let others: Vec<String> = here
                .iter()
                .filter(|c| c.rule.starts_with("derived:") && !c.default_model)
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
            if let Some(e) = emp {
                s.push(format!("Empirically, {}.", e.describe()));
            }
            if let Some(r) = rule10 {
                s.push(format!("10 U: {}.", run_words(r)));
            }
            if let Some(t) = table2 {
                if t.c0_over_u > 0.0 && t.c0_over_u.is_finite() {
                    s.push(format!(
                        "Table 2 as printed: {} U, {}.",
                        fmt_num(t.c0_over_u),
                        run_words(t)
                    ));
                }
            }
            // The conclusion at this Re.
            let emp_c0 = emp.and_then(|e| e.c0_over_u);
            let emp_ok = emp.is_some_and(|e| e.criterion == "ok");
            let conclusion = match (derived, derived_c0) {
                (Some(d), Some(c)) => {
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
                    if let Some(r) = rule10 {
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
                _ => match (emp_c0, emp_ok) {
                    (Some(e), true) => format!(
                        "So the derivation gives nothing to use here, while runs were ok from {} U{}.",
                        fmt_num(e),
                        match emp.and_then(|x| x.above.map(|a| (x.top, a))) {
                            Some((Some(top), (_, class))) => format!(" to {} U (above: {class})", fmt_num(top)),
                            _ => " up".to_string(),
                        }
                    ),
                    _ => "So the derivation gives nothing to use here, and no c0 tried ran ok.".into(),
                },
            };
            s.push(conclusion);
            at_re.push(VerdictAtRe {
                re,
                n: config.maps.n,
                alpha: config.maps.alpha,
                derived_c0_over_u: derived_c0,
                derived_class: derived
                    .and_then(|d| d.class)
                    .filter(|_| derived_c0.is_some()),
                empirical_c0_over_u: emp_c0,
                empirical_criterion: emp.map_or(String::new(), |e| e.criterion.to_string()),
                rule10_class: rule10.and_then(|r| r.class),
                sentences: s,
            });
        }
        let total = at_re.len();
        let ok = at_re
            .iter()
            .filter(|v| v.derived_class == Some(Class::Ok))
            .count();
        let none = at_re
            .iter()
            .filter(|v| v.derived_c0_over_u.is_none())
            .count();
        let r10 = at_re
            .iter()
            .filter(|v| v.rule10_class == Some(Class::Ok))
            .count();
        let summary = if none == total {
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
        };
        out.push(Verdict {
            kernel: info.name.to_string(),
            at_re,
            summary,
        });
    }
    out
}
