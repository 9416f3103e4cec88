//! A run's outputs in one folder: `summary.json`, `profile.csv`,
//! `timeseries.csv`, `scene.toml` (the scene as run) and the charts
//! `profile.svg` and `timeseries.svg`. Every file is written to a temporary
//! file in the same folder and renamed into place, so a reader never sees
//! half a file; an existing non-empty folder is not touched without `force`.

use std::fmt::Write as _;
use std::io::Write as _;
use std::path::Path;
use std::sync::atomic::{AtomicU64, Ordering};

use anyhow::{bail, Context, Result};
use serde::Serialize;

use crate::charts::run::{profile_svg, timeseries_svg};
use crate::solver::{Class, DtLimitSteps, Outcome, Particle, RunResult, Sample};

/// The figures of one run, as `summary.json` and `shearsph run --json`.
#[derive(Debug, Clone, Serialize)]
pub struct Summary {
    pub kernel: String,
    pub n_layers: u32,
    /// All particles, fluid and wall.
    pub particles: usize,
    pub fluid_particles: usize,
    pub wall_particles: usize,
    pub d: f64,
    pub h: f64,
    /// Half-width B = N dy.
    pub b: f64,
    pub u: f64,
    pub re: f64,
    pub nu: f64,
    pub p: f64,
    pub alpha: f64,
    pub initial: crate::config::Initial,
    pub t_end: f64,
    /// Time reached (below t_end when the run failed or was interrupted).
    pub t: f64,
    pub steps: u64,
    /// The last full step's dt and the limit that bound it (the limit that
    /// bound the most steps is results.csv's `dt_limit_dominant`).
    pub dt: f64,
    pub dt_limit: crate::problem::cost::DtLimit,
    pub dt_min: f64,
    pub dt_max: f64,
    /// Steps bound by each limit.
    pub dt_limit_steps: DtLimitSteps,
    pub c0: f64,
    pub c0_rule: String,
    pub wall_s: f64,
    /// Particles (fluid and wall) times steps per wall-clock second.
    pub particle_steps_per_s: f64,
    /// Errors of the layer-mean velocity relative to U at the end, against
    /// the start-up series (from rest) or (7) (from the steady profile).
    pub linf_rel_err: f64,
    pub l2_rel_err: f64,
    /// Largest L_inf error over the output times.
    pub linf_rel_err_max: f64,
    /// Largest fluid compaction over every step of the run.
    pub max_eps: f64,
    /// Mean fluid compaction at the end.
    pub mean_eps: f64,
    /// RMS transverse velocity of the fluid at the end.
    pub rms_v: f64,
    pub kinetic_energy: f64,
    pub neighbour_rebuilds: u64,
    /// Mean neighbour-list length (R h + skin) per particle, at the start.
    pub mean_neighbours: f64,
    /// `ok`, `failed` or `interrupted` (stopped early, e.g. by Ctrl-C; `t`
    /// and `steps` say where).
    pub outcome: &'static str,
    /// The class the sweep gives the same run: `ok`, `inaccurate`,
    /// `over-compressed` or `failed`, by the scene's bounds below.
    pub class: Class,
    /// Inaccurate above this L_inf error (relative to U) over the outputs.
    pub linf_bound: f64,
    /// Over-compressed above this compaction (the kernel's eps0 plus the
    /// scene's eps_margin).
    pub eps_bound: f64,
    pub failure_reason: Option<String>,
    pub failure_t: Option<f64>,
    pub failure_step: Option<u64>,
    /// The fluid particle that triggered the failure.
    pub failure_particle: Option<Particle>,
}

impl Summary {
    pub fn new(r: &RunResult) -> Summary {
        let pr = &r.problem;
        let last = r.last();
        let (failure_reason, failure_t, failure_step, failure_particle) = match &r.outcome {
            Outcome::Ok | Outcome::Interrupted { .. } => (None, None, None, None),
            Outcome::Failed {
                failure,
                t,
                step,
                particle,
            } => (
                Some(failure.to_string()),
                Some(*t),
                Some(*step),
                Some(*particle),
            ),
        };
        let particles = r.particles();
        let rules = pr.scene.classes();
        Summary {
            kernel: r.kernel.to_string(),
            n_layers: pr.lattice.n_layers,
            particles,
            fluid_particles: r.n_fluid,
            wall_particles: r.n_wall,
            d: pr.lattice.d,
            h: pr.lattice.h,
            b: pr.flow.b,
            u: pr.flow.u,
            re: pr.re,
            nu: pr.flow.nu,
            p: pr.flow.p,
            alpha: pr.alpha,
            initial: pr.initial,
            t_end: pr.t_end,
            t: r.t,
            steps: r.steps,
            dt: r.dt.last,
            dt_limit: r.dt.last_limit,
            dt_min: r.dt.min.min(r.dt.last),
            dt_max: r.dt.max.max(r.dt.last),
            dt_limit_steps: r.dt.steps,
            c0: pr.c0,
            c0_rule: pr.c0_rule.clone(),
            wall_s: r.wall_s,
            particle_steps_per_s: particles as f64 * r.steps as f64 / r.wall_s.max(1e-9),
            linf_rel_err: last.linf_rel_err,
            l2_rel_err: last.l2_rel_err,
            linf_rel_err_max: r.linf_rel_err_max(),
            max_eps: r.max_eps_run,
            mean_eps: last.mean_eps,
            rms_v: last.rms_v,
            kinetic_energy: last.kinetic_energy,
            neighbour_rebuilds: r.neighbour_rebuilds,
            mean_neighbours: r.mean_neighbours,
            outcome: r.outcome.status(),
            class: r.class(&rules),
            linf_bound: rules.linf_bound,
            eps_bound: r.eps_bound(&rules),
            failure_reason,
            failure_t,
            failure_step,
            failure_particle,
        }
    }

    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).expect("a summary serialises")
    }
}

/// Make sure `dir` can take a run's outputs: create it, or refuse when it
/// exists with files in it and `force` is not set. Call before running, so a
/// refused folder costs nothing.
pub fn prepare_dir(dir: &Path, force: bool) -> Result<()> {
    if dir.exists() {
        if !dir.is_dir() {
            bail!("output path {} exists and is not a folder", dir.display());
        }
        let non_empty = std::fs::read_dir(dir)
            .with_context(|| format!("reading output folder {}", dir.display()))?
            .next()
            .is_some();
        if non_empty && !force {
            bail!(
                "output folder {} already exists and is not empty; pass --force to overwrite its files, or choose \
                 another with --out",
                dir.display()
            );
        }
    }
    std::fs::create_dir_all(dir)
        .with_context(|| format!("creating output folder {}", dir.display()))?;
    // Writable? A probe file of our own, created and removed now, so a
    // read-only folder is found before the run, not after it.
    let probe = dir.join(format!(".shearsph-probe-{}", std::process::id()));
    std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&probe)
        .with_context(|| {
            format!(
                "output folder {} is not writable (a test file could not be created there); \
                 fix its permissions or choose another with --out",
                dir.display()
            )
        })?;
    std::fs::remove_file(&probe).with_context(|| format!("removing {}", probe.display()))
}

/// Write `bytes` to `path` atomically: a new file beside it (same folder,
/// so the rename cannot cross file systems), renamed over the target. The
/// file gets the usual permissions (the umask's), like any other.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    static SERIAL: AtomicU64 = AtomicU64::new(0);
    let dir = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("out");
    let tmp = dir.join(format!(
        ".{name}.tmp-{}-{}",
        std::process::id(),
        SERIAL.fetch_add(1, Ordering::Relaxed)
    ));
    let written = (|| -> std::io::Result<()> {
        let mut f = std::fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
        std::fs::rename(&tmp, path)
    })();
    if written.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    written.with_context(|| format!("writing {}", path.display()))
}

/// Write every output of `result` into `dir` (see [`prepare_dir`]).
pub fn write_outputs(dir: &Path, result: &RunResult, force: bool) -> Result<()> {
    prepare_dir(dir, force)?;
    write_atomic(
        &dir.join("summary.json"),
        Summary::new(result).to_json().as_bytes(),
    )?;
    write_atomic(
        &dir.join("scene.toml"),
        result.problem.scene.to_toml().as_bytes(),
    )?;
    write_atomic(
        &dir.join("profile.csv"),
        profile_csv(result.last()).as_bytes(),
    )?;
    write_atomic(
        &dir.join("timeseries.csv"),
        timeseries_csv(&result.samples).as_bytes(),
    )?;
    write_atomic(&dir.join("profile.svg"), profile_svg(result)?.as_bytes())?;
    write_atomic(
        &dir.join("timeseries.svg"),
        timeseries_svg(result)?.as_bytes(),
    )?;
    Ok(())
}

/// The layer profile of one sample.
pub fn profile_csv(s: &Sample) -> String {
    let mut out = String::from("layer,y,u,u_analytic,u_steady,v_rms\n");
    for l in &s.profile {
        let _ = writeln!(
            out,
            "{},{},{},{},{},{}",
            l.layer, l.y, l.u, l.u_analytic, l.u_steady, l.v_rms
        );
    }
    out
}

pub fn timeseries_csv(samples: &[Sample]) -> String {
    let mut out =
        String::from("t,step,dt,linf_rel_err,l2_rel_err,max_eps,mean_eps,rms_v,kinetic_energy\n");
    for s in samples {
        let _ = writeln!(
            out,
            "{},{},{},{},{},{},{},{},{}",
            s.t,
            s.step,
            s.dt,
            s.linf_rel_err,
            s.l2_rel_err,
            s.max_eps,
            s.mean_eps,
            s.rms_v,
            s.kinetic_energy
        );
    }
    out
}
