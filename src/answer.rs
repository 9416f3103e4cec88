//! The answer for one scene (`shearsph c0 --empirical`): the smallest c0
//! that is `ok` on the perfect lattice and on every seed of a perturbed one,
//! by bisection on log c0 with the solver in the loop, and every rule's c0
//! run the same way beside it.
//!
//! What makes it fast without changing what it means:
//! - a run stops at the first output time its class is no longer `ok` (its
//!   L_inf error above `linf_bound`, or its compaction above its bound): the
//!   class is the worst over the output times, so such a run can never end
//!   `ok`. Its class is the one seen then, and `decided_t` says when (run
//!   on, it could only have got worse: over-compressed or failed);
//!   `--full` runs every run to its end for the final classes;
//! - the perturbed seeds of one c0 stop as soon as one of them is not ok
//!   (their outcome is the worst over the seeds: not ok already); the
//!   perfect lattice's run goes on to its own verdict;
//! - every run is one thread, and all the runs of a phase (a trial's
//!   starts, every rule's starts) share the cores;
//! - a c0 already run (10 U is the first probe and `rule10`; `morris1997`
//!   is often 10 U too) is run once.

use std::collections::HashMap;
use std::sync::atomic::{AtomicBool, Ordering};

use anyhow::{bail, Result};
use indicatif::ProgressBar;
use rayon::prelude::*;
use serde::Serialize;

use crate::config::{C0Spec, ClassRules, Scene};
use crate::problem::c0::{all_rules, by_rule};
use crate::problem::channel::Channel;
use crate::run::run_scene;
use crate::solver::{Class, Observer, Outcome, Sample};

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
    /// Run every run to its end (the final classes) instead of stopping it
    /// when it is decided not ok.
    pub full: bool,
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
            full: false,
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
    /// When the perfect run was stopped as not ok (None: it ran to its end
    /// or failed there): its class is the one seen at that time.
    pub decided_t_perfect: Option<f64>,
    /// When the perturbed seeds were stopped as not ok (None: every seed ran
    /// to its end or failed there).
    pub decided_t_perturbed: Option<f64>,
    /// The worst L_inf error (relative to U) over all the runs, up to where
    /// each stopped.
    pub linf: f64,
    /// Steps of the perfect run (to where it stopped).
    pub steps: u64,
    /// Steps of the perfect run to t_end: taken, or extrapolated from the
    /// time it stopped at (steps x t_end / t).
    pub steps_to_end: f64,
    /// Wall-clock seconds of all the runs, summed (they overlap).
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
    /// See [`Trial::decided_t_perfect`].
    pub decided_t_perfect: Option<f64>,
    pub decided_t_perturbed: Option<f64>,
    pub linf: f64,
    pub steps: u64,
    pub wall_s: f64,
    /// Steps to t_end relative to the recommended c0's perfect run.
    pub cost_rel: f64,
}

/// The bisection alone: the smallest c0 ok on every start and its bracket.
#[derive(Debug, Clone, Serialize)]
pub struct Bisection {
    /// The smallest c0 found ok on every start (None: none in the bracket).
    pub c0_min_ok: Option<f64>,
    /// The largest c0 found not ok below it (None: ok down to the lowest
    /// probe, or nothing ok).
    pub c0_max_not_ok: Option<f64>,
    pub trials: Vec<Trial>,
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

/// Watches one run's output times and asks it to stop once its class can
/// no longer be `ok` (see the module's notes), or once a sibling perturbed
/// seed was found not ok.
struct Decider<'a> {
    rules: ClassRules,
    /// The discretisation's over-compression bound (its eps0 + margin).
    kernel_bound: f64,
    jittered: bool,
    /// This run's bound, set at its first (t = 0) sample as
    /// `RunResult::eps_bound` sets it.
    eps_bound: Option<f64>,
    full: bool,
    verdict: Option<(Class, f64)>,
    /// Set when a perturbed seed of the same c0 is not ok (None: the perfect
    /// lattice's run, which goes on alone).
    siblings: Option<&'a AtomicBool>,
}

impl Observer for Decider<'_> {
    fn output(&mut self, s: &Sample) {
        let (kernel, margin, jittered) = (self.kernel_bound, self.rules.eps_margin, self.jittered);
        let eps_bound = *self.eps_bound.get_or_insert_with(|| {
            if jittered {
                kernel.max(s.max_eps + margin)
            } else {
                kernel
            }
        });
        if self.full || self.verdict.is_some() {
            return;
        }
        // classify()'s order: over-compressed before inaccurate; a NaN is
        // left to the solver, which fails the run on it.
        let class = if s.max_eps > eps_bound {
            Class::OverCompressed
        } else if s.linf_rel_err > self.rules.linf_bound {
            Class::Inaccurate
        } else {
            return;
        };
        self.verdict = Some((class, s.t));
        if let Some(flag) = self.siblings {
            flag.store(true, Ordering::Relaxed);
        }
    }

    fn should_stop(&self) -> bool {
        self.verdict.is_some()
            || self
                .siblings
                .is_some_and(|f| !self.full && f.load(Ordering::Relaxed))
    }
}

/// One run's result for a trial.
struct StartRun {
    /// None: stopped, undecided, because a sibling seed was not ok.
    class: Option<Class>,
    decided_t: Option<f64>,
    linf: f64,
    steps: u64,
    steps_to_end: f64,
    wall_s: f64,
}

/// The perfect lattice (jitter 0) and the perturbed seeds of a trial.
fn starts(search: &Search) -> Vec<(f64, u32)> {
    std::iter::once((0.0, 0))
        .chain((1..=search.seeds).map(|s| (search.amplitude, s)))
        .collect()
}

/// Run the starts of every c0 in `c0s` (all at once, each run on one
/// thread), ticking `bar` per run; one [`Trial`] per c0, in order.
pub fn trials(
    scene: &Scene,
    c0s: &[f64],
    search: &Search,
    bar: &ProgressBar,
) -> Result<Vec<Trial>> {
    let starts = starts(search);
    let flags: Vec<AtomicBool> = c0s.iter().map(|_| AtomicBool::new(false)).collect();
    let jobs: Vec<(usize, usize)> = (0..c0s.len())
        .flat_map(|i| (0..starts.len()).map(move |j| (i, j)))
        .collect();
    let info = scene.kernel_info()?;
    let runs: Vec<Result<StartRun>> = jobs
        .par_iter()
        .map(|&(i, j)| {
            let (jitter, seed) = starts[j];
            let mut s = scene.clone();
            s.c0 = C0Spec::Value(c0s[i]);
            s.jitter = jitter;
            s.jitter_seed = seed;
            let rules = s.classes();
            let disc = s.discretisation(info)?;
            let mut obs = Decider {
                rules,
                kernel_bound: rules.eps_bound(disc),
                jittered: jitter > 0.0,
                eps_bound: None,
                full: search.full,
                verdict: None,
                siblings: (jitter > 0.0).then_some(&flags[i]),
            };
            // One thread per run: the runs of a phase share the cores.
            let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build()?;
            let r = pool.install(|| run_scene(&s, &mut obs))?;
            bar.inc(1);
            let (class, decided_t) = match (&r.outcome, obs.verdict) {
                (Outcome::Interrupted { .. }, Some((c, t))) => (Some(c), Some(t)),
                (Outcome::Interrupted { .. }, None) => (None, None),
                _ => (Some(r.class(&rules)), None),
            };
            let steps_to_end = if r.t > 0.0 && r.t < r.problem.t_end {
                r.steps as f64 * r.problem.t_end / r.t
            } else {
                r.steps as f64
            };
            Ok(StartRun {
                class,
                decided_t,
                linf: r.linf_rel_err_max(),
                steps: r.steps,
                steps_to_end,
                wall_s: r.wall_s,
            })
        })
        .collect();
    let mut runs = runs.into_iter().collect::<Result<Vec<_>>>()?.into_iter();
    let per = starts.len();
    Ok(c0s
        .iter()
        .map(|&c0| {
            let rs: Vec<StartRun> = runs.by_ref().take(per).collect();
            let perfect = &rs[0];
            let seeds = &rs[1..];
            let linf = rs.iter().map(|r| r.linf).fold(0.0, crate::format::nan_max);
            let worst = seeds.iter().filter_map(|r| r.class).max();
            Trial {
                c0,
                outcome_perfect: perfect.class.unwrap_or(Class::Failed),
                outcome_perturbed: worst.or(perfect.class).unwrap_or(Class::Failed),
                decided_t_perfect: perfect.decided_t,
                decided_t_perturbed: seeds.iter().filter_map(|r| r.decided_t).reduce(f64::min),
                linf,
                steps: perfect.steps,
                steps_to_end: perfect.steps_to_end,
                wall_s: rs.iter().map(|r| r.wall_s).sum(),
            }
        })
        .collect())
}

/// Run `scene` at `c0` on the perfect lattice and `search.seeds` perturbed
/// ones (in parallel); each finished run ticks `bar`.
pub fn trial(scene: &Scene, c0: f64, search: &Search, bar: &ProgressBar) -> Result<Trial> {
    Ok(trials(scene, &[c0], search, bar)?.remove(0))
}

fn check(search: &Search) -> Result<()> {
    search.check(|field| format!("--{}", field.replace('_', "-")))
}

impl Search {
    /// Every number of the search in its range, finite; `name` gives how the
    /// caller calls a field (a flag, or a config file's field), for the
    /// message.
    pub fn check(&self, name: impl Fn(&str) -> String) -> Result<()> {
        if !(self.amplitude > 0.0 && self.amplitude < 0.5) {
            bail!(
                "{} = {} (in d) must be in (0, 0.5)",
                name("amplitude"),
                self.amplitude
            );
        }
        if self.seeds == 0 {
            bail!(
                "{} = 0: at least one perturbed seed is needed (the answer is the smallest c0 ok on every seed)",
                name("seeds")
            );
        }
        for (field, v, ok) in [
            ("margin", self.margin, self.margin >= 1.0),
            ("rel_tol", self.rel_tol, self.rel_tol > 0.0),
            ("lo_over_u", self.lo_over_u, self.lo_over_u > 0.0),
            ("hi_over_u", self.hi_over_u, self.hi_over_u > self.lo_over_u),
        ] {
            if !(ok && v.is_finite()) {
                bail!(
                    "{} = {v} must be a finite number ({})",
                    name(field),
                    match field {
                        "margin" => "at least 1",
                        "rel_tol" => "positive",
                        "lo_over_u" => "positive: the bracket's low end, in U",
                        _ => "above the bracket's low end lo_over_u, in U",
                    }
                );
            }
        }
        Ok(())
    }
}

/// The trials the bisection takes at most, for a progress bar's length.
pub fn bisection_trials(search: &Search) -> u64 {
    let probes = (2.0 * (search.hi_over_u / search.lo_over_u).log10()).ceil() as u64 + 1;
    probes.min(4)
        + ((10f64.sqrt().ln() / (1.0 + search.rel_tol).ln())
            .log2()
            .ceil() as u64)
}

/// Bisect on log c0 for the smallest c0 ok on every start: down from the
/// top of the bracket by factors of sqrt(10) to the first c0 ok on every
/// start (a c0 too large is inaccurate: the artificial viscosity grows with
/// it), then down to the first that is not, then bisect between the two.
/// Every trial is kept in `cache` by its c0.
pub fn bisect(
    scene: &Scene,
    search: &Search,
    bar: &ProgressBar,
    cache: &mut HashMap<u64, Trial>,
) -> Result<Bisection> {
    check(search)?;
    let info = scene.kernel_info()?;
    let u = Channel::resolve(scene, info)?.flow.u;
    let mut run = |c: f64| -> Result<Trial> {
        let t = trial(scene, c, search, bar)?;
        cache.insert(c.to_bits(), t.clone());
        Ok(t)
    };
    let mut trials = Vec::new();
    let factor = 10f64.sqrt();
    let mut c = search.hi_over_u * u;
    let mut hi: Option<f64> = None;
    let mut lo = None;
    while c >= search.lo_over_u * u * (1.0 - 1e-12) {
        let t = run(c)?;
        let ok = t.ok();
        trials.push(t);
        match (hi, ok) {
            (_, true) => hi = Some(c),
            (Some(_), false) => {
                lo = Some(c);
                break;
            }
            (None, false) => {}
        }
        c /= factor;
    }
    if let (Some(h), Some(l)) = (hi.as_mut(), lo.as_mut()) {
        while *h / *l > 1.0 + search.rel_tol {
            let mid = (*h * *l).sqrt();
            let t = run(mid)?;
            if t.ok() {
                *h = mid;
            } else {
                *l = mid;
            }
            trials.push(t);
        }
    }
    Ok(Bisection {
        c0_min_ok: hi,
        c0_max_not_ok: lo.filter(|_| hi.is_some()),
        trials,
    })
}

/// Bisect on log c0 for the smallest c0 ok on every start, then run every
/// rule the same way (all the rules' runs at once; a c0 already run is
/// taken from the bisection).
pub fn answer(scene: &Scene, search: &Search, bar: &ProgressBar) -> Result<Answer> {
    check(search)?;
    let info = scene.kernel_info()?;
    let channel = Channel::resolve(scene, info)?;
    let u = channel.flow.u;
    let per_trial = u64::from(search.seeds) + 1;
    let rules = all_rules(info);
    bar.set_length(per_trial * (bisection_trials(search) + rules.len() as u64 + 1));

    let mut cache = HashMap::new();
    let b = bisect(scene, search, bar, &mut cache)?;
    let recommended = b.c0_min_ok.map(|c| c * search.margin);

    let mut named: Vec<(String, f64)> = Vec::new();
    if let Some(c) = recommended {
        named.push(("empirical".into(), c));
    }
    for rule in &rules {
        let (c0, name) = by_rule(rule, info, &channel, scene.alpha)?;
        named.push((name, c0));
    }
    let runnable = |c0: f64| c0 > 0.0 && c0.is_finite();
    // Each c0 once: not yet run, and not twice among the rules.
    let mut todo: Vec<f64> = Vec::new();
    for &(_, c0) in &named {
        if runnable(c0) && !cache.contains_key(&c0.to_bits()) && !todo.contains(&c0) {
            todo.push(c0);
        }
    }
    let skipped = named.iter().filter(|(_, c)| !runnable(*c)).count() as u64;
    let reused = named.len() as u64 - skipped - todo.len() as u64;
    bar.inc(per_trial * (skipped + reused));
    for t in trials(scene, &todo, search, bar)? {
        cache.insert(t.c0.to_bits(), t);
    }
    let base = recommended
        .and_then(|c| cache.get(&c.to_bits()))
        .map(|t| t.steps_to_end);
    let answers = named
        .into_iter()
        .map(|(name, c0)| {
            let t = runnable(c0).then(|| &cache[&c0.to_bits()]);
            rule_answer(name, c0, u, t, base)
        })
        .collect();
    Ok(Answer {
        kernel: info.name.to_string(),
        n_layers: scene.n_layers,
        re: channel.re,
        alpha: scene.alpha,
        u,
        search: *search,
        c0_min_ok: b.c0_min_ok,
        recommended,
        c0_max_not_ok: b.c0_max_not_ok,
        bisection: b.trials,
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
        decided_t_perfect: t.and_then(|t| t.decided_t_perfect),
        decided_t_perturbed: t.and_then(|t| t.decided_t_perturbed),
        linf: t.map_or(f64::NAN, |t| t.linf),
        steps: t.map_or(0, |t| t.steps),
        wall_s: t.map_or(0.0, |t| t.wall_s),
        cost_rel: match (t, base) {
            (Some(t), Some(b)) if b > 0.0 => t.steps_to_end / b,
            _ => f64::NAN,
        },
    }
}

/// The scene with its c0 resolved when it is `[F*]empirical`: the
/// bisection first (its runs tick `bar`), then c0 = F x the recommended
/// c0 (the smallest ok on every start times `search.margin`); any other c0
/// is left as it is (None: nothing ran).
pub fn resolve_empirical(
    scene: &Scene,
    search: &Search,
    bar: &ProgressBar,
) -> Result<Option<(Scene, Bisection)>> {
    let C0Spec::Rule {
        factor,
        rule: crate::config::C0Rule::Empirical,
    } = scene.c0
    else {
        return Ok(None);
    };
    // everything but c0 valid before the first run
    crate::problem::c0::table(scene)?;
    bar.set_length((u64::from(search.seeds) + 1) * bisection_trials(search));
    let b = bisect(scene, search, bar, &mut HashMap::new())?;
    let Some(min) = b.c0_min_ok else {
        bail!(
            "c0 = {}: no c0 from {} U to {} U is ok on the perfect lattice and on every one of {} \
             starts jittered by {} d, so there is no empirical c0 for this scene; give a number or \
             another rule (`shearsph c0 --empirical` shows every trial)",
            scene.c0,
            search.lo_over_u,
            search.hi_over_u,
            search.seeds,
            search.amplitude
        );
    };
    let mut s = scene.clone();
    s.c0 = C0Spec::Value(factor * min * search.margin);
    Ok(Some((s, b)))
}
