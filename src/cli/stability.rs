//! `shearsph stability`: the growth rate of small perturbations of a
//! scene's sheared lattice per Bloch sector and c0, the most unstable mode
//! and the time to disorder it predicts; with `--measure`, beside it the
//! growth a nonlinear run from a small jitter measures (src/studies/stability/).

use std::process::ExitCode;

use anyhow::{bail, Result};
use clap::Args;
use serde::Serialize;

use super::SceneArgs;
use crate::solver::tangent::Options;
use crate::stability::measure::{measure, Measured};
use crate::stability::{analyse, multipliers, AtC0, Multipliers, Request};

/// The growth of perturbations of a scene's sheared lattice.
#[derive(Debug, Args)]
#[command(allow_negative_numbers = true, args_override_self = true)]
pub struct StabilityArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// c0 values to analyse, in U, comma-separated.
    #[arg(long, value_delimiter = ',', default_value = "10")]
    pub c0_over_u: Vec<f64>,
    /// Bloch sectors j (q = 2 pi j / W), comma-separated (default: 0 to columns / 2).
    #[arg(long, value_delimiter = ',')]
    pub sectors: Vec<u32>,
    /// Time over which the rate is measured, after --warm (scene units).
    #[arg(long, default_value_t = Request::default().options.horizon)]
    pub horizon_t: f64,
    /// Time followed first, so the perturbation turns into its fastest-growing form.
    #[arg(long, default_value_t = Request::default().options.warm)]
    pub warm: f64,
    /// The perturbation's size (d and U) the finite differences use.
    #[arg(long, default_value_t = Request::default().options.eps)]
    pub eps: f64,
    /// Steps between renormalisations of the perturbation.
    #[arg(long, default_value_t = Request::default().options.block)]
    pub block: u64,
    /// The jitter amplitude (d) the predicted time to disorder is for.
    #[arg(long, default_value_t = Request::default().amplitude)]
    pub amplitude: f64,
    /// Also run the scene from a jitter of --amplitude and fit the growth
    /// of its rms displacement from the lattice (the check against the solver).
    #[arg(long)]
    pub measure: bool,
    /// With --measure: the run's end time.
    #[arg(long, default_value_t = 600.0)]
    pub measure_t_end: f64,
    /// Also the multipliers of the flow over this time from the base state
    /// (the eigenvalues of its Jacobian by finite differences: 8 runs per
    /// fluid particle of this length); 0: not computed.
    #[arg(long, default_value_t = 0.0, conflicts_with = "floquet")]
    pub multipliers_t: f64,
    /// The multipliers over one lattice period T = d N^2 / U, over which
    /// the steady profile's lattice repeats: the Floquet multipliers.
    #[arg(long)]
    pub floquet: bool,
    /// Write the most unstable mode's picture (SVG) here: with several c0,
    /// one file each, named with `-c0-C` before the extension.
    #[arg(long)]
    pub mode_svg: Option<std::path::PathBuf>,
    /// Print JSON on stdout.
    #[arg(long)]
    pub json: bool,
}

/// One c0's analysis with what `--measure` and `--floquet` /
/// `--multipliers-t` added, as the JSON shows it.
#[derive(Serialize)]
struct AtC0Out {
    #[serde(flatten)]
    analysis: AtC0,
    measured: Option<Measured>,
    multipliers: Option<Multipliers>,
}

#[derive(Serialize)]
struct Out<'a> {
    kernel: &'a str,
    discretisation: String,
    n_layers: u32,
    re: Option<f64>,
    alpha: f64,
    columns: u32,
    eps: f64,
    block: u64,
    warm: f64,
    horizon: f64,
    amplitude: f64,
    results: Vec<AtC0Out>,
}

fn check(args: &StabilityArgs) -> Result<()> {
    for &c in &args.c0_over_u {
        if !(c.is_finite() && c > 0.0 && c <= 1e4) {
            bail!("--c0-over-u = {c}: give values above 0, at most 1e4");
        }
    }
    if args.c0_over_u.is_empty() || args.c0_over_u.len() > 64 {
        bail!("--c0-over-u: give 1 to 64 values");
    }
    if !(args.eps.is_finite() && args.eps >= 1e-12 && args.eps <= 1e-3) {
        bail!(
            "--eps = {}: give 1e-12 to 1e-3 (larger is not linear, smaller is round-off)",
            args.eps
        );
    }
    if args.block == 0 || args.block > 100_000 {
        bail!("--block = {}: give 1 to 100000 steps", args.block);
    }
    for (flag, v) in [
        ("--horizon-t", args.horizon_t),
        ("--measure-t-end", args.measure_t_end),
    ] {
        if !(v.is_finite() && v > 0.0 && v <= 1e5) {
            bail!("{flag} = {v}: give a time above 0, at most 1e5");
        }
    }
    if !(args.multipliers_t.is_finite() && args.multipliers_t >= 0.0 && args.multipliers_t <= 1e3) {
        bail!(
            "--multipliers-t = {}: give a time from 0 (off) to 1e3",
            args.multipliers_t
        );
    }
    if !(args.warm.is_finite() && args.warm >= 0.0 && args.warm <= 1e5) {
        bail!("--warm = {}: give a time from 0 to 1e5", args.warm);
    }
    if !(args.amplitude.is_finite() && args.amplitude > 0.0 && args.amplitude < 0.5) {
        bail!(
            "--amplitude = {}: give a jitter above 0, below 0.5 d",
            args.amplitude
        );
    }
    if args.sectors.len() > 1000 {
        bail!("--sectors: give at most 1000");
    }
    Ok(())
}

fn request(args: &StabilityArgs) -> Request {
    Request {
        c0_over_u: args.c0_over_u.clone(),
        sectors: args.sectors.clone(),
        options: Options {
            eps: args.eps,
            block: args.block,
            horizon: args.horizon_t,
            warm: args.warm,
        },
        amplitude: args.amplitude,
    }
}

pub fn main(args: StabilityArgs) -> Result<ExitCode> {
    check(&args)?;
    let scene = args.scene.load()?;
    let info = scene.kernel_info().map_err(|e| args.scene.label(e))?;
    let problem = crate::problem::Problem::resolve(
        &crate::stability::base_scene(&scene, 10.0 * scene.u).map_err(|e| args.scene.label(e))?,
        info,
    )
    .map_err(|e| args.scene.label(e))?;
    let columns = problem.lattice.columns;
    if let Some(&j) = args.sectors.iter().find(|&&j| j > columns / 2) {
        bail!(
            "--sectors: {j} is above columns / 2 = {} (the strip has {columns} columns)",
            columns / 2
        );
    }
    if args.floquet || args.multipliers_t > 0.0 {
        crate::stability::check_jacobian(&problem)?;
    }
    let req = request(&args);
    let at = analyse(&scene, &req)?;
    let mut results = Vec::new();
    for a in at {
        let m = if args.measure {
            Some(measure(
                &scene,
                a.c0_over_u * scene.u,
                args.amplitude,
                1,
                args.measure_t_end,
                2.0,
            )?)
        } else {
            None
        };
        let over = if args.floquet {
            a.period
        } else {
            args.multipliers_t
        };
        let mu = if over > 0.0 {
            Some(multipliers(&scene, a.c0_over_u * scene.u, over, args.eps)?)
        } else {
            None
        };
        results.push(AtC0Out {
            analysis: a,
            measured: m,
            multipliers: mu,
        });
    }
    if let Some(path) = &args.mode_svg {
        for r in &results {
            let a = &r.analysis;
            let file = if results.len() == 1 {
                path.clone()
            } else {
                let stem = path
                    .file_stem()
                    .map_or("mode".into(), |s| s.to_string_lossy().into_owned());
                let ext = path
                    .extension()
                    .map_or("svg".into(), |s| s.to_string_lossy().into_owned());
                path.with_file_name(format!("{stem}-c0-{}.{ext}", a.c0_over_u))
            };
            let title = format!(
                "{} ({}), N = {}, c0 = {} U: the mode of sector j = {} (rate {:.3e})",
                info.name,
                problem.discretisation.label(),
                scene.n_layers,
                a.c0_over_u,
                a.most_unstable_j,
                a.growth_rate
            );
            let svg = crate::charts::mode::mode_svg(&a.mode, &title)
                .map_err(|e| anyhow::anyhow!("{}: {e}", file.display()))?;
            crate::output::atomic::write_atomic(&file, svg.as_bytes())?;
            if !args.json {
                eprintln!("wrote {}", file.display());
            }
        }
    }
    let out = Out {
        kernel: info.name,
        discretisation: problem.discretisation.label(),
        n_layers: scene.n_layers,
        re: scene.re,
        alpha: scene.alpha,
        columns,
        eps: args.eps,
        block: args.block,
        warm: args.warm,
        horizon: args.horizon_t,
        amplitude: args.amplitude,
        results,
    };
    if args.json {
        println!("{}", serde_json::to_string(&out)?);
        return Ok(ExitCode::SUCCESS);
    }
    println!(
        "kernel {} ({}), N = {}, Re = {}, alpha = {}, {} columns; perfect lattice in the steady profile, perturbations of size {} renormalised every {} steps, rate over t in ({}, {}]",
        out.kernel,
        out.discretisation,
        out.n_layers,
        out.re.map_or("-".into(), |r| r.to_string()),
        out.alpha,
        columns,
        out.eps,
        out.block,
        out.warm,
        out.warm + out.horizon
    );
    for r in &out.results {
        let (a, m) = (&r.analysis, &r.measured);
        println!(
            "c0 = {} U: growth rate {:.4e} per unit time, {:.3} per period T = d N^2 / U = {} (sector j = {})",
            a.c0_over_u, a.growth_rate, a.growth_rate_per_period, a.period, a.most_unstable_j
        );
        for s in &a.sectors {
            println!(
                "  j = {:>3}  q d = {:.4}  rate {:>11.4e}{}{}",
                s.j,
                s.q_d,
                s.growth_rate,
                s.e_fold_time
                    .map_or(String::new(), |e| format!("  e-fold {e:.1}")),
                if s.failed { "  (the run failed)" } else { "" }
            );
        }
        match a.t_disorder_predicted {
            Some(t) => println!(
                "  a {} d jitter reaches dy_rms = 0.1 d at t = {t:.0} at that rate",
                out.amplitude
            ),
            None if !a.growth_rate.is_finite() => println!(
                "  every sector's run failed: the perfect lattice itself does not last at this c0, no ordered state to follow"
            ),
            None => println!("  no sector grows: the ordered state holds at this c0"),
        }
        if let Some(m) = m {
            let late = m
                .growth_rate
                .map_or("the late phase not reached".to_string(), |r| {
                    format!(
                        "late slope {r:.4e} over t in [{:.0}, {:.0}] (dy_rms from twice the perfect lattice's {:.4} to 0.05 d), predicted / measured {:.2}",
                        m.fit_from.unwrap_or(f64::NAN),
                        m.fit_to.unwrap_or(f64::NAN),
                        m.floor,
                        a.growth_rate / r
                    )
                });
            match (m.t_disorder, m.mean_rate) {
                (Some(t), Some(r)) => println!(
                    "  measured ({} d jitter, seed 1): dy_rms = 0.1 d at t = {t:.0}, mean rate {r:.4e}, predicted / measured {:.2}; {late}",
                    m.amplitude,
                    a.growth_rate / r
                ),
                _ => println!("  measured ({} d jitter, seed 1): not disordered by t = {}; {late}", m.amplitude, m.t_end),
            }
        }
        if let Some(mu) = &r.multipliers {
            let lead: Vec<String> = mu
                .leading
                .iter()
                .take(4)
                .map(|z| format!("{:.6}", z[0].hypot(z[1])))
                .collect();
            println!(
                "  flow map over t = {}{} ({} steps, dimension {}): largest |mu| {}; ln |mu| / t = {:.4e}",
                mu.t,
                if mu.t == a.period { " = T (Floquet multipliers)" } else { "" },
                mu.steps,
                mu.dimension,
                lead.join(", "),
                mu.growth_rate
            );
        }
    }
    Ok(ExitCode::SUCCESS)
}

/// `c0 --stability`'s table: beside each rule's c0, the ordered lattice's
/// growth there and when a 1e-4 d jitter has disordered it.
pub fn print_ordered(rows: &[crate::stability::OrderedAt]) {
    println!();
    println!(
        "the ordered lattice at each c0 (shearsph stability, docs/stability.md): the leading growth rate of a perturbation of the perfect sheared lattice, and when a 1e-4 d jitter has disordered it (dy_rms = 0.1 d); past that the derived rules' premise, the ordered lattice, no longer holds"
    );
    println!(
        "{:<24} {:>10} {:>12} {:>10} {:>12}",
        "rule", "c0/U", "growth rate", "q d", "t_disorder"
    );
    for o in rows {
        let tail = if o.failed {
            "   the perfect lattice's run fails at this c0".to_string()
        } else {
            match o.t_disorder_from_1e_4 {
                Some(t) => format!(" {t:>12.0}"),
                None => format!(" {:>12}", "stable"),
            }
        };
        println!(
            "{:<24} {:>10.4} {:>12.3e} {:>10}{tail}",
            o.rule,
            o.c0_over_u,
            o.growth_rate,
            o.most_unstable_q_d
                .map_or("-".into(), |q| format!("{q:.3}"))
        );
    }
}
