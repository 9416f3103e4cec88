//! `shearsph bench`: time a fixed number of steps per kernel and particle
//! count, single-threaded and on all cores; a table, or `--json`.

use std::process::ExitCode;

use anyhow::{bail, Result};
use clap::Args;

use crate::bench::{self, Options};
use crate::config::{ViscousNormalisation, WallVelocity};
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
    /// The disordered scene: the bench scene at N = 10 jittered by 0.05 d
    /// on a strip as wide as the channel, run into its disordered,
    /// stationary state (to t = 640), then tiled along x to each particle
    /// count: every size times the same state, the neighbour list
    /// rebuilding as a disordered run's does.
    #[arg(long, conflicts_with_all = ["pysph_match", "sphinxsys_match"])]
    pub disordered: bool,
    /// Instead: the wall time of the empirical answer (`c0 --empirical`,
    /// every rule beside it) for Monaghan, N = 10, at Re = 1 and 10, each
    /// answered `--repeats` times (the median kept), with the runs it made,
    /// their work and whether every repeat gave the same answer.
    #[arg(long, conflicts_with_all = ["pysph_match", "sphinxsys_match", "disordered"])]
    pub empirical: bool,
    /// Skip measuring the memory bandwidth (the roofline's second roof, a
    /// triad over 3 x 128 MiB after the runs): the roof is then not given.
    #[arg(long)]
    pub no_bandwidth: bool,
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
    /// With --pysph-match: layers in the half-width (default 30, PySPH's
    /// resolution). With --sphinxsys-match: B = N d (default 10, the stock
    /// case's dx = DH / 20).
    #[arg(long)]
    pub layers: Option<u32>,
    /// Instead: one run of the scene matched to SPHinXsys's stock
    /// `test_2d_poiseuille_flow` (bench/peers/sphinxsys_poiseuille.sh):
    /// Wendland C2, square lattice, h = 13/10 d, U B / nu = 7.5, c0 = 10 U,
    /// to t nu / B^2 = --tau, on the first of --threads; prints one JSON line.
    #[arg(long, conflicts_with = "pysph_match")]
    pub sphinxsys_match: bool,
    /// With --sphinxsys-match: the viscous term, `none` (the paper's
    /// Laplacian) or `lattice` (divided by what it gives on the perfect
    /// lattice for a quadratic velocity: Wendland C2 at h = 13/10 d on the
    /// square lattice is otherwise 4.6 % less viscous than asked; see
    /// bench/peers/ACCURACY.md).
    #[arg(long, default_value = "none", requires = "sphinxsys_match")]
    pub viscous_normalisation: ViscousNormalisation,
    /// With --sphinxsys-match: the CFL factor, a number or `default` (the
    /// kernel's own, as `run` takes it: 0.898 here, which `c0 --kernel
    /// wendland_c2 --lattice square --h-over-d 1.3` prints). Default 0.5,
    /// the factor the peer figures in docs/performance.md were measured at.
    #[arg(long, requires = "sphinxsys_match", value_parser = parse_cfl)]
    pub cfl: Option<PeerCfl>,
    /// With --sphinxsys-match: the end time in units of B^2 / nu.
    #[arg(long, default_value_t = 1.0, requires = "sphinxsys_match")]
    pub tau: f64,
    /// With --sphinxsys-match or --pysph-match: columns of the periodic strip
    /// (as many as the peer's channel runs the same particle count; default
    /// with --sphinxsys-match the narrowest the kernel allows, with
    /// --pysph-match the fewest holding as many particles as PySPH's channel
    /// at the same h / B).
    #[arg(long)]
    pub columns: Option<u32>,
}

/// `--cfl` of a matched scene: a factor, or the kernel's own default.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum PeerCfl {
    Factor(f64),
    KernelDefault,
}

impl PeerCfl {
    /// The scene's `cfl` field: `None` leaves it to the kernel's default.
    fn scene_field(arg: Option<PeerCfl>) -> Option<f64> {
        match arg {
            None => Some(bench::PEER_MATCH_CFL),
            Some(PeerCfl::Factor(f)) => Some(f),
            Some(PeerCfl::KernelDefault) => None,
        }
    }
}

fn parse_cfl(s: &str) -> Result<PeerCfl, String> {
    if s.trim() == "default" {
        return Ok(PeerCfl::KernelDefault);
    }
    s.trim()
        .parse()
        .map(PeerCfl::Factor)
        .map_err(|_| format!("{s:?} is neither a number nor `default`"))
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

impl BenchArgs {
    /// Every count checked before any work (at least 1, within its bound,
    /// no value twice, the whole bench within its time bound), and the
    /// options of the default bench (for `--pysph-match` and
    /// `--sphinxsys-match` their counts are checked and the options unused).
    pub fn options(&self) -> Result<Options> {
        if self.layers == Some(0) {
            bail!("--layers must be at least 1 (30 is PySPH's resolution, 10 SPHinXsys's)");
        }
        if self.layers.is_some() && !(self.pysph_match || self.sphinxsys_match) {
            bail!("--layers goes with --pysph-match or --sphinxsys-match");
        }
        if self.columns.is_some() && !(self.pysph_match || self.sphinxsys_match) {
            bail!("--columns goes with --pysph-match or --sphinxsys-match");
        }
        if self.columns == Some(0) {
            bail!("--columns must be at least 1 (120 is SPHinXsys's stock channel at 10 layers)");
        }
        if self.empirical {
            for (flag, given) in [
                ("--kernels", !self.kernels.is_empty()),
                ("--particles", !self.particles.is_empty()),
                ("--steps", self.steps.is_some()),
                ("--threads", !self.threads.is_empty()),
            ] {
                if given {
                    bail!(
                        "{flag} does not go with --empirical: it answers Monaghan N = 10 at Re = 1 \
                         and 10 on every core (RAYON_NUM_THREADS sets fewer); --repeats sets how often"
                    );
                }
            }
        }
        let mut opts = Options::defaults();
        if !self.kernels.is_empty() {
            for k in &self.kernels {
                if kernels::kernel_info(k).is_none() {
                    bail!(
                        "unknown kernel {k:?} (flag --kernels); known kernels: {}",
                        kernels::NAMES.join(", ")
                    );
                }
            }
            opts.kernels = self.kernels.clone();
        }
        if !self.particles.is_empty() {
            opts.particles = self.particles.clone();
        }
        if !self.threads.is_empty() {
            opts.threads = self.threads.clone();
        }
        opts.steps = self.steps;
        opts.repeats = self.repeats;
        opts.bandwidth = !self.no_bandwidth;
        opts.disordered = self.disordered;
        if self.pysph_match || self.sphinxsys_match {
            // One run: its thread count, and its steps by the peer's own
            // estimate (bench::pysph_match checks them).
            if self.steps == Some(0) {
                bail!("--steps must be at least 1: a measurement of no steps has no throughput");
            }
            if self.threads.contains(&0) {
                bail!("--threads must be at least 1");
            }
            let threads = crate::config::bounds::threads();
            for &t in &self.threads {
                threads.check_usize("--threads", t)?;
            }
        } else {
            bench::check(&opts)?;
        }
        Ok(opts)
    }
}

pub fn main(args: BenchArgs) -> Result<ExitCode> {
    // Every count flag within its bound before any work (clap's
    // u64/usize/u32 already refuse negative, fractional and non-finite
    // values, naming the flag).
    let opts = args.options()?;
    let threads = args
        .threads
        .first()
        .copied()
        .unwrap_or_else(|| *bench::thread_counts().last().expect("one count"));
    if args.sphinxsys_match {
        let layers = args.layers.unwrap_or(10);
        let run = bench::sphinxsys_match(
            layers,
            args.tau,
            threads,
            args.columns,
            args.viscous_normalisation,
            PeerCfl::scene_field(args.cfl),
        )?;
        println!("{}", serde_json::to_string(&run)?);
        return Ok(ExitCode::SUCCESS);
    }
    if args.pysph_match {
        // Fewer layers run the same flow coarser, to the same t nu / B^2
        // (`--steps` scaled by (layers / 30)^2): the time to reach an accuracy.
        let run = bench::pysph_match(
            args.steps.unwrap_or(2000),
            threads,
            args.wall_velocity,
            args.layers.unwrap_or(bench::PYSPH_MATCH_LAYERS),
            args.columns,
        )?;
        println!("{}", serde_json::to_string(&run)?);
        return Ok(ExitCode::SUCCESS);
    }
    let quiet = args.quiet;
    let progress = |msg: &str| {
        if !quiet {
            eprintln!("bench: {msg}");
        }
    };
    if args.empirical {
        let rows = bench::empirical(args.repeats, progress)?;
        return print(args.json, rows.as_slice(), bench::empirical_table);
    }
    let report = bench::run(&opts, progress)?;
    print(args.json, &report, bench::table)
}

/// `value` as JSON on stdout with `--json`, else as its table.
fn print<T: serde::Serialize + ?Sized>(
    json: bool,
    value: &T,
    table: impl FnOnce(&T) -> String,
) -> Result<ExitCode> {
    if json {
        println!("{}", serde_json::to_string_pretty(value)?);
    } else {
        print!("{}", table(value));
    }
    Ok(ExitCode::SUCCESS)
}
