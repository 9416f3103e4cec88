//! One c0 run from every start of the search: the perfect lattice and the
//! jittered seeds, each to the stationary horizon; the seeds pooled into
//! one class (docs/stationary.md). The runs themselves are made by the
//! engine's queue ([`super::queue`]), once per (c0, start), so a c0 that two
//! questions ask (a probe and a rule) is run once.

use serde::Serialize;

use super::Search;
use crate::config::{C0Spec, ClassRules, Scene};
use crate::problem::horizon::HorizonKind;
use crate::solver::{classify, Class, Outcome, Regime, RunResult};

/// One start's run at one c0: its class and the window's statistics.
#[derive(Debug, Clone, Serialize)]
pub struct StartRun {
    /// Jitter amplitude in d (0: the perfect lattice) and seed.
    pub jitter: f64,
    pub seed: u32,
    pub class: Class,
    /// Why it failed (None: it did not).
    pub failure: Option<String>,
    pub eps_stat: f64,
    pub eps_max_mean: f64,
    pub linf_stat: f64,
    pub rms_v_stat: f64,
    pub dy_rms: f64,
    pub regime: Regime,
    pub stationary: bool,
    /// The time the run reached: the checkpoint it stopped at, the cap, or
    /// its failure.
    pub t: f64,
    /// The first output time it had left its lattice (dy_rms >= 0.1 d).
    pub t_disorder: Option<f64>,
    /// The window it was judged on.
    pub window: (f64, f64),
    pub steps: u64,
    pub wall_s: f64,
    /// (t, eps_p99, max_eps, dy_rms) at every frame: the run's history.
    #[serde(skip)]
    pub series: Vec<[f64; 4]>,
}

impl StartRun {
    pub(super) fn of(r: &RunResult, rules: &ClassRules) -> StartRun {
        let w = &r.window;
        StartRun {
            jitter: r.problem.jitter,
            seed: r.problem.scene.jitter_seed,
            class: r.class(rules),
            failure: match &r.outcome {
                Outcome::Failed { failure, t, .. } => Some(format!("{failure} at t = {t:.4}")),
                _ => None,
            },
            eps_stat: w.eps_stat,
            eps_max_mean: w.eps_max_mean,
            linf_stat: w.linf_stat,
            rms_v_stat: w.rms_v_stat / r.problem.flow.u,
            dy_rms: w.dy_rms,
            regime: w.regime,
            stationary: w.stationary,
            t: r.t,
            t_disorder: r.t_disorder,
            window: (w.from, w.to),
            steps: r.steps,
            wall_s: r.wall_s,
            series: r
                .samples
                .iter()
                .map(|s| [s.t, s.eps_p99, s.max_eps, s.dy_rms])
                .collect(),
        }
    }
}

/// The seeds of one c0 as one: failed if any failed; else the means of
/// their window statistics, classified as a run is.
#[derive(Debug, Clone, Serialize)]
pub struct Pooled {
    pub class: Class,
    /// The first failed seed's reason.
    pub failure: Option<String>,
    /// Means over the seeds, and the spread of eps_stat.
    pub eps_stat: f64,
    pub linf_stat: f64,
    pub eps_stat_min: f64,
    pub eps_stat_max: f64,
    pub seeds: usize,
    /// Seeds whose window was stationary, and those disordered.
    pub stationary: usize,
    pub disordered: usize,
    /// Mean time to disorder over the seeds that disordered.
    pub t_disorder: Option<f64>,
}

impl Pooled {
    /// Every seed stationary and disordered: a point of the disordered law.
    pub fn settled(&self) -> bool {
        self.class != Class::Failed
            && self.stationary == self.seeds
            && self.disordered == self.seeds
    }
}

/// Pool `runs` (the seeds of one c0) under `rules` and the bound `eps_bound`.
pub fn pool(runs: &[StartRun], rules: &ClassRules, eps_bound: f64) -> Pooled {
    let n = runs.len() as f64;
    let mean = |f: &dyn Fn(&StartRun) -> f64| runs.iter().map(f).sum::<f64>() / n;
    let eps_stat = mean(&|r| r.eps_stat);
    let linf_stat = mean(&|r| r.linf_stat);
    let failed = runs.iter().find(|r| r.class == Class::Failed);
    let disordered: Vec<f64> = runs.iter().filter_map(|r| r.t_disorder).collect();
    Pooled {
        class: match failed {
            Some(_) => Class::Failed,
            None => classify(linf_stat, eps_stat, rules.linf_bound, eps_bound),
        },
        failure: failed.and_then(|r| r.failure.clone()),
        eps_stat,
        linf_stat,
        eps_stat_min: runs
            .iter()
            .map(|r| r.eps_stat)
            .fold(f64::INFINITY, f64::min),
        eps_stat_max: runs
            .iter()
            .map(|r| r.eps_stat)
            .fold(f64::NEG_INFINITY, f64::max),
        seeds: runs.len(),
        stationary: runs.iter().filter(|r| r.stationary).count(),
        disordered: runs
            .iter()
            .filter(|r| r.regime == Regime::Disordered)
            .count(),
        t_disorder: (!disordered.is_empty())
            .then(|| disordered.iter().sum::<f64>() / disordered.len() as f64),
    }
}

/// One c0 on the perfect lattice, or on every seed, or both.
#[derive(Debug, Clone, Serialize)]
pub struct Trial {
    pub c0: f64,
    pub c0_over_u: f64,
    /// The perfect lattice: the ordered regime while it lasts (None: not
    /// run at this c0).
    pub perfect: Option<StartRun>,
    /// The seeds pooled: the answer's class (None: not run at this c0).
    pub pooled: Option<Pooled>,
    pub seeds: Vec<StartRun>,
}

impl Trial {
    fn runs(&self) -> impl Iterator<Item = &StartRun> {
        self.perfect.iter().chain(&self.seeds)
    }
    /// Steps of every run, and their wall-clock seconds summed (they overlap).
    pub fn steps(&self) -> u64 {
        self.runs().map(|r| r.steps).sum()
    }
    pub fn wall_s(&self) -> f64 {
        self.runs().map(|r| r.wall_s).sum()
    }
}

/// Which starts a trial runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Starts {
    /// The perfect lattice alone.
    Perfect,
    /// The jittered seeds alone.
    Seeds,
    Both,
}

/// The starts of a trial: the perfect lattice (seed 0) and seeds 1..=n.
pub fn starts(search: &Search, which: Starts) -> Vec<(f64, u32)> {
    let perfect = (which != Starts::Seeds).then_some((0.0, 0));
    let seeds = (which != Starts::Perfect)
        .then(|| (1..=search.seeds).map(|s| (search.amplitude, s)))
        .into_iter()
        .flatten();
    perfect.into_iter().chain(seeds).collect()
}

/// The scene a start runs: c0 set, the stationary horizon, the jitter.
pub fn start_scene(scene: &Scene, c0: f64, (jitter, seed): (f64, u32)) -> Scene {
    let mut s = scene.clone();
    s.c0 = C0Spec::Value(c0);
    s.horizon = HorizonKind::Stationary;
    s.t_end = None;
    s.jitter = jitter;
    s.jitter_seed = seed;
    s
}
