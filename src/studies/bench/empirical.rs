//! `shearsph bench --empirical`: the wall time of the empirical answer,
//! `c0 --empirical` with every rule beside it, on the scenes a user asks
//! first: Monaghan, N = 10, at Re = 1 and Re = 10 (the built-in scene
//! otherwise, the stationary horizon and the search's defaults). Each scene
//! is answered `repeats` times and the median wall time kept; beside it the
//! runs the answer made, their solver steps, the process's CPU seconds
//! (user and system, the operating system's account) and their share of
//! the wall time on every core (how full the cores were), how the runs
//! split between the perfect lattice's and the jittered seeds', and whether
//! every repeat gave the same answer, bit for bit (it must: the queue's
//! order changes no run).

use std::sync::atomic::AtomicBool;
use std::time::Instant;

use anyhow::{bail, Result};
use indicatif::ProgressBar;
use serde::Serialize;

use crate::config::Scene;
use crate::empirical::{answer, Extras, Search};

/// The scenes: Re of the built-in scene (Monaghan, N = 10).
pub const EMPIRICAL_RE: [f64; 2] = [1.0, 10.0];

/// One scene's figures.
#[derive(Debug, Clone, Serialize)]
pub struct EmpiricalBench {
    pub kernel: String,
    pub n_layers: u32,
    pub re: f64,
    /// Wall seconds of each repeat, and their median.
    pub wall_s: Vec<f64>,
    pub wall_s_median: f64,
    /// Of the first repeat: runs made and their solver steps (the trials'
    /// and, when no c0 is ok, the diagnosis's check).
    pub runs: usize,
    pub steps: u64,
    /// Of those, the perfect lattice's runs and steps (the rest are the
    /// jittered seeds'), and the perfect lattice's share of the runs' wall
    /// seconds summed (each run's own; the runs share the cores).
    pub perfect_runs: usize,
    pub perfect_steps: u64,
    pub perfect_share: f64,
    /// CPU seconds of each repeat (None: not measured on this system),
    /// and the median's share of the median wall time on every core.
    pub cpu_s: Vec<Option<f64>>,
    pub cpu_s_median: Option<f64>,
    pub cores: usize,
    pub core_use: Option<f64>,
    /// The answer: the smallest c0 ok (None: none), the recommendation, and
    /// the disordered search's probes, in U.
    pub c0_min_ok_over_u: Option<f64>,
    pub recommended_over_u: Option<f64>,
    pub probes_over_u: Vec<f64>,
    /// Every repeat gave the same trials (classes and statistics, bitwise).
    pub identical: bool,
}

/// The answer's trials as bits, for the repeats' comparison.
fn fingerprint(a: &crate::empirical::Answer) -> Vec<(u64, u32, u64, u64, u64)> {
    a.trials
        .iter()
        .flat_map(|t| {
            t.perfect.iter().chain(&t.seeds).map(move |r| {
                (
                    t.c0.to_bits(),
                    r.seed,
                    r.eps_stat.to_bits(),
                    r.linf_stat.to_bits(),
                    r.steps,
                )
            })
        })
        .collect()
}

/// Answer each scene `repeats` times; `progress` hears of each repeat.
pub fn empirical(repeats: usize, mut progress: impl FnMut(&str)) -> Result<Vec<EmpiricalBench>> {
    if !(1..=20).contains(&repeats) {
        bail!("--repeats = {repeats} must be from 1 to 20 with --empirical (each repeat is a whole answer, about a minute)");
    }
    let search = Search::default();
    let extras = Extras {
        rules: true,
        ordered: true,
        law_ladder: false,
    };
    let stop = AtomicBool::new(false);
    let mut out = Vec::new();
    for re in EMPIRICAL_RE {
        let mut scene = Scene::builtin();
        scene.re = Some(re);
        scene.p = None;
        let mut walls = Vec::new();
        let mut cpus = Vec::new();
        let mut first: Option<crate::empirical::Answer> = None;
        let mut identical = true;
        for k in 0..repeats {
            let (start, cpu0) = (Instant::now(), cpu_seconds());
            let a = answer(&scene, &search, extras, &stop, &ProgressBar::hidden())?;
            let wall = start.elapsed().as_secs_f64();
            cpus.push(cpu_seconds().zip(cpu0).map(|(b, a)| b - a));
            progress(&format!(
                "empirical answer, {} N = {} Re = {re}: repeat {} of {repeats}, {wall:.1} s",
                a.kernel,
                a.n_layers,
                k + 1
            ));
            walls.push(wall);
            match &first {
                Some(f) => identical &= fingerprint(f) == fingerprint(&a),
                None => first = Some(a),
            }
        }
        let a = first.expect("at least one repeat");
        // The trials' runs and the diagnosis's check (when no c0 is ok).
        let runs: Vec<_> = a
            .trials
            .iter()
            .flat_map(|t| t.perfect.iter().chain(&t.seeds))
            .chain(a.diagnosis.iter().flat_map(|d| &d.check_runs))
            .collect();
        let perfect: Vec<_> = a.trials.iter().flat_map(|t| &t.perfect).collect();
        let run_s =
            |runs: &[&crate::empirical::StartRun]| runs.iter().map(|r| r.wall_s).sum::<f64>();
        let cores = rayon::current_num_threads();
        let median = |v: &[f64]| {
            let mut v = v.to_vec();
            v.sort_by(f64::total_cmp);
            v[v.len() / 2]
        };
        let wall_median = median(&walls);
        let cpu: Option<Vec<f64>> = cpus.iter().copied().collect();
        out.push(EmpiricalBench {
            kernel: a.kernel.clone(),
            n_layers: a.n_layers,
            re,
            wall_s_median: wall_median,
            wall_s: walls,
            runs: runs.len(),
            steps: runs.iter().map(|r| r.steps).sum(),
            perfect_runs: perfect.len(),
            perfect_steps: perfect.iter().map(|r| r.steps).sum(),
            perfect_share: run_s(&perfect) / run_s(&runs),
            cpu_s: cpus,
            cpu_s_median: cpu.as_ref().map(|c| median(c)),
            cores,
            core_use: cpu.map(|c| median(&c) / (wall_median * cores as f64)),
            c0_min_ok_over_u: a.c0_min_ok.map(|c| c / a.u),
            recommended_over_u: a.recommended.map(|c| c / a.u),
            probes_over_u: a.disordered.probes.iter().map(|c| c / a.u).collect(),
            identical,
        });
    }
    Ok(out)
}

/// The figures as a table.
pub fn empirical_table(rows: &[EmpiricalBench]) -> String {
    let mut s = String::from(
        "empirical answer (c0 --empirical, every rule beside it), median of the repeats\n\
         kernel      N     Re   wall s (min-max)      runs    steps  perfect: runs    steps  run-s      cpu s  core use  c0_min_ok/U  probes  identical\n",
    );
    for r in rows {
        let min = r.wall_s.iter().copied().fold(f64::INFINITY, f64::min);
        let max = r.wall_s.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        s.push_str(&format!(
            "{:<10} {:>2} {:>6} {:>7.1} ({:.1}-{:.1}) {:>9} {:>8} {:>14} {:>8} {:>6.2} {:>10.1} {:>9.2} {:>12} {:>7} {:>10}\n",
            r.kernel,
            r.n_layers,
            r.re,
            r.wall_s_median,
            min,
            max,
            r.runs,
            r.steps,
            r.perfect_runs,
            r.perfect_steps,
            r.perfect_share,
            r.cpu_s_median.unwrap_or(f64::NAN),
            r.core_use.unwrap_or(f64::NAN),
            r.c0_min_ok_over_u
                .map_or("none".to_string(), |c| format!("{c:.3}")),
            r.probes_over_u.len(),
            if r.identical { "yes" } else { "NO" },
        ));
    }
    s.push_str(
        "perfect: the perfect lattice's runs, their steps and their share of the runs' wall seconds summed (the rest are the\n\
         jittered seeds'); cpu s: the process's user and system seconds, the median repeat's; core use: cpu s / (wall x cores)\n",
    );
    s
}

/// The process's user and system CPU seconds so far (None where the system
/// does not say).
fn cpu_seconds() -> Option<f64> {
    #[cfg(unix)]
    {
        // SAFETY: getrusage writes one rusage struct, zeroed here first.
        let mut u: libc::rusage = unsafe { std::mem::zeroed() };
        if unsafe { libc::getrusage(libc::RUSAGE_SELF, &mut u) } != 0 {
            return None;
        }
        let secs = |t: libc::timeval| t.tv_sec as f64 + t.tv_usec as f64 * 1e-6;
        Some(secs(u.ru_utime) + secs(u.ru_stime))
    }
    #[cfg(not(unix))]
    {
        None
    }
}
