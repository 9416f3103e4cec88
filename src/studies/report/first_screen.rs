//! The report's first screen: per kernel, c0 by every rule against the
//! empirical ok bands (perfect and perturbed lattice), and the sentences
//! that say which rules were sufficient, which necessary and what each
//! cost, all from the report's own runs.

use serde::Serialize;

use super::empirical::Empirical;
use super::plan::Case;
use super::tables::C0Compare;
use super::ReportData;
use crate::charts::{Band, RuleMark, RulesPanel};
use crate::format::fmt_num;
use crate::sweep::Class;

/// One rule at one Re on the paper's discretisation, perfect and perturbed.
struct RuleAt<'a> {
    perfect: &'a C0Compare,
    perturbed: Option<&'a C0Compare>,
}

impl RuleAt<'_> {
    fn c0(&self) -> Option<f64> {
        Some(self.perfect.c0_over_u).filter(|c| *c > 0.0 && c.is_finite())
    }

    fn label(&self) -> String {
        let c = self.perfect;
        if c.default_model {
            format!("{} (default)", c.rule)
        } else {
            c.rule.to_string()
        }
    }

    /// Ok on the perfect lattice and on every seed of the perturbed one.
    fn sufficient(&self) -> bool {
        self.perfect.class == Some(Class::Ok)
            && self.perturbed.is_some_and(|p| p.class == Some(Class::Ok))
    }
}

fn rules_at<'a>(d: &'a ReportData, ki: usize, ri: usize) -> Vec<RuleAt<'a>> {
    let at = |case: Case| {
        d.c0_compare
            .iter()
            .filter(move |c| c.kernel_index == ki && c.re_index == ri && c.case == case)
    };
    at(Case::PAPER)
        .map(|perfect| RuleAt {
            perfect,
            perturbed: at(Case::PAPER_PERTURBED).find(|p| p.rule == perfect.rule),
        })
        .collect()
}

fn empirical_at(d: &ReportData, ki: usize, ri: usize, case: Case) -> Option<&Empirical> {
    d.empirical
        .iter()
        .find(|e| e.kernel_index == ki && e.re_index == ri && e.case == case)
}

/// The ok band of an empirical c0: from it to the top of its ok block
/// (only when some c0 ran ok).
fn band(e: Option<&Empirical>) -> Option<Band> {
    let e = e?;
    Some(Band {
        lo: e.c0_over_u?,
        hi: e.top?,
    })
}

/// The picture's panels for kernel `ki`, one per verdict Re.
pub fn panels(d: &ReportData, ki: usize) -> Vec<RulesPanel> {
    (0..d.config.empirical.re.len())
        .map(|ri| RulesPanel {
            re: d.config.empirical.re[ri],
            rules: rules_at(d, ki, ri)
                .iter()
                .map(|r| RuleMark {
                    label: r.label(),
                    c0_over_u: r.c0(),
                    perfect: r.perfect.class.filter(|_| r.c0().is_some()),
                    perturbed: r
                        .perturbed
                        .and_then(|p| p.class)
                        .filter(|_| r.c0().is_some()),
                })
                .collect(),
            perfect: band(empirical_at(d, ki, ri, Case::PAPER)),
            perturbed: band(empirical_at(d, ki, ri, Case::PAPER_PERTURBED)),
        })
        .collect()
}

/// The first screen's words for one kernel at one Re.
#[derive(Debug, Clone, Serialize)]
pub struct AnswerAtRe {
    pub re: f64,
    /// The smallest c0 / U ok on the perfect lattice, and on every seed of
    /// the perturbed one (None: none ok).
    pub empirical_perfect: Option<f64>,
    pub empirical_perturbed: Option<f64>,
    /// Rules ok on both (sufficient), on the perfect lattice only, and on
    /// neither; the sufficient rules within the bisection's tolerance of
    /// the perturbed empirical c0 (about necessary).
    pub sufficient: Vec<String>,
    pub perfect_only: Vec<String>,
    pub insufficient: Vec<String>,
    pub necessary: Vec<String>,
    pub sentences: Vec<String>,
}

/// The first screen's words for kernel `ki`, one per verdict Re.
pub fn answers(d: &ReportData, ki: usize) -> Vec<AnswerAtRe> {
    (0..d.config.empirical.re.len())
        .map(|ri| answer_at(d, ki, ri))
        .collect()
}

fn answer_at(d: &ReportData, ki: usize, ri: usize) -> AnswerAtRe {
    let rules = rules_at(d, ki, ri);
    let (perfect, perturbed) = (
        empirical_at(d, ki, ri, Case::PAPER),
        empirical_at(d, ki, ri, Case::PAPER_PERTURBED),
    );
    let ok_c0 = |e: Option<&Empirical>| e.and_then(|e| e.c0_over_u);
    let (e_perfect, e_perturbed) = (ok_c0(perfect), ok_c0(perturbed));
    let tol = (1.0 + d.config.empirical.rel_tol).powi(2);
    let with_c0: Vec<&RuleAt> = rules.iter().filter(|r| r.c0().is_some()).collect();
    let names = |f: &dyn Fn(&RuleAt) -> bool| -> Vec<String> {
        with_c0.iter().filter(|r| f(r)).map(|r| r.label()).collect()
    };
    let sufficient = names(&|r| r.sufficient());
    let perfect_only = names(&|r| !r.sufficient() && r.perfect.class == Some(Class::Ok));
    let insufficient = names(&|r| r.perfect.class != Some(Class::Ok));
    let necessary = names(&|r| {
        r.sufficient() && e_perturbed.is_some_and(|e| r.c0().is_some_and(|c| c <= e * tol))
    });
    let mut s = Vec::new();
    s.push(match e_perturbed {
        Some(b) => format!(
            "The answer (a real run: long, never a perfect lattice): the smallest c0 ok in the stationary, disordered state is {} U ({}).",
            fmt_num(b),
            d.config.perturbed_label()
        ),
        None => format!(
            "No c0 tried is ok in the stationary, disordered state ({}).",
            d.config.perturbed_label()
        ),
    });
    s.push(match e_perfect {
        Some(a) => format!(
            "In the ordered regime (the perfect lattice, the paper's analysis, while its order lasts) runs were ok from {} U.",
            fmt_num(a)
        ),
        None => "No c0 tried was ok on the perfect lattice either.".to_string(),
    });
    if let Some(a) = perturbed.map(|e| &e.answer) {
        if let Some(t) = &a.time_to_disorder {
            s.push(format!(
                "The order lasts: at {} U a {} d jitter {}, the perfect lattice {} (B / U = {}).",
                fmt_num(t.c0 / a.u),
                t.amplitude,
                t.seeds.map_or(
                    "did not leave its lattice (dy_rms >= 0.1 d) within the runs".to_string(),
                    |s| format!("left its lattice (dy_rms >= 0.1 d) at t = {}", fmt_num(s))
                ),
                t.perfect.map_or(
                    format!("stayed ordered to t = {}", fmt_num(t.perfect_t)),
                    |p| format!("from round-off at t = {}", fmt_num(p))
                ),
                fmt_num(a.horizon.shear_time)
            ));
        }
        if let Some(l) = &a.law {
            s.push(format!(
                "Disordered law: eps_stat - eps0 = {} (U / c0)^{} (m +- {}), so a density tolerance delta needs c0 = U ({} / delta)^(1/{}).",
                fmt_num(l.k),
                fmt_num(l.m),
                fmt_num(l.m_se),
                fmt_num(l.k),
                fmt_num(l.m)
            ));
        }
        if let Some(dg) = &a.diagnosis {
            s.push(format!("Why no c0 works: {}.", dg.binds));
            for w in &dg.would {
                s.push(format!("What would allow one: {w}."));
            }
        }
        if let Some(o) =
            super::stability::sentence(&d.ordered, d.infos[ki].name, d.config.empirical.re[ri])
        {
            s.push(o);
        }
        s.push(format!(
            "Horizon: each run went past the start-up ({}) to its stationary window, t = {} to {} ({} of {} runs stationary; docs/stationary.md).",
            fmt_num(a.horizon.t_startup),
            fmt_num(a.horizon.t_min),
            fmt_num(a.horizon.t_max),
            a.horizon.stationary,
            a.horizon.runs
        ));
    }
    let list = |v: &[String]| {
        if v.is_empty() {
            "none".to_string()
        } else {
            v.join(", ")
        }
    };
    s.push(format!(
        "Sufficient (ok in both regimes: on the perfect lattice and in the pooled disordered state): {}.",
        list(&sufficient)
    ));
    if !perfect_only.is_empty() {
        s.push(format!(
            "Ok in the ordered regime only, not in the disordered state: {}.",
            list(&perfect_only)
        ));
    }
    s.push(format!(
        "Not ok even on the perfect lattice: {}.",
        list(&insufficient)
    ));
    if let Some(e) = e_perturbed {
        s.push(format!(
            "About necessary (sufficient, and within the bisection's tolerance of the disordered empirical c0 {} U): {}.",
            fmt_num(e),
            list(&necessary)
        ));
    }
    if let Some(cost) = cost_sentence(&with_c0, perturbed) {
        s.push(cost);
    }
    let no_c0: Vec<String> = rules
        .iter()
        .filter(|r| r.c0().is_none())
        .map(|r| r.label())
        .collect();
    if !no_c0.is_empty() {
        s.push(format!("No positive c0 here: {}.", no_c0.join(", ")));
    }
    AnswerAtRe {
        re: d.config.empirical.re[ri],
        empirical_perfect: e_perfect,
        empirical_perturbed: e_perturbed,
        sufficient,
        perfect_only,
        insufficient,
        necessary,
        sentences: s,
    }
}

/// What the sufficient rules cost: steps of each perturbed run against the
/// run at the perturbed empirical c0.
fn cost_sentence(rules: &[&RuleAt], perturbed: Option<&Empirical>) -> Option<String> {
    let at = perturbed
        .and_then(|e| e.at.as_ref())
        .filter(|r| r.steps > 0)?;
    let costs: Vec<String> = rules
        .iter()
        .filter(|r| r.sufficient())
        .filter_map(|r| {
            let p = r.perturbed?;
            (p.steps > 0).then(|| {
                format!(
                    "{} {} steps ({}x)",
                    r.label(),
                    p.steps,
                    fmt_num(p.steps as f64 / at.steps as f64)
                )
            })
        })
        .collect();
    (!costs.is_empty()).then(|| {
        format!(
            "Cost of the sufficient rules on a perturbed start to their horizons, against the {} steps at the empirical c0 ({} U): {}.",
            at.steps,
            fmt_num(at.c0_over_u),
            costs.join("; ")
        )
    })
}
