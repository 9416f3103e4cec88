//! `shearsph run`: one scene, with a progress bar; writes the summary, the
//! profile, the time series and the charts, and prints the summary. Ctrl-C
//! ends the run at the next step and writes the same outputs up to there.
//! Every output, the particle snapshots too, is staged while the run goes
//! and swapped into `--out` as one set at the end ([`StagedSet`]): over an
//! earlier run (`--force`), an error on the way (a full disk) leaves that
//! run's files as they were.

use std::io::IsTerminal;
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, Ordering};

use anyhow::{Context, Result};
use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};

use super::interrupt::{stop_flag, EXIT_INTERRUPTED};
use super::SceneArgs;
use crate::charts::run::stage_charts;
use crate::output::{self, StagedSet, Summary};
use crate::particles::series::{self, ParticleOutput, Snapshot};
use crate::problem::cost::{cfl_warning, viscous_dt_warning};
use crate::problem::Problem;
use crate::run::run_problem;
use crate::solver::{Class, Observer, Outcome, RunResult, Sample};

/// Exit status of a run that completed but whose class is `failed`.
pub const EXIT_FAILED_RUN: u8 = 3;
/// Exit status of a run that reached t_end but is `inaccurate`.
pub const EXIT_INACCURATE: u8 = 4;
/// Exit status of a run that reached t_end but is `over-compressed`.
pub const EXIT_OVER_COMPRESSED: u8 = 5;

/// Run one scene and classify it as the sweep does (the scene's
/// `linf_bound` and `eps_margin`, or --linf-bound and --eps-margin).
///
/// Exit status: 0 when the run is `ok`; 3 `failed`; 4 `inaccurate` (L_inf
/// error above linf_bound); 5 `over-compressed` (compaction above the
/// kernel's eps0 + eps_margin); 130 when a signal (Ctrl-C, SIGTERM, SIGHUP)
/// stopped it (`interrupted`);
/// the outputs are written in all these cases. 1 on an error (bad input).
#[derive(Debug, Args)]
#[command(allow_negative_numbers = true, args_override_self = true)]
pub struct RunArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Output folder.
    #[arg(long, default_value = "out/run")]
    pub out: PathBuf,
    /// Overwrite the files of an existing output folder.
    #[arg(long)]
    pub force: bool,
    /// No progress bar.
    #[arg(long)]
    pub quiet: bool,
    /// Print the summary as JSON on stdout.
    #[arg(long)]
    pub json: bool,
    /// Write no particle snapshots (`particles.pvd` and its `.vtu` files);
    /// the picture `particles.svg` is still drawn.
    #[arg(long)]
    pub no_particles: bool,
    /// Keep every K-th output time's particle snapshot (from t = 0; the
    /// last one always).
    #[arg(long, value_name = "K", default_value_t = 1, value_parser = clap::value_parser!(u64).range(1..))]
    pub particles_every: u64,
}

pub fn main(args: RunArgs) -> Result<ExitCode> {
    let scene = args.scene.load()?;
    let stop = stop_flag("ending the run at this step and writing its outputs so far")?;
    // `--c0 empirical`: the search first, then this run at its answer.
    let scene = super::c0::empirical_scene(scene, args.quiet, !args.json, stop)?;
    // Check everything before touching the output folder: the scene, and a
    // run that covers at least one time step.
    let problem = Problem::resolve(&scene, scene.kernel_info()?)
        .and_then(|p| p.check_duration().map(|()| p))
        .map_err(|e| args.scene.label(e))?;
    let what = format!(
        "kernel {} ({})",
        problem.kernel.name,
        problem.discretisation.label()
    );
    let warnings = [
        cfl_warning(
            problem.dt_factors.cfl,
            problem.acoustic_stable_factor(),
            &what,
        ),
        viscous_dt_warning(
            problem.dt_factors.viscous,
            problem.viscous_stable_factor(),
            &what,
        ),
    ];
    for w in warnings.into_iter().flatten() {
        eprintln!("{w}");
    }
    output::prepare_dir(&args.out, args.force)?;
    let set = StagedSet::begin(&args.out)?;

    let bar = if args.quiet || !std::io::stderr().is_terminal() {
        ProgressBar::hidden()
    } else {
        let bar = ProgressBar::new(1000);
        bar.set_style(
            ProgressStyle::with_template(
                "{spinner} [{elapsed_precise}] {wide_bar} {percent:>3}% {msg}",
            )
            .expect("valid template"),
        );
        bar
    };
    if !args.quiet {
        // After the handler is in place: from here Ctrl-C keeps the outputs.
        eprintln!(
            "running {} N = {} to t = {:.6} (Ctrl-C stops and writes the outputs so far)",
            scene.kernel, problem.lattice.n_layers, problem.t_end
        );
        if !args.no_particles {
            let particles = problem.lattice.n_particles();
            let outputs = series::output_times(problem.t_end, problem.output_interval);
            let (frames, bytes) = series::series_size(outputs, args.particles_every, particles);
            eprintln!(
                "particle snapshots: {frames} of {particles} particles, about {:.1} MB in {} \
                 ({:.0} kB per 1,000 particles each; --particles-every K or --no-particles for fewer)",
                bytes / 1e6,
                args.out.join("particles.pvd").display(),
                series::VTU_BYTES_PER_PARTICLE
            );
        }
    }
    let mut progress = Progress {
        bar: bar.clone(),
        t_end: problem.t_end,
        stop,
    };
    let every = (!args.no_particles).then_some(args.particles_every);
    let mut observer = ParticleOutput::new(&mut progress, set.path(), every);
    let result = run_problem(&problem, &mut observer);
    bar.finish_and_clear();
    let last = observer.finish();
    write_set(set, &result, last).with_context(|| {
        format!(
            "writing the outputs of the run; {} keeps its earlier files",
            args.out.display()
        )
    })?;
    let class = result.class(&result.problem.scene.classes());
    let summary = Summary::new(&result);
    if args.json {
        println!("{}", summary.to_json());
        if let Outcome::Failed { .. } = result.outcome {
            eprintln!("class: {}", verdict(&summary, &result.outcome, class));
        }
    } else {
        print_summary(&summary, &result.outcome, class, &args.out);
    }
    if class == Class::Interrupted {
        eprintln!(
            "{}: the outputs up to there are in {}",
            result.outcome,
            args.out.display()
        );
    }
    Ok(exit_code(class))
}

/// Every output of the run, staged beside the particle series already in
/// `set`, then swapped in as one set.
fn write_set(set: StagedSet, result: &RunResult, last: Result<Option<Snapshot>>) -> Result<()> {
    output::write_outputs(&set, result)?;
    stage_charts(&set, result)?;
    if let Some(last) = last? {
        series::write_picture(set.path(), &last, result)?;
    }
    set.commit()?;
    Ok(())
}

struct Progress {
    bar: ProgressBar,
    t_end: f64,
    /// Set by a signal.
    stop: &'static AtomicBool,
}

impl Observer for Progress {
    fn step(&mut self, t: f64, steps: u64) {
        if steps.is_multiple_of(256) {
            self.bar.set_position((1000.0 * t / self.t_end) as u64);
        }
    }
    fn output(&mut self, s: &Sample) {
        self.bar.set_position((1000.0 * s.t / self.t_end) as u64);
        self.bar.set_message(format!(
            "t = {:.4}  Linf = {:.2e}  max eps = {:.2e}",
            s.t, s.linf_rel_err, s.max_eps
        ));
    }
    fn should_stop(&self) -> bool {
        self.stop.load(Ordering::Relaxed)
    }
}

/// The exit status of a finished run's class.
pub fn exit_code(class: Class) -> ExitCode {
    match class {
        Class::Ok => ExitCode::SUCCESS,
        Class::Inaccurate => ExitCode::from(EXIT_INACCURATE),
        Class::OverCompressed => ExitCode::from(EXIT_OVER_COMPRESSED),
        Class::Failed => ExitCode::from(EXIT_FAILED_RUN),
        Class::Interrupted => ExitCode::from(EXIT_INTERRUPTED),
    }
}

/// The run's class and, in the same line, what made it that: one statement
/// (never "outcome: ok" beside "class: over-compressed").
fn verdict(s: &Summary, outcome: &Outcome, class: Class) -> String {
    let within = format!(
        "mean-flow L_inf {:.4} of U (bound {:.4}), eps_stat {:.4} (bound {:.4}) over its window",
        s.linf_stat, s.linf_bound, s.eps_stat, s.eps_bound
    );
    match (class, outcome) {
        (Class::Ok, _) => format!("ok: within both bounds, {within}"),
        (Class::Inaccurate, _) => format!(
            "inaccurate: its window's mean-flow error {:.4} of U is above {:.4}",
            s.linf_stat, s.linf_bound
        ),
        (Class::OverCompressed, _) => format!(
            "over-compressed: its window's compaction eps_stat (mean p99 eps) {:.4} is above {:.4} \
             (the kernel's eps0 plus eps_margin)",
            s.eps_stat, s.eps_bound
        ),
        // "failed at t = ..., step ...: what, the particle"
        (Class::Failed, Outcome::Failed { .. }) => outcome.to_string(),
        (Class::Failed, _) => format!(
            "failed: reached t_end with {}",
            s.failure_reason
                .as_deref()
                .unwrap_or("an error that is not finite")
        ),
        (Class::Interrupted, _) => format!(
            "interrupted: stopped at t = {:.6} of {:.6} (step {}), before t_end: not judged, {within} so far",
            s.t, s.t_end, s.steps
        ),
    }
}

fn print_summary(s: &Summary, outcome: &Outcome, class: Class, out: &std::path::Path) {
    println!(
        "{} N = {} ({} particles), Re = {:.4}, U = {}, alpha = {}",
        s.kernel, s.n, s.particles, s.re, s.u, s.alpha
    );
    println!(
        "c0 = {:.6} ({}), c0 / U = {:.4}",
        s.c0,
        s.c0_rule,
        s.c0 / s.u
    );
    println!(
        "t = {:.6} of {:.6} in {} steps, dt = {:.4e} ({}), {:.2} s, {:.3e} particle-steps/s",
        s.t,
        s.t_end,
        s.steps,
        s.dt,
        s.dt_limit.map_or("none", |l| l.name()),
        s.wall_s,
        s.particle_steps_per_s
    );
    println!(
        "error / U: Linf = {:.4e}, L2 = {:.4e}; max eps = {:.4e}, mean eps = {:.4e}, RMS v / U = {:.4e}",
        s.linf,
        s.l2,
        s.max_eps,
        s.mean_eps,
        s.rms_v / s.u
    );
    println!(
        "window {:.6} < t <= {:.6} ({} frames, {} horizon): {}, {}; eps_stat (mean p99 eps) = \
         {:.4e}, mean-flow L_inf / U = {:.4e}, RMS v / U = {:.4e}, dy_rms = {:.3e} d{}",
        s.window_from,
        s.window_to,
        s.window_frames,
        s.horizon,
        if s.stationary {
            "stationary"
        } else {
            "not stationary"
        },
        s.regime,
        s.eps_stat,
        s.linf_stat,
        s.rms_v_stat / s.u,
        s.dy_rms,
        s.t_disorder
            .map_or(String::new(), |t| format!(", disordered from t = {t:.4}"))
    );
    if let Some(why) = &s.unsteady {
        println!("  not stationary: {why}");
    }
    println!("class: {}", verdict(s, outcome, class));
    println!("outputs in {}", out.display());
}
