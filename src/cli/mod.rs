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
#[derive(Debug, Clone, Default, Args)]
pub struct SceneArgs {
    /// Scene file (TOML); its fields override the built-in scene's.
    #[arg(long, value_name = "FILE")]
    pub scene: Option<PathBuf>,
    /// Kernel name (see `shearsph kernels`).
    #[arg(long)]
    pub kernel: Option<String>,
    /// N: fluid layers in the half-width (B = N dy).
    #[arg(long, value_name = "N")]
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
    /// Starting lattice: `triangular` (the paper's) or `square`.
    #[arg(long)]
    pub lattice: Option<String>,
    /// Smoothing length in units of d: a number (1.3) or an exact rational
    /// (13/10); with --lattice it selects a generated discretisation
    /// (kernels/discretisations.toml).
    #[arg(long, value_parser = crate::config::parse_h_over_d)]
    pub h_over_d: Option<f64>,
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
    /// Time-step factor of the CFL limit, dt <= CFL h / (c0 + |v|max) (0.5).
    #[arg(long)]
    pub cfl: Option<f64>,
    /// Time-step factor of the viscous limit, dt <= F h^2 / nu (0.125).
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
    /// The flags as scene fields, to lay over the scene file.
    pub fn overrides(&self) -> toml::Table {
        use toml::Value;
        let mut t = toml::Table::new();
        let mut put = |key: &str, v: Option<Value>| {
            if let Some(v) = v {
                t.insert(key.to_string(), v);
            }
        };
        put("kernel", self.kernel.clone().map(Value::String));
        put("n_layers", self.n.map(|n| Value::Integer(n.into())));
        put("re", self.re.map(Value::Float));
        put("p", self.p.map(Value::Float));
        put("u", self.u.map(Value::Float));
        put("d", self.d.map(Value::Float));
        put("columns", self.columns.map(|c| Value::Integer(c.into())));
        put("lattice", self.lattice.clone().map(Value::String));
        put("h_over_d", self.h_over_d.map(Value::Float));
        put("rho0", self.rho0.map(Value::Float));
        put("alpha", self.alpha.map(Value::Float));
        put("c0", self.c0.clone().map(Value::String));
        put("initial", self.initial.clone().map(Value::String));
        put("t_end", self.t_end.map(Value::Float));
        put("decay_tol", self.decay_tol.map(Value::Float));
        put("horizon", self.horizon.clone().map(Value::String));
        put("horizon_span", self.horizon_span.map(Value::Float));
        put("output_interval", self.output_interval.map(Value::Float));
        put("gamma", self.gamma.map(Value::Float));
        put(
            "allow_negative_pressure",
            self.allow_negative_pressure.then_some(Value::Boolean(true)),
        );
        put(
            "pressure_form",
            self.pressure_form.clone().map(Value::String),
        );
        put(
            "wall_velocity",
            self.wall_velocity.clone().map(Value::String),
        );
        put(
            "viscous_normalisation",
            self.viscous_normalisation.clone().map(Value::String),
        );
        put("eps_limit", self.eps_limit.map(Value::Float));
        put("jitter", self.jitter.map(Value::Float));
        put(
            "jitter_seed",
            self.jitter_seed.map(|s| Value::Integer(s.into())),
        );
        put("linf_bound", self.linf_bound.map(Value::Float));
        put("eps_margin", self.eps_margin.map(Value::Float));
        put("skin", self.skin.map(Value::Float));
        put("cfl", self.cfl.map(Value::Float));
        put("viscous_dt", self.viscous_dt.map(Value::Float));
        put("max_run_s", self.max_run_s.map(Value::Float));
        t
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
