//! The particle state (structure of arrays) and the passes of one step:
//! kick-drift, density by summation with the EOS, forces with the closing
//! kick. Each pass is a gather over the neighbour list, parallel over fixed
//! chunks of particles; a particle's sums run in its list's order, so results
//! do not depend on the thread count.

use rayon::prelude::*;

use super::lattice::Lattice;
use super::neighbours::{Displacements, Entry, NeighbourList};
use crate::kernel::Kernel;
use crate::scene::{Initial, PressureForm, Problem};

/// Particles per parallel task: large enough that a task outweighs rayon's
/// overhead on the small scenes this problem needs.
const CHUNK: usize = 128;

/// Fluid particles come first (indices < n_fluid), the fixed walls after.
pub(crate) struct State {
    pub n_fluid: usize,
    pub x: Vec<f64>,
    pub y: Vec<f64>,
    /// Velocity: v(t) between steps, v(t + dt/2) inside one. Zero on walls.
    pub vx: Vec<f64>,
    pub vy: Vec<f64>,
    /// The velocity the forces see, v(t) + dt a(t), a prediction of
    /// v(t + dt) (viscosity and artificial viscosity depend on it).
    pub vpx: Vec<f64>,
    pub vpy: Vec<f64>,
    /// Acceleration of the fluid particles.
    pub ax: Vec<f64>,
    pub ay: Vec<f64>,
    pub rho: Vec<f64>,
    pub press: Vec<f64>,
    /// m / rho and P / rho^2, per particle, so the pair loops do not divide.
    pub vol: Vec<f64>,
    pub p_rho2: Vec<f64>,
    /// Fluid positions at the last neighbour-list rebuild.
    pub x0: Vec<f64>,
    pub y0: Vec<f64>,
    /// Layer each particle started in.
    pub layer: Vec<i32>,
    /// What the density pass leaves for the force pass, per fluid particle:
    /// its neighbours within the support now (neighbour-list entries) and
    /// their (dW/dq)/q, so the kernel is evaluated once per pair and step
    /// and the force pass has neither a distance test nor a kernel branch.
    /// `near_stride` slots per particle, as the neighbour list.
    pub near: Vec<u32>,
    pub near_g: Vec<f64>,
    pub near_count: Vec<u32>,
    pub near_stride: usize,
}

impl State {
    pub fn new(lattice: &Lattice, problem: &Problem) -> Self {
        let (mut x, mut y, layer) = lattice.positions();
        let n = x.len();
        let n_fluid = lattice.n_fluid();
        let jitter = problem.scene.jitter * lattice.d;
        if jitter > 0.0 {
            let mut rng = SplitMix64(0x5eed_5be5);
            for i in 0..n_fluid {
                x[i] += jitter * rng.symmetric();
                y[i] += jitter * rng.symmetric();
            }
        }
        let mut vx = vec![0.0; n];
        if problem.initial == Initial::Steady {
            for i in 0..n_fluid {
                vx[i] = problem.flow.steady(y[i]);
            }
        }
        State {
            n_fluid,
            vpx: vx.clone(),
            vx,
            vy: vec![0.0; n],
            vpy: vec![0.0; n],
            ax: vec![0.0; n_fluid],
            ay: vec![0.0; n_fluid],
            rho: vec![problem.rho0; n],
            press: vec![0.0; n],
            vol: vec![0.0; n],
            p_rho2: vec![0.0; n],
            x0: x[..n_fluid].to_vec(),
            y0: y[..n_fluid].to_vec(),
            x,
            y,
            layer,
            near: Vec::new(),
            near_g: Vec::new(),
            near_count: vec![0; n_fluid],
            near_stride: 0,
        }
    }

    /// Bytes held by the arrays.
    pub fn bytes(&self) -> usize {
        let f64s = [
            &self.x,
            &self.y,
            &self.vx,
            &self.vy,
            &self.vpx,
            &self.vpy,
            &self.ax,
            &self.ay,
            &self.rho,
            &self.press,
            &self.vol,
            &self.p_rho2,
            &self.x0,
            &self.y0,
        ]
        .iter()
        .map(|v| v.capacity())
        .sum::<usize>();
        (f64s + self.near_g.capacity()) * size_of::<f64>()
            + (self.layer.capacity() + self.near.capacity() + self.near_count.capacity())
                * size_of::<u32>()
    }

    /// Wrap the fluid into the strip and take the current positions as the
    /// reference for the rebuild rule.
    pub fn wrap(&mut self, width: f64) {
        for i in 0..self.n_fluid {
            self.x[i] = self.x[i].rem_euclid(width);
        }
        self.x0.copy_from_slice(&self.x[..self.n_fluid]);
        self.y0.copy_from_slice(&self.y[..self.n_fluid]);
    }
}

/// A small deterministic generator (SplitMix64) for the initial jitter.
struct SplitMix64(u64);

impl SplitMix64 {
    /// Uniform in [-1, 1).
    fn symmetric(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^= z >> 31;
        2.0 * ((z >> 11) as f64 / (1u64 << 53) as f64) - 1.0
    }
}

/// Everything the pair loops need, with the h powers folded in once.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Params {
    pub inv_h2: f64,
    /// m / h^2: rho = (m / h^2) sum w(q^2).
    pub mass_over_h2: f64,
    pub mass: f64,
    pub rho0: f64,
    /// rho0 c0^2 / gamma.
    pub b_eos: f64,
    pub gamma: f64,
    pub allow_negative: bool,
    pub symmetric: bool,
    /// grad_i W_ij = (dw_over_q / h^4) r_ij.
    pub grad_scale: f64,
    /// alpha c0 h m (31).
    pub av: f64,
    /// 2 mu (the Laplacian (14) with the right sign).
    pub visc: f64,
    /// Body force along +x.
    pub body: f64,
}

impl Params {
    pub fn new(problem: &Problem) -> Self {
        let h = problem.lattice.h;
        Params {
            inv_h2: 1.0 / (h * h),
            mass_over_h2: problem.mass / (h * h),
            mass: problem.mass,
            rho0: problem.rho0,
            b_eos: problem.rho0 * problem.c0 * problem.c0 / problem.scene.gamma,
            gamma: problem.scene.gamma,
            allow_negative: problem.scene.allow_negative_pressure,
            symmetric: problem.scene.pressure_form == PressureForm::Symmetric,
            grad_scale: 1.0 / (h * h * h * h),
            av: problem.scene.alpha * problem.c0 * h * problem.mass,
            visc: 2.0 * problem.mu,
            body: problem.flow.p,
        }
    }

    /// EOS (13): P = rho0 c0^2 / gamma ((rho/rho0)^gamma - 1), no tension
    /// unless allowed.
    #[inline]
    fn pressure(&self, rho: f64) -> f64 {
        let ratio = rho / self.rho0;
        let compression = if self.gamma == 1.0 {
            ratio - 1.0
        } else {
            ratio.powf(self.gamma) - 1.0
        };
        let p = self.b_eos * compression;
        if self.allow_negative {
            p
        } else {
            p.max(0.0)
        }
    }
}

/// First half of the leapfrog: v += dt/2 a, x += dt v, and the prediction
/// v + dt/2 a of the end-of-step velocity for the forces. Fills `motion`
/// with each block's displacements since the last rebuild and how far from
/// the centre line it reached. Parallel over tasks of whole blocks (a block,
/// one lattice layer, is only a few particles).
pub(crate) fn kick_drift(
    s: &mut State,
    dt: f64,
    block: usize,
    motion: &mut Vec<(Displacements, f64)>,
) {
    let nf = s.n_fluid;
    let half = 0.5 * dt;
    // Sized once: every later step reuses it.
    motion.resize(nf / block, (Displacements::EMPTY, 0.0));
    let blocks_per_task = CHUNK.div_ceil(block);
    let span = blocks_per_task * block;
    (
        s.x[..nf].par_chunks_mut(span),
        s.y[..nf].par_chunks_mut(span),
        s.vx[..nf].par_chunks_mut(span),
        s.vy[..nf].par_chunks_mut(span),
        s.vpx[..nf].par_chunks_mut(span),
        s.vpy[..nf].par_chunks_mut(span),
        s.ax.par_chunks(span),
        s.ay.par_chunks(span),
        s.x0.par_chunks(span),
        s.y0.par_chunks(span),
        motion.par_chunks_mut(blocks_per_task),
    )
        .into_par_iter()
        .for_each(|(x, y, vx, vy, vpx, vpy, ax, ay, x0, y0, motion)| {
            for (b, m) in motion.iter_mut().enumerate() {
                let r = b * block..(b + 1) * block;
                let (x, y, vx, vy) = (
                    &mut x[r.clone()],
                    &mut y[r.clone()],
                    &mut vx[r.clone()],
                    &mut vy[r.clone()],
                );
                let (vpx, vpy) = (&mut vpx[r.clone()], &mut vpy[r.clone()]);
                let (ax, ay, x0, y0) = (&ax[r.clone()], &ay[r.clone()], &x0[r.clone()], &y0[r]);
                let mut d = Displacements::EMPTY;
                let mut max_abs_y = 0.0f64;
                for k in 0..block {
                    vx[k] += half * ax[k];
                    vy[k] += half * ay[k];
                    x[k] += dt * vx[k];
                    y[k] += dt * vy[k];
                    vpx[k] = vx[k] + half * ax[k];
                    vpy[k] = vy[k] + half * ay[k];
                    d.add(x[k] - x0[k], y[k] - y0[k]);
                    // NaN compares false: make it count as out of the channel.
                    let ya = y[k].abs();
                    max_abs_y = if ya.is_nan() {
                        f64::INFINITY
                    } else {
                        max_abs_y.max(ya)
                    };
                }
                *m = (d, max_abs_y);
            }
        });
}

/// Floating-point operations per pair in the density pass's loop, the
/// kernel's (W, (dW/dq)/q) aside: dx with its image, dy (3), q^2 (4), the
/// support test (1), the sum (1).
pub(crate) const DENSITY_PAIR_FLOPS: u32 = 9;

/// Density by summation (11) over fluid and wall neighbours, self included,
/// then the EOS. Returns the largest compaction eps = rho/rho0 - 1 of the
/// fluid. For the fluid it also keeps, per particle, the neighbours within
/// the support and their (dW/dq)/q for [`forces`]: W and (dW/dq)/q come from
/// one fused evaluation.
pub(crate) fn density<K: Kernel>(s: &mut State, list: &NeighbourList, prm: &Params) -> f64 {
    let n = s.x.len();
    let nf = s.n_fluid;
    // Room for the longest list: grows only when a rebuild lengthened it.
    let stride = list.stride().max(1);
    if s.near_stride != stride {
        s.near_stride = stride;
        s.near.resize(nf * stride, 0);
        s.near_g.resize(nf * stride, 0.0);
    }
    // Slices of one known length: one bounds check per neighbour covers all.
    let (x, y) = (&s.x[..n], &s.y[..n]);
    let images = list.images();
    let w_self = K::w(0.0);
    let eos = |k: usize,
               sum: f64,
               rho: &mut [f64],
               press: &mut [f64],
               vol: &mut [f64],
               p_rho2: &mut [f64]| {
        let r = prm.mass_over_h2 * sum;
        let p = prm.pressure(r);
        rho[k] = r;
        press[k] = p;
        vol[k] = prm.mass / r;
        p_rho2[k] = p / (r * r);
        r
    };
    // The fluid: W and (dW/dq)/q together, the pairs in reach kept.
    let fluid = (
        s.rho[..nf].par_chunks_mut(CHUNK),
        s.press[..nf].par_chunks_mut(CHUNK),
        s.vol[..nf].par_chunks_mut(CHUNK),
        s.p_rho2[..nf].par_chunks_mut(CHUNK),
        s.near.par_chunks_mut(CHUNK * stride),
        s.near_g.par_chunks_mut(CHUNK * stride),
        s.near_count.par_chunks_mut(CHUNK),
    )
        .into_par_iter()
        .enumerate()
        .map(|(c, (rho, press, vol, p_rho2, near, near_g, near_count))| {
            let mut max_eps = f64::NEG_INFINITY;
            for (k, (near, near_g)) in near
                .chunks_exact_mut(stride)
                .zip(near_g.chunks_exact_mut(stride))
                .enumerate()
            {
                let i = c * CHUNK + k;
                let (xi, yi) = (x[i], y[i]);
                let mut sum = w_self;
                let mut kept = 0;
                for &e in list.of(i) {
                    let j = Entry::index(e);
                    let dx = xi - x[j] + images[Entry::image(e)];
                    let dy = yi - y[j];
                    let q2 = (dx * dx + dy * dy) * prm.inv_h2;
                    if q2 <= K::SUPPORT2_CLOSED {
                        let (w, g) = K::w_dw_over_q(q2);
                        sum += w;
                        near[kept] = e;
                        near_g[kept] = g;
                        kept += 1;
                    }
                }
                near_count[k] = kept as u32;
                let r = eos(k, sum, rho, press, vol, p_rho2);
                max_eps = max_eps.max(r / prm.rho0 - 1.0);
            }
            max_eps
        })
        .reduce(|| f64::NEG_INFINITY, f64::max);
    // The walls: W only.
    (
        s.rho[nf..].par_chunks_mut(CHUNK),
        s.press[nf..].par_chunks_mut(CHUNK),
        s.vol[nf..].par_chunks_mut(CHUNK),
        s.p_rho2[nf..].par_chunks_mut(CHUNK),
    )
        .into_par_iter()
        .enumerate()
        .for_each(|(c, (rho, press, vol, p_rho2))| {
            for k in 0..rho.len() {
                let i = nf + c * CHUNK + k;
                let (xi, yi) = (x[i], y[i]);
                let mut sum = w_self;
                for &e in list.of(i) {
                    let j = Entry::index(e);
                    let dx = xi - x[j] + images[Entry::image(e)];
                    let dy = yi - y[j];
                    let q2 = (dx * dx + dy * dy) * prm.inv_h2;
                    if q2 <= K::SUPPORT2_CLOSED {
                        sum += K::w(q2);
                    }
                }
                eos(k, sum, rho, press, vol, p_rho2);
            }
        });
    fluid
}

/// What the force pass saw at the end of the step.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Forces {
    /// Largest |v| and |a| of the fluid.
    pub v_max: f64,
    pub a_max: f64,
    /// false when any velocity or acceleration is NaN or infinite.
    pub finite: bool,
}

impl Forces {
    const NONE: Forces = Forces {
        v_max: 0.0,
        a_max: 0.0,
        finite: true,
    };

    fn merge(self, o: Forces) -> Forces {
        Forces {
            v_max: self.v_max.max(o.v_max),
            a_max: self.a_max.max(o.a_max),
            finite: self.finite && o.finite,
        }
    }
}

/// Floating-point operations per pair in the force pass's loop (the kernel
/// was evaluated in the density pass): dx with its image, dy (3); pressure
/// p_ij, p_ij g, two products and sums (6); v_ij (2), the Laplacian's
/// vol_j g and two products and sums (5). With artificial viscosity also
/// r^2 (3), v_ij . r_ij (3), min, division, product and two sums (7).
pub(crate) const FORCE_PAIR_FLOPS: u32 = 16;
pub(crate) const FORCE_PAIR_FLOPS_AV: u32 = FORCE_PAIR_FLOPS + 13;

/// Accelerations of the fluid, then the closing kick v += dt/2 a, over the
/// pairs [`density`] kept (within the support, with their (dW/dq)/q).
///
/// - pressure (12): -(m / rho_i^2) sum (P_i + P_j) grad_i W_ij, or the
///   symmetric -m sum (P_i / rho_i^2 + P_j / rho_j^2) grad_i W_ij;
/// - artificial viscosity (31): (alpha c0 h m / rho_i) sum over approaching
///   pairs of (v_ij . r_ij) / r_ij^2 grad_i W_ij, repulsive;
/// - viscosity, the Laplacian (14) with the right sign on both components:
///   (2 mu m / rho_i) sum (v_i - v_j) / rho_j (dW/dr) / r_ij;
/// - the body force p along +x.
pub(crate) fn forces(s: &mut State, list: &NeighbourList, prm: &Params, half_dt: f64) -> Forces {
    match (prm.symmetric, prm.av != 0.0) {
        (true, true) => forces_with::<true, true>(s, list, prm, half_dt),
        (true, false) => forces_with::<true, false>(s, list, prm, half_dt),
        (false, true) => forces_with::<false, true>(s, list, prm, half_dt),
        (false, false) => forces_with::<false, false>(s, list, prm, half_dt),
    }
}

fn forces_with<const SYMMETRIC: bool, const AV: bool>(
    s: &mut State,
    list: &NeighbourList,
    prm: &Params,
    half_dt: f64,
) -> Forces {
    let nf = s.n_fluid;
    let stride = s.near_stride;
    // Slices of one known length: one bounds check per neighbour covers all.
    let n = s.x.len();
    let (x, y, vpx, vpy) = (&s.x[..n], &s.y[..n], &s.vpx[..n], &s.vpy[..n]);
    let (rho, press, vol, p_rho2) = (&s.rho[..n], &s.press[..n], &s.vol[..n], &s.p_rho2[..n]);
    let (near, near_g, near_count) = (&s.near, &s.near_g, &s.near_count);
    let images = list.images();
    (
        s.ax.par_chunks_mut(CHUNK),
        s.ay.par_chunks_mut(CHUNK),
        s.vx[..nf].par_chunks_mut(CHUNK),
        s.vy[..nf].par_chunks_mut(CHUNK),
    )
        .into_par_iter()
        .enumerate()
        .map(|(c, (ax, ay, vx, vy))| {
            let mut out = Forces::NONE;
            for k in 0..ax.len() {
                let i = c * CHUNK + k;
                let (xi, yi, vxi, vyi) = (x[i], y[i], vpx[i], vpy[i]);
                let (pi, pri) = (press[i], p_rho2[i]);
                let (mut px, mut py) = (0.0, 0.0);
                let (mut avx, mut avy) = (0.0, 0.0);
                let (mut lx, mut ly) = (0.0, 0.0);
                let start = i * stride;
                let end = start + near_count[i] as usize;
                for (&e, &g) in near[start..end].iter().zip(&near_g[start..end]) {
                    let j = Entry::index(e);
                    // grad_i W_ij = g r_ij, up to the h^-4 applied at the end.
                    let dx = xi - x[j] + images[Entry::image(e)];
                    let dy = yi - y[j];
                    let pij = if SYMMETRIC {
                        pri + p_rho2[j]
                    } else {
                        pi + press[j]
                    };
                    let pg = pij * g;
                    px += pg * dx;
                    py += pg * dy;
                    let (dvx, dvy) = (vxi - vpx[j], vyi - vpy[j]);
                    if AV {
                        let r2 = dx * dx + dy * dy;
                        let vr = dvx * dx + dvy * dy;
                        // Only approaching pairs (v_ij . r_ij < 0); branch-free,
                        // since the sign changes unpredictably from pair to pair.
                        let f = vr.min(0.0) / r2 * g;
                        avx += f * dx;
                        avy += f * dy;
                    }
                    let f = vol[j] * g;
                    lx += f * dvx;
                    ly += f * dvy;
                }
                let inv_rho = 1.0 / rho[i];
                let p_scale = if SYMMETRIC {
                    prm.mass
                } else {
                    prm.mass * inv_rho * inv_rho
                };
                let av = prm.av * inv_rho;
                let visc = prm.visc * inv_rho;
                let axi = prm.grad_scale * (-p_scale * px + av * avx + visc * lx) + prm.body;
                let ayi = prm.grad_scale * (-p_scale * py + av * avy + visc * ly);
                ax[k] = axi;
                ay[k] = ayi;
                vx[k] += half_dt * axi;
                vy[k] += half_dt * ayi;
                let a2 = axi * axi + ayi * ayi;
                let v2 = vx[k] * vx[k] + vy[k] * vy[k];
                out.finite &= (a2 + v2).is_finite();
                out.a_max = out.a_max.max(a2);
                out.v_max = out.v_max.max(v2);
            }
            out.a_max = out.a_max.sqrt();
            out.v_max = out.v_max.sqrt();
            out
        })
        .reduce(|| Forces::NONE, Forces::merge)
}
