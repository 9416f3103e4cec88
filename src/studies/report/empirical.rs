//! The empirical c0 in the report: for every kernel, verdict Re and
//! discretisation, the engine's answer ([`crate::empirical::answer`], the
//! one `c0 --empirical` gives for the same scene): the smallest c0 ok in
//! the stationary, disordered state (the report's perturbed case) and on
//! the perfect lattice (its perfect case, the ordered regime), with the
//! horizon, the disordered law and the diagnosis when none is ok.

use std::fmt::Write as _;
use std::sync::atomic::AtomicBool;
use std::sync::Arc;

use anyhow::Result;
use indicatif::ProgressBar;
use serde::Serialize;

use super::config::ReportConfig;
use super::plan::Case;
use crate::config::Scene;
use crate::empirical::{answer, Answer, Bracket, Extras, Regime, Search, Trial};
use crate::kernel::KernelInfo;
use crate::sweep::store::csv_field;
use crate::sweep::{Class, Discretisation, Parallel};

/// The run at an empirical c0.
#[derive(Debug, Clone, Serialize)]
pub struct AtRun {
    pub c0_over_u: f64,
    pub class: Class,
    /// The judged statistics (pooled over the seeds in the perturbed case).
    pub eps_stat: f64,
    pub linf_stat: f64,
    /// Steps per run (the perfect lattice's, or the seeds' mean) and
    /// wall-clock seconds summed.
    pub steps: u64,
    pub wall_s: f64,
}

/// The result for one kernel at one Re in one case.
#[derive(Debug, Clone, Serialize)]
pub struct Empirical {
    pub kernel: String,
    /// The kernel's index in [`ReportConfig::kernel_infos`] and the Re's in
    /// `empirical.re`: the keys the report joins by.
    #[serde(skip)]
    pub kernel_index: usize,
    #[serde(skip)]
    pub re_index: usize,
    /// The discretisation and start (perturbed: the disordered regime of
    /// the pooled seeds; perfect: the ordered regime).
    #[serde(skip)]
    pub case: Case,
    #[serde(skip)]
    pub disc: Discretisation,
    pub discretisation: String,
    pub n: u32,
    pub re: f64,
    pub alpha: f64,
    /// The smallest c0 / U found ok (None: none).
    pub c0_over_u: Option<f64>,
    /// The largest c0 / U below it found over-compressed or failed, and
    /// how that run ended (None: not compressed down to the search's low
    /// end).
    pub below: Option<f64>,
    pub below_class: Option<Class>,
    pub below_reason: Option<String>,
    pub rel_tol: f64,
    /// The c0 / U range that was tried.
    pub tried_min: f64,
    pub tried_max: f64,
    pub at: Option<AtRun>,
    /// The largest c0 / U of the block of ok trials from the answer up,
    /// and the first trial above it with its class (None: the block reaches
    /// the top trial).
    pub top: Option<f64>,
    pub above: Option<(f64, Class)>,
    /// The whole answer (shared by the two cases of a target).
    #[serde(skip)]
    pub answer: Arc<Answer>,
}

impl Empirical {
    /// Plain words: the answer, its bracket, how far up the ok runs reach.
    pub fn describe(&self) -> String {
        let regime = if self.case.perturbed {
            "in the stationary, disordered state"
        } else {
            "on the perfect lattice"
        };
        let mut t = match (self.c0_over_u, self.below) {
            (None, _) => {
                let why = self
                    .answer
                    .diagnosis
                    .as_ref()
                    .filter(|_| self.case.perturbed)
                    .map(|d| format!(" ({})", d.binds))
                    .unwrap_or_default();
                return format!(
                    "no c0 from {} U to {} U ran ok {regime}{why}",
                    fmt(self.tried_min),
                    fmt(self.tried_max)
                );
            }
            (Some(c), Some(b)) => format!(
                "the smallest c0 that ran ok {regime} is {} U (bisection to {} %: at {} U the run was {})",
                fmt(c),
                fmt(100.0 * self.rel_tol),
                fmt(b),
                self.below_reason.clone().unwrap_or_default()
            ),
            (Some(c), None) => format!("every c0 tried down to {} U ran ok {regime}", fmt(c)),
        };
        if let Some(at) = &self.at {
            t.push_str(&format!(
                "; at {} U: eps_stat {}, mean-flow error {} % of U",
                fmt(at.c0_over_u),
                fmt(at.eps_stat),
                fmt(100.0 * at.linf_stat)
            ));
        }
        match &self.above {
            Some((c, class)) => t.push_str(&format!(
                "; trials stayed ok up to {} U, and at {} U the run was {class}",
                fmt(self.top.unwrap_or(f64::NAN)),
                fmt(*c)
            )),
            None => t.push_str(&format!(
                "; every trial above it ran ok too, up to {} U",
                fmt(self.tried_max)
            )),
        }
        t
    }
}

fn fmt(v: f64) -> String {
    crate::format::fmt_num(v)
}

/// One target: a kernel at one Re on one discretisation.
struct Target {
    info: &'static KernelInfo,
    kernel: usize,
    /// Index into `empirical.re`.
    re_index: usize,
    re: f64,
    case_disc: super::plan::CaseDiscretisation,
}

/// The engine's search as the report configures it: the perturbed starts'
/// jitter and seeds, the bisection's tolerance, the rest `c0 --empirical`'s
/// defaults.
pub fn search(config: &ReportConfig) -> Search {
    Search {
        amplitude: config.perturbed.jitter,
        seeds: config.perturbed.seeds,
        rel_tol: config.empirical.rel_tol,
        ..Search::default()
    }
}

/// The scene of a target: the built-in scene, the report's `[scene]`, then
/// the kernel, N, Re, alpha and discretisation.
pub fn scene(
    config: &ReportConfig,
    kernel: &str,
    re: f64,
    disc: Discretisation,
) -> Result<Scene, crate::config::SceneError> {
    let mut over = config.scene.clone();
    over.insert("kernel".into(), toml::Value::String(kernel.into()));
    over.insert(
        "n_layers".into(),
        toml::Value::Integer(config.maps.n.into()),
    );
    over.insert("re".into(), toml::Value::Float(re));
    over.insert("alpha".into(), toml::Value::Float(config.maps.alpha));
    over.insert(
        "lattice".into(),
        toml::Value::String(disc.lattice.name().into()),
    );
    over.insert(
        "h_over_d".into(),
        toml::Value::String(disc.h_over_d.to_string()),
    );
    over.insert(
        "linf_bound".into(),
        toml::Value::Float(config.classes.linf_bound),
    );
    over.insert(
        "eps_margin".into(),
        toml::Value::Float(config.classes.eps_margin),
    );
    Scene::load(None, over)
}

/// The empirical c0 for every kernel at every `config.empirical.re` on
/// every discretisation the report runs, the targets in parallel (each
/// engine on its worker's threads). `None` when the stop flag cut it short.
pub fn find_all(
    config: &ReportConfig,
    infos: &[&'static KernelInfo],
    par: Parallel,
    stop: &AtomicBool,
    bar: &ProgressBar,
) -> Result<Option<Vec<Empirical>>> {
    let mut targets = Vec::new();
    let discs: Vec<super::plan::CaseDiscretisation> = {
        let mut v: Vec<_> = config.cases().iter().map(|c| c.disc).collect();
        v.dedup();
        v
    };
    for &case_disc in &discs {
        for (kernel, &info) in infos.iter().enumerate() {
            if case_disc.of(info).is_none() {
                continue;
            }
            for (re_index, &re) in config.empirical.re.iter().enumerate() {
                targets.push(Target {
                    info,
                    kernel,
                    re_index,
                    re,
                    case_disc,
                });
            }
        }
    }
    let s = search(config);
    let results = par.map(
        &targets,
        stop,
        |t| {
            let (disc, _) = t.case_disc.of(t.info)?;
            let scene = match scene(config, t.info.name, t.re, disc) {
                Ok(s) => s,
                Err(e) => return Some(Err(anyhow::Error::from(e))),
            };
            let extras = Extras {
                ordered: true,
                ..Extras::default()
            };
            match answer(&scene, &s, extras, stop, bar) {
                Ok(a) => Some(Ok(cases(config, t, disc, a))),
                Err(_) if stop.load(std::sync::atomic::Ordering::Relaxed) => None,
                Err(e) => Some(Err(e)),
            }
        },
        |_, _| {},
    )?;
    if results.iter().any(Option::is_none) {
        return Ok(None);
    }
    let mut out = Vec::new();
    for r in results.into_iter().flatten() {
        out.extend(r?);
    }
    Ok(Some(out))
}

/// The two cases of one answer: perfect (ordered) and perturbed
/// (disordered).
fn cases(config: &ReportConfig, t: &Target, disc: Discretisation, a: Answer) -> Vec<Empirical> {
    let a = Arc::new(a);
    let u = a.u;
    [false, true]
        .into_iter()
        .map(|perturbed| {
            let case = Case {
                disc: t.case_disc,
                perturbed,
            };
            let (regime, bracket): (Regime, &Bracket) = if perturbed {
                (Regime::Disordered, &a.disordered)
            } else {
                (Regime::Ordered, &a.ordered)
            };
            let trials: Vec<&Trial> = a
                .trials
                .iter()
                .filter(|t| match regime {
                    Regime::Ordered => t.perfect.is_some(),
                    Regime::Disordered => t.pooled.is_some(),
                })
                .collect();
            let class = |t: &Trial| regime.class(t);
            let c0_min = bracket.c0_min_ok;
            let at = c0_min.and_then(|c| trials.iter().find(|t| t.c0 == c));
            // The block of ok trials from the answer up.
            let (mut top, mut above) = (None, None);
            if let Some(c) = c0_min {
                for t in trials.iter().filter(|t| t.c0 >= c) {
                    if class(t) == Class::Ok {
                        top = Some(t.c0 / u);
                    } else {
                        above = Some((t.c0 / u, class(t)));
                        break;
                    }
                }
            }
            let below = bracket.compressed;
            let below_trial = below.and_then(|(c, _)| trials.iter().find(|t| t.c0 == c));
            Empirical {
                kernel: t.info.name.to_string(),
                kernel_index: t.kernel,
                re_index: t.re_index,
                case,
                disc,
                discretisation: a.discretisation.clone(),
                n: config.maps.n,
                re: t.re,
                alpha: config.maps.alpha,
                c0_over_u: c0_min.map(|c| c / u),
                below: below.map(|b| b.0 / u),
                below_class: below.map(|b| b.1),
                below_reason: below_trial.map(|t| reason(t, regime)),
                rel_tol: a.search.rel_tol,
                tried_min: trials.first().map_or(f64::NAN, |t| t.c0 / u),
                tried_max: trials.last().map_or(f64::NAN, |t| t.c0 / u),
                at: at.map(|t| at_run(t, regime)),
                top,
                above,
                answer: a.clone(),
            }
        })
        .collect()
}

fn at_run(t: &Trial, regime: Regime) -> AtRun {
    match regime {
        Regime::Ordered => {
            let p = t.perfect.as_ref().expect("an ordered trial");
            AtRun {
                c0_over_u: t.c0_over_u,
                class: p.class,
                eps_stat: p.eps_stat,
                linf_stat: p.linf_stat,
                steps: p.steps,
                wall_s: p.wall_s,
            }
        }
        Regime::Disordered => {
            let p = t.pooled.as_ref().expect("a disordered trial");
            AtRun {
                c0_over_u: t.c0_over_u,
                class: p.class,
                eps_stat: p.eps_stat,
                linf_stat: p.linf_stat,
                steps: t.seeds.iter().map(|s| s.steps).sum::<u64>() / t.seeds.len().max(1) as u64,
                wall_s: t.seeds.iter().map(|s| s.wall_s).sum(),
            }
        }
    }
}

/// A row's class with its reason or figures, in a few words.
pub fn row_reason(r: &crate::sweep::Row) -> String {
    match r.class {
        Class::Failed | Class::Interrupted => format!(
            "{}: {}",
            r.class,
            r.failure_reason.clone().unwrap_or_default()
        ),
        Class::OverCompressed => format!(
            "over-compressed: eps_stat {} above {}",
            fmt(r.eps_stat),
            fmt(r.eps_bound)
        ),
        Class::Inaccurate => format!(
            "inaccurate: mean-flow error {} % of U",
            fmt(100.0 * r.linf_stat)
        ),
        Class::Ok => format!("ok: mean-flow error {} % of U", fmt(100.0 * r.linf_stat)),
    }
}

/// A trial's class with its reason or figures, in a few words.
fn reason(t: &Trial, regime: Regime) -> String {
    let a = at_run(t, regime);
    let failure = match regime {
        Regime::Ordered => t.perfect.as_ref().and_then(|p| p.failure.clone()),
        Regime::Disordered => t.pooled.as_ref().and_then(|p| p.failure.clone()),
    };
    match a.class {
        Class::Failed | Class::Interrupted => format!("failed: {}", failure.unwrap_or_default()),
        Class::OverCompressed => format!("over-compressed: eps_stat {}", fmt(a.eps_stat)),
        Class::Inaccurate => format!(
            "inaccurate: mean-flow error {} % of U",
            fmt(100.0 * a.linf_stat)
        ),
        Class::Ok => format!("ok: mean-flow error {} % of U", fmt(100.0 * a.linf_stat)),
    }
}

pub fn csv(list: &[Empirical]) -> String {
    let mut out = String::from(
        "kernel,n,re,alpha,start,c0_over_u,below_c0_over_u,below_class,below_reason,rel_tol,tried_min,tried_max,eps_stat_at,linf_stat_at,wall_s_at,trials,lattice,h_over_d,law_k,law_m,binds\n",
    );
    let f = |v: Option<f64>| v.map_or(String::new(), |v| v.to_string());
    for e in list {
        let law = e.answer.law.as_ref().filter(|_| e.case.perturbed);
        let _ = writeln!(
            out,
            "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}",
            csv_field(&e.kernel),
            e.n,
            e.re,
            e.alpha,
            e.case.start_name(),
            f(e.c0_over_u),
            f(e.below),
            e.below_class.map_or(String::new(), |c| c.to_string()),
            csv_field(&e.below_reason.clone().unwrap_or_default()),
            e.rel_tol,
            e.tried_min,
            e.tried_max,
            f(e.at.as_ref().map(|r| r.eps_stat)),
            f(e.at.as_ref().map(|r| r.linf_stat)),
            f(e.at.as_ref().map(|r| r.wall_s)),
            e.answer.trials.len(),
            e.disc.lattice.name(),
            e.disc.h_over_d,
            f(law.map(|l| l.k)),
            f(law.map(|l| l.m)),
            csv_field(
                &e.answer
                    .diagnosis
                    .as_ref()
                    .filter(|_| e.case.perturbed)
                    .map_or(String::new(), |d| d.binds.clone())
            ),
        );
    }
    out
}

/// Every trial of every answer, one row per c0: perfect and pooled classes.
pub fn trials_csv(list: &[Empirical]) -> String {
    let mut out = String::from(
        "kernel,re,lattice,h_over_d,c0_over_u,perfect_class,perfect_eps_stat,perfect_linf_stat,pooled_class,pooled_eps_stat,pooled_eps_stat_min,pooled_eps_stat_max,pooled_linf_stat,stationary_seeds,disordered_seeds,seeds,t_disorder\n",
    );
    let f = |v: Option<f64>| v.map_or(String::new(), |v| v.to_string());
    for e in list.iter().filter(|e| e.case.perturbed) {
        for t in &e.answer.trials {
            let p = t.perfect.as_ref();
            let s = t.pooled.as_ref();
            let _ = writeln!(
                out,
                "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}",
                csv_field(&e.kernel),
                e.re,
                e.disc.lattice.name(),
                e.disc.h_over_d,
                t.c0_over_u,
                p.map_or(String::new(), |p| p.class.to_string()),
                f(p.map(|p| p.eps_stat)),
                f(p.map(|p| p.linf_stat)),
                s.map_or(String::new(), |s| s.class.to_string()),
                f(s.map(|s| s.eps_stat)),
                f(s.map(|s| s.eps_stat_min)),
                f(s.map(|s| s.eps_stat_max)),
                f(s.map(|s| s.linf_stat)),
                s.map_or(String::new(), |s| s.stationary.to_string()),
                s.map_or(String::new(), |s| s.disordered.to_string()),
                s.map_or(String::new(), |s| s.seeds.to_string()),
                f(s.and_then(|s| s.t_disorder)),
            );
        }
    }
    out
}
