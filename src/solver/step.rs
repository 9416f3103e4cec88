//! The particle state (structure of arrays) and the passes of one step:
//! kick-drift, density by summation with the EOS, forces with the closing
//! kick. Each pass is a gather over the neighbour list, parallel over fixed
//! chunks of particles; a particle's sums run in its list's order, so results
//! do not depend on the thread count.

use rayon::prelude::*;

use super::neighbours::{padded, Displacements, Entry, NeighbourList, LANES};
use crate::kernel::Kernel;
use crate::problem::lattice::Lattice;
use crate::problem::{Initial, PressureForm, Problem};

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
    /// How far beyond the no-slip plane |y| = B each particle sits: |y| - B
    /// for the walls (which never move), 0 for the fluid. For mirrored walls.
    pub depth: Vec<f64>,
    /// What the density pass leaves for the force pass: W and (dW/dq)/q of
    /// every listed pair (0 beyond the support), evaluated once per pair
    /// and step, in the slot (`near_stride` per particle) of the entry it
    /// was evaluated for ([`NeighbourList::own`]), and after them a slot
    /// kept at zero for padding; each entry finds its pair's through
    /// [`NeighbourList::sources_padded`]. The force pass has no distance
    /// test and no kernel.
    pub pair_w: Vec<f64>,
    pub pair_g: Vec<f64>,
    pub near_stride: usize,
}

impl State {
    pub fn new(lattice: &Lattice, problem: &Problem) -> Self {
        let (mut x, mut y, layer) = lattice.positions();
        let n = x.len();
        let n_fluid = lattice.n_fluid();
        let jitter = problem.jitter * lattice.d;
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
        let b = lattice.b();
        let depth = (0..n)
            .map(|i| {
                if i < n_fluid {
                    0.0
                } else {
                    (y[i].abs() - b).max(0.0)
                }
            })
            .collect();
        State {
            n_fluid,
            depth,
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
            near_stride: 0,
            pair_w: Vec::new(),
            pair_g: Vec::new(),
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
            &self.depth,
        ]
        .iter()
        .map(|v| v.capacity())
        .sum::<usize>();
        (f64s + self.pair_w.capacity() + self.pair_g.capacity()) * size_of::<f64>()
            + self.layer.capacity() * size_of::<u32>()
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
    /// Whether (31) acts at all: [`Problem::has_artificial_viscosity`], the
    /// same test the flop count makes.
    pub has_av: bool,
    /// 2 mu (the Laplacian (14) with the right sign).
    pub visc: f64,
    /// Body force along +x.
    pub body: f64,
    /// Walls mirror the fluid's velocity in the viscous term ([`forces`]).
    pub mirror_walls: bool,
    /// The no-slip plane |y| = B.
    pub b: f64,
    /// The cap on the mirrored walls' factor beta = 1 + D_j / g_i: the
    /// largest beta of the undisturbed lattice (the deepest wall layer, at
    /// D = (layers - 1) dy, seen from the first fluid layer, g = dy), so
    /// that only a fluid particle nearer the plane than one layer spacing
    /// is capped, and a particle reaching the plane does not take an
    /// unbounded viscous force. Morris, Fox and Zhu (1997) capped it at
    /// 1.5; one, two and three wall layers give 1, 2 and 3 here.
    pub beta_max: f64,
}

impl Params {
    pub fn new(problem: &Problem) -> Self {
        let h = problem.lattice.h;
        Params {
            inv_h2: 1.0 / (h * h),
            mass_over_h2: problem.mass / (h * h),
            mass: problem.mass,
            rho0: problem.rho0,
            b_eos: problem.rho0 * problem.c0 * problem.c0 / problem.gamma,
            gamma: problem.gamma,
            allow_negative: problem.allow_negative_pressure,
            symmetric: problem.pressure_form == PressureForm::Symmetric,
            grad_scale: 1.0 / (h * h * h * h),
            av: problem.alpha * problem.c0 * h * problem.mass,
            has_av: problem.has_artificial_viscosity(),
            visc: 2.0 * problem.mu,
            body: problem.flow.p,
            mirror_walls: problem.mirrored_walls(),
            b: problem.lattice.b(),
            beta_max: f64::from(problem.lattice.wall_layers.max(1)),
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

/// Floating-point operations of the density pass, the kernel's (W,
/// (dW/dq)/q) aside: per pair evaluated (once for both directions), dx with
/// its image, dy (3) and q^2 (4); per directed pair, the sum of W (1).
pub(crate) const DENSITY_DISTANCE_FLOPS: u32 = 7;
pub(crate) const DENSITY_SUM_FLOPS: u32 = 1;

/// Entries a pair loop takes at a time, in buffers on the stack (a whole
/// number of lane groups; a list longer than this takes several).
const BLOCK: usize = 8 * LANES;

/// Two buffers of a block's entries, made once per parallel task (zeroing
/// them per particle would cost more than some particles' pairs).
type Scratch = ([f64; BLOCK], [f64; BLOCK]);

/// The pairwise sum of the lane accumulators, in a fixed order.
#[inline(always)]
fn lane_sum(a: [f64; LANES]) -> f64 {
    ((a[0] + a[1]) + (a[2] + a[3])) + ((a[4] + a[5]) + (a[6] + a[7]))
}

/// The vector instructions the pair loops are compiled for, chosen at run
/// time. Each is the same source, the same operations in the same order:
/// the results are the same bits on every CPU.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Isa {
    #[cfg(target_arch = "x86_64")]
    Avx512,
    #[cfg(target_arch = "x86_64")]
    Avx2,
    Base,
}

impl Isa {
    /// Name and f64 lanes per vector register.
    pub(crate) fn describe(self) -> (&'static str, u32) {
        match self {
            #[cfg(target_arch = "x86_64")]
            Isa::Avx512 => ("AVX-512", 8),
            #[cfg(target_arch = "x86_64")]
            Isa::Avx2 => ("AVX2", 4),
            Isa::Base => ("baseline (SSE2 on x86-64)", 2),
        }
    }

    pub(crate) fn detect() -> Isa {
        #[cfg(target_arch = "x86_64")]
        {
            if std::arch::is_x86_feature_detected!("avx512f")
                && std::arch::is_x86_feature_detected!("avx512dq")
                && std::arch::is_x86_feature_detected!("avx512vl")
            {
                return Isa::Avx512;
            }
            if std::arch::is_x86_feature_detected!("avx2") {
                return Isa::Avx2;
            }
        }
        Isa::Base
    }
}

/// [`pair_kernel`] for AVX-512 (8 lanes), alone: the passes call it through
/// [`kernel_chunk_avx512`]; the test that compares ISAs calls it directly.
///
/// # Safety
/// The CPU must have AVX-512 F, DQ and VL ([`Isa::detect`]).
#[cfg(test)]
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx512dq,avx512vl,avx2")]
unsafe fn pair_kernel_avx512<K: Kernel>(
    at: (f64, f64),
    entries: &[u32],
    xs: (&[f64], &[f64]),
    width: f64,
    inv_h2: f64,
    out: (&mut [f64], &mut [f64]),
    scratch: &mut Scratch,
) {
    pair_kernel::<K>(at, entries, xs, width, inv_h2, out, scratch)
}

/// [`pair_kernel`] for AVX2 (4 lanes).
///
/// # Safety
/// The CPU must have AVX2 ([`Isa::detect`]).
#[cfg(test)]
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn pair_kernel_avx2<K: Kernel>(
    at: (f64, f64),
    entries: &[u32],
    xs: (&[f64], &[f64]),
    width: f64,
    inv_h2: f64,
    out: (&mut [f64], &mut [f64]),
    scratch: &mut Scratch,
) {
    pair_kernel::<K>(at, entries, xs, width, inv_h2, out, scratch)
}

/// W and (dW/dq)/q of each of the entries of the particle at `at` into
/// `out` (W, g), with its neighbours' positions `xs`. Two loops without
/// branches or bounds checks, so that they vectorise: distances (a gather)
/// and the kernel (all pieces, then a select). Element by element: the
/// results do not depend on how the loops are compiled.
#[inline(always)]
fn pair_kernel<K: Kernel>(
    at: (f64, f64),
    entries: &[u32],
    xs: (&[f64], &[f64]),
    width: f64,
    inv_h2: f64,
    out: (&mut [f64], &mut [f64]),
    scratch: &mut Scratch,
) {
    let ((xi, yi), (x, y), (w_out, g_out)) = (at, xs, out);
    let n = x.len();
    assert!(n > 0 && y.len() == n);
    // Every index is clamped into the arrays: no bounds check (an index
    // is below n by construction of the list anyway).
    let last = n - 1;
    let q2 = &mut scratch.0;
    for ((block, w_block), g_block) in entries
        .chunks(BLOCK)
        .zip(w_out.chunks_mut(BLOCK))
        .zip(g_out.chunks_mut(BLOCK))
    {
        let m = block.len();
        for (q2, &e) in q2[..m].iter_mut().zip(block) {
            let j = Entry::index_below(e, last);
            let dx = xi - x[j] + Entry::offset(e, width);
            let dy = yi - y[j];
            *q2 = (dx * dx + dy * dy) * inv_h2;
        }
        for ((&q2, w), g) in q2[..m].iter().zip(w_block).zip(g_block) {
            (*w, *g) = K::w_dw_over_q_lanes(q2);
        }
    }
}

/// [`pair_gather`] for AVX-512.
///
/// # Safety
/// The CPU must have AVX-512 F, DQ and VL ([`Isa::detect`]).
#[cfg(test)]
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx512dq,avx512vl,avx2")]
unsafe fn pair_gather_avx512(sources: &[u32], pair_w: &[f64]) -> f64 {
    pair_gather(sources, pair_w)
}

/// [`pair_gather`] for AVX2.
///
/// # Safety
/// The CPU must have AVX2 ([`Isa::detect`]).
#[cfg(test)]
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn pair_gather_avx2(sources: &[u32], pair_w: &[f64]) -> f64 {
    pair_gather(sources, pair_w)
}

/// Sum of W over a particle's padded slots, taken from the slots `sources`
/// name ([`NeighbourList::sources_padded`]), in LANES accumulators (a fixed
/// order: the result does not depend on how the loop is compiled).
#[inline(always)]
fn pair_gather(sources: &[u32], pair_w: &[f64]) -> f64 {
    let n = pair_w.len();
    assert!(n > 0);
    let last = n - 1;
    let mut acc = [0.0; LANES];
    for src in sources.chunks_exact(LANES) {
        for l in 0..LANES {
            acc[l] += pair_w[(src[l] as usize).min(last)];
        }
    }
    lane_sum(acc)
}

/// Density by summation (11) over fluid and wall neighbours, self included,
/// then the EOS. Returns the largest compaction eps = rho/rho0 - 1 of the
/// fluid. Two passes: the kernel, W and (dW/dq)/q from one fused
/// evaluation, once per pair, on the lists' own entries
/// ([`NeighbourList::own`]); then per particle the sum of W over all its
/// slots, each taken from where it was evaluated, and the (dW/dq)/q of
/// every slot kept for [`forces`].
pub(crate) fn density<K: Kernel>(s: &mut State, list: &NeighbourList, prm: &Params) -> f64 {
    density_with::<K>(s, list, prm, Isa::detect())
}

fn density_with<K: Kernel>(s: &mut State, list: &NeighbourList, prm: &Params, isa: Isa) -> f64 {
    let n = s.x.len();
    let nf = s.n_fluid;
    // Room for the longest list: grows only when a rebuild lengthened it.
    let stride = list.stride();
    let slots = list.slots();
    if s.near_stride != stride {
        s.near_stride = stride;
        // And the zero slot that padding reads, never written.
        s.pair_w.resize(slots + 1, 0.0);
        s.pair_g.resize(slots + 1, 0.0);
        s.pair_w[slots] = 0.0;
        s.pair_g[slots] = 0.0;
    }
    let inp = DensityIn {
        x: &s.x[..n],
        y: &s.y[..n],
        list,
        width: list.width(),
        prm,
        nf,
        stride,
    };
    (
        s.pair_w[..slots].par_chunks_mut(CHUNK * stride),
        s.pair_g[..slots].par_chunks_mut(CHUNK * stride),
    )
        .into_par_iter()
        .enumerate()
        .for_each(|(c, out)| match isa {
            // SAFETY: Isa::detect found the CPU features.
            #[cfg(target_arch = "x86_64")]
            Isa::Avx512 => unsafe { kernel_chunk_avx512::<K>(c, out, &inp) },
            #[cfg(target_arch = "x86_64")]
            Isa::Avx2 => unsafe { kernel_chunk_avx2::<K>(c, out, &inp) },
            Isa::Base => kernel_chunk::<K>(c, out, &inp),
        });
    let pair_w = &s.pair_w[..];
    (
        s.rho.par_chunks_mut(CHUNK),
        s.press.par_chunks_mut(CHUNK),
        s.vol.par_chunks_mut(CHUNK),
        s.p_rho2.par_chunks_mut(CHUNK),
    )
        .into_par_iter()
        .enumerate()
        .map(|(c, out)| match isa {
            // SAFETY: Isa::detect found the CPU features.
            #[cfg(target_arch = "x86_64")]
            Isa::Avx512 => unsafe { density_chunk_avx512::<K>(c, out, &inp, pair_w) },
            #[cfg(target_arch = "x86_64")]
            Isa::Avx2 => unsafe { density_chunk_avx2::<K>(c, out, &inp, pair_w) },
            Isa::Base => density_chunk::<K>(c, out, &inp, pair_w),
        })
        .reduce(|| f64::NEG_INFINITY, f64::max)
}

/// What every task of the density pass reads.
struct DensityIn<'a> {
    x: &'a [f64],
    y: &'a [f64],
    list: &'a NeighbourList,
    width: f64,
    prm: &'a Params,
    nf: usize,
    stride: usize,
}

/// One task's outputs of the kernel pass: the W and (dW/dq)/q slots.
type KernelOut<'a> = (&'a mut [f64], &'a mut [f64]);

/// [`kernel_chunk`] for AVX-512: one call per task, so that the vector
/// code's set-up is paid per task, not per particle.
///
/// # Safety
/// The CPU must have AVX-512 F, DQ and VL ([`Isa::detect`]).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx512dq,avx512vl,avx2")]
unsafe fn kernel_chunk_avx512<K: Kernel>(c: usize, out: KernelOut, inp: &DensityIn) {
    kernel_chunk::<K>(c, out, inp)
}

/// [`kernel_chunk`] for AVX2.
///
/// # Safety
/// The CPU must have AVX2 ([`Isa::detect`]).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn kernel_chunk_avx2<K: Kernel>(c: usize, out: KernelOut, inp: &DensityIn) {
    kernel_chunk::<K>(c, out, inp)
}

/// W and (dW/dq)/q of the own entries of the particles of task `c`, in
/// whole groups of LANES: the few entries past the own ones that this
/// takes are evaluated too (their slots are never read), rather than left
/// to a scalar remainder.
#[inline(always)]
fn kernel_chunk<K: Kernel>(c: usize, out: KernelOut, inp: &DensityIn) {
    let (pair_w, pair_g) = out;
    let scratch = &mut ([0.0; BLOCK], [0.0; BLOCK]);
    for (k, (w_out, g_out)) in pair_w
        .chunks_exact_mut(inp.stride)
        .zip(pair_g.chunks_exact_mut(inp.stride))
        .enumerate()
    {
        let i = c * CHUNK + k;
        let own = padded(inp.list.own(i));
        let entries = &inp.list.of_padded(i)[..own];
        pair_kernel::<K>(
            (inp.x[i], inp.y[i]),
            entries,
            (inp.x, inp.y),
            inp.width,
            inp.prm.inv_h2,
            (&mut w_out[..own], &mut g_out[..own]),
            scratch,
        );
    }
}

/// One task's outputs: rho, P, m/rho, P/rho^2.
type DensityOut<'a> = (&'a mut [f64], &'a mut [f64], &'a mut [f64], &'a mut [f64]);

/// [`density_chunk`] for AVX-512.
///
/// # Safety
/// The CPU must have AVX-512 F, DQ and VL ([`Isa::detect`]).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx512dq,avx512vl,avx2")]
unsafe fn density_chunk_avx512<K: Kernel>(
    c: usize,
    out: DensityOut,
    inp: &DensityIn,
    pair_w: &[f64],
) -> f64 {
    density_chunk::<K>(c, out, inp, pair_w)
}

/// [`density_chunk`] for AVX2.
///
/// # Safety
/// The CPU must have AVX2 ([`Isa::detect`]).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn density_chunk_avx2<K: Kernel>(
    c: usize,
    out: DensityOut,
    inp: &DensityIn,
    pair_w: &[f64],
) -> f64 {
    density_chunk::<K>(c, out, inp, pair_w)
}

/// Density and EOS for the particles of task `c`, from the kernel pass's
/// `pair_w`; returns their largest fluid compaction.
#[inline(always)]
fn density_chunk<K: Kernel>(c: usize, out: DensityOut, inp: &DensityIn, pair_w: &[f64]) -> f64 {
    let (rho, press, vol, p_rho2) = out;
    let prm = inp.prm;
    let w_self = K::w(0.0);
    let mut max_eps = f64::NEG_INFINITY;
    for k in 0..rho.len() {
        let i = c * CHUNK + k;
        let pairs = pair_gather(inp.list.sources_padded(i), pair_w);
        let sum = w_self + pairs;
        let r = prm.mass_over_h2 * sum;
        let p = prm.pressure(r);
        rho[k] = r;
        press[k] = p;
        vol[k] = prm.mass / r;
        p_rho2[k] = p / (r * r);
        if i < inp.nf {
            max_eps = max_eps.max(r / prm.rho0 - 1.0);
        }
    }
    max_eps
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
/// was evaluated in the density pass): dx with its image, dy (3), p_ij (1),
/// v_ij (2), the pressure and Laplacian terms of both components, scaled per
/// particle, summed and times (dW/dq)/q (10), the two lane sums (2). With
/// artificial viscosity also r^2 (3), v_ij . r_ij (3), its min, division and
/// scale (3), its two terms (4).
pub(crate) const FORCE_PAIR_FLOPS: u32 = 18;
pub(crate) const FORCE_PAIR_FLOPS_AV: u32 = FORCE_PAIR_FLOPS + 13;
/// Mirrored walls add the factor beta: a product, a min and a sum (3), and
/// its product with the viscous scale (1).
pub(crate) const FORCE_PAIR_FLOPS_MIRROR: u32 = 4;

/// The particle-level factors of the force terms.
#[derive(Clone, Copy)]
struct Scales {
    /// m / rho_i^2 (paper) or m (symmetric).
    pressure: f64,
    /// alpha c0 h m / rho_i.
    av: f64,
    /// 2 mu / rho_i.
    visc: f64,
    /// 1 / (B - |y_i|), the inverse distance to the no-slip plane (mirrored
    /// walls only).
    inv_gap: f64,
    /// The largest factor beta of mirrored walls ([`Params::beta_max`]).
    beta_max: f64,
}

/// One particle's force inputs: i, its padded list, its slots' sources and
/// the (dW/dq)/q they point into, (x, y),
/// (vx, vy) predicted, P or P/rho^2, (m/rho, wall depth), the strip's
/// width (for the images' offsets), its scales.
type ForceArgs<'a> = (
    usize,
    &'a [u32],
    (&'a [u32], &'a [f64]),
    (&'a [f64], &'a [f64]),
    (&'a [f64], &'a [f64]),
    &'a [f64],
    (&'a [f64], &'a [f64]),
    f64,
    Scales,
);

/// [`pair_forces`] for AVX-512.
///
/// # Safety
/// The CPU must have AVX-512 F, DQ and VL ([`Isa::detect`]).
#[cfg(test)]
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx512dq,avx512vl,avx2")]
unsafe fn pair_forces_avx512<const AV: bool, const MIRROR: bool>(
    args: ForceArgs,
    scratch: &mut Scratch,
) -> (f64, f64) {
    pair_forces::<AV, MIRROR>(args, scratch)
}

/// [`pair_forces`] for AVX2.
///
/// # Safety
/// The CPU must have AVX2 ([`Isa::detect`]).
#[cfg(test)]
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn pair_forces_avx2<const AV: bool, const MIRROR: bool>(
    args: ForceArgs,
    scratch: &mut Scratch,
) -> (f64, f64) {
    pair_forces::<AV, MIRROR>(args, scratch)
}

/// The particle i's (sum_x, sum_y) of its force terms, up to h^-4: three
/// loops without branches or bounds checks, as in [`pair_kernel`].
#[inline(always)]
fn pair_forces<const AV: bool, const MIRROR: bool>(
    args: ForceArgs,
    scratch: &mut Scratch,
) -> (f64, f64) {
    let (i, entries, (sources, pair_g), xs, vs, pq, (vol, depth), width, sc) = args;
    let (x, y) = xs;
    let (vpx, vpy) = vs;
    let n = x.len();
    assert!(n > i && y.len() == n && vpx.len() == n && vpy.len() == n);
    assert!(pq.len() == n && vol.len() == n && (!MIRROR || depth.len() == n));
    assert!(!pair_g.is_empty());
    let last = n - 1;
    let last_g = u32::try_from(pair_g.len() - 1).expect("slots fit in u32");
    let (xi, yi, vxi, vyi, pqi) = (x[i], y[i], vpx[i], vpy[i], pq[i]);
    let beta_cap = sc.beta_max - 1.0;
    let mut acc_x = [0.0; LANES];
    let mut acc_y = [0.0; LANES];
    let (cx, cy) = (&mut scratch.0, &mut scratch.1);
    for (block, src_block) in entries.chunks(BLOCK).zip(sources.chunks(BLOCK)) {
        let m = block.len();
        for (((cx, cy), &e), &src) in cx[..m]
            .iter_mut()
            .zip(&mut cy[..m])
            .zip(block)
            .zip(src_block)
        {
            let j = Entry::index_below(e, last);
            let g = pair_g[src.min(last_g) as usize];
            // grad_i W_ij = g r_ij, up to the h^-4 applied at the end.
            let dx = xi - x[j] + Entry::offset(e, width);
            let dy = yi - y[j];
            let p = sc.pressure * (pqi + pq[j]);
            let (dvx, dvy) = (vxi - vpx[j], vyi - vpy[j]);
            let mut l = sc.visc * vol[j];
            if MIRROR {
                // A wall particle at depth D beyond the no-slip plane shows
                // fluid particle i, at distance g from it, the velocity
                // -(D / g) v_i: the velocity difference grows by beta.
                l *= 1.0 + (depth[j] * sc.inv_gap).min(beta_cap);
            }
            let (mut fx, mut fy) = (l * dvx - p * dx, l * dvy - p * dy);
            if AV {
                // Only approaching pairs (v_ij . r_ij < 0), branch-free.
                let r2 = dx * dx + dy * dy;
                let vr = dvx * dx + dvy * dy;
                let a = sc.av * (vr.min(0.0) / r2);
                fx += a * dx;
                fy += a * dy;
            }
            *cx = fx * g;
            *cy = fy * g;
        }
        for (a, b) in cx[..m].chunks_exact(LANES).zip(cy[..m].chunks_exact(LANES)) {
            for l in 0..LANES {
                acc_x[l] += a[l];
                acc_y[l] += b[l];
            }
        }
    }
    (lane_sum(acc_x), lane_sum(acc_y))
}

/// Accelerations of the fluid, then the closing kick v += dt/2 a, over the
/// listed pairs with the (dW/dq)/q that [`density`] left (0 out of reach).
///
/// - pressure (12): -(m / rho_i^2) sum (P_i + P_j) grad_i W_ij, or the
///   symmetric -m sum (P_i / rho_i^2 + P_j / rho_j^2) grad_i W_ij;
/// - artificial viscosity (31): (alpha c0 h m / rho_i) sum over approaching
///   pairs of (v_ij . r_ij) / r_ij^2 grad_i W_ij, repulsive;
/// - viscosity, the Laplacian (14) with the right sign on both components:
///   (2 mu m / rho_i) sum (v_i - v_j) / rho_j (dW/dr) / r_ij; with mirrored
///   walls (Morris, Fox and Zhu 1997), a wall particle j at depth D_j beyond
///   the no-slip plane shows fluid particle i, at distance g_i from it, the
///   velocity -(D_j / g_i) v_i, so v_i - v_j = beta v_i with
///   beta = min(1 + D_j / g_i, beta_max) ([`Params::beta_max`]);
/// - the body force p along +x.
pub(crate) fn forces(s: &mut State, list: &NeighbourList, prm: &Params, half_dt: f64) -> Forces {
    let isa = Isa::detect();
    match (prm.symmetric, prm.has_av) {
        (true, true) => forces_walls::<true, true>(s, list, prm, half_dt, isa),
        (true, false) => forces_walls::<true, false>(s, list, prm, half_dt, isa),
        (false, true) => forces_walls::<false, true>(s, list, prm, half_dt, isa),
        (false, false) => forces_walls::<false, false>(s, list, prm, half_dt, isa),
    }
}

fn forces_walls<const SYMMETRIC: bool, const AV: bool>(
    s: &mut State,
    list: &NeighbourList,
    prm: &Params,
    half_dt: f64,
    isa: Isa,
) -> Forces {
    if prm.mirror_walls {
        forces_with::<SYMMETRIC, AV, true>(s, list, prm, half_dt, isa)
    } else {
        forces_with::<SYMMETRIC, AV, false>(s, list, prm, half_dt, isa)
    }
}

fn forces_with<const SYMMETRIC: bool, const AV: bool, const MIRROR: bool>(
    s: &mut State,
    list: &NeighbourList,
    prm: &Params,
    half_dt: f64,
    isa: Isa,
) -> Forces {
    let nf = s.n_fluid;
    let n = s.x.len();
    let (x, y, vpx, vpy) = (&s.x[..n], &s.y[..n], &s.vpx[..n], &s.vpy[..n]);
    let (rho, vol, depth) = (&s.rho[..n], &s.vol[..n], &s.depth[..n]);
    let pq = if SYMMETRIC {
        &s.p_rho2[..n]
    } else {
        &s.press[..n]
    };
    let inp = ForcesIn {
        x,
        y,
        vpx,
        vpy,
        rho,
        vol,
        depth,
        pq,
        pair_g: &s.pair_g,
        list,
        width: list.width(),
        prm,
        half_dt,
    };
    (
        s.ax.par_chunks_mut(CHUNK),
        s.ay.par_chunks_mut(CHUNK),
        s.vx[..nf].par_chunks_mut(CHUNK),
        s.vy[..nf].par_chunks_mut(CHUNK),
    )
        .into_par_iter()
        .enumerate()
        .map(|(c, out)| match isa {
            // SAFETY: Isa::detect found the CPU features.
            #[cfg(target_arch = "x86_64")]
            Isa::Avx512 => unsafe { forces_chunk_avx512::<SYMMETRIC, AV, MIRROR>(c, out, &inp) },
            #[cfg(target_arch = "x86_64")]
            Isa::Avx2 => unsafe { forces_chunk_avx2::<SYMMETRIC, AV, MIRROR>(c, out, &inp) },
            Isa::Base => forces_chunk::<SYMMETRIC, AV, MIRROR>(c, out, &inp),
        })
        .reduce(|| Forces::NONE, Forces::merge)
}

/// What every task of the force pass reads.
struct ForcesIn<'a> {
    x: &'a [f64],
    y: &'a [f64],
    vpx: &'a [f64],
    vpy: &'a [f64],
    rho: &'a [f64],
    vol: &'a [f64],
    depth: &'a [f64],
    /// P (paper form) or P / rho^2 (symmetric).
    pq: &'a [f64],
    pair_g: &'a [f64],
    list: &'a NeighbourList,
    width: f64,
    prm: &'a Params,
    half_dt: f64,
}

/// One task's outputs: ax, ay, vx, vy.
type ForcesOut<'a> = (&'a mut [f64], &'a mut [f64], &'a mut [f64], &'a mut [f64]);

/// [`forces_chunk`] for AVX-512: one call per task.
///
/// # Safety
/// The CPU must have AVX-512 F, DQ and VL ([`Isa::detect`]).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx512dq,avx512vl,avx2")]
unsafe fn forces_chunk_avx512<const SYMMETRIC: bool, const AV: bool, const MIRROR: bool>(
    c: usize,
    out: ForcesOut,
    inp: &ForcesIn,
) -> Forces {
    forces_chunk::<SYMMETRIC, AV, MIRROR>(c, out, inp)
}

/// [`forces_chunk`] for AVX2.
///
/// # Safety
/// The CPU must have AVX2 ([`Isa::detect`]).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn forces_chunk_avx2<const SYMMETRIC: bool, const AV: bool, const MIRROR: bool>(
    c: usize,
    out: ForcesOut,
    inp: &ForcesIn,
) -> Forces {
    forces_chunk::<SYMMETRIC, AV, MIRROR>(c, out, inp)
}

/// Accelerations and the closing kick for the fluid particles of task `c`.
#[inline(always)]
fn forces_chunk<const SYMMETRIC: bool, const AV: bool, const MIRROR: bool>(
    c: usize,
    out: ForcesOut,
    inp: &ForcesIn,
) -> Forces {
    let (ax, ay, vx, vy) = out;
    let prm = inp.prm;
    let scratch = &mut ([0.0; BLOCK], [0.0; BLOCK]);
    let mut seen = Forces::NONE;
    for k in 0..ax.len() {
        let i = c * CHUNK + k;
        let entries = inp.list.of_padded(i);
        let sources = inp.list.sources_padded(i);
        let inv_rho = 1.0 / inp.rho[i];
        let sc = Scales {
            pressure: if SYMMETRIC {
                prm.mass
            } else {
                prm.mass * inv_rho * inv_rho
            },
            av: prm.av * inv_rho,
            visc: prm.visc * inv_rho,
            // Capped by beta_max anyway: a particle at the plane is no
            // division by zero.
            inv_gap: 1.0 / (prm.b - inp.y[i].abs()).max(f64::MIN_POSITIVE),
            beta_max: prm.beta_max,
        };
        let args = (
            i,
            entries,
            (sources, inp.pair_g),
            (inp.x, inp.y),
            (inp.vpx, inp.vpy),
            inp.pq,
            (inp.vol, inp.depth),
            inp.width,
            sc,
        );
        let (fx, fy) = pair_forces::<AV, MIRROR>(args, scratch);
        let axi = prm.grad_scale * fx + prm.body;
        let ayi = prm.grad_scale * fy;
        ax[k] = axi;
        ay[k] = ayi;
        vx[k] += inp.half_dt * axi;
        vy[k] += inp.half_dt * ayi;
        let a2 = axi * axi + ayi * ayi;
        let v2 = vx[k] * vx[k] + vy[k] * vy[k];
        seen.finite &= (a2 + v2).is_finite();
        seen.a_max = seen.a_max.max(a2);
        seen.v_max = seen.v_max.max(v2);
    }
    seen.a_max = seen.a_max.sqrt();
    seen.v_max = seen.v_max.sqrt();
    seen
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kernels::Morris;

    /// The pair loops give the same bits whatever instructions they were
    /// compiled for: the vector builds only run the same operations in the
    /// same order in lanes.
    #[test]
    fn pair_loops_give_the_same_bits_on_every_isa() {
        let n = 200;
        let x: Vec<f64> = (0..n).map(|i| (i as f64 * 0.618).fract() * 7.0).collect();
        let y: Vec<f64> = (0..n).map(|i| (i as f64 * 0.377).fract() * 7.0).collect();
        let v: Vec<f64> = (0..n).map(|i| (i as f64 * 0.123).sin()).collect();
        let width = 7.0;
        // 37 neighbours (two whole blocks and a part) and padding.
        let mut entries: Vec<u32> = (1..38)
            .map(|j| Entry::pack(j * 5 % n, (j % 3) as i8 - 1))
            .collect();
        entries.resize(40, Entry::padding(0));
        let sc = Scales {
            pressure: 0.7,
            av: 0.3,
            visc: 0.2,
            inv_gap: 0.9,
            beta_max: 3.0,
        };
        // Where each slot's kernel values come from: a permutation of the
        // evaluated slots, and for the padding the zero slot after them.
        let sources: Vec<u32> = (0..entries.len() as u32)
            .map(|s| if s < 37 { (s * 7 + 3) % 37 } else { 40 })
            .collect();
        let run = |isa: Isa| {
            let mut w = vec![0.0; entries.len() + 1];
            let mut pg = vec![0.0; entries.len() + 1];
            let scratch = &mut ([0.0; BLOCK], [0.0; BLOCK]);
            let at = (x[0], y[0]);
            let xs = (&x[..], &y[..]);
            let out = (&mut w[..40], &mut pg[..40]);
            let w_sum = match isa {
                #[cfg(target_arch = "x86_64")]
                Isa::Avx512 => unsafe {
                    pair_kernel_avx512::<Morris>(at, &entries, xs, width, 0.5, out, scratch);
                    pair_gather_avx512(&sources, &w)
                },
                #[cfg(target_arch = "x86_64")]
                Isa::Avx2 => unsafe {
                    pair_kernel_avx2::<Morris>(at, &entries, xs, width, 0.5, out, scratch);
                    pair_gather_avx2(&sources, &w)
                },
                Isa::Base => {
                    pair_kernel::<Morris>(at, &entries, xs, width, 0.5, out, scratch);
                    pair_gather(&sources, &w)
                }
            };
            let args = (
                0,
                &entries[..],
                (&sources[..], &pg[..]),
                (&x[..], &y[..]),
                (&v[..], &v[..]),
                &v[..],
                (&x[..], &y[..]),
                width,
                sc,
            );
            let f = match isa {
                #[cfg(target_arch = "x86_64")]
                Isa::Avx512 => unsafe { pair_forces_avx512::<true, true>(args, scratch) },
                #[cfg(target_arch = "x86_64")]
                Isa::Avx2 => unsafe { pair_forces_avx2::<true, true>(args, scratch) },
                Isa::Base => pair_forces::<true, true>(args, scratch),
            };
            let mut bits: Vec<u64> = w.iter().chain(&pg).map(|v| v.to_bits()).collect();
            bits.extend([w_sum.to_bits(), f.0.to_bits(), f.1.to_bits()]);
            bits
        };
        let base = run(Isa::Base);
        assert!(
            f64::from_bits(base[base.len() - 3]) > 0.0,
            "some pairs are in reach"
        );
        let detected = Isa::detect();
        assert_eq!(run(detected), base, "{detected:?} against the base build");
        #[cfg(target_arch = "x86_64")]
        if detected == Isa::Avx512 {
            assert_eq!(run(Isa::Avx2), base, "AVX2 against the base build");
        }
    }
}
