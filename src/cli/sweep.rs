//! `shearsph sweep`: many scenes in parallel over a grid (kernels x N x Re x
//! alpha x c0), resumable and shardable; `shearsph sweep merge` combines
//! shard folders. Writes `results.jsonl`, `results.csv` and the charts (speed
//! against accuracy, a stability map per kernel) into the output folder.

use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::Result;
use clap::{Args, Subcommand};
use indicatif::{ProgressBar, ProgressStyle};
use serde::Serialize;

use super::interrupt::{stop_on_ctrl_c, EXIT_INTERRUPTED};
use crate::charts;
use crate::config::bounds;
use crate::output::write_atomic;
use crate::report;
use crate::sweep::{self, store, Class, Parallel, Row, ShardArg, SweepSpec};

mod grid;
pub use grid::{GridArgs, GridClassArgs, GridSceneArgs, SweepOrigins};

/// Run a grid of scenes in parallel, or merge shard folders.
///
/// The grid comes from --sweep FILE (TOML: kernels, n, re, alpha, c0,
/// c0_over_u, lattice, h_over_d, jitter, seeds, [classes], [scene]) and/or the flags (lists, comma-separated;
/// a flag replaces the file's list). With neither, the folder's own sweep is
/// resumed (or the default grid started). A finished point is never rerun.
#[derive(Debug, Args)]
#[command(args_conflicts_with_subcommands = true)]
pub struct SweepArgs {
    #[command(subcommand)]
    pub command: Option<SweepCommand>,
    #[command(flatten)]
    pub run: RunSweepArgs,
}

#[derive(Debug, Subcommand)]
pub enum SweepCommand {
    /// Combine the folders of shards (--shard k/n) of one sweep into one.
    Merge(MergeArgs),
}

#[derive(Debug, Args)]
pub struct MergeArgs {
    /// Shard folders, each holding the same sweep.toml.
    #[arg(required = true, value_name = "DIR")]
    pub dirs: Vec<PathBuf>,
    /// Folder for the merged rows and charts.
    #[arg(long)]
    pub out: PathBuf,
    /// Overwrite the files of an existing output folder.
    #[arg(long)]
    pub force: bool,
    /// No charts, only the rows.
    #[arg(long)]
    pub no_charts: bool,
    /// Merge even when some points of the grid are finished in none of the
    /// folders (by default that is an error naming what is missing).
    #[arg(long)]
    pub partial: bool,
}

#[derive(Debug, Args)]
#[command(allow_negative_numbers = true)]
pub struct RunSweepArgs {
    /// Write each point's particle snapshots (every K-th output time, the
    /// last always) and picture under OUT/particles/POINT/ (none by default).
    #[arg(long, value_name = "K", value_parser = clap::value_parser!(u64).range(1..))]
    pub particles_every: Option<u64>,
    #[command(flatten)]
    pub grid: GridArgs,
    /// Output folder.
    #[arg(long, default_value = "out/sweep")]
    pub out: PathBuf,
    /// Start over in an existing folder (its rows are dropped).
    #[arg(long)]
    pub force: bool,
    /// Run only grid points k, k + n, k + 2n, ... (0 <= k < n); `auto` takes
    /// k and n from a Slurm job array (SLURM_ARRAY_TASK_ID - _MIN, _COUNT).
    /// A folder keeps its shard (shard.toml): a resubmitted task resumes it.
    #[arg(long, value_name = "K/N|auto", allow_hyphen_values = true)]
    pub shard: Option<ShardArg>,
    /// Scenes at once (default: cores / threads-per-scene; at most 8 threads
    /// per core in all).
    #[arg(long)]
    pub jobs: Option<usize>,
    /// Threads inside each scene (at most 8 threads per core in all).
    #[arg(long, default_value_t = 1)]
    pub threads_per_scene: usize,
    /// No progress bar.
    #[arg(long)]
    pub quiet: bool,
    /// No charts, only the rows.
    #[arg(long)]
    pub no_charts: bool,
    /// Print what the sweep did as JSON on stdout.
    #[arg(long)]
    pub json: bool,
}

impl RunSweepArgs {
    /// Scenes at once and threads in each, checked against the threads'
    /// bound ([`bounds::threads`]) before any work: 0 of either is an error
    /// (not silently 1), and so is more than 8 threads per core in all.
    pub fn parallel(&self) -> Result<Parallel> {
        let threads = bounds::threads();
        threads.check_usize("--threads-per-scene", self.threads_per_scene)?;
        if let Some(j) = self.jobs {
            threads.check_usize("--jobs", j)?;
        }
        let par = Parallel::new(self.jobs, self.threads_per_scene);
        threads.check_usize(
            &format!(
                "--jobs x --threads-per-scene ({} x {})",
                par.jobs, par.threads_per_scene
            ),
            par.jobs.saturating_mul(par.threads_per_scene),
        )?;
        Ok(par)
    }
}

/// A progress bar over `len` scenes on stderr, hidden when stderr is not a
/// terminal or `quiet`.
pub fn scenes_bar(quiet: bool) -> ProgressBar {
    if quiet || !std::io::stderr().is_terminal() {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::new(0);
    bar.set_style(
        ProgressStyle::with_template(
            "{spinner} [{elapsed_precise}] {wide_bar} {pos}/{len} scenes  {msg}",
        )
        .expect("valid template"),
    );
    bar
}

#[derive(Debug, Serialize)]
struct SweepReport<'a> {
    out: &'a Path,
    points: usize,
    ran: usize,
    already: usize,
    remaining: usize,
    interrupted: bool,
    ok: usize,
    inaccurate: usize,
    over_compressed: usize,
    failed: usize,
}

pub fn main(args: SweepArgs) -> Result<ExitCode> {
    match args.command {
        Some(SweepCommand::Merge(m)) => merge(m),
        None => run(args.run),
    }
}

fn run(args: RunSweepArgs) -> Result<ExitCode> {
    // Every count and value before any work.
    let par = args.parallel()?;
    let spec = args.grid.spec()?;
    let origins = args.grid.origins()?;
    let stop = stop_on_ctrl_c()?;
    let bar = scenes_bar(args.quiet);
    let r = sweep::run_sweep(
        sweep::SweepRequest {
            dir: &args.out,
            spec,
            force: args.force,
            shard: args.shard,
            par,
            particles_every: args.particles_every,
            origins: Some(&origins),
        },
        stop,
        &bar,
        &|_| {},
    )?;
    bar.finish_and_clear();
    if !args.no_charts {
        write_charts(&args.out, &r.spec, &r.rows)?;
    }
    if let Some(s) = r.shard {
        if r.ran + r.already + r.remaining == 0 {
            eprintln!(
                "warning: shard {}/{} gets no point of the {}-point grid (points k, k + n, ...): it ran nothing",
                s.k,
                s.n,
                r.spec.points().len()
            );
        }
    }
    let count = |c: Class| r.rows.iter().filter(|row| row.class == c).count();
    let summary = SweepReport {
        out: &args.out,
        points: r.rows.len(),
        ran: r.ran,
        already: r.already,
        remaining: r.remaining,
        interrupted: r.interrupted,
        ok: count(Class::Ok),
        inaccurate: count(Class::Inaccurate),
        over_compressed: count(Class::OverCompressed),
        failed: count(Class::Failed),
    };
    if args.json {
        println!("{}", serde_json::to_string_pretty(&summary)?);
    } else {
        println!(
            "{} points in {}: ran {} now, {} were done before, {} to go",
            r.ran + r.already + r.remaining,
            args.out.display(),
            r.ran,
            r.already,
            r.remaining
        );
        println!(
            "rows: {} ok, {} inaccurate, {} over-compressed, {} failed (results.csv, results.jsonl)",
            summary.ok, summary.inaccurate, summary.over_compressed, summary.failed
        );
    }
    if r.interrupted {
        eprintln!(
            "interrupted: {} finished rows kept; run the same command again to resume",
            r.rows.len()
        );
        return Ok(ExitCode::from(EXIT_INTERRUPTED));
    }
    Ok(ExitCode::SUCCESS)
}

fn merge(args: MergeArgs) -> Result<ExitCode> {
    let (spec, rows) = store::merge(&args.dirs, &args.out, args.force, args.partial)?;
    if !args.no_charts {
        write_charts(&args.out, &spec, &rows)?;
    }
    let total = spec.points().len();
    println!(
        "merged {} folders into {}: {} of {} points finished",
        args.dirs.len(),
        args.out.display(),
        rows.len(),
        total
    );
    Ok(ExitCode::SUCCESS)
}

/// Speed against accuracy (by wall time and by particle-steps), and a
/// stability map per kernel with more than one c0 (at the grid's first N and
/// alpha), each with the CSV behind it.
pub fn write_charts(dir: &Path, spec: &SweepSpec, rows: &[Row]) -> Result<()> {
    let pts = charts::speed_points(rows);
    if !pts.is_empty() {
        write_atomic(
            &dir.join("speed_accuracy.csv"),
            charts::speed_csv(&pts).as_bytes(),
        )?;
        write_atomic(
            &dir.join("speed_accuracy.svg"),
            charts::speed_svg(&pts, charts::Cost::WallTime)?.as_bytes(),
        )?;
        write_atomic(
            &dir.join("speed_accuracy_work.svg"),
            charts::speed_svg(&pts, charts::Cost::ParticleSteps)?.as_bytes(),
        )?;
    }
    let (Some(&n), Some(&alpha)) = (spec.n.first(), spec.alpha.first()) else {
        return Ok(());
    };
    // The map is drawn at the grid's first N, alpha, discretisation and
    // jitter amplitude (by grid position, not by value); a jittered
    // point's cell pools its seeds.
    let Some(disc) = spec.points().first().map(|p| (p.disc, p.start)) else {
        return Ok(());
    };
    let mut base = spec.scene.clone();
    base.insert("lattice".into(), disc.0.lattice.name().into());
    base.insert("h_over_d".into(), disc.0.h_over_d.to_string().into());
    let mut what = String::new();
    if disc.0 != sweep::Discretisation::PAPER {
        what = format!(
            ", {} lattice, h = {} d",
            disc.0.lattice.name(),
            disc.0.h_over_d
        );
    }
    if let sweep::Start::Jittered { amplitude, .. } = disc.1 {
        what.push_str(&format!(
            ", jitter {amplitude} d, {} seeds pooled",
            spec.seeds
        ));
    }
    for (kernel, krows) in charts::by_kernel(rows) {
        let first: Vec<Row> = krows
            .into_iter()
            .filter(|r| {
                let a = r.at;
                (a.n, a.alpha, a.lattice, a.h_over_d, a.jitter) == (0, 0, 0, 0, 0)
            })
            .cloned()
            .collect();
        let pooled: Vec<Row> = sweep::pool_over_seeds(&first)
            .into_iter()
            .map(|g| g.pooled)
            .filter(|r| r.c0_over_u.is_finite() && r.c0_over_u > 0.0)
            .collect();
        let here: Vec<&Row> = pooled.iter().collect();
        let mut c0s: Vec<f64> = here.iter().map(|r| r.c0_over_u).collect();
        c0s.sort_by(f64::total_cmp);
        c0s.dedup();
        if c0s.len() < 2 {
            continue;
        }
        let cells = report::map_cells(&here);
        let res: Vec<f64> = here.iter().map(|r| r.re).collect();
        let lines = report::rule_lines(&kernel, &base, n, alpha, &res)?;
        let title =
            format!("{kernel}: outcome over c0 / U and Re (N = {n}, alpha = {alpha}{what})");
        write_atomic(
            &dir.join(format!("stability_{kernel}.csv")),
            charts::map_csv(&kernel, &cells).as_bytes(),
        )?;
        write_atomic(
            &dir.join(format!("stability_{kernel}_lines.csv")),
            charts::map_lines_csv(&kernel, &lines).as_bytes(),
        )?;
        write_atomic(
            &dir.join(format!("stability_{kernel}.svg")),
            charts::map_svg(&title, &cells, &lines, &[])?.as_bytes(),
        )?;
    }
    Ok(())
}
