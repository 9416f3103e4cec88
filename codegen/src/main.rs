use anyhow::{bail, Context, Result};
use clap::{Parser, Subcommand};
use shearsph_codegen::{analysis, claims, discretisation, emit, kernel, show};
use std::path::PathBuf;
use std::time::Instant;

/// Exact derivation of SPH shear compaction and model sound speed; emits generated/.
#[derive(Parser)]
#[command(name = "shearsph-codegen", version)]
struct Cli {
    /// Folder of kernel definitions.
    #[arg(long, global = true, default_value = "kernels")]
    kernels: PathBuf,
    #[command(subcommand)]
    cmd: Cmd,
}

#[derive(Subcommand)]
enum Cmd {
    /// Write generated/ from kernels/*.toml (all or nothing: one bad kernel changes nothing).
    Generate {
        /// Output folder.
        #[arg(long, default_value = "generated")]
        out: PathBuf,
    },
    /// Exit non-zero, naming the stale files, when generated/ differs from what generate would write.
    Check {
        /// Folder to check.
        #[arg(long, default_value = "generated")]
        out: PathBuf,
    },
    /// Print the derivation for one kernel.
    Show {
        /// Kernel name (a file kernels/NAME.toml).
        kernel: String,
        /// Machine-readable output.
        #[arg(long)]
        json: bool,
        /// Significant digits of the decimals.
        #[arg(long, default_value_t = 30)]
        digits: usize,
        /// N used for the checks of the paper's claims about layers n and the
        /// wall: from ceil(R h/d) + 1 (on the widest discretisation) to 100
        /// (the checks' time grows as N^2).
        #[arg(long = "n-layers", default_value_t = 10, allow_negative_numbers = true)]
        n_layers: i64,
    },
}

fn main() -> std::process::ExitCode {
    match run(Cli::parse()) {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            std::process::ExitCode::FAILURE
        }
    }
}

fn run(cli: Cli) -> Result<()> {
    match cli.cmd {
        Cmd::Generate { out } => {
            let start = Instant::now();
            let files = render_all(&cli.kernels)?;
            let changes = emit::ensure(&out, &files, false)
                .with_context(|| format!("writing {}", out.display()))?;
            for p in &changes.written {
                eprintln!("wrote {}", p.display());
            }
            for p in &changes.removed {
                eprintln!(
                    "removed {} (generated earlier, its kernel is gone)",
                    p.display()
                );
            }
            for p in &changes.foreign {
                eprintln!("left {} alone (not written by the generator)", p.display());
            }
            eprintln!(
                "{} file(s) in {}, {} written, {} removed, in {:.2} s",
                files.len(),
                out.display(),
                changes.written.len(),
                changes.removed.len(),
                start.elapsed().as_secs_f64()
            );
        }
        Cmd::Check { out } => {
            let files = render_all(&cli.kernels)?;
            let changes = emit::ensure(&out, &files, true)?;
            if !changes.is_empty() {
                let list: Vec<String> = changes
                    .stale()
                    .iter()
                    .map(|p| format!("  {}", p.display()))
                    .collect();
                bail!(
                    "generated code is stale:\n{}\nrun `{}` and commit",
                    list.join("\n"),
                    emit::COMMAND
                );
            }
            eprintln!("{} is up to date ({} files)", out.display(), files.len());
        }
        Cmd::Show {
            kernel: name,
            json,
            digits,
            n_layers,
        } => {
            if !(1..=200).contains(&digits) {
                bail!("--digits {digits}: choose from 1 to 200");
            }
            if n_layers > claims::MAX_CHECK_LAYERS {
                bail!(
                    "--n-layers {n_layers}: at most {}. The claims search eps(t) at every layer \
                     n = 1 .. N - R, and layer n's curve has a top frequency of about 2 n R h/d, \
                     so the time grows as N^2 (N = 100: one to two minutes for a shipped kernel); choose N \
                     from ceil(R h/d) + 1 up to {}",
                    claims::MAX_CHECK_LAYERS,
                    claims::MAX_CHECK_LAYERS
                );
            }
            let defs = kernel::load_dir(&cli.kernels).map_err(|e| anyhow::anyhow!("{e}"))?;
            let def = defs.iter().find(|k| k.name == name).with_context(|| {
                format!(
                    "no kernel `{name}` in {}; known: {}",
                    cli.kernels.display(),
                    defs.iter()
                        .map(|k| k.name.as_str())
                        .collect::<Vec<_>>()
                        .join(", ")
                )
            })?;
            let discs = discretisation::load(&cli.kernels).map_err(|e| anyhow::anyhow!("{e}"))?;
            // the discretisation whose support reaches the most layers sets the least N
            let (need, widest) = discs
                .iter()
                .map(|d| (claims::min_check_layers(def, d), d))
                .max_by_key(|(n, _)| *n)
                .expect("the paper's discretisation is always there");
            if n_layers < need {
                bail!(
                    "--n-layers {n_layers}: needs at least {need} layers: on {} the support \
                     R h/d = {} reaches {} layers, and the claims compare layers 1 .. N - {}",
                    widest.label(),
                    widest.support_d(&def.support),
                    need - 1,
                    need - 1
                );
            }
            let start = Instant::now();
            let a = analysis::analyse(
                def,
                &discs,
                analysis::Options {
                    digits,
                    check_layers: n_layers,
                },
            );
            let took = start.elapsed();
            if json {
                println!("{}", serde_json::to_string_pretty(&show::json(&a))?);
            } else {
                print!("{}", show::text(&a));
                println!("\n(derived in {:.2} s)", took.as_secs_f64());
            }
        }
    }
    Ok(())
}

/// Loads, validates and analyses every kernel, then renders generated/. Any
/// error stops before anything is written.
fn render_all(dir: &std::path::Path) -> Result<Vec<(PathBuf, String)>> {
    let defs = kernel::load_dir(dir).map_err(|e| anyhow::anyhow!("{e}"))?;
    if defs.is_empty() {
        bail!("no kernel definitions (*.toml) in {}", dir.display());
    }
    let discs = discretisation::load(dir).map_err(|e| anyhow::anyhow!("{e}"))?;
    let analyses: Vec<analysis::Analysis> = defs
        .iter()
        .map(|d| analysis::analyse(d, &discs, analysis::Options::default()))
        .collect();
    let files = emit::render(&analyses);
    // the same tree with every kernel renamed to a neutral stand-in: whatever
    // it names is the generator's own, and no kernel may take it
    let neutral: Vec<analysis::Analysis> = analyses
        .iter()
        .enumerate()
        .map(|(i, a)| {
            let mut a = a.clone();
            a.def.name = kernel::neutral_name(i);
            a
        })
        .collect();
    kernel::check_emitted_names(&defs, &files, &emit::render(&neutral))
        .map_err(|e| anyhow::anyhow!("{e}"))?;
    Ok(files)
}
