//! The ordered lattice beside the answer: per kernel on the paper's
//! discretisation at the maps' N and alpha, at each verdict Re, the growth
//! rate of perturbations of the perfect sheared lattice (`shearsph
//! stability`'s analysis, src/studies/stability/) at the kernel's derived c0 and at
//! rule10's, and when a 1e-4 d jitter disorders it: how long the derived
//! rules' premise, the ordered lattice, lasts in a run.

use std::sync::atomic::{AtomicBool, Ordering};

use anyhow::Result;
use serde::Serialize;

use super::plan::CaseDiscretisation;
use super::ReportConfig;
use crate::config::C0Spec;
use crate::format::fmt_num;
use crate::kernel::KernelInfo;
use crate::problem::Problem;
use crate::solver::tangent::Options;
use crate::stability::{analyse, Request};

/// The rules whose c0 the report analyses.
pub const RULES: [&str; 2] = ["derived", "rule10"];

/// One kernel's ordered lattice at one Re and one rule's c0.
#[derive(Debug, Clone, Serialize)]
pub struct Ordered {
    pub kernel: String,
    pub re: f64,
    pub rule: String,
    /// None: the rule has no c0 here (`note` says why).
    pub c0_over_u: Option<f64>,
    /// The leading growth rate per unit time; None when every sector's run
    /// failed (the perfect lattice does not last at this c0).
    pub growth_rate: Option<f64>,
    pub q_d: Option<f64>,
    /// When a 1e-4 d jitter reaches dy_rms = 0.1 d at that rate; None where
    /// nothing grows.
    pub t_disorder: Option<f64>,
    pub note: Option<String>,
}

/// Every kernel's, Re's and rule's; None when `stop` was raised. The quick
/// report follows each perturbation over 60 t instead of 300.
pub fn ordered_all(
    config: &ReportConfig,
    infos: &[&'static KernelInfo],
    quick: bool,
    stop: &AtomicBool,
) -> Result<Option<Vec<Ordered>>> {
    let mut req = Request::default();
    if quick {
        req.options = Options {
            horizon: 60.0,
            warm: 10.0,
            ..req.options
        };
    }
    let mut out = Vec::new();
    for &info in infos {
        let Some((disc, _)) = CaseDiscretisation::PAPER.of(info) else {
            continue;
        };
        for &re in &config.empirical.re {
            let mut scene = super::empirical::scene(config, info.name, re, disc)?;
            for rule in RULES {
                if stop.load(Ordering::Relaxed) {
                    return Ok(None);
                }
                scene.c0 = rule
                    .parse::<C0Spec>()
                    .map_err(|e| anyhow::anyhow!("{rule}: {e}"))?;
                let mut row = Ordered {
                    kernel: info.name.to_string(),
                    re,
                    rule: rule.to_string(),
                    c0_over_u: None,
                    growth_rate: None,
                    q_d: None,
                    t_disorder: None,
                    note: None,
                };
                match Problem::resolve(&scene, info) {
                    Err(e) => row.note = Some(e.to_string()),
                    Ok(p) => {
                        let c = p.c0 / scene.u;
                        row.c0_over_u = Some(c);
                        let a = analyse(
                            &scene,
                            &Request {
                                c0_over_u: vec![c],
                                ..req.clone()
                            },
                        )?
                        .remove(0);
                        if a.growth_rate.is_finite() {
                            row.growth_rate = Some(a.growth_rate);
                            row.q_d = a.most_unstable_q_d();
                            row.t_disorder = a.t_disorder_predicted;
                        } else {
                            row.note = Some(
                                "every sector's run failed: the perfect lattice does not last at this c0"
                                    .into(),
                            );
                        }
                    }
                }
                out.push(row);
            }
        }
    }
    Ok(Some(out))
}

/// The answer's sentence on the ordered lattice for `kernel` at `re`.
pub fn sentence(rows: &[Ordered], kernel: &str, re: f64) -> Option<String> {
    let fmt = fmt_num;
    let at: Vec<String> = rows
        .iter()
        .filter(|r| r.kernel == kernel && r.re == re)
        .map(|r| match (r.c0_over_u, r.growth_rate) {
            (None, _) => format!("{} has no c0 here", r.rule),
            (Some(c), None) => format!(
                "at {}'s {} U {}",
                r.rule,
                fmt(c),
                r.note.as_deref().unwrap_or("the analysis failed")
            ),
            (Some(c), Some(g)) => match r.t_disorder {
                Some(t) => format!(
                    "at {}'s {} U perturbations grow at {} per unit time (a 1e-4 d jitter disorders it by t = {})",
                    r.rule,
                    fmt(c),
                    fmt(g),
                    fmt(t)
                ),
                None => format!(
                    "at {}'s {} U no perturbation grows ({} per unit time): the ordered lattice holds",
                    r.rule,
                    fmt(c),
                    fmt(g)
                ),
            },
        })
        .collect();
    (!at.is_empty()).then(|| {
        format!(
            "The ordered lattice the derived rules assume (shearsph stability, docs/stability.md): {}.",
            at.join("; ")
        )
    })
}

/// One cell of the growth map: a kernel's ordered lattice on one
/// discretisation at one Re and c0.
#[derive(Debug, Clone, Serialize)]
pub struct GrowthCell {
    pub kernel: String,
    pub discretisation: String,
    pub re: f64,
    pub c0_over_u: f64,
    /// The leading growth rate per unit time and per period T = d N^2 / U,
    /// its sector's q d, and when a 1e-4 d jitter disorders the lattice
    /// at that rate (None: nothing grows); all None when every sector's
    /// run failed (`note`).
    pub growth_rate: Option<f64>,
    pub growth_rate_per_period: Option<f64>,
    pub q_d: Option<f64>,
    pub t_disorder: Option<f64>,
    pub note: Option<String>,
}

/// The growth map (`[growth]`): every kernel on each case's discretisation
/// at maps.n and maps.alpha, every `growth.re` x `growth.c0_over_u`, each
/// perturbation followed over `growth.horizon`; empty when either list is.
/// None when `stop` was raised.
pub fn growth_map(
    config: &ReportConfig,
    infos: &[&'static KernelInfo],
    stop: &AtomicBool,
) -> Result<Option<Vec<GrowthCell>>> {
    let g = &config.growth;
    let mut out = Vec::new();
    if g.re.is_empty() || g.c0_over_u.is_empty() {
        return Ok(Some(out));
    }
    let defaults = Request::default();
    let req = Request {
        c0_over_u: g.c0_over_u.clone(),
        options: Options {
            horizon: g.horizon,
            warm: defaults.options.warm.min(g.horizon / 4.0),
            ..defaults.options
        },
        ..defaults
    };
    let mut discs: Vec<CaseDiscretisation> = config.cases().iter().map(|c| c.disc).collect();
    discs.dedup();
    for disc_kind in discs {
        for &info in infos {
            let Some((disc, on)) = disc_kind.of(info) else {
                continue;
            };
            for &re in &g.re {
                if stop.load(Ordering::Relaxed) {
                    return Ok(None);
                }
                let scene = super::empirical::scene(config, info.name, re, disc)?;
                let cell = |c0_over_u: f64| GrowthCell {
                    kernel: info.name.to_string(),
                    discretisation: on.label(),
                    re,
                    c0_over_u,
                    growth_rate: None,
                    growth_rate_per_period: None,
                    q_d: None,
                    t_disorder: None,
                    note: None,
                };
                match analyse(&scene, &req) {
                    Err(e) => out.extend(g.c0_over_u.iter().map(|&c| GrowthCell {
                        note: Some(format!("{e:#}")),
                        ..cell(c)
                    })),
                    Ok(at) => out.extend(at.into_iter().map(|a| {
                        if a.growth_rate.is_finite() {
                            GrowthCell {
                                growth_rate: Some(a.growth_rate),
                                growth_rate_per_period: Some(a.growth_rate_per_period),
                                q_d: a.most_unstable_q_d(),
                                t_disorder: a.t_disorder_predicted,
                                ..cell(a.c0_over_u)
                            }
                        } else {
                            GrowthCell {
                                note: Some(
                                    "every sector's run failed: the perfect lattice does not last at this c0"
                                        .into(),
                                ),
                                ..cell(a.c0_over_u)
                            }
                        }
                    })),
                }
            }
        }
    }
    Ok(Some(out))
}
