//! `shearsph c0`: the sound speed for a kernel and a scene by every rule side
//! by side (each derived model, 10 U, the paper's printed Table 2 row), with
//! the time step each implies and the limit that binds it.

use std::process::ExitCode;

use anyhow::{bail, Result};
use clap::Args;

use std::io::IsTerminal;

use indicatif::{ProgressBar, ProgressStyle};

use super::SceneArgs;
use crate::answer::{answer, resolve_empirical, Search};
use crate::config::{C0Spec, Scene};
use crate::format::fmt_value;
use crate::problem::c0::table;
use crate::solver::Class;

/// c0 by every rule for a scene, and the time step each implies.
#[derive(Debug, Args)]
#[command(allow_negative_numbers = true, args_override_self = true)]
pub struct C0Args {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Print the table as JSON on stdout.
    #[arg(long)]
    pub json: bool,
    /// Find the scene's c0 with the solver: bisection on log c0 for the
    /// smallest c0 ok on the perfect lattice and on every perturbed seed,
    /// then every rule run the same way.
    #[arg(long)]
    pub empirical: bool,
    /// Perturbed starts: jitter amplitude in d (with --empirical).
    #[arg(long, default_value_t = 0.05)]
    pub amplitude: f64,
    /// Perturbed starts: number of seeds (with --empirical).
    #[arg(long, default_value_t = 3)]
    pub seeds: u32,
    /// Recommended c0 = smallest ok c0 times this (with --empirical).
    #[arg(long, default_value_t = 1.5)]
    pub margin: f64,
    /// Bisection tolerance on c0, relative (with --empirical).
    #[arg(long, default_value_t = 0.1)]
    pub rel_tol: f64,
    /// Run every run to its end for its final class (with --empirical; by
    /// default a run stops at the first output time it is not ok, its class
    /// the one seen then, and the perturbed seeds of a c0 stop when one is
    /// not ok: the answer is the same, faster).
    #[arg(long)]
    pub full: bool,
    /// No progress bar.
    #[arg(long)]
    pub quiet: bool,
}

pub fn main(args: C0Args) -> Result<ExitCode> {
    // `--c0 empirical` (or a scene's) asks for the solver's answer
    let asks_empirical = matches!(
        args.scene.load()?.c0,
        crate::config::C0Spec::Rule {
            rule: crate::config::C0Rule::Empirical,
            ..
        }
    );
    if args.empirical || asks_empirical {
        return empirical(&args);
    }
    let t = table(&args.scene.load()?).map_err(|e| args.scene.label(e))?;
    if args.json {
        println!("{}", serde_json::to_string_pretty(&t)?);
        return Ok(ExitCode::SUCCESS);
    }
    println!(
        "kernel {} on the {} lattice, h = {} d (the derived rules are this discretisation's)",
        t.kernel,
        t.lattice.name(),
        t.h_over_d
    );
    println!(
        "N = {}, Re = {:.6}, U = {}, p = {:.6e}, nu = {:.6e}, alpha = {}, A = p d N^4 / U^2 = {:.6}",
        t.n_layers, t.re, t.u, t.p, t.nu, t.alpha, t.a
    );
    println!(
        "time steps with |v|max = U and |a|max = p; steps to t_end = {:.6}",
        t.t_end
    );
    println!(
        "{:<24} {:>12} {:>10} {:>12} {:>8} {:>12} {:>12} {:>10}",
        "rule", "c0", "c0/U", "dt", "limit", "dt_cfl", "dt_viscous", "steps"
    );
    for r in &t.rows {
        match &r.cost {
            Some(c) => println!(
                "{:<24} {:>12.6} {:>10.4} {:>12.4e} {:>8} {:>12.4e} {:>12.4e} {:>10}",
                r.rule,
                r.c0,
                r.c0_over_u,
                c.dt,
                c.dt_limit.name(),
                c.dt_cfl,
                c.dt_viscous,
                c.steps
            ),
            None => match r.no_c0 {
                Some(fact) => println!("{:<24} {:>12}   {fact}", r.rule, "none"),
                None => println!(
                    "{:<24} {:>12.6}   no positive sound speed for this scene",
                    r.rule, r.c0
                ),
            },
        }
    }
    if let Some(e) = &t.scene_c0_error {
        println!("the scene's own c0 ({}) does not resolve: {e}", t.scene_c0);
    }
    Ok(ExitCode::SUCCESS)
}

/// A progress bar of runs on stderr (hidden when quiet or not a terminal).
fn runs_bar(quiet: bool) -> ProgressBar {
    if quiet || !std::io::stderr().is_terminal() {
        ProgressBar::hidden()
    } else {
        let bar = ProgressBar::new(1);
        bar.set_style(
            ProgressStyle::with_template("[{elapsed_precise}] {wide_bar} {pos}/{len} runs {msg}")
                .expect("valid template"),
        );
        bar
    }
}

/// For `run`: a scene whose c0 is `[F*]empirical` gets the `c0
/// --empirical` recommendation for itself (the bisection with the default
/// search: 3 seeds jittered by 0.05 d, margin 1.5), found first and said
/// (on stdout, or stderr when stdout carries JSON); any other scene is
/// returned as it is.
pub fn empirical_scene(scene: Scene, quiet: bool, to_stdout: bool) -> Result<Scene> {
    let search = Search::default();
    if matches!(
        scene.c0,
        C0Spec::Rule {
            rule: crate::config::C0Rule::Empirical,
            ..
        }
    ) {
        crate::problem::c0::table(&scene)?;
        check_search_top(&scene, &search, &|_| None)?;
    }
    let bar = runs_bar(quiet);
    bar.set_message("c0 = empirical: the bisection first");
    let Some((s, b)) = resolve_empirical(&scene, &search, &bar)? else {
        return Ok(scene);
    };
    bar.finish_and_clear();
    let C0Spec::Value(c0) = s.c0 else {
        unreachable!("resolve_empirical gives a number")
    };
    let line = format!(
        "c0 = {} = {c0:.6} ({:.4} U): the smallest c0 ok on the perfect lattice and on {} seeds \
         jittered by {} d is {:.6} ({} trials{}), times the margin {}; now the run itself",
        scene.c0,
        c0 / s.u,
        search.seeds,
        search.amplitude,
        b.c0_min_ok.unwrap_or(f64::NAN),
        b.trials.len(),
        b.c0_max_not_ok
            .map(|c| format!(", not ok at {c:.6}"))
            .unwrap_or_default(),
        search.margin
    );
    if to_stdout {
        println!("{line}");
    } else {
        eprintln!("{line}");
    }
    Ok(s)
}

/// The search's extreme runs valid before any run: its first probe, c0 =
/// `hi_over_u` U (the top of the bracket), and the largest c0 it may
/// recommend and then run, `margin` times that. An error names the
/// search's own field as `name` gives it (`--margin`, a law config's
/// `hi_over_u`; `None`: a field the command does not take), not the c0
/// the scene would have had.
pub(crate) fn check_search_top(
    scene: &Scene,
    search: &Search,
    name: &dyn Fn(&str) -> Option<String>,
) -> Result<()> {
    use crate::problem::Problem;
    let info = scene.kernel_info()?;
    let u = crate::problem::channel::Channel::resolve(scene, info)?
        .flow
        .u;
    let at = |c0: f64| {
        let s = Scene {
            c0: C0Spec::Value(c0),
            ..scene.clone()
        };
        Problem::resolve(&s, info).and_then(|p| p.check_duration())
    };
    let top = search.hi_over_u * u;
    if let Err(e) = at(top) {
        let who = name("hi_over_u").map_or_else(
            || "the search's first probe".to_string(),
            |n| {
                format!(
                    "{n} = {}: the search's first probe",
                    fmt_value(search.hi_over_u)
                )
            },
        );
        bail!(
            "{who}, c0 = {} U, would not run: {e}",
            fmt_value(search.hi_over_u)
        );
    }
    if let Err(e) = at(top * search.margin) {
        let who = name("margin").unwrap_or_else(|| "the margin".into());
        bail!(
            "{who} = {}: the recommended c0 may be as large as margin x {} U = {} U, and it is run \
             (on every start) once found, but a run at it would not: {e}",
            fmt_value(search.margin),
            fmt_value(search.hi_over_u),
            fmt_value(search.margin * search.hi_over_u)
        );
    }
    Ok(())
}

fn empirical(args: &C0Args) -> Result<ExitCode> {
    let scene = args.scene.load()?;
    // Everything but c0 must be valid before the first run.
    table(&scene).map_err(|e| args.scene.label(e))?;
    let search = Search {
        amplitude: args.amplitude,
        seeds: args.seeds,
        margin: args.margin,
        rel_tol: args.rel_tol,
        full: args.full,
        ..Search::default()
    };
    // The engine's own ranges first (Search::check), then the runs at the
    // top of the search.
    search.check(|field| format!("--{}", field.replace('_', "-")))?;
    check_search_top(&scene, &search, &|field| {
        (field != "hi_over_u").then(|| format!("--{}", field.replace('_', "-")))
    })?;
    let bar = runs_bar(args.quiet);
    let a = answer(&scene, &search, &bar)?;
    bar.finish_and_clear();
    let stopped_note = !search.full
        && a.rules
            .iter()
            .any(|r| r.decided_t_perfect.is_some() || r.decided_t_perturbed.is_some());
    if args.json {
        println!("{}", serde_json::to_string_pretty(&a)?);
        return Ok(ExitCode::SUCCESS);
    }
    println!(
        "kernel {}, N = {}, Re = {:.6}, alpha = {}, U = {}; perfect lattice and {} seeds jittered by {} d",
        a.kernel, a.n_layers, a.re, a.alpha, a.u, search.seeds, search.amplitude
    );
    match (a.c0_min_ok, a.recommended) {
        (Some(min), Some(rec)) => println!(
            "recommended c0 = {rec:.6} ({:.4} U): the smallest c0 ok on every start, {min:.6} ({:.4} U), times {}{}",
            rec / a.u,
            min / a.u,
            search.margin,
            a.c0_max_not_ok
                .map(|c| format!("; not ok at {:.4} U", c / a.u))
                .unwrap_or_else(|| format!("; ok down to the lowest probe, {} U", search.lo_over_u))
        ),
        _ => println!(
            "no c0 up to {} U is ok on every start: no recommendation",
            search.hi_over_u
        ),
    }
    println!(
        "{:<20} {:>12} {:>10} {:>20} {:>20} {:>10} {:>9} {:>8} {:>9}",
        "rule", "c0", "c0/U", "perfect", "perturbed", "linf", "steps", "wall_s", "cost_rel"
    );
    // "inaccurate@12.3": stopped at t = 12.3, where it was decided not ok
    let cls = |c: Option<Class>, t: Option<f64>| match (c, t) {
        (None, _) => "not run".to_string(),
        (Some(c), None) => c.to_string(),
        (Some(c), Some(t)) => format!("{c}@{}", crate::format::fmt_num(t)),
    };
    for r in &a.rules {
        println!(
            "{:<20} {:>12.6} {:>10.4} {:>20} {:>20} {:>10.3e} {:>9} {:>8.2} {:>9.2}",
            r.name,
            r.c0,
            r.c0_over_u,
            cls(r.outcome_perfect, r.decided_t_perfect),
            cls(r.outcome_perturbed, r.decided_t_perturbed),
            r.linf,
            r.steps,
            r.wall_s,
            r.cost_rel
        );
    }
    if stopped_note {
        println!(
            "CLASS@T: stopped at t = T, the first output time it was not ok (its class then; run on \
             it could only get worse, never ok); steps to there, cost_rel from the steps to t_end \
             extrapolated; --full runs every run to its end"
        );
    }
    Ok(ExitCode::SUCCESS)
}
