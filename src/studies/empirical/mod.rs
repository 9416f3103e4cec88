//! The solver's answer for one scene, the one engine every command asks
//! (`c0 --empirical`, `run --c0 empirical`, `law`, the report): the
//! smallest c0 whose stationary, disordered state (the jittered seeds
//! pooled, docs/stationary.md) is `ok`, found by [`search`]; beside it the
//! ordered regime (the perfect lattice, the paper's analysis while it
//! lasts), the disordered law eps_stat = k (U / c0)^m ([`law`]), how long
//! the order lasts, and, when no c0 works, which limit binds and what would
//! allow one ([`diagnose`]). Every rule's c0 is run the same way beside it.

pub mod diagnose;
pub mod law;
pub mod queue;
pub mod search;
pub mod trial;

use std::sync::atomic::AtomicBool;

use anyhow::{bail, Result};
use indicatif::ProgressBar;
use serde::Serialize;

use crate::config::{C0Rule, C0Spec, Scene};
use crate::problem::c0::{all_rules_on, by_rule};
use crate::problem::channel::Channel;
use crate::problem::Problem;
use crate::solver::Class;
pub use diagnose::Diagnosis;
pub use law::DisorderedLaw;
pub use queue::{Priority, RunQueue};
pub use search::{Bracket, OkBand, Regime};
pub use trial::{Pooled, StartRun, Starts, Trial};

/// How the answer is searched.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Search {
    /// Jitter of the perturbed starts, in d.
    pub amplitude: f64,
    /// Perturbed starts (seeds 1..=seeds), pooled.
    pub seeds: u32,
    /// The recommended c0 is the smallest ok one times this, when that is
    /// ok too ([`OkBand::recommended`]).
    pub margin: f64,
    /// The bisection stops when its bracket is narrower than this ratio - 1.
    pub rel_tol: f64,
    /// The first probe and the bounds of the search, in units of U.
    pub first_over_u: f64,
    pub lo_over_u: f64,
    pub hi_over_u: f64,
}

/// The most seeds a search takes: each is a run of the scene at every c0
/// probed, and past a few dozen the pooled mean's noise no longer shrinks
/// enough to pay for them.
pub const MAX_SEEDS: u32 = 64;
/// The smallest relative tolerance: the pooled statistics of a c0 vary by a
/// few per cent from seed to seed, so a bisection finer than 0.1 % would
/// chase noise (and below 2.2e-16, 1 + tol == 1 would never end it).
pub const MIN_REL_TOL: f64 = 1e-3;
/// The widest bracket, hi / lo.
pub const MAX_SPAN: f64 = 1e6;

impl Default for Search {
    fn default() -> Self {
        Search {
            amplitude: 0.05,
            seeds: 3,
            margin: 1.5,
            rel_tol: 0.1,
            first_over_u: 10.0,
            lo_over_u: 0.01,
            hi_over_u: 100.0,
        }
    }
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
        if !(1..=MAX_SEEDS).contains(&self.seeds) {
            bail!(
                "{} = {} must be from 1 to {MAX_SEEDS}: each seed is a run of the scene at every \
                 c0 the search probes (the answer pools the seeds' statistics)",
                name("seeds"),
                self.seeds
            );
        }
        for (field, v, ok, what) in [
            (
                "margin",
                self.margin,
                (1.0..=100.0).contains(&self.margin),
                "from 1 to 100",
            ),
            (
                "rel_tol",
                self.rel_tol,
                (MIN_REL_TOL..=10.0).contains(&self.rel_tol),
                "from 0.001 to 10: finer than 0.1 % is below the seeds' noise",
            ),
            (
                "lo_over_u",
                self.lo_over_u,
                self.lo_over_u > 0.0,
                "positive: the search's low end, in U",
            ),
            (
                "hi_over_u",
                self.hi_over_u,
                self.hi_over_u > self.lo_over_u && self.hi_over_u <= self.lo_over_u * MAX_SPAN,
                "above lo_over_u and at most 1e6 times it, in U",
            ),
            (
                "first_over_u",
                self.first_over_u,
                (self.lo_over_u..=self.hi_over_u).contains(&self.first_over_u),
                "between lo_over_u and hi_over_u, in U",
            ),
        ] {
            if !(ok && v.is_finite()) {
                bail!(
                    "{} = {} must be a finite number {what}",
                    name(field),
                    crate::format::fmt_value(v)
                );
            }
        }
        Ok(())
    }

    fn steps(&self, u: f64, law: Option<(f64, f64)>) -> search::Steps {
        search::Steps {
            first: self.first_over_u * u,
            lo: self.lo_over_u * u,
            hi: self.hi_over_u * u,
            rel_tol: self.rel_tol,
            law,
        }
    }
}

/// The horizon the answer's runs used.
#[derive(Debug, Clone, Serialize)]
pub struct HorizonUsed {
    /// The start-up allowance t_su and B / U.
    pub t_startup: f64,
    pub shear_time: f64,
    /// The first checkpoint and the cap (docs/stationary.md).
    pub first: f64,
    pub cap: f64,
    /// Runs, those whose window was stationary, those that failed, and the
    /// range of the times they reached (the others).
    pub runs: usize,
    pub stationary: usize,
    pub failed: usize,
    pub t_min: f64,
    pub t_max: f64,
}

/// How long the order lasted at one c0.
#[derive(Debug, Clone, Serialize)]
pub struct TimeToDisorder {
    pub c0: f64,
    /// The seeds' mean time to disorder (jitter `amplitude` d), and the
    /// perfect lattice's (None: still ordered at `perfect_t`).
    pub amplitude: f64,
    pub seeds: Option<f64>,
    pub perfect: Option<f64>,
    pub perfect_t: f64,
}

/// One rule's c0 run the same way.
#[derive(Debug, Clone, Serialize)]
pub struct RuleAnswer {
    pub name: String,
    /// None: the rule gives no c0 here (`not_applicable` says why).
    pub c0: Option<f64>,
    pub c0_over_u: Option<f64>,
    pub not_applicable: Option<String>,
    /// The perfect lattice's class, and the seeds' pooled one.
    pub ordered: Option<Class>,
    pub disordered: Option<Class>,
    pub eps_stat: f64,
    pub linf_stat: f64,
    /// Steps per unit time relative to the recommended c0's (or, with none,
    /// the smallest c0 that does not compress).
    pub cost_rel: f64,
    pub wall_s: f64,
}

/// The answer for one scene.
#[derive(Debug, Clone, Serialize)]
pub struct Answer {
    pub kernel: String,
    pub discretisation: String,
    pub n_layers: u32,
    pub re: f64,
    pub alpha: f64,
    pub u: f64,
    pub search: Search,
    pub horizon: HorizonUsed,
    /// The smallest c0 ok in the disordered regime.
    pub c0_min_ok: Option<f64>,
    /// The statistical uncertainty of that answer, relative: the standard
    /// error of the seeds' mean eps_stat - eps0+ at the answer's c0 (their
    /// spread over sqrt(seeds)), relative to the mean, over the law's m (2,
    /// Monaghan's, without a law): how far the boundary moves in c0 when
    /// the compaction moves by its error. The bisection's own tolerance
    /// comes on top.
    pub c0_rel_uncertainty: Option<f64>,
    /// The recommended c0, always one whose disordered run was ok: the
    /// smallest ok one times the margin when that is ok too, else the ok
    /// band's centre ([`OkBand::recommended`]); None with no c0 ok.
    pub recommended: Option<f64>,
    /// The ok band above the smallest ok c0, as far as the recommendation
    /// searched it.
    pub band: Option<OkBand>,
    pub disordered: Bracket,
    pub ordered: Bracket,
    pub law: Option<DisorderedLaw>,
    pub time_to_disorder: Option<TimeToDisorder>,
    pub diagnosis: Option<Diagnosis>,
    /// Every trial, by c0.
    pub trials: Vec<Trial>,
    pub rules: Vec<RuleAnswer>,
}

/// What the engine is asked besides the search.
#[derive(Debug, Clone, Copy, Default)]
pub struct Extras {
    /// Run every rule's c0 too.
    pub rules: bool,
    /// The ordered regime's own search (the perfect lattice).
    pub ordered: bool,
    /// Ladder points about the answer for the law (c0_min x 2^(+-1/2),
    /// 2^(+-1)).
    pub law_ladder: bool,
}

/// Check `scene` (everything but c0) and `search` before the first run.
fn check(scene: &Scene, search: &Search) -> Result<()> {
    crate::problem::c0::table(scene)?;
    search.check(|field| format!("--{}", field.replace('_', "-")))?;
    // The horizon itself must resolve (a scene too long for the cap, say).
    let probe = trial::start_scene(scene, search.first_over_u * scene.u, (search.amplitude, 1));
    Problem::resolve(&probe, scene.kernel_info()?)?;
    Ok(())
}

/// The answer for `scene`: the disordered search, then what `extras` ask.
/// `stop` ends it (an error, "interrupted"); each run ticks `bar`.
pub fn answer(
    scene: &Scene,
    search: &Search,
    extras: Extras,
    stop: &AtomicBool,
    bar: &ProgressBar,
) -> Result<Answer> {
    check(scene, search)?;
    let info = scene.kernel_info()?;
    let channel = Channel::resolve(scene, info)?;
    let disc = channel.discretisation;
    let u = channel.flow.u;
    let eps0 = disc.eps.max.value.max(0.0);
    let bound = scene.classes().eps_bound(disc);
    // The rules' c0s: they do not depend on the search, so their runs are
    // queued from the start, behind the searches' (a c0 a probe also asks
    // is run once).
    let rules = all_rules_on(info, disc);
    let named: Vec<(String, Result<f64, String>)> = if extras.rules {
        rules
            .iter()
            .map(|rule| match by_rule(rule, info, &channel, scene.alpha) {
                Ok((c0, name)) if c0 > 0.0 && c0.is_finite() => (name, Ok(c0)),
                Ok((c0, name)) => {
                    let why = crate::problem::c0::no_c0_fact(rule, info, &channel)
                        .map(str::to_string)
                        .unwrap_or_else(|| format!("no positive c0 for this scene (c0 = {c0})"));
                    (name, Err(why))
                }
                Err(err) => (rule.to_string(), Err(err.to_string())),
            })
            .collect()
    } else {
        Vec::new()
    };
    let rule_c0s: Vec<f64> = named.iter().filter_map(|(_, c)| c.clone().ok()).collect();
    let q = RunQueue::new(scene, search, stop, bar);
    let dis_steps = search.steps(u, Some((eps0, bound)));
    // The searches' first probes first, then the rules' runs.
    q.ask(
        &q.runs_of(&[search::first(&dis_steps)], Starts::Seeds),
        Priority::Disordered,
    );
    if extras.ordered {
        q.ask(
            &q.runs_of(&[search::first(&search.steps(u, None))], Starts::Perfect),
            Priority::Ordered,
        );
    }
    q.ask(&q.runs_of(&rule_c0s, Starts::Both), Priority::Background);
    let (disordered, band, ordered, both, ladder) = queue::with_workers(&q, || -> Result<_> {
        // The two searches at once: the ordered one's single runs fill the
        // cores the disordered one's seeds leave.
        let (disordered, ordered) = std::thread::scope(|s| {
            let ordered = extras.ordered.then(|| {
                s.spawn(|| {
                    search::search(Regime::Ordered, search.steps(u, None), &mut |c| {
                        q.trial(c, Starts::Perfect, Priority::Ordered)
                    })
                })
            });
            let mut seeds = |c| q.trial(c, Starts::Seeds, Priority::Disordered);
            // The search, then the ok band above its answer, as far as the
            // recommendation needs it (while the ordered search goes on).
            let disordered =
                search::search(Regime::Disordered, dis_steps, &mut seeds).and_then(|b| {
                    let band = b
                        .c0_min_ok
                        .map(|lo| {
                            search::ok_band(
                                Regime::Disordered,
                                lo,
                                search.margin,
                                search.rel_tol,
                                &mut seeds,
                            )
                        })
                        .transpose()?;
                    Ok((b, band))
                });
            if disordered.is_err() {
                // Nothing more is worth running: the ordered search ends.
                q.close();
            }
            let ordered =
                ordered.map(|h| h.join().unwrap_or_else(|p| std::panic::resume_unwind(p)));
            (disordered, ordered)
        });
        let (disordered, band) = disordered?;
        let ordered = match ordered {
            Some(o) => o?,
            None => Bracket {
                regime: Regime::Ordered,
                not_compressed: None,
                compressed: None,
                c0_min_ok: None,
                probes: Vec::new(),
            },
        };
        // The recommended c0 (or, with none, where compression ends) on
        // every start (how long the order lasts there), the law's ladder
        // about the answer on the seeds, and the rules' runs still to make.
        let recommended = band.as_ref().map(OkBand::recommended);
        let mut both = Vec::new();
        let mut ladder = Vec::new();
        if let Some(c) = recommended.or(disordered.not_compressed.map(|h| h.0)) {
            both.push(c);
        }
        if extras.law_ladder {
            if let Some((c, _)) = disordered.not_compressed {
                let r = 2f64.sqrt();
                ladder.extend([c / 2.0, c / r, c * r, c * 2.0].iter().copied());
            }
        }
        let mut rest = q.runs_of(&both, Starts::Both);
        rest.extend(q.runs_of(&ladder, Starts::Seeds));
        rest.extend(q.runs_of(&rule_c0s, Starts::Both));
        // With no c0 ok, the diagnosis checks another alpha at the smallest
        // c0 that does not compress. The seeds' trials below that c0 set
        // the alpha (diagnose::check_alpha): once they are made, the
        // check's seeds are queued with the rest, instead of run after it
        // (a rule above that c0 that turns out accurate makes the alpha the
        // scene's own, whose runs are made anyway).
        if let (None, Some((c_comp, _))) = (disordered.c0_min_ok, disordered.not_compressed) {
            let below: Vec<f64> = disordered
                .probes
                .iter()
                .chain(&ladder)
                .chain(&rule_c0s)
                .copied()
                .filter(|&c| c < c_comp)
                .collect();
            q.wait(&q.runs_of(&below, Starts::Seeds), Priority::Ordered)?;
            if let Some(alpha) = diagnose::check_alpha(scene, c_comp, &q.collect(&below)?) {
                rest.extend(q.runs_at(alpha, &[c_comp], Starts::Seeds));
            }
        }
        q.wait(&rest, Priority::Ordered)?;
        Ok((disordered, band, ordered, both, ladder))
    })?;
    let c0_min_ok = disordered.c0_min_ok;
    let recommended = band.as_ref().map(OkBand::recommended);
    // Every trial made, by c0 (a c0 asked twice is one trial).
    let mut all: Vec<f64> = disordered
        .probes
        .iter()
        .chain(band.iter().flat_map(|b| &b.probes))
        .chain(&ordered.probes)
        .chain(&both)
        .chain(&ladder)
        .chain(&rule_c0s)
        .copied()
        .collect();
    all.sort_by(f64::total_cmp);
    all.dedup();
    let trials = q.collect(&all)?;
    let by_c0 = |c: f64| trials.iter().find(|t| t.c0 == c);
    let law = law::fit(&trials.iter().collect::<Vec<_>>(), eps0);
    // Steps per unit time, of the perfect lattice's run.
    let rate = |t: &Trial| {
        t.perfect
            .as_ref()
            .map_or(f64::NAN, |p| p.steps as f64 / p.t.max(f64::MIN_POSITIVE))
    };
    let base = recommended
        .or(disordered.not_compressed.map(|h| h.0))
        .and_then(by_c0)
        .map(rate);
    let rule_answers = named
        .into_iter()
        .map(|(name, c)| match c {
            Ok(c0) => {
                let t = by_c0(c0).expect("every rule's c0 was run");
                RuleAnswer {
                    name,
                    c0: Some(c0),
                    c0_over_u: Some(c0 / u),
                    not_applicable: None,
                    ordered: t.perfect.as_ref().map(|p| p.class),
                    disordered: t.pooled.as_ref().map(|p| p.class),
                    eps_stat: t.pooled.as_ref().map_or(f64::NAN, |p| p.eps_stat),
                    linf_stat: t.pooled.as_ref().map_or(f64::NAN, |p| p.linf_stat),
                    cost_rel: base.map_or(f64::NAN, |b| rate(t) / b),
                    wall_s: t.wall_s(),
                }
            }
            Err(why) => RuleAnswer {
                name,
                c0: None,
                c0_over_u: None,
                not_applicable: Some(why),
                ordered: None,
                disordered: None,
                eps_stat: f64::NAN,
                linf_stat: f64::NAN,
                cost_rel: f64::NAN,
                wall_s: 0.0,
            },
        })
        .collect();
    let at = recommended
        .or(disordered.not_compressed.map(|h| h.0))
        .and_then(by_c0);
    let time_to_disorder = at.map(|t| TimeToDisorder {
        c0: t.c0,
        amplitude: search.amplitude,
        seeds: t.pooled.as_ref().and_then(|p| p.t_disorder),
        perfect: t.perfect.as_ref().and_then(|p| p.t_disorder),
        perfect_t: t.perfect.as_ref().map_or(f64::NAN, |p| p.t),
    });
    let diagnosis = match c0_min_ok {
        Some(_) => None,
        None => Some(diagnose::diagnose(
            scene,
            &channel,
            &disordered,
            &trials,
            law.as_ref(),
            &mut |alpha, c| match q.collect_at(alpha, &[c])?.remove(0) {
                t if t.pooled.is_some() => Ok(t),
                _ => {
                    let mut s = scene.clone();
                    s.alpha = alpha;
                    Ok(queue::trials(&s, search, &[c], Starts::Seeds, stop, bar)?.remove(0))
                }
            },
        )?),
    };
    let horizon = horizon_used(scene, search, &trials)?;
    let c0_rel_uncertainty = disordered
        .not_compressed
        .and_then(|(c, _)| by_c0(c))
        .and_then(|t| uncertainty(&t.seeds, eps0, law.as_ref().map_or(2.0, |l| l.m)));
    Ok(Answer {
        kernel: info.name.to_string(),
        discretisation: disc.label(),
        n_layers: scene.n_layers,
        re: channel.re,
        alpha: scene.alpha,
        u,
        search: *search,
        horizon,
        c0_min_ok,
        c0_rel_uncertainty,
        recommended,
        band,
        disordered,
        ordered,
        law,
        time_to_disorder,
        diagnosis,
        trials,
        rules: rule_answers,
    })
}

/// The relative uncertainty in c0 of a boundary at the seeds `runs` (see
/// [`Answer::c0_rel_uncertainty`]); None with fewer than two seeds.
fn uncertainty(runs: &[StartRun], eps0: f64, m: f64) -> Option<f64> {
    let x: Vec<f64> = runs.iter().map(|r| r.eps_stat - eps0).collect();
    let n = x.len() as f64;
    if x.len() < 2 || m.is_nan() || m <= 0.0 {
        return None;
    }
    let mean = x.iter().sum::<f64>() / n;
    let var = x.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
    let u = (var / n).sqrt() / mean / m;
    (u.is_finite() && mean > 0.0).then_some(u)
}

/// The horizon of the answer's runs.
fn horizon_used(scene: &Scene, search: &Search, trials: &[Trial]) -> Result<HorizonUsed> {
    let s = trial::start_scene(scene, search.first_over_u * scene.u, (search.amplitude, 1));
    let p = Problem::resolve(&s, s.kernel_info()?)?;
    let runs: Vec<&StartRun> = trials
        .iter()
        .flat_map(|t| t.perfect.iter().chain(&t.seeds))
        .collect();
    let reached = runs
        .iter()
        .filter(|r| r.class != Class::Failed)
        .map(|r| r.t);
    Ok(HorizonUsed {
        t_startup: p.horizon.t_startup,
        shear_time: p.horizon.shear_time,
        first: p.horizon.checkpoints[0],
        cap: p.horizon.cap(),
        runs: runs.len(),
        stationary: runs.iter().filter(|r| r.stationary).count(),
        failed: runs.iter().filter(|r| r.class == Class::Failed).count(),
        t_min: reached.clone().fold(f64::INFINITY, f64::min),
        t_max: reached.fold(f64::NEG_INFINITY, f64::max),
    })
}

/// The scene with its c0 resolved when it is `[F*]empirical`: the search
/// first (its runs tick `bar`), then c0 = F x the recommended c0; any other
/// c0 is left as it is (None: nothing ran).
pub fn resolve_empirical(
    scene: &Scene,
    search: &Search,
    stop: &AtomicBool,
    bar: &ProgressBar,
) -> Result<Option<(Scene, Answer)>> {
    let C0Spec::Rule {
        factor,
        rule: C0Rule::Empirical,
    } = scene.c0
    else {
        return Ok(None);
    };
    let a = answer(scene, search, Extras::default(), stop, bar)?;
    let Some(rec) = a.recommended else {
        bail!(
            "c0 = {}: no c0 from {} U to {} U is ok in the stationary, disordered state of {} \
             starts jittered by {} d, so there is no empirical c0 for this scene{}; give a number \
             or another rule (`shearsph c0 --empirical` shows every trial)",
            scene.c0,
            search.lo_over_u,
            search.hi_over_u,
            search.seeds,
            search.amplitude,
            a.diagnosis
                .as_ref()
                .map(|d| format!(" ({})", d.binds))
                .unwrap_or_default()
        );
    };
    let mut s = scene.clone();
    s.c0 = C0Spec::Value(factor * rec);
    Ok(Some((s, a)))
}
