//! `shearsph law`: the law of the minimal c0. Runs the embedded law config
//! (src/law/law.toml; --quick the tiny one, --config a file), writes
//! law.csv (every point), law.json (the points and the fits) and one chart
//! per kernel (law_KERNEL.svg), and prints each kernel's fits.

use std::io::IsTerminal;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use anyhow::Result;
use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};

use crate::law::{self, describe, Config, Law};
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
    /// A law config (TOML, as src/law/law.toml) instead of the embedded one.
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
        Config::parse,
        Config::quick,
        Config::default_full,
    )?;
    if !args.kernel.is_empty() {
        config.kernels = args.kernel.clone();
    }
    for k in &config.kernels {
        crate::config::kernel_info(k)?;
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
    let stop = super::interrupt::stop_on_ctrl_c_saying("stopping the law's runs")?;
    let t0 = Instant::now();
    let points = match law::run(&config, &stop, &bar) {
        Err(_) if stop.load(std::sync::atomic::Ordering::Relaxed) => {
            bar.finish_and_clear();
            eprintln!("interrupted: the law's points are not written");
            return Ok(ExitCode::from(super::interrupt::EXIT_INTERRUPTED));
        }
        r => r?,
    };
    bar.finish_and_clear();
    let result = Law::new(&config, points, t0.elapsed().as_secs_f64());
    write_atomic(
        &args.out.join("law.csv"),
        law::csv(&result.points).as_bytes(),
    )?;
    write_atomic(
        &args.out.join("law.json"),
        serde_json::to_string_pretty(&result)?.as_bytes(),
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
    Ok(ExitCode::SUCCESS)
}
