//! `shearsph bench`: time a fixed number of steps per kernel and particle
//! count, single-threaded and on all cores; a table, or `--json`.

use std::process::ExitCode;

use anyhow::{bail, Result};
use clap::Args;

use crate::bench::{self, Options};
use crate::config::WallVelocity;
use crate::kernels;

/// Time the solver's steps: throughput, ns per pair, memory, GFLOP/s against
/// the machine's peak, and the growth of the cost with the particle count.
#[derive(Debug, Args)]
#[command(allow_negative_numbers = true)]
pub struct BenchArgs {
    /// Kernels, comma-separated (default: every kernel).
    #[arg(long, value_delimiter = ',')]
    pub kernels: Vec<String>,
    /// Particle counts to measure (each scene is the smallest channel with
    /// at least this many, walls included), comma-separated; 1e4 is accepted.
    #[arg(long, value_delimiter = ',', value_parser = parse_count)]
    pub particles: Vec<usize>,
    /// Steps per measurement (default: about 4e6 particle-steps, at least 10).
    #[arg(long)]
    pub steps: Option<u64>,
    /// Repeats per measurement; the median is reported.
    #[arg(long, default_value_t = 3)]
    pub repeats: usize,
    /// Thread counts, comma-separated (default: 1 and every core).
    #[arg(long, value_delimiter = ',')]
    pub threads: Vec<usize>,
    /// Print the report as JSON on stdout.
    #[arg(long)]
    pub json: bool,
    /// No progress lines on stderr.
    #[arg(long)]
    pub quiet: bool,
    /// Instead: one run of the scene matched to PySPH's stock
    /// `pysph.examples.poiseuille` (see bench/peers/), `--steps` steps (default
    /// 2000) on the first of `--threads` (default all cores); prints JSON.
    #[arg(long)]
    pub pysph_match: bool,
    /// With --pysph-match: the walls' velocity in the viscous term, `zero`
    /// (the paper's walls) or `mirrored` (no-slip at y = B, the class of
    /// wall PySPH's example uses).
    #[arg(long, default_value = "mirrored", requires = "pysph_match")]
    pub wall_velocity: WallVelocity,
    /// With --pysph-match: layers in the half-width. 35 is PySPH's
    /// resolution; fewer run the same flow coarser, to the same t nu / B^2
    /// (`--steps` scaled by (layers / 35)^2): the time to reach an accuracy.
    #[arg(long, default_value_t = bench::PYSPH_MATCH_LAYERS, requires = "pysph_match")]
    pub layers: u32,
}

fn parse_count(s: &str) -> Result<usize, String> {
    let v: f64 = s
        .trim()
        .parse()
        .map_err(|_| format!("{s:?} is not a particle count"))?;
    if v >= 1.0 && v.is_finite() && v.fract() == 0.0 {
        Ok(v as usize)
    } else {
        Err(format!("{s:?} is not a positive whole number"))
    }
}

pub fn main(args: BenchArgs) -> Result<ExitCode> {
    // Every count flag at least 1 (clap's u64/usize/u32 already refuse
    // negative, fractional and non-finite values, naming the flag).
    if args.steps == Some(0) {
        bail!("--steps must be at least 1: a measurement of no steps has no throughput");
    }
    if args.repeats == 0 {
        bail!("--repeats must be at least 1");
    }
    if args.threads.contains(&0) {
        bail!("--threads must be at least 1");
    }
    if args.pysph_match && args.layers == 0 {
        bail!("--layers must be at least 1 (35 is PySPH's resolution)");
    }
    if args.pysph_match {
        let threads = args
            .threads
            .first()
            .copied()
            .unwrap_or_else(|| *bench::thread_counts().last().expect("one count"));
        let run = bench::pysph_match(
            args.steps.unwrap_or(2000),
            threads,
            args.wall_velocity,
            args.layers,
        )?;
        println!("{}", serde_json::to_string(&run)?);
        return Ok(ExitCode::SUCCESS);
    }
    let mut opts = Options::defaults();
    if !args.kernels.is_empty() {
        for k in &args.kernels {
            if kernels::kernel_info(k).is_none() {
                bail!(
                    "unknown kernel {k:?} (flag --kernels); known kernels: {}",
                    kernels::NAMES.join(", ")
                );
            }
        }
        opts.kernels = args.kernels;
    }
    if !args.particles.is_empty() {
        opts.particles = args.particles;
    }
    if !args.threads.is_empty() {
        opts.threads = args.threads;
    }
    opts.steps = args.steps;
    opts.repeats = args.repeats;
    let quiet = args.quiet;
    let report = bench::run(&opts, |msg| {
        if !quiet {
            eprintln!("bench: {msg}");
        }
    })?;
    if args.json {
        println!("{}", serde_json::to_string_pretty(&report)?);
    } else {
        print!("{}", bench::table(&report));
    }
    Ok(ExitCode::SUCCESS)
}
