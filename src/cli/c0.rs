//! `shearsph c0`: the sound speed for a kernel and a scene by every rule side
//! by side (each derived model, 10 U, the paper's printed Table 2 row), with
//! the time step each implies and the limit that binds it.

use std::process::ExitCode;

use anyhow::{bail, Result};
use clap::Args;

use std::io::IsTerminal;

use indicatif::{ProgressBar, ProgressStyle};

use std::sync::atomic::AtomicBool;

use super::interrupt::{stop_flag, EXIT_INTERRUPTED};
use super::SceneArgs;
use crate::config::{C0Spec, Scene};
use crate::empirical::{answer, resolve_empirical, Extras, Search};
use crate::format::fmt_value;
use crate::problem::c0::table;
use crate::problem::cost::{cfl_warning, viscous_dt_warning};
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
    /// Find the scene's c0 with the solver: the smallest c0 whose
    /// stationary, disordered state (the jittered seeds pooled) is ok, by
    /// bisection on log c0; beside it the perfect lattice (the ordered
    /// regime), the disordered law, and every rule run the same way
    /// (docs/stationary.md).
    #[arg(long)]
    pub empirical: bool,
    /// With --empirical: also the c0 the disordered law gives for this
    /// density tolerance delta (c0 = U (k / delta)^(1/m), beside Monaghan's
    /// M^2 rule, rule10 and Morris 1997 at delta).
    #[arg(long)]
    pub tolerance: Option<f64>,
    /// Perturbed starts: jitter amplitude in d (with --empirical).
    #[arg(long, default_value_t = Search::default().amplitude)]
    pub amplitude: f64,
    /// Perturbed starts: number of seeds, pooled (with --empirical).
    #[arg(long, default_value_t = Search::default().seeds)]
    pub seeds: u32,
    /// Recommended c0 = smallest ok c0 times this, when that is ok too;
    /// else the middle of the ok band (with --empirical).
    #[arg(long, default_value_t = Search::default().margin)]
    pub margin: f64,
    /// Bisection tolerance on c0, relative (with --empirical).
    #[arg(long, default_value_t = Search::default().rel_tol)]
    pub rel_tol: f64,
    /// The search's first probe and bounds, in U (with --empirical).
    #[arg(long, default_value_t = Search::default().first_over_u)]
    pub first_over_u: f64,
    #[arg(long, default_value_t = Search::default().lo_over_u)]
    pub lo_over_u: f64,
    #[arg(long, default_value_t = Search::default().hi_over_u)]
    pub hi_over_u: f64,
    /// With --empirical: the answer alone (the disordered search and the
    /// ordered one), not every rule's c0 run beside it.
    #[arg(long)]
    pub no_rules: bool,
    /// No progress bar.
    #[arg(long)]
    pub quiet: bool,
    /// Beside each rule's c0, whether the ordered lattice the paper's
    /// analysis assumes lasts at it: the leading growth rate of a
    /// perturbation of the perfect sheared lattice (`shearsph stability`'s
    /// defaults) and the time a 1e-4 d jitter takes to disorder it. About
    /// 10 to 20 s per distinct c0 at N = 10 on 2 cores.
    #[arg(long)]
    pub stability: bool,
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
    let scene = args.scene.load()?;
    let t = table(&scene).map_err(|e| args.scene.label(e))?;
    warn_factors(&t);
    let ordered = if args.stability {
        Some(crate::stability::ordered_at(&scene, &t)?)
    } else {
        None
    };
    if args.json {
        #[derive(serde::Serialize)]
        struct Out<'a> {
            #[serde(flatten)]
            table: &'a crate::problem::c0::C0Table,
            #[serde(skip_serializing_if = "Option::is_none")]
            ordered_lattice: Option<&'a Vec<crate::stability::OrderedAt>>,
        }
        let out = Out {
            table: &t,
            ordered_lattice: ordered.as_ref(),
        };
        println!("{}", serde_json::to_string_pretty(&out)?);
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
    use crate::problem::cost::{
        default_cfl, default_viscous_dt, CFL_DEFAULT_MAX, CFL_SHARE, VISCOUS_SHARE,
    };
    println!("time-step factors (docs/timestep.md):");
    println!(
        "  {}",
        factor_in_use(
            "cfl",
            "pressure",
            (t.cfl, t.cfl_stable),
            (t.cfl == default_cfl(t.cfl_stable)).then(|| format!(
                "{CFL_SHARE} of {:.4}, at most {CFL_DEFAULT_MAX}",
                t.cfl_stable
            )),
        )
    );
    println!(
        "  {}",
        factor_in_use(
            "viscous_dt",
            "viscous",
            (t.viscous_dt, t.viscous_dt_stable),
            (t.viscous_dt == default_viscous_dt(t.viscous_dt_stable))
                .then(|| format!("{VISCOUS_SHARE} of {:.4}", t.viscous_dt_stable)),
        )
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
    if let Some(rows) = &ordered {
        super::stability::print_ordered(rows);
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
/// --empirical` recommendation for itself (the default search), found first
/// and said (on stdout, or stderr when stdout carries JSON); any other scene
/// is returned as it is.
pub fn empirical_scene(
    scene: Scene,
    quiet: bool,
    to_stdout: bool,
    stop: &AtomicBool,
) -> Result<Scene> {
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
    bar.set_message("c0 = empirical: the search first");
    let Some((s, a)) = resolve_empirical(&scene, &search, stop, &bar)? else {
        return Ok(scene);
    };
    bar.finish_and_clear();
    let C0Spec::Value(c0) = s.c0 else {
        unreachable!("resolve_empirical gives a number")
    };
    let line = format!(
        "c0 = {} = {c0:.6} ({:.4} U): the smallest c0 ok in the stationary, disordered state of {} \
         seeds jittered by {} d is {:.6} ({} trials{}, runs to t = {:.4}..{:.4}), {}; now the run \
         itself",
        scene.c0,
        c0 / s.u,
        search.seeds,
        search.amplitude,
        a.c0_min_ok.unwrap_or(f64::NAN),
        a.trials.len(),
        a.disordered
            .compressed
            .map(|c| format!(", over-compressed at {:.6}", c.0))
            .unwrap_or_default(),
        a.horizon.t_min,
        a.horizon.t_max,
        match a.band.as_ref().and_then(|b| b.above.map(|above| (b, above))) {
            None => format!("times the margin {}", search.margin),
            Some((b, (c, k))) => format!(
                "the recommendation {:.6} inside the ok band up to {:.6} ({k} at {c:.6}), which is \
                 narrower than the margin {}",
                a.recommended.unwrap_or(f64::NAN),
                b.hi_ok,
                search.margin
            ),
        }
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
    // The scene as the engine runs it: a jittered start to the
    // stationary horizon.
    let at = |c0: f64| {
        let s = crate::empirical::trial::start_scene(scene, c0, (search.amplitude, 1));
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
    warn_factors(&table(&scene).map_err(|e| args.scene.label(e))?);
    let search = Search {
        amplitude: args.amplitude,
        seeds: args.seeds,
        margin: args.margin,
        rel_tol: args.rel_tol,
        first_over_u: args.first_over_u,
        lo_over_u: args.lo_over_u,
        hi_over_u: args.hi_over_u,
    };
    if let Some(t) = args.tolerance {
        if !(t > 0.0 && t < 1.0) {
            bail!("--tolerance = {t} must be a density tolerance in (0, 1), e.g. 0.01");
        }
    }
    // The engine's own ranges first (Search::check), then the runs at the
    // top of the search.
    search.check(|field| format!("--{}", field.replace('_', "-")))?;
    check_search_top(&scene, &search, &|field| {
        (field != "hi_over_u").then(|| format!("--{}", field.replace('_', "-")))
    })?;
    let stop = stop_flag("stopping the search")?;
    let bar = runs_bar(args.quiet);
    let extras = Extras {
        rules: !args.no_rules,
        ordered: true,
        law_ladder: args.tolerance.is_some(),
    };
    let a = match answer(&scene, &search, extras, stop, &bar) {
        Err(_) if stop.load(std::sync::atomic::Ordering::Relaxed) => {
            bar.finish_and_clear();
            eprintln!("interrupted: no answer");
            return Ok(ExitCode::from(EXIT_INTERRUPTED));
        }
        r => r?,
    };
    bar.finish_and_clear();
    let tolerance = args.tolerance.map(|d| Tolerance::new(&a, &scene, d));
    if args.json {
        #[derive(serde::Serialize)]
        struct Out<'a> {
            #[serde(flatten)]
            answer: &'a crate::empirical::Answer,
            tolerance: Option<Tolerance>,
        }
        println!(
            "{}",
            serde_json::to_string_pretty(&Out {
                answer: &a,
                tolerance
            })?
        );
        return Ok(ExitCode::SUCCESS);
    }
    print_answer(&a, &search);
    if let Some(t) = tolerance {
        t.print(a.u);
    }
    Ok(ExitCode::SUCCESS)
}

fn print_answer(a: &crate::empirical::Answer, search: &Search) {
    let f = crate::format::fmt_num;
    println!(
        "kernel {} ({}), N = {}, Re = {}, alpha = {}, U = {}; {} seeds jittered by {} d (pooled), \
         and the perfect lattice",
        a.kernel,
        a.discretisation,
        a.n_layers,
        f(a.re),
        a.alpha,
        a.u,
        search.seeds,
        search.amplitude
    );
    let h = &a.horizon;
    println!(
        "horizon: stationary (docs/stationary.md): start-up {} + checkpoints from {} to the cap {} \
         (B/U = {}); the {} runs ended at t = {}..{}, {} stationary, {} failed",
        f(h.t_startup),
        f(h.first),
        f(h.cap),
        f(h.shear_time),
        h.runs,
        f(h.t_min),
        f(h.t_max),
        h.stationary,
        h.failed
    );
    let below = a
        .disordered
        .compressed
        .map(|(c, k)| format!("; {k} at {} U", f(c / a.u)))
        .unwrap_or_else(|| format!("; ok down to the lowest c0, {} U", search.lo_over_u));
    let min_said = |min: f64| {
        format!(
            "{min:.6} ({} U{})",
            f(min / a.u),
            a.c0_rel_uncertainty.map_or(String::new(), |u| format!(
                " +- {} % from the seeds",
                f(100.0 * u)
            ))
        )
    };
    match (a.c0_min_ok, a.recommended, &a.band) {
        (Some(min), Some(rec), Some(band)) if band.above.is_none() => println!(
            "recommended c0 = {rec:.6} ({} U): the smallest c0 ok in the disordered state, {}, \
             times {}, ok too{below}",
            f(rec / a.u),
            min_said(min),
            search.margin,
        ),
        (Some(min), Some(rec), Some(band)) if band.hi_ok == min => {
            let (c, k) = band.above.expect("the band's end, searched");
            println!(
                "recommended c0 = {rec:.6} ({} U): the smallest c0 ok in the disordered state, {}, \
                 and the only one found: the band ok ends within the bisection's {} % above it \
                 ({k} at {} U), so no margin {} fits{below}",
                f(rec / a.u),
                min_said(min),
                f(100.0 * search.rel_tol),
                f(c / a.u),
                search.margin,
            );
        }
        (Some(min), Some(rec), Some(band)) => {
            let (c, k) = band.above.expect("the band's end, searched");
            println!(
                "recommended c0 = {rec:.6} ({} U): inside the band ok in the disordered state, \
                 from its smallest c0, {}, to {} U ({k} at {} U, bisection to {} %), a factor \
                 {} from its lower edge and {} from its upper: the band is narrower than the \
                 margin {}{below}",
                f(rec / a.u),
                min_said(min),
                f(band.hi_ok / a.u),
                f(c / a.u),
                f(100.0 * search.rel_tol),
                f(rec / min),
                f(band.hi_ok / rec),
                search.margin,
            );
        }
        _ => println!(
            "no c0 from {} U to {} U is ok in the disordered state: no recommendation",
            search.lo_over_u, search.hi_over_u
        ),
    }
    if let Some(band) = &a.band {
        let inside: Vec<String> = band
            .not_ok
            .iter()
            .filter(|(c, _)| *c < band.hi_ok)
            .map(|(c, k)| format!("{k} at {} U", f(c / a.u)))
            .collect();
        if !inside.is_empty() {
            println!(
                "  the classes alternate inside the band ({}): its statistics sit within the \
                 seeds' noise of a bound (their spread is in the trials below), so its edges are \
                 that uncertain; more --seeds narrow the noise",
                inside.join(", ")
            );
        }
    }
    if let Some(d) = &a.diagnosis {
        println!("why: {}", d.binds);
        for w in &d.would {
            println!("  would allow a c0: {w}");
        }
    }
    match a.ordered.c0_min_ok {
        Some(c) => println!(
            "ordered regime (the perfect lattice, the paper's analysis): ok from {} U{}",
            f(c / a.u),
            a.ordered
                .compressed
                .map(|(c, k)| format!(" ({k} at {} U)", f(c / a.u)))
                .unwrap_or_else(|| " down to the lowest c0".into())
        ),
        None => println!("ordered regime (the perfect lattice): no c0 tried is ok"),
    }
    if let Some(t) = &a.time_to_disorder {
        println!(
            "order lasts, at {} U: a {} d jitter disorders at t = {} (dy_rms >= 0.1 d, mean over \
             the seeds); the perfect lattice {}",
            f(t.c0 / a.u),
            t.amplitude,
            t.seeds.map_or("(not within the runs)".into(), f),
            t.perfect
                .map_or(format!("stayed ordered to t = {}", f(t.perfect_t)), |p| {
                    format!("disordered from round-off at t = {}", f(p))
                })
        );
    }
    if let Some(l) = &a.law {
        let (lo, hi) = l.range();
        println!(
            "disordered law: eps_stat - {} = k (U/c0)^m, k = {} (ln k +- {}), m = {} +- {} (rms {} \
             in ln eps; {} trials, c0 = {}..{} U)",
            f(l.eps0),
            f(l.k),
            f(l.ln_k_se),
            f(l.m),
            f(l.m_se),
            f(l.rms),
            l.points.len(),
            f(lo),
            f(hi)
        );
    } else {
        println!(
            "disordered law: not fitted: fewer than 3 settled trials whose compaction above the \
             lattice's own is at least 1e-3 and at least eps0, spanning a factor 1.5 in c0"
        );
    }
    println!(
        "{:<20} {:>11} {:>9} {:>16} {:>16} {:>10} {:>10} {:>9} {:>8}",
        "rule",
        "c0",
        "c0/U",
        "ordered",
        "disordered",
        "eps_stat",
        "linf_stat",
        "cost_rel",
        "wall_s"
    );
    let cls = |c: Option<Class>| c.map_or("-".to_string(), |c| c.to_string());
    for r in &a.rules {
        match (r.c0, &r.not_applicable) {
            (Some(c0), _) => println!(
                "{:<20} {:>11.6} {:>9.4} {:>16} {:>16} {:>10.3e} {:>10.3e} {:>9.2} {:>8.2}",
                r.name,
                c0,
                c0 / a.u,
                cls(r.ordered),
                cls(r.disordered),
                r.eps_stat,
                r.linf_stat,
                r.cost_rel,
                r.wall_s
            ),
            (None, why) => println!(
                "{:<20} {:>11}   not applicable: {}",
                r.name,
                "-",
                why.as_deref().unwrap_or("")
            ),
        }
    }
    println!(
        "trials (c0/U: perfect lattice | pooled seeds eps_stat, linf_stat, stationary seeds):"
    );
    for t in &a.trials {
        let perfect = t
            .perfect
            .as_ref()
            .map_or("-".to_string(), |p| p.class.to_string());
        let seeds = match &t.pooled {
            None => "-".to_string(),
            Some(p) => format!(
                "{:<15} eps {:.3e} (seeds {:.3e}..{:.3e}), linf {:.3e}, {}/{} stationary{}",
                p.class.to_string(),
                p.eps_stat,
                p.eps_stat_min,
                p.eps_stat_max,
                p.linf_stat,
                p.stationary,
                p.seeds,
                p.failure
                    .as_ref()
                    .map(|w| format!("; {w}"))
                    .unwrap_or_default()
            ),
        };
        println!("  {:>9.4}: {perfect:<15} | {seeds}", t.c0_over_u);
    }
}

/// `--tolerance delta`: the disordered law's c0 beside the field's rules.
#[derive(Debug, Clone, serde::Serialize)]
struct Tolerance {
    delta: f64,
    /// c0 / U from the law (None: no law fitted).
    law_c0_over_u: Option<f64>,
    /// Whether that c0 lies outside the c0 range of the trials the law was
    /// fitted on (None: no law fitted).
    law_extrapolated: Option<bool>,
    /// Monaghan's M^2 <= delta: c0 = U / sqrt(delta); rule10; Morris 1997
    /// at delta; each with the law's compaction at it (what it gives).
    rules: Vec<(String, f64, Option<f64>)>,
}

impl Tolerance {
    fn new(a: &crate::empirical::Answer, scene: &Scene, delta: f64) -> Tolerance {
        let law = a.law.as_ref();
        let (b, nu, p) = flow_of(scene);
        let l = 2.0 * b;
        let u = a.u;
        let morris = (u * u / delta)
            .max(nu * u / (l * delta))
            .max(p * l / delta)
            .sqrt();
        let rules = [
            (
                "monaghan M^2 (U / sqrt(delta))".to_string(),
                u / delta.sqrt(),
            ),
            ("rule10".to_string(), 10.0 * u),
            ("morris1997 at delta".to_string(), morris),
        ]
        .into_iter()
        .map(|(n, c)| (n, c / u, law.map(|l| l.eps_at(c / u))))
        .collect();
        let law_c0_over_u = law.map(|l| l.c0_over_u(delta));
        Tolerance {
            delta,
            law_c0_over_u,
            law_extrapolated: law.zip(law_c0_over_u).map(|(l, c)| !l.covers(c)),
            rules,
        }
    }

    fn print(&self, _u: f64) {
        let f = crate::format::fmt_num;
        match self.law_c0_over_u {
            Some(c) => println!(
                "for a density tolerance delta = {} (on eps_stat - eps0+): c0 = {} U by the disordered law{}",
                f(self.delta),
                f(c),
                if self.law_extrapolated == Some(true) {
                    " (extrapolated: outside the c0 of the trials it was fitted on; docs/stationary.md)"
                } else {
                    ""
                }
            ),
            None => println!(
                "for a density tolerance delta = {}: no disordered law was fitted (too few settled trials)",
                f(self.delta)
            ),
        }
        for (name, c, eps) in &self.rules {
            println!(
                "  {name:<34} c0 = {:>8} U: the law's eps_stat - eps0+ there {}",
                f(*c),
                eps.map_or("-".into(), |e| format!(
                    "{} ({} delta)",
                    f(e),
                    f(e / self.delta)
                ))
            );
        }
    }
}

/// B, nu and p of a scene.
fn flow_of(scene: &Scene) -> (f64, f64, f64) {
    let info = scene.kernel_info().expect("checked by the answer");
    let ch = crate::problem::channel::Channel::resolve(scene, info).expect("checked by the answer");
    (ch.flow.b, ch.flow.nu, ch.flow.p)
}

/// On stderr, the warnings when the table's CFL or viscous factor is
/// above the largest the kernel's pressure or viscous term is stable at.
fn warn_factors(t: &crate::problem::c0::C0Table) {
    let what = format!("kernel {} ({})", t.kernel, t.discretisation);
    let warnings = [
        cfl_warning(t.cfl, t.cfl_stable, &what),
        viscous_dt_warning(t.viscous_dt, t.viscous_dt_stable, &what),
    ];
    for w in warnings.into_iter().flatten() {
        eprintln!("{w}");
    }
}

/// A time-step factor in use, for `c0`'s header: its value and the largest
/// at which the kernel's `term` is stable on the perfect lattice, with how
/// the default follows from it (`default`, e.g. "0.85 of 0.1866") where the
/// factor is the default.
fn factor_in_use(
    name: &str,
    term: &str,
    (value, stable): (f64, f64),
    default: Option<String>,
) -> String {
    let bound = format!(
        "the kernel's {term} term is stable on the perfect lattice up to {name} = {stable:.4}"
    );
    match default {
        Some(how) => format!("{name} = {value:.4}, the default ({how}): {bound}"),
        None => format!("{name} = {} (given): {bound}", fmt_value(value)),
    }
}
