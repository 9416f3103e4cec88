//! `shearsph report`: the main job. Runs the embedded report config (or the
//! tiny one with --quick) and writes `index.html` with every table, figure
//! and verdict, the figures as SVG files and the CSV behind each.

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Result;
use clap::Args;

use super::interrupt::{stop_flag, EXIT_INTERRUPTED};
use super::sweep::scenes_bar;
use crate::report::{self, Options, ReportConfig};
use crate::sweep::Parallel;

/// Reproduce the paper's tables and figure, test the derived c0 with the
/// solver, and write a self-contained report.
#[derive(Debug, Args)]
pub struct ReportArgs {
    /// Output folder.
    #[arg(long, default_value = "out/report")]
    pub out: PathBuf,
    /// Overwrite the files of an existing output folder.
    #[arg(long)]
    pub force: bool,
    /// Add the law of the minimal c0 from a folder `shearsph law` wrote.
    #[arg(long, value_name = "DIR")]
    pub law: Option<PathBuf>,
    /// A tiny report in seconds (short runs, small grids): for tests.
    #[arg(long)]
    pub quick: bool,
    /// A report config (TOML, as src/studies/report/report.toml) instead of the
    /// embedded one.
    #[arg(long, value_name = "FILE", conflicts_with = "quick")]
    pub config: Option<PathBuf>,
    /// Scenes at once (default: one per core; at most 8 per core).
    #[arg(long)]
    pub jobs: Option<usize>,
    /// No progress bar (the stage lines still go to stderr).
    #[arg(long)]
    pub quiet: bool,
}

pub fn main(args: ReportArgs) -> Result<ExitCode> {
    if let Some(j) = args.jobs {
        crate::config::bounds::threads().check_usize("--jobs", j)?;
    }
    let config = super::load_config(
        args.config.as_deref(),
        args.quick,
        ReportConfig::parse,
        ReportConfig::quick,
        ReportConfig::default_full,
    )?;
    let stop =
        stop_flag("stopping the report's scenes; the report keeps only files already complete")?;
    let bar = scenes_bar(args.quiet);
    let log = |line: &str| bar.suspend(|| eprintln!("{line}"));
    let opts = Options {
        par: Parallel::new(args.jobs, 1),
        force: args.force,
        law: args.law.clone(),
    };
    let data = match report::run(&config, args.quick, &args.out, opts, stop, &bar, &log) {
        Ok(data) => data,
        Err(e) if stop.load(std::sync::atomic::Ordering::SeqCst) => {
            bar.finish_and_clear();
            eprintln!("{e}");
            return Ok(ExitCode::from(EXIT_INTERRUPTED));
        }
        Err(e) => return Err(e),
    };
    for v in &data.verdicts {
        println!("{}", v.summary);
    }
    println!("open {}", args.out.join("index.html").display());
    Ok(ExitCode::SUCCESS)
}
