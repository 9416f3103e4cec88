//! `shearsph law`: the law of the minimal c0. Runs the embedded law config
//! (src/studies/law/law.toml; --quick the tiny one, --config a file), writes
//! law.csv (every point), law.json (the points and the fits) and one chart
//! per kernel (law_KERNEL.svg), and prints each kernel's fits.

use std::io::IsTerminal;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use anyhow::{Context, Result};
use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};

use super::interrupt::{stop_flag, EXIT_INTERRUPTED};
use crate::law::{self, describe, Law, LawConfig};
use crate::output::{prepare_dir, write_atomic};

/// The empirical c0_min per kernel over N x Re x alpha, and its fitted law
/// against the paper's scaling U / sqrt(N Re) and (2N - 1) U / N^2.
#[derive(Debug, Args)]
pub struct LawArgs {
    /// Output folder.
    #[arg(long, default_value = "out/law")]
    pub out: PathBuf,
    /// Overwrite the files of an existing output folder.
    #[arg(long)]
    pub force: bool,
    /// A tiny law in seconds (short runs, small grid): for tests.
    #[arg(long)]
    pub quick: bool,
    /// A law config (TOML, as src/studies/law/law.toml) instead of the embedded one.
    #[arg(long, value_name = "FILE", conflicts_with = "quick")]
    pub config: Option<PathBuf>,
    /// Only these kernels of the config (repeatable).
    #[arg(long)]
    pub kernel: Vec<String>,
    /// No progress bar.
    #[arg(long)]
    pub quiet: bool,
}

pub fn main(args: LawArgs) -> Result<ExitCode> {
    let mut config = super::load_config(
        args.config.as_deref(),
        args.quick,
        LawConfig::parse,
        LawConfig::quick,
        LawConfig::default_full,
    )?;
    if !args.kernel.is_empty() {
        crate::config::bounds::distinct("--kernel", &args.kernel)?;
        config.kernels = args.kernel.clone();
    }
    for k in &config.kernels {
        crate::config::kernel_info(k)?;
    }
    // Every point's search within its scene's bounds before any run: the
    // first probe (hi_over_u U) and the largest recommendation (the law
    // runs none, but its margin is the engine's) named as the config's.
    let origin = args.config.as_ref().map_or_else(
        || "the embedded law config".to_string(),
        |p| format!("law config {}", p.display()),
    );
    let search = config.search();
    for (k, n, re, a) in config.points() {
        let scene = config.scene(&k, n, re, a)?;
        super::c0::check_search_top(
            &scene,
            &crate::empirical::Search {
                margin: 1.0,
                ..search
            },
            &|field| Some(format!("{origin}: `{field}`")),
        )
        .with_context(|| format!("law point kernel {k}, N = {n}, Re = {re}, alpha = {a}"))?;
    }
    prepare_dir(&args.out, args.force)?;
    let bar = if args.quiet || !std::io::stderr().is_terminal() {
        ProgressBar::hidden()
    } else {
        let bar = ProgressBar::new(1);
        bar.set_style(
            ProgressStyle::with_template("[{elapsed_precise}] {wide_bar} {pos}/{len} points")
                .expect("valid template"),
        );
        bar
    };
    let t0 = Instant::now();
    let stop = stop_flag(
        "starting no more points; the finished ones are written (the one running is dropped)",
    )?;
    let planned = config.points().len();
    let points = law::run_until(&config, &bar, stop)?;
    bar.finish_and_clear();
    let interrupted = points.len() < planned;
    let result = Law::new(&config, points, t0.elapsed().as_secs_f64());
    write_atomic(
        &args.out.join("law.csv"),
        law::csv(&result.points).as_bytes(),
    )?;
    // An interrupted law says so in its JSON: its fits are of the points
    // finished, not of the config's grid.
    let mut json = serde_json::to_value(&result)?;
    if let Some(obj) = json.as_object_mut() {
        obj.insert("interrupted".into(), interrupted.into());
        obj.insert("points_planned".into(), planned.into());
    }
    write_atomic(
        &args.out.join("law.json"),
        serde_json::to_string_pretty(&json)?.as_bytes(),
    )?;
    for kl in &result.laws {
        let svg = crate::charts::law::law_svg(kl, &result.points)?;
        write_atomic(
            &args.out.join(format!("law_{}.svg", kl.kernel)),
            svg.as_bytes(),
        )?;
        println!(
            "kernel {}: {} points fitted, {} not (no bracketed c0_min)",
            kl.kernel,
            kl.fitted,
            kl.unfitted.len()
        );
        for u in &kl.unfitted {
            println!("  not fitted: {u}");
        }
        let show = |label: &str, f: &Option<law::fit::Fit>| match f {
            Some(f) => println!("  {label}: {}", describe(f)),
            None => println!("  {label}: too few points"),
        };
        show("free fit ln c0_min/U", &kl.free);
        show("free fit, alpha = 0 only", &kl.free_alpha0);
        show("paper's U/sqrt(N Re), alpha = 0", &kl.paper);
        show("(2N - 1) U / N^2", &kl.layers);
    }
    println!(
        "{} points in {:.1} s; wrote {}",
        result.points.len(),
        result.wall_s,
        args.out.display()
    );
    if interrupted {
        eprintln!(
            "interrupted: {} of {planned} points finished, written (law.json says \"interrupted\": true); \
             the fits are of those",
            result.points.len()
        );
        return Ok(ExitCode::from(EXIT_INTERRUPTED));
    }
    Ok(ExitCode::SUCCESS)
}
