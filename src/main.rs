//! The `shearsph` command line: parses the flags and hands each subcommand
//! to its module in `shearsph::cli`.

use std::process::ExitCode;

use clap::{Parser, Subcommand};
use shearsph::cli;

/// Model sound speed c0 for SPH plane shear flow: exact derivation and a
/// fast 2D solver.
#[derive(Debug, Parser)]
#[command(name = "shearsph", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Every kernel: support, eps at 0 and 0.5 T, true extremes and where, mean, c0 coefficients.
    Kernels(cli::kernels::KernelsArgs),
    /// Run one scene: progress bar; summary, profile, time series, charts.
    Run(cli::run::RunArgs),
    /// c0 for a kernel and a scene by every rule, with the time step each implies.
    C0(cli::c0::C0Args),
    /// Many scenes in parallel over a grid: resumable, shardable; error against cost, stability maps.
    Sweep(cli::sweep::SweepArgs),
    /// The main job: the paper's tables and Figure 4, c0 by every rule, the solver's verdicts, in out/report/index.html.
    Report(cli::report::ReportArgs),
    /// The law of the minimal c0: the empirical c0_min over N x Re x alpha per kernel, fitted, against the paper's scaling and (2N - 1) U / N^2.
    Law(cli::law::LawArgs),
    /// Time the solver per kernel and particle count, on one core and all: throughput, ns per pair, memory, GFLOP/s against peak.
    Bench(cli::bench::BenchArgs),
    /// Does the sheared lattice keep its order? Growth rates of small perturbations by the solver's own step, per Bloch sector and c0.
    Stability(cli::stability::StabilityArgs),
}

fn main() -> ExitCode {
    // A closed pipe on stdout (`shearsph c0 | head`) ends the process
    // quietly, as for any Unix filter, instead of a panic in println!.
    // Files are written atomically, so none is left half-written.
    #[cfg(unix)]
    // SAFETY: restoring the default disposition of one signal, before any
    // thread is started.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
    // Before any work: a signal during parsing or checking ends the
    // command with the one status every command gives (130).
    if let Err(e) = cli::interrupt::install() {
        return cli::report(Err(e));
    }
    // Bad flags are bad input like any other: exit 1 (clap's own is 2);
    // --help and --version print and exit 0.
    let command = match Cli::try_parse() {
        Ok(c) => c.command,
        Err(e) => {
            let _ = e.print();
            return if e.use_stderr() {
                ExitCode::FAILURE
            } else {
                ExitCode::SUCCESS
            };
        }
    };
    let result = match command {
        Command::Kernels(args) => cli::kernels::main(args),
        Command::Run(args) => cli::run::main(args),
        Command::C0(args) => cli::c0::main(args),
        Command::Sweep(args) => cli::sweep::main(args),
        Command::Report(args) => cli::report::main(args),
        Command::Bench(args) => cli::bench::main(args),
        Command::Law(args) => cli::law::main(args),
        Command::Stability(args) => cli::stability::main(args),
    };
    cli::report(result)
}
