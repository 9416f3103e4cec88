//! shearsph on the scenes matched to the peers' stock Poiseuille cases
//! (bench/peers/): PySPH's `pysph.examples.poiseuille` and SPHinXsys's
//! `test_2d_poiseuille_flow`, one JSON line per run.

use anyhow::{bail, Result};
use serde::Serialize;

use super::measure;
use crate::config::{Initial, Scene, ViscousNormalisation, WallVelocity};
use crate::problem::{cost, Problem};

/// shearsph on the scene matched to PySPH's stock example
/// `pysph.examples.poiseuille` (see bench/peers/): one run of fixed steps.
#[derive(Debug, Clone, Serialize)]
pub struct PeerRun {
    pub code: String,
    /// The walls' velocity in the viscous term (`zero`: the paper's walls).
    pub wall_velocity: WallVelocity,
    /// The viscous term's scale (`lattice`: divided by what it gives on the
    /// perfect lattice for a quadratic velocity).
    pub viscous_normalisation: ViscousNormalisation,
    /// Layers in the half-width (PySPH: 30 is the matched resolution).
    pub layers: u32,
    /// The discretisation ("square, h = 1 d").
    pub discretisation: String,
    /// U B / nu and c0 / U of the scene.
    pub re: f64,
    pub c0_over_u: f64,
    pub particles: usize,
    /// Columns of the periodic strip.
    pub columns: u32,
    pub n_fluid: usize,
    pub n_wall: usize,
    pub steps: u64,
    /// The CFL factor of the run's time step, dt <= cfl h / (c0 + |v|max).
    pub cfl: f64,
    pub threads: usize,
    /// Wall-clock seconds of the steps alone.
    pub wall_s: f64,
    pub particle_steps_per_s: f64,
    pub t: f64,
    /// t in units of B^2 / nu (B the half-width): the physical time that
    /// both codes reach after the same number of steps.
    pub tau: f64,
    /// max over layers of |mean u - start-up series| / U at t.
    pub linf_rel_err: f64,
    /// Neighbour-list rebuilds during the timed steps, and the seconds
    /// they took.
    pub neighbour_rebuilds: u64,
    pub rebuild_s: f64,
    /// Seconds of the timed steps in each pass: the kernel pass, the
    /// density sums, the force pass (the rest of the wall time is the
    /// rebuilds, the kick-drift, the rebuild rule's check and the time
    /// step).
    pub kernel_s: f64,
    pub sums_s: f64,
    pub forces_s: f64,
}

/// PySPH's example, in shearsph's terms: the quintic spline (shearsph's
/// `morris`, R = 3 h), h / B = 1/30 (dx = h = 1/60 across Ly = 1 = 2 B, the
/// example's square lattice with hdx = 1), Re = Vmax Ly / nu = 0.0125, i.e.
/// U B / nu = 0.00625, c0 = 10 U, no artificial viscosity (TVF has none),
/// from rest. The time step is then bound by the viscous limit
/// 0.125 h^2 / nu in both codes (shearsph's factor set to PySPH's, below
/// the default 0.85 F* = 0.221 of this kernel and lattice), so equal steps
/// reach equal t nu / B^2.
/// N = 30 layers in the half-width on the square lattice, h = d, and a strip
/// 26 columns wide (the rule below): 1690 particles with the walls, against
/// PySPH's 1680 (24 x 60 fluid, 2 x 5 x 24 wall).
///
/// `layers` other than [`PYSPH_MATCH_LAYERS`] gives the same flow at another
/// resolution (h = d, so h / B = 1 / N). The strip follows one rule at every
/// resolution, the matched one included: the fewest columns (and no fewer
/// than the kernel needs) with at least as many particles as PySPH's channel
/// at the same h / B ([`pysph_particles`]); `columns` sets it instead.
pub fn pysph_match_problem(
    wall_velocity: WallVelocity,
    layers: u32,
    columns: Option<u32>,
) -> Result<Problem> {
    let n_layers = layers;
    let scene = Scene {
        kernel: "morris".into(),
        n_layers,
        lattice: crate::kernel::Lattice::Square,
        h_over_d: 1.0,
        re: Some(0.00625),
        p: None,
        c0: "rule10".parse().expect("a valid c0 rule"),
        alpha: 0.0,
        initial: Initial::Rest,
        wall_velocity,
        t_end: Some(1e-6),
        viscous_dt: Some(0.125),
        cfl: Some(PEER_MATCH_CFL),
        ..Scene::builtin()
    };
    let mut problem = Problem::resolve(&scene, scene.kernel_info()?)
        .map_err(|e| e.with_flag("n_layers", "layers"))?;
    let lat = &problem.lattice;
    let narrowest = lat.columns;
    let per_column = lat.n_particles() / lat.columns as usize;
    let c = match columns {
        Some(c) if c < narrowest => bail!(
            "--columns {c} is narrower than kernel morris needs at h = d (at least {narrowest} columns)"
        ),
        Some(c) => c,
        None => {
            let want = pysph_particles(2 * layers);
            (want.div_ceil(per_column) as u32).max(narrowest)
        }
    };
    check_columns(&problem, c)?;
    let lat = &mut problem.lattice;
    // The flow does not depend on x: a wider strip only holds more particles.
    lat.columns = c;
    lat.width = f64::from(c) * lat.d;
    Ok(problem)
}

/// `--columns` within the memory a run may take ([`cost::MAX_RUN_BYTES`],
/// [`cost::MAX_PARTICLES`]), checked before the strip is widened.
fn check_columns(problem: &Problem, columns: u32) -> Result<()> {
    let lat = &problem.lattice;
    let per_column = lat.n_particles() as f64 / f64::from(lat.columns);
    let particles = per_column * f64::from(columns);
    let neighbours =
        cost::listed_neighbours(lat.kind, lat.d, lat.h, problem.kernel.support, problem.skin);
    let bytes = cost::memory_bytes(particles, neighbours, 0.0, 0.0);
    if !(particles <= cost::MAX_PARTICLES && bytes <= cost::MAX_RUN_BYTES) {
        bail!(
            "--columns {columns}: the strip would hold {} particles, about {} of memory, over the \
             bound of {} particles and {}; give fewer columns",
            crate::format::fmt_value(particles),
            cost::human_bytes(bytes),
            crate::format::fmt_value(cost::MAX_PARTICLES),
            cost::human_bytes(cost::MAX_RUN_BYTES)
        );
    }
    Ok(())
}

/// `steps` steps of `problem` within the bench's time bound
/// ([`super::MAX_BENCH_S`], by the scene's own estimate), or an error
/// naming `what` set them (`--steps 2000`, `--tau 1`).
fn check_steps(problem: &Problem, steps: f64, what: &str) -> Result<()> {
    let channel = problem.channel();
    let est = cost::Estimate::new(&channel, problem.c0, problem.t_end);
    let s = steps
        * channel.lattice.n_particles() as f64
        * est.neighbours(&channel, problem.kernel.support, problem.skin)
        * 2.0
        * cost::EST_S_PER_PAIR_PASS;
    if s.is_nan() || s > super::MAX_BENCH_S {
        bail!(
            "{what}: the run would take about {} on one core ({} steps of {} particles), over the \
             bound of {}; give less",
            cost::human_seconds(s),
            crate::format::fmt_value(steps),
            channel.lattice.n_particles(),
            cost::human_seconds(super::MAX_BENCH_S)
        );
    }
    Ok(())
}

/// Particles of PySPH's example at `rows` rows across the channel
/// (bench/peers/pysph_poiseuille.py): rows x C fluid and 2 x 5 x C wall
/// (ghost layers 5 dx deep), the channel 0.4 Ly long in C = round(0.4 rows)
/// whole columns (Python's round, half to even), at least 1. 1680 at the
/// example's 60 rows.
pub fn pysph_particles(rows: u32) -> usize {
    let c = (0.4 * f64::from(rows)).round_ties_even().max(1.0) as usize;
    (rows as usize + 10) * c
}

/// Layers in the half-width of the scene matched to PySPH's resolution.
pub const PYSPH_MATCH_LAYERS: u32 = 30;

/// `steps` steps of the matched scene, or with `layers` other than 30 the
/// steps that reach the same t nu / B^2 (the viscous limit binds: steps
/// scale as layers^2). Layers other than 30 keep h = d.
pub fn pysph_match(
    steps: u64,
    threads: usize,
    wall_velocity: WallVelocity,
    layers: u32,
    columns: Option<u32>,
) -> Result<PeerRun> {
    let problem = pysph_match_problem(wall_velocity, layers, columns)?;
    let scale = (f64::from(layers) / f64::from(PYSPH_MATCH_LAYERS)).powi(2);
    let scaled = (steps as f64 * scale).round().max(1.0);
    check_steps(&problem, scaled, &format!("--steps {steps}"))?;
    let steps = scaled as u64;
    run_matched(
        "shearsph (morris = quintic spline)",
        &problem,
        layers,
        steps,
        threads,
    )
}

/// SPHinXsys's stock `test_2d_poiseuille_flow` in shearsph's terms (see
/// bench/peers/sphinxsys_poiseuille.sh, whose header fixes it): Wendland C2
/// (`wendland_c2`), the square lattice with h = 13/10 d, B = N d,
/// U B / nu = 7.5, c0 = 10 U, no artificial viscosity (SPHinXsys's Riemann
/// solvers have none), no-slip walls (`mirrored`), from rest, to
/// t nu / B^2 = `tau`, on a strip of `columns` columns (default: the
/// narrowest the kernel allows), with the viscous term scaled by `viscous`
/// (`lattice`: shearsph's correction of the lattice's viscous deficit, as
/// SPHinXsys corrects its kernel gradients), at the CFL factor `cfl`
/// ([`PEER_MATCH_CFL`] for the figures measured so; `None`: the kernel's
/// own default, as a run takes it).
pub fn sphinxsys_match_problem(
    layers: u32,
    tau: f64,
    columns: Option<u32>,
    viscous: ViscousNormalisation,
    cfl: Option<f64>,
) -> Result<Problem> {
    if !(tau > 0.0 && tau.is_finite()) {
        bail!(
            "--tau {} must be a positive number (t nu / B^2)",
            crate::format::fmt_value(tau)
        );
    }
    let scene = Scene {
        kernel: "wendland_c2".into(),
        n_layers: layers,
        lattice: crate::kernel::Lattice::Square,
        h_over_d: 1.3,
        re: Some(SPHINXSYS_MATCH_RE),
        p: None,
        c0: "rule10".parse().expect("a valid c0 rule"),
        alpha: 0.0,
        initial: Initial::Rest,
        wall_velocity: WallVelocity::Mirrored,
        viscous_normalisation: viscous,
        t_end: Some(1.0),
        viscous_dt: Some(SPHINXSYS_MATCH_VISCOUS_DT),
        cfl,
        ..Scene::builtin()
    };
    let info = scene.kernel_info()?;
    // The flow's scales first, at the pinned factor (they do not depend on
    // it; the user's factor is checked with the end time below).
    let flow = Problem::resolve(
        &Scene {
            cfl: Some(PEER_MATCH_CFL),
            ..scene.clone()
        },
        info,
    )?
    .flow;
    let t_end = tau * flow.b * flow.b / flow.nu;
    let scene = Scene {
        t_end: Some(t_end),
        ..scene
    };
    // The end time is --tau's and the step --cfl's: a run too long for the
    // scene's bound is refused naming them (the scene's own fields are not
    // the user's here).
    let mut probe = Problem::resolve(&scene, info).map_err(|e| match e.field() {
        Some("t_end" | "max_run_s" | "output_interval") => {
            let factor = match cfl {
                Some(f) => crate::format::fmt_value(f),
                None => "default".into(),
            };
            anyhow::anyhow!(
                "--tau {} at --cfl {factor} (t_end = tau B^2 / nu = {} here): {e}",
                crate::format::fmt_value(tau),
                crate::format::fmt_value(t_end)
            )
        }
        _ => e.into(),
    })?;
    if let Some(c) = columns {
        if c < probe.lattice.columns {
            bail!(
                "--columns {c} is narrower than kernel {} needs at h = {} d (at least {} columns)",
                info.name,
                scene.h_over_d,
                probe.lattice.columns
            );
        }
        check_columns(&probe, c)?;
        let lat = &mut probe.lattice;
        // A wider strip than the kernel needs: the flow does not depend on x.
        lat.columns = c;
        lat.width = f64::from(c) * lat.d;
    }
    Ok(probe)
}

/// U B / nu of the SPHinXsys-matched scene: the stock case's Re = 10 on the
/// mean speed and the full width.
pub const SPHINXSYS_MATCH_RE: f64 = 7.5;

/// The viscous factor of the SPHinXsys-matched scene: 0.125, the factor its
/// ladders were measured at (the viscous limit binds from N = 27 layers,
/// the finest rung), below the default 0.85 F* = 0.138 of Wendland C2 on
/// the square lattice at 13/10.
pub const SPHINXSYS_MATCH_VISCOUS_DT: f64 = 0.125;

/// The CFL factor of both peer-matched scenes: 0.5, the factor their
/// ladders and the peer figures in docs/performance.md were measured at,
/// below the default half of each kernel's stable factor (0.898 for
/// Wendland C2 on the square lattice at 13/10, 1 for Morris's kernel; a
/// larger factor takes fewer steps per unit of physical time).
/// `bench --sphinxsys-match --cfl` sets another, or the kernel's own.
pub const PEER_MATCH_CFL: f64 = 0.5;

/// One run of the SPHinXsys-matched scene to t nu / B^2 = `tau`. The solver
/// runs whole steps whose dt follows the flow (c0 = 10 U: the CFL limit
/// cfl h / (c0 + |v|max) binds, up to 10 % longer than at |v| = U), so a
/// first run at the starting estimate's step count measures the mean dt
/// and the timed run takes the steps that reach t_end at it.
pub fn sphinxsys_match(
    layers: u32,
    tau: f64,
    threads: usize,
    columns: Option<u32>,
    viscous: ViscousNormalisation,
    cfl: Option<f64>,
) -> Result<PeerRun> {
    let problem = sphinxsys_match_problem(layers, tau, columns, viscous, cfl)?;
    let est = crate::problem::cost::Estimate::new(&problem.channel(), problem.c0, problem.t_end);
    let first = (est.steps as u64).max(1);
    let (probe, _) = measure(&problem, None, first, threads)?;
    let steps = ((first as f64 * problem.t_end / probe.last.t).round() as u64).max(1);
    run_matched(
        "shearsph (wendland_c2 = Wendland C2)",
        &problem,
        layers,
        steps,
        threads,
    )
}

/// Run a matched scene `steps` steps on `threads` threads and report it.
fn run_matched(
    code: &str,
    problem: &Problem,
    layers: u32,
    steps: u64,
    threads: usize,
) -> Result<PeerRun> {
    let (r, _) = measure(problem, None, steps, threads)?;
    let particles = r.n_fluid + r.n_wall;
    let flow = &problem.flow;
    Ok(PeerRun {
        code: code.into(),
        wall_velocity: problem.wall_velocity,
        viscous_normalisation: problem.scene.viscous_normalisation,
        layers,
        discretisation: problem.discretisation.label(),
        re: problem.re,
        c0_over_u: problem.c0 / flow.u,
        particles,
        columns: problem.lattice.columns,
        n_fluid: r.n_fluid,
        n_wall: r.n_wall,
        steps: r.steps,
        cfl: problem.dt_factors.cfl,
        threads,
        wall_s: r.wall_s,
        particle_steps_per_s: particles as f64 * r.steps as f64 / r.wall_s,
        t: r.last.t,
        tau: r.last.t * flow.nu / (flow.b * flow.b),
        linf_rel_err: r.last.linf_rel_err,
        neighbour_rebuilds: r.neighbour_rebuilds,
        rebuild_s: r.rebuild_s,
        kernel_s: r.pass_s[0],
        sums_s: r.pass_s[1],
        forces_s: r.pass_s[2],
    })
}
