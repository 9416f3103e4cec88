//! The answer for one scene (`shearsph c0 --empirical`): the smallest c0
//! that is `ok` on the perfect lattice and on every seed of a perturbed one,
//! by bisection on log c0 with the solver in the loop, and every rule's c0
//! run the same way beside it.

use std::time::Instant;

use anyhow::{bail, Result};
use indicatif::ProgressBar;
use rayon::prelude::*;
use serde::Serialize;

use crate::config::{C0Spec, Scene};
use crate::problem::c0::{all_rules, by_rule};
use crate::problem::channel::Channel;
use crate::run::run_scene;
use crate::solver::{Class, Quiet};

/// How the answer is searched.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct Search {
    /// Jitter of the perturbed starts, in d.
    pub amplitude: f64,
    /// Perturbed starts (seeds 1..=seeds), besides the perfect lattice.
    pub seeds: u32,
    /// The recommended c0 is the smallest ok one times this.
    pub margin: f64,
    /// The bisection stops when its bracket is narrower than this ratio - 1.
    pub rel_tol: f64,
    /// The bracket, in units of U.
    pub lo_over_u: f64,
    pub hi_over_u: f64,
}

impl Default for Search {
    fn default() -> Self {
        Search {
            amplitude: 0.05,
            seeds: 3,
            margin: 1.5,
            rel_tol: 0.1,
            lo_over_u: 0.01,
            hi_over_u: 10.0,
        }
    }
}

/// One c0 run on the perfect lattice and on every perturbed seed.
#[derive(Debug, Clone, Serialize)]
pub struct Trial {
    pub c0: f64,
    pub outcome_perfect: Class,
    /// The worst class over the seeds.
    pub outcome_perturbed: Class,
    /// The worst L_inf error (relative to U) over all the runs.
    pub linf: f64,
    /// Steps of the perfect run.
    pub steps: u64,
    /// Wall-clock seconds of all the runs.
    pub wall_s: f64,
}

impl Trial {
    pub fn ok(&self) -> bool {
        self.outcome_perfect == Class::Ok && self.outcome_perturbed == Class::Ok
    }
}

#[derive(Debug, Clone, Serialize)]
pub struct RuleAnswer {
    pub name: String,
    pub c0: f64,
    pub c0_over_u: f64,
    pub outcome_perfect: Option<Class>,
    pub outcome_perturbed: Option<Class>,
    pub linf: f64,
    pub steps: u64,
    pub wall_s: f64,
    /// Steps relative to the recommended c0's perfect run.
    pub cost_rel: f64,
}

#[derive(Debug, Clone, Serialize)]
pub struct Answer {
    pub kernel: String,
    pub n_layers: u32,
    pub re: f64,
    pub alpha: f64,
    pub u: f64,
    pub search: Search,
    /// The smallest c0 found ok on every start (None: none in the bracket).
    pub c0_min_ok: Option<f64>,
    /// c0_min_ok times the margin.
    pub recommended: Option<f64>,
    /// The largest c0 found not ok below it.
    pub c0_max_not_ok: Option<f64>,
    pub bisection: Vec<Trial>,
    pub rules: Vec<RuleAnswer>,
}

/// Run `scene` at `c0` on the perfect lattice and `search.seeds` perturbed
/// ones (in parallel); each finished run ticks `bar`.
pub fn trial(scene: &Scene, c0: f64, search: &Search, bar: &ProgressBar) -> Result<Trial> {
    let starts: Vec<(f64, u32)> = std::iter::once((0.0, 0))
        .chain((1..=search.seeds).map(|s| (search.amplitude, s)))
        .collect();
    let t0 = Instant::now();
    let runs: Vec<Result<(Class, f64, u64)>> = starts
        .par_iter()
        .map(|&(jitter, seed)| {
            let mut s = scene.clone();
            s.c0 = C0Spec::Value(c0);
            s.jitter = jitter;
            s.jitter_seed = seed;
            let r = run_scene(&s, &mut Quiet)?;
            bar.inc(1);
            Ok((r.class(&s.classes()), r.linf_rel_err_max(), r.steps))
        })
        .collect();
    let runs = runs.into_iter().collect::<Result<Vec<_>>>()?;
    let linf = runs
        .iter()
        .map(|r| r.1)
        .fold(0.0f64, |a, b| if b.is_nan() { f64::NAN } else { a.max(b) });
    Ok(Trial {
        c0,
        outcome_perfect: runs[0].0,
        outcome_perturbed: runs[1..].iter().map(|r| r.0).max().unwrap_or(runs[0].0),
        linf,
        steps: runs[0].2,
        wall_s: t0.elapsed().as_secs_f64(),
    })
}

/// Bisect on log c0 for the smallest c0 ok on every start, then run every
/// rule the same way.
pub fn answer(scene: &Scene, search: &Search, bar: &ProgressBar) -> Result<Answer> {
    if !(search.amplitude > 0.0 && search.amplitude < 0.5) {
        bail!(
            "--amplitude {} (in d) must be in (0, 0.5)",
            search.amplitude
        );
    }
    if !(search.margin >= 1.0 && search.rel_tol > 0.0) {
        bail!("--margin must be at least 1 and --rel-tol positive");
    }
    let info = scene.kernel_info()?;
    let channel = Channel::resolve(scene, info)?;
    let u = channel.flow.u;
    let per_trial = u64::from(search.seeds) + 1;
    // The probes down the bracket and the bisection's steps, as an estimate.
    let probes = (2.0 * (search.hi_over_u / search.lo_over_u).log10()).ceil() as u64 + 1;
    let steps = probes.min(4)
        + ((10f64.sqrt().ln() / (1.0 + search.rel_tol).ln())
            .log2()
            .ceil() as u64);
    let rules = all_rules(info);
    bar.set_length(per_trial * (steps + rules.len() as u64 + 1));

    // Down from the top of the bracket by factors of sqrt(10) to the first
    // c0 ok on every start (a c0 too large is inaccurate: the artificial
    // viscosity grows with it), then down to the first that is not, then
    // bisect between the two.
    let mut bisection = Vec::new();
    let factor = 10f64.sqrt();
    let mut c = search.hi_over_u * u;
    let mut hi: Option<Trial> = None;
    let mut lo_c0 = None;
    while c >= search.lo_over_u * u * (1.0 - 1e-12) {
        let t = trial(scene, c, search, bar)?;
        bisection.push(t.clone());
        match (&hi, t.ok()) {
            (_, true) => hi = Some(t),
            (Some(_), false) => {
                lo_c0 = Some(c);
                break;
            }
            (None, false) => {}
        }
        c /= factor;
    }
    let found = hi.is_some();
    if let (Some(h), Some(mut lo_c)) = (&mut hi, lo_c0) {
        while h.c0 / lo_c > 1.0 + search.rel_tol {
            let mid = (h.c0 * lo_c).sqrt();
            let t = trial(scene, mid, search, bar)?;
            bisection.push(t.clone());
            if t.ok() {
                *h = t;
            } else {
                lo_c = mid;
            }
        }
        lo_c0 = Some(lo_c);
    }
    let c0_min_ok = hi.as_ref().filter(|_| found).map(|h| h.c0);
    let recommended = c0_min_ok.map(|c| c * search.margin);
    let rec_trial = match recommended {
        Some(c) => Some(trial(scene, c, search, bar)?),
        None => None,
    };
    let base_steps = rec_trial.as_ref().map(|t| t.steps as f64);

    let mut named: Vec<(String, f64)> = Vec::new();
    for rule in &rules {
        let (c0, name) = by_rule(rule, info, &channel, scene.alpha)?;
        named.push((name, c0));
    }
    let mut answers = Vec::new();
    if let Some(t) = &rec_trial {
        answers.push(rule_answer(
            "empirical".into(),
            t.c0,
            u,
            Some(t),
            base_steps,
        ));
    }
    for (name, c0) in named {
        if c0 > 0.0 && c0.is_finite() {
            let t = trial(scene, c0, search, bar)?;
            answers.push(rule_answer(name, c0, u, Some(&t), base_steps));
        } else {
            bar.inc(per_trial);
            answers.push(rule_answer(name, c0, u, None, base_steps));
        }
    }
    Ok(Answer {
        kernel: info.name.to_string(),
        n_layers: scene.n_layers,
        re: channel.re,
        alpha: scene.alpha,
        u,
        search: *search,
        c0_min_ok,
        recommended,
        c0_max_not_ok: lo_c0,
        bisection,
        rules: answers,
    })
}

fn rule_answer(name: String, c0: f64, u: f64, t: Option<&Trial>, base: Option<f64>) -> RuleAnswer {
    RuleAnswer {
        name,
        c0,
        c0_over_u: c0 / u,
        outcome_perfect: t.map(|t| t.outcome_perfect),
        outcome_perturbed: t.map(|t| t.outcome_perturbed),
        linf: t.map_or(f64::NAN, |t| t.linf),
        steps: t.map_or(0, |t| t.steps),
        wall_s: t.map_or(0.0, |t| t.wall_s),
        cost_rel: match (t, base) {
            (Some(t), Some(b)) if b > 0.0 => t.steps as f64 / b,
            _ => f64::NAN,
        },
    }
}
