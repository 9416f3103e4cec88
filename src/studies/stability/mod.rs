//! Does the sheared lattice keep its order? The growth rate of small
//! perturbations of a scene's perfect lattice in steady Poiseuille flow,
//! by the solver's own step ([`crate::solver::tangent`]), per Bloch
//! wavenumber along x, and the time to disorder it predicts; beside it the
//! growth a nonlinear run of the same scene from a small jitter measures.
//!
//! The base state is the scene's perfect lattice with the steady profile
//! (7) (`initial = steady`: no start-up transient), on the scene's periodic
//! strip of `columns` columns between its walls. It is invariant under a
//! shift by one column, so a perturbation whose x dependence is
//! exp(i q x) with q = 2 pi j / W (W the strip's width, j = 0 ..= columns / 2)
//! stays in its sector under the linearised step: each sector is seeded
//! with a generic pattern of that q (cos and sin phases that vary from
//! layer to layer, in both displacement components) and followed on its
//! own. The rate is the leading Lyapunov exponent of the sector over the
//! horizon, in the scene's units (1/t, t in d/U for U = d = 1). The strip
//! is the one a jittered start of the scene runs on (2B wide) unless the
//! scene sets `columns`. Over the period T = d N^2 / U the base repeats:
//! [`multipliers`] gives the flow map's Floquet multipliers there.

use anyhow::{bail, Result};
use serde::Serialize;

use crate::config::{C0Spec, Initial, Scene, SceneError};
use crate::kernel::{Kernel, KernelVisitor};
use crate::kernels;
use crate::problem::Problem;
use crate::solver::tangent::{self, Options, Perturbation};

pub mod measure;

/// The rms transverse displacement from the lattice, in d, at which the
/// order counts as lost (`dy_rms >= 0.1 d`, docs/stationary.md).
pub const DISORDER_DY_RMS: f64 = 0.1;

/// One sector's growth.
#[derive(Debug, Clone, Serialize)]
pub struct Sector {
    /// The sector: q = 2 pi j / W.
    pub j: u32,
    /// q d.
    pub q_d: f64,
    pub growth_rate: f64,
    /// 1 / growth_rate, where positive.
    pub e_fold_time: Option<f64>,
    pub failed: bool,
}

/// The analysis of one c0.
#[derive(Debug, Clone, Serialize)]
pub struct AtC0 {
    pub c0_over_u: f64,
    pub sectors: Vec<Sector>,
    /// The largest rate and its sector.
    pub growth_rate: f64,
    pub most_unstable_j: u32,
    /// The steady profile's period T = d N^2 / U (SPEC (19): in T every
    /// layer moves a whole number of d, so the sheared lattice repeats).
    pub period: f64,
    /// growth_rate T: the e-folds per period.
    pub growth_rate_per_period: f64,
    /// ln(0.1 sqrt 3 / a) / growth_rate: when a jitter of amplitude a (d)
    /// reaches dy_rms = 0.1 d at the leading rate (a jitter of amplitude a
    /// starts at dy_rms = a / sqrt 3); none where the rate is not positive.
    pub t_disorder_predicted: Option<f64>,
    /// The most unstable mode at the end: per fluid particle x, y (d) and
    /// its displacement dx, dy (normalised).
    pub mode: Vec<[f64; 4]>,
}

impl AtC0 {
    /// The most unstable sector's q d.
    pub fn most_unstable_q_d(&self) -> Option<f64> {
        self.sectors
            .iter()
            .find(|s| s.j == self.most_unstable_j)
            .map(|s| s.q_d)
    }
}

/// What is analysed, beyond the scene. Its `Default` is `shearsph
/// stability`'s defaults (at c0 = 10 U), which the command's flags read.
#[derive(Debug, Clone)]
pub struct Request {
    pub c0_over_u: Vec<f64>,
    /// Sectors; empty: every j from 0 to columns / 2.
    pub sectors: Vec<u32>,
    pub options: Options,
    /// The jitter the predicted time to disorder is for, in d.
    pub amplitude: f64,
}

impl Default for Request {
    fn default() -> Self {
        Request {
            c0_over_u: vec![10.0],
            sectors: Vec::new(),
            options: Options {
                eps: 1e-7,
                block: 50,
                horizon: 300.0,
                warm: 20.0,
            },
            amplitude: 1e-4,
        }
    }
}

/// One rule's c0 and the ordered lattice's growth there.
#[derive(Debug, Clone, Serialize)]
pub struct OrderedAt {
    pub rule: String,
    pub c0_over_u: f64,
    pub growth_rate: f64,
    pub most_unstable_q_d: Option<f64>,
    pub t_disorder_from_1e_4: Option<f64>,
    /// Every sector's run failed: the perfect lattice itself does not last.
    pub failed: bool,
}

/// The stability of the ordered lattice at each of a c0 table's rules'
/// c0 (`shearsph c0 --stability`), with the analysis's defaults; each
/// distinct c0 analysed once.
pub fn ordered_at(scene: &Scene, t: &crate::problem::c0::C0Table) -> Result<Vec<OrderedAt>> {
    let defaults = Request::default();
    let mut seen: Vec<(u64, AtC0)> = Vec::new();
    let mut out = Vec::new();
    for r in t.rows.iter().filter(|r| r.cost.is_some()) {
        let c = r.c0_over_u;
        if !seen.iter().any(|(b, _)| *b == c.to_bits()) {
            let req = Request {
                c0_over_u: vec![c],
                ..defaults.clone()
            };
            let a = analyse(scene, &req)?.remove(0);
            seen.push((c.to_bits(), a));
        }
        let a = &seen
            .iter()
            .find(|(b, _)| *b == c.to_bits())
            .expect("analysed")
            .1;
        out.push(OrderedAt {
            rule: r.rule.to_string(),
            c0_over_u: c,
            growth_rate: a.growth_rate,
            most_unstable_q_d: a.most_unstable_q_d(),
            t_disorder_from_1e_4: a.t_disorder_predicted,
            failed: !a.growth_rate.is_finite(),
        });
    }
    Ok(out)
}

/// The scene the analysis linearises about: the perfect lattice in the
/// steady profile at `c0`, on the strip a jittered start of the scene runs
/// on (unless the scene sets `columns`): at least the channel's width 2B,
/// so that the sectors include the long waves a real run has. The fastest
/// growth is there: Wendland C2, square h = d, N = 10, Re = 1, 10 U, grows
/// at 3.0e-2 in the sector q d = 0.314 (wavelength 2B) of the 20-column
/// strip, the same to 5 digits on 40 columns, and every sector of the
/// 5-column strip, q d >= 1.26, decays.
pub fn base_scene(scene: &Scene, c0: f64) -> Result<Scene, SceneError> {
    let mut s = scene.clone();
    if s.columns.is_none() {
        let mut jittered = scene.clone();
        jittered.jitter = 1e-3;
        jittered.c0 = C0Spec::Value(c0);
        s.columns = Some(
            Problem::resolve(&jittered, scene.kernel_info()?)?
                .lattice
                .columns,
        );
    }
    s.c0 = C0Spec::Value(c0);
    s.initial = Initial::Steady;
    s.jitter = 0.0;
    Ok(s)
}

/// A generic perturbation of sector `j`: both components, cos and sin
/// phases varying from layer to layer by a fixed sequence (no randomness:
/// the result is the same every run).
fn seed(x: &[f64], y: &[f64], width: f64, d: f64, j: u32) -> Perturbation {
    let q = 2.0 * std::f64::consts::PI * f64::from(j) / width;
    let phase =
        |y: f64, k: f64| ((y / d).round() * 0.754_877_666 * k).fract() * std::f64::consts::TAU;
    let comp = |k: f64| -> Vec<f64> {
        x.iter()
            .zip(y)
            .map(|(&x, &y)| (q * x + phase(y, k)).cos())
            .collect()
    };
    let zeros = vec![0.0; x.len()];
    Perturbation {
        dx: comp(1.0),
        dy: comp(2.0),
        dvx: zeros.clone(),
        dvy: zeros,
    }
}

/// The growth rates of every requested c0 and sector.
pub fn analyse(scene: &Scene, req: &Request) -> Result<Vec<AtC0>> {
    if req.c0_over_u.is_empty() {
        bail!("no c0 to analyse: give --c0-over-u");
    }
    let info = scene.kernel_info()?;
    let mut out = Vec::new();
    for &c in &req.c0_over_u {
        let s = base_scene(scene, c * scene.u)?;
        let problem = Problem::resolve(&s, info)?;
        out.push(
            kernels::with_kernel(
                info.name,
                AtC0Visit {
                    problem: &problem,
                    req,
                    c,
                },
            )
            .expect("the registry has a solver for every kernel it lists"),
        );
    }
    Ok(out)
}

struct AtC0Visit<'a> {
    problem: &'a Problem,
    req: &'a Request,
    c: f64,
}

impl KernelVisitor for AtC0Visit<'_> {
    type Output = AtC0;
    fn visit<K: Kernel>(self) -> AtC0 {
        let p = self.problem;
        let lat = &p.lattice;
        let (x, y) = tangent::start_positions::<K>(p);
        let js: Vec<u32> = if self.req.sectors.is_empty() {
            (0..=lat.columns / 2).collect()
        } else {
            self.req.sectors.clone()
        };
        use rayon::prelude::*;
        let runs: Vec<(Sector, tangent::Growth)> = js
            .par_iter()
            .map(|&j| {
                let g =
                    tangent::growth::<K>(p, &seed(&x, &y, lat.width, lat.d, j), self.req.options);
                let rate = g.rate;
                let sector = Sector {
                    j,
                    q_d: 2.0 * std::f64::consts::PI * f64::from(j) / lat.width * lat.d,
                    growth_rate: rate,
                    e_fold_time: (rate > 0.0).then(|| 1.0 / rate),
                    failed: g.failed,
                };
                (sector, g)
            })
            .collect();
        let best = runs
            .iter()
            .filter(|(s, _)| s.growth_rate.is_finite())
            .max_by(|a, b| a.0.growth_rate.total_cmp(&b.0.growth_rate));
        let (rate, j, mode) = best.map_or((f64::NAN, 0, Vec::new()), |(s, g)| {
            let d = lat.d;
            let mode = (0..g.x.len())
                .map(|i| [g.x[i] / d, g.y[i] / d, g.mode.dx[i], g.mode.dy[i]])
                .collect();
            (s.growth_rate, s.j, mode)
        });
        let a = self.req.amplitude;
        AtC0 {
            c0_over_u: self.c,
            sectors: runs.into_iter().map(|(s, _)| s).collect(),
            growth_rate: rate,
            most_unstable_j: j,
            period: period(p),
            growth_rate_per_period: rate * period(p),
            t_disorder_predicted: (rate > 0.0 && a > 0.0)
                .then(|| (DISORDER_DY_RMS * 3f64.sqrt() / a).ln() / rate),
            mode,
        }
    }
}

/// The lattice period T = d N^2 / U of `problem`'s steady profile: layer
/// n moves (N^2 - n^2) d in T, a whole number of lattice spacings, so the
/// sheared lattice is periodic with T (SPEC (19)).
pub fn period(problem: &Problem) -> f64 {
    let n = f64::from(problem.scene.n_layers);
    problem.lattice.d * n * n / problem.flow.u
}

/// The flow map's multipliers: the eigenvalues (nalgebra's) of the
/// Jacobian of the solver's flow over a time t from the base state
/// ([`tangent::flow_jacobian`]), all sectors at once. Over the period
/// T = d N^2 / U ([`period`]) the steady profile's lattice repeats, so the
/// flow map over T is the monodromy matrix and these are its Floquet
/// multipliers (up to the solver's base not being exactly the analytic
/// state: its own pulsation, and its round-off growing); ln |mu| / t of the
/// largest is the growth rate. Over another t it is a finite-time rate.
#[derive(Debug, Clone, Serialize)]
pub struct Multipliers {
    pub t: f64,
    pub steps: usize,
    /// The state's dimension: 4 per fluid particle.
    pub dimension: usize,
    /// The largest multipliers by modulus, (re, im), at most 8.
    pub leading: Vec<[f64; 2]>,
    /// ln |mu| / t of the largest.
    pub growth_rate: f64,
}

/// The largest state the flow map's Jacobian is built for: 400 fluid
/// particles, a 1600 x 1600 matrix (20 MB, its eigenvalues in seconds)
/// and 3200 runs of the solver.
pub const MAX_JACOBIAN_DIMENSION: usize = 1600;

/// Err when `problem`'s flow map Jacobian would be above
/// [`MAX_JACOBIAN_DIMENSION`]: checked before any run.
pub fn check_jacobian(problem: &Problem) -> Result<()> {
    let lat = &problem.lattice;
    let dimension = 4 * lat.fluid_layers() as usize * lat.columns as usize;
    if dimension > MAX_JACOBIAN_DIMENSION {
        bail!(
            "--floquet / --multipliers-t: the flow map's Jacobian would be {dimension} x {dimension} \
             ({} fluid particles, 4 components each: 2 runs of the solver per column), above the \
             bound of {MAX_JACOBIAN_DIMENSION}; give fewer --columns or a smaller --n",
            dimension / 4
        );
    }
    Ok(())
}

/// The multipliers of the flow over `t` about the base state at `c0`.
pub fn multipliers(scene: &Scene, c0: f64, t: f64, eps: f64) -> Result<Multipliers> {
    let info = scene.kernel_info()?;
    let problem = Problem::resolve(&base_scene(scene, c0)?, info)?;
    check_jacobian(&problem)?;
    struct Visit<'a> {
        problem: &'a Problem,
        t: f64,
        eps: f64,
    }
    impl KernelVisitor for Visit<'_> {
        type Output = Multipliers;
        fn visit<K: Kernel>(self) -> Multipliers {
            let (m, steps) = tangent::flow_jacobian::<K>(self.problem, self.t, self.eps);
            let mut mu: Vec<_> = m.complex_eigenvalues().iter().copied().collect();
            mu.sort_by(|a, b| b.norm().total_cmp(&a.norm()));
            Multipliers {
                t: self.t,
                steps,
                dimension: m.nrows(),
                leading: mu.iter().take(8).map(|z| [z.re, z.im]).collect(),
                growth_rate: mu.first().map_or(f64::NAN, |z| z.norm().ln() / self.t),
            }
        }
    }
    Ok(kernels::with_kernel(
        info.name,
        Visit {
            problem: &problem,
            t,
            eps,
        },
    )
    .expect("the registry has a solver for every kernel it lists"))
}
