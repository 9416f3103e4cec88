//! Density by summation (11) with the EOS: the kernel pass (W and
//! (dW/dq)/q once per pair) and the per-particle sums.

use rayon::prelude::*;

use super::isa::{lane_sum, Isa, Scratch, BLOCK};
use super::state::{Params, State};
use super::CHUNK;
use crate::kernel::Kernel;
use crate::solver::neighbours::{padded, Entry, NeighbourList, LANES};

/// Floating-point operations of the density pass, the kernel's (W,
/// (dW/dq)/q) aside: per pair evaluated (once for both directions), dx with
/// its image, dy (3) and q^2 (4); per directed pair, the sum of W (1).
pub(crate) const DENSITY_DISTANCE_FLOPS: u32 = 7;
pub(crate) const DENSITY_SUM_FLOPS: u32 = 1;

/// W and (dW/dq)/q of each of the entries of the particle at `at` into
/// `out` (W, g), with its neighbours' positions `xs`. Two loops without
/// branches or bounds checks, so that they vectorise: distances (a gather)
/// and the kernel (all pieces, then a select). Element by element: the
/// results do not depend on how the loops are compiled.
#[inline(always)]
pub(super) fn pair_kernel<K: Kernel>(
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

/// Sum of W over a particle's padded slots, taken from the slots `sources`
/// name ([`NeighbourList::sources_padded`]), in LANES accumulators (a fixed
/// order: the result does not depend on how the loop is compiled).
#[inline(always)]
pub(super) fn pair_gather(sources: &[u32], pair_w: &[f64]) -> f64 {
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
/// every slot kept for [`super::forces::forces`].
pub(crate) fn density<K: Kernel>(s: &mut State, list: &NeighbourList, prm: &Params) -> f64 {
    density_with::<K>(s, list, prm, Isa::detect())
}

pub(super) fn density_with<K: Kernel>(
    s: &mut State,
    list: &NeighbourList,
    prm: &Params,
    isa: Isa,
) -> f64 {
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
        .for_each(|(c, out)| kernel_chunk_on::<K>(isa, c, out, &inp));
    let pair_w = &s.pair_w[..];
    (
        s.rho.par_chunks_mut(CHUNK),
        s.press.par_chunks_mut(CHUNK),
        s.vol.par_chunks_mut(CHUNK),
        s.p_rho2.par_chunks_mut(CHUNK),
    )
        .into_par_iter()
        .enumerate()
        .map(|(c, out)| density_chunk_on::<K>(isa, c, out, &inp, pair_w))
        .reduce(|| f64::NEG_INFINITY, f64::max)
}

/// What every task of the density pass reads.
pub(super) struct DensityIn<'a> {
    x: &'a [f64],
    y: &'a [f64],
    list: &'a NeighbourList,
    width: f64,
    prm: &'a Params,
    nf: usize,
    stride: usize,
}

/// One task's outputs of the kernel pass: the W and (dW/dq)/q slots.
pub(super) type KernelOut<'a> = (&'a mut [f64], &'a mut [f64]);

/// W and (dW/dq)/q of the own entries of the particles of task `c`, in
/// whole groups of LANES: the few entries past the own ones that this
/// takes are evaluated too (their slots are never read), rather than left
/// to a scalar remainder.
#[inline(always)]
pub(super) fn kernel_chunk<K: Kernel>(c: usize, out: KernelOut, inp: &DensityIn) {
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
pub(super) type DensityOut<'a> = (&'a mut [f64], &'a mut [f64], &'a mut [f64], &'a mut [f64]);

/// Density and EOS for the particles of task `c`, from the kernel pass's
/// `pair_w`; returns their largest fluid compaction.
#[inline(always)]
pub(super) fn density_chunk<K: Kernel>(
    c: usize,
    out: DensityOut,
    inp: &DensityIn,
    pair_w: &[f64],
) -> f64 {
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

on_isa! {
    /// [`kernel_chunk`] compiled for the instruction set `isa`.
    pub(super) fn kernel_chunk_on[K: Kernel] => kernel_chunk[K](c: usize, out: KernelOut, inp: &DensityIn)
}

on_isa! {
    /// [`density_chunk`] compiled for the instruction set `isa`.
    pub(super) fn density_chunk_on[K: Kernel] => density_chunk[K](
        c: usize,
        out: DensityOut,
        inp: &DensityIn,
        pair_w: &[f64]
    ) -> f64
}

on_isa! {
    /// [`pair_kernel`] alone, for the test that compares instruction sets.
    #[cfg(test)]
    #[allow(clippy::too_many_arguments)]
    pub(super) fn pair_kernel_on[K: Kernel] => pair_kernel[K](
        at: (f64, f64),
        entries: &[u32],
        xs: (&[f64], &[f64]),
        width: f64,
        inv_h2: f64,
        out: (&mut [f64], &mut [f64]),
        scratch: &mut Scratch
    )
}

on_isa! {
    /// [`pair_gather`] alone, for the test that compares instruction sets.
    #[cfg(test)]
    pub(super) fn pair_gather_on[] => pair_gather[](sources: &[u32], pair_w: &[f64]) -> f64
}
