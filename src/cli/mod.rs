//! The `shearsph` commands. `src/main.rs` parses the command line and calls
//! one `cli::<command>::main`; each command lives in its own file here, and
//! the ones that take a scene share [`SceneArgs`].

pub mod bench;
pub mod c0;
pub mod interrupt;
pub mod kernels;
pub mod law;
pub mod report;
pub mod run;
pub mod stability;
pub mod sweep;

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Result;
use clap::Args;

use crate::config::Scene;

/// The scene: the built-in one, overridden by `--scene FILE`, then by these
/// flags.
/// Every field but `scene` is a scene field of the same name (`n` is
/// `n_layers`): [`SceneArgs::overrides`] serialises them, a flag not given
/// (None) left out.
#[derive(Debug, Clone, Default, Args, serde::Serialize)]
pub struct SceneArgs {
    /// Scene file (TOML); its fields override the built-in scene's.
    #[arg(long, value_name = "FILE")]
    #[serde(skip)]
    pub scene: Option<PathBuf>,
    /// Kernel name (see `shearsph kernels`).
    #[arg(long)]
    pub kernel: Option<String>,
    /// N: fluid layers in the half-width (B = N dy).
    #[arg(long, value_name = "N")]
    #[serde(rename = "n_layers")]
    pub n: Option<u32>,
    /// Reynolds number U B / nu (replaces --p).
    #[arg(long, conflicts_with = "p")]
    pub re: Option<f64>,
    /// Body force per unit mass (replaces --re).
    #[arg(long)]
    pub p: Option<f64>,
    /// Centre-line speed U.
    #[arg(long)]
    pub u: Option<f64>,
    /// Columns of the periodic strip (default: the fewest wider than the
    /// support's diameter).
    #[arg(long)]
    pub columns: Option<u32>,
    /// Particle spacing d.
    #[arg(long)]
    pub d: Option<f64>,
    /// Starting lattice, by name: the help lists the kinds (`Lattice::ALL`).
    #[arg(long, help = format!("Starting lattice: {}", crate::kernel::Lattice::choices("`")))]
    pub lattice: Option<String>,
    /// Smoothing length in units of d: a number (1.3) or an exact rational
    /// (13/10); with --lattice it selects a generated discretisation
    /// (kernels/discretisations.toml).
    #[arg(long)]
    pub h_over_d: Option<crate::config::HOverD>,
    /// Rest density.
    #[arg(long)]
    pub rho0: Option<f64>,
    /// Artificial viscosity coefficient, in [0, 1].
    #[arg(long)]
    pub alpha: Option<f64>,
    /// Sound speed: a number, or [F*]RULE (`shearsph c0` lists every rule's
    /// c0; --help says each).
    #[arg(long, allow_hyphen_values = true, long_help = crate::config::c0_help())]
    pub c0: Option<String>,
    /// Start from `rest` or from the `steady` profile.
    #[arg(long)]
    pub initial: Option<String>,
    /// End time (default: until the start-up's slowest mode is below
    /// decay_tol U).
    #[arg(long, allow_hyphen_values = true)]
    pub t_end: Option<f64>,
    /// Tolerance for the default end time.
    #[arg(long)]
    pub decay_tol: Option<f64>,
    /// `fixed` (run to t_end) or `stationary` (run past the start-up until
    /// the statistics are stationary: docs/stationary.md; no t_end then).
    #[arg(long)]
    pub horizon: Option<String>,
    /// With `--horizon stationary`: the first checkpoint's span after the
    /// start-up, in shear times B / U (default 64).
    #[arg(long)]
    pub horizon_span: Option<f64>,
    /// Time between diagnostics (default t_end / 20).
    #[arg(long)]
    pub output_interval: Option<f64>,
    /// EOS exponent (1: the paper's (13); above 1: Tait).
    #[arg(long)]
    pub gamma: Option<f64>,
    /// Keep negative pressures instead of clipping them to zero.
    #[arg(long)]
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub allow_negative_pressure: bool,
    /// Pressure acceleration: `paper` (12) or `symmetric`.
    #[arg(long)]
    pub pressure_form: Option<String>,
    /// Wall particles' velocity in the viscous term: `zero` (the paper) or
    /// `mirrored` (Morris, Fox and Zhu 1997 no-slip).
    #[arg(long)]
    pub wall_velocity: Option<String>,
    /// Viscous term: `none` (the Laplacian (14)) or `lattice` (divided by
    /// its sum on the perfect lattice, exact for a quadratic velocity there).
    #[arg(long)]
    pub viscous_normalisation: Option<String>,
    /// Fail the run when the compaction exceeds this.
    #[arg(long)]
    pub eps_limit: Option<f64>,
    /// Random initial displacement of the fluid, in units of d.
    #[arg(long)]
    pub jitter: Option<f64>,
    /// Seed of the jitter: each seed is another perturbed lattice.
    #[arg(long)]
    pub jitter_seed: Option<u32>,
    /// A run is `inaccurate` above this L_inf error of the velocity,
    /// relative to U (default 0.05).
    #[arg(long)]
    pub linf_bound: Option<f64>,
    /// A run is `over-compressed` when its compaction exceeds the kernel's
    /// lattice pulsation eps0 by more than this (default 0.01).
    #[arg(long)]
    pub eps_margin: Option<f64>,
    /// Time-step factor of the CFL limit, dt <= CFL h / (c0 + |v|max)
    /// (default half the largest factor the kernel's pressure term is
    /// stable at on its lattice, at most 1: 0.93 for Monaghan's kernel at
    /// h = d; `c0` prints both, docs/timestep.md).
    #[arg(long)]
    pub cfl: Option<f64>,
    /// Time-step factor of the viscous limit, dt <= F h^2 / nu (default
    /// 0.85 of the largest factor the kernel's viscous term is stable at on
    /// its lattice, which `c0` prints: docs/timestep.md).
    #[arg(long)]
    pub viscous_dt: Option<f64>,
    /// Neighbour-list skin in units of h.
    #[arg(long)]
    pub skin: Option<f64>,
    /// Refuse runs estimated to take longer than this many seconds on one core.
    #[arg(long)]
    pub max_run_s: Option<f64>,
}

impl SceneArgs {
    /// The flags as scene fields, to lay over the scene file: every flag
    /// given, by its scene field's name.
    pub fn overrides(&self) -> toml::Table {
        toml::Table::try_from(self).expect("scene flags are numbers, strings and booleans")
    }

    pub fn load(&self) -> Result<Scene> {
        Ok(Scene::load(self.scene.as_deref(), self.overrides())?)
    }

    /// `e` naming where its field's value came from: the flag when one set
    /// it; the scene file (`--scene FILE`) when that did; else the flag that
    /// would set it (the built-in default's field).
    pub fn label(&self, e: crate::config::SceneError) -> crate::config::SceneError {
        let Some(field) = e.field() else {
            return e;
        };
        if self.overrides().contains_key(field) {
            return e;
        }
        let in_file = self.scene.as_deref().and_then(|path| {
            let table: toml::Table = std::fs::read_to_string(path).ok()?.parse().ok()?;
            table.contains_key(field).then_some(path)
        });
        match in_file {
            Some(path) => e.from_origin(format!("scene file {}", path.display())),
            None => e,
        }
    }
}

/// Print an error with its causes and give the exit code for it.
/// The config of a command that embeds two (`report`, `law`): the file
/// `--config` names, else the quick one with `--quick`, else the full one.
pub(crate) fn load_config<C>(
    path: Option<&std::path::Path>,
    quick: bool,
    parse: fn(&str, &str) -> Result<C>,
    quick_config: fn() -> C,
    full_config: fn() -> C,
) -> Result<C> {
    use anyhow::Context;
    match (path, quick) {
        (Some(path), _) => {
            let text = std::fs::read_to_string(path)
                .with_context(|| format!("reading {}", path.display()))?;
            parse(&text, &path.display().to_string())
        }
        (None, true) => Ok(quick_config()),
        (None, false) => Ok(full_config()),
    }
}

pub fn report(result: Result<ExitCode>) -> ExitCode {
    match result {
        Ok(code) => code,
        Err(e) => {
            eprintln!("error: {e}");
            for cause in e.chain().skip(1) {
                eprintln!("  caused by: {cause}");
            }
            ExitCode::FAILURE
        }
    }
}

#[cfg(test)]
mod tests {
    use clap::Parser;

    use super::SceneArgs;

    #[derive(Parser)]
    struct Cli {
        #[command(flatten)]
        scene: SceneArgs,
    }

    /// Every scene flag given lands in the scene field of its name (the
    /// scene refuses unknown fields), and a flag not given is left out, so a
    /// scene file's value stands (`allow_negative_pressure` false included).
    #[test]
    fn every_scene_flag_is_the_scene_field_of_its_name() {
        let all = Cli::parse_from([
            "x",
            "--kernel",
            "wendland_c2",
            "--n",
            "8",
            "--re",
            "3",
            "--u",
            "2",
            "--columns",
            "9",
            "--d",
            "0.5",
            "--lattice",
            "square",
            "--h-over-d",
            "13/10",
            "--rho0",
            "2",
            "--alpha",
            "0.05",
            "--c0",
            "2*rule10",
            "--initial",
            "steady",
            "--t-end",
            "3",
            "--decay-tol",
            "0.02",
            "--horizon",
            "fixed",
            "--horizon-span",
            "16",
            "--output-interval",
            "0.5",
            "--gamma",
            "7",
            "--allow-negative-pressure",
            "--pressure-form",
            "symmetric",
            "--wall-velocity",
            "mirrored",
            "--viscous-normalisation",
            "lattice",
            "--eps-limit",
            "0.3",
            "--jitter",
            "0.01",
            "--jitter-seed",
            "4",
            "--linf-bound",
            "0.1",
            "--eps-margin",
            "0.02",
            "--skin",
            "0.4",
            "--cfl",
            "0.4",
            "--viscous-dt",
            "0.1",
            "--max-run-s",
            "60",
        ])
        .scene;
        let t = all.overrides();
        // Every flag but `--p`, which `--re` replaces.
        assert_eq!(t.len(), 31, "{t:?}");
        assert_eq!(t["n_layers"].as_integer(), Some(8));
        assert_eq!(t["allow_negative_pressure"].as_bool(), Some(true));
        let s = all.load().expect("every flag a known scene field");
        assert_eq!((s.n_layers, s.re, s.jitter_seed), (8, Some(3.0), 4));
        assert!(s.allow_negative_pressure);
        let none = Cli::parse_from(["x"]).scene.overrides();
        assert!(none.is_empty(), "{none:?}");
    }
}
