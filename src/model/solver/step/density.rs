//! Density by summation (11) with the EOS: the kernel pass (W and
//! (dW/dq)/q once per pair) and the per-particle sums.

use std::sync::atomic::{AtomicU64, Ordering};

use rayon::prelude::*;

use super::isa::{lane_sum, Isa, Scratch, BLOCK};
use super::state::{Params, State};
use super::CHUNK;
use crate::kernel::Kernel;
use crate::solver::neighbours::{Entry, NeighbourList, LANES};

/// Floating-point operations of the density pass, the kernel's (W,
/// (dW/dq)/q) aside: per pair evaluated (once for both directions), dx with
/// its image, dy (3) and q^2 (4); per directed pair, the sum of W (1).
pub(crate) const DENSITY_DISTANCE_FLOPS: u32 = 7;
pub(crate) const DENSITY_SUM_FLOPS: u32 = 1;

/// W and (dW/dq)/q of a piece of the pair table's stream
/// ([`NeighbourList::own_stream`]): `entries` and the particles `owners`
/// whose lists they are in, into `out` (W, g), with the positions `xs`.
/// Two loops without branches or bounds checks, so that they vectorise:
/// distances (gathers of both ends) and the kernel (all pieces, then a
/// select). Element by element, x_i - x_j + offset as ever: the results do
/// not depend on how the loops are compiled nor on how the stream is cut.
#[inline(always)]
pub(super) fn pair_kernel<K: Kernel>(
    entries: &[u32],
    owners: &[u32],
    xs: (&[f64], &[f64]),
    width: f64,
    inv_h2: f64,
    out: (&mut [f64], &mut [f64]),
    scratch: &mut Scratch,
) {
    let ((x, y), (w_out, g_out)) = (xs, out);
    let n = x.len();
    assert!(n > 0 && y.len() == n);
    assert!(owners.len() == entries.len() && w_out.len() == entries.len());
    // Every index is clamped into the arrays: no bounds check (an index
    // is below n by construction of the list anyway).
    let last = n - 1;
    let last32 = u32::try_from(last).unwrap_or(u32::MAX);
    let q2 = &mut scratch.0;
    for (((block, own_block), w_block), g_block) in entries
        .chunks(BLOCK)
        .zip(owners.chunks(BLOCK))
        .zip(w_out.chunks_mut(BLOCK))
        .zip(g_out.chunks_mut(BLOCK))
    {
        let m = block.len();
        for ((q2, &e), &o) in q2[..m].iter_mut().zip(block).zip(own_block) {
            let j = Entry::index_below(e, last);
            let i = o.min(last32) as usize;
            let dx = x[i] - x[j] + Entry::offset(e, width);
            let dy = y[i] - y[j];
            *q2 = (dx * dx + dy * dy) * inv_h2;
        }
        for ((&q2, w), g) in q2[..m].iter().zip(w_block).zip(g_block) {
            (*w, *g) = K::w_dw_over_q_lanes(q2);
        }
    }
}

/// Sum of W over a particle's padded slots, taken from the slots `sources`
/// name ([`NeighbourList::sources_padded`]), in LANES accumulators (a fixed
/// order: the result does not depend on how the loop is compiled). `run`
/// = (first, whole): the first `whole` groups of LANES slots name the
/// consecutive places from `first` (a particle's own entries, from
/// [`NeighbourList::own_start`]), loaded as contiguous vectors instead of
/// gathered: the same values in the same order, the same bits.
#[inline(always)]
pub(super) fn pair_gather(sources: &[u32], run: (usize, usize), pair_w: &[f64]) -> f64 {
    let n = pair_w.len();
    assert!(n > 0);
    // Clamped in 32 bits, as the force pass's: a vector gather.
    let last = u32::try_from(n - 1).expect("slots fit in u32");
    let mut acc = [0.0; LANES];
    let (first, whole) = run;
    let direct = &pair_w[first..first + whole * LANES];
    for w in direct.chunks_exact(LANES) {
        for l in 0..LANES {
            acc[l] += w[l];
        }
    }
    for src in sources[whole * LANES..].chunks_exact(LANES) {
        for l in 0..LANES {
            acc[l] += pair_w[src[l].min(last) as usize];
        }
    }
    lane_sum(acc)
}

/// Density by summation (11) over fluid and wall neighbours, self included,
/// then the EOS. Returns the largest compaction eps = rho/rho0 - 1 of the
/// fluid. Two passes: the kernel, W and (dW/dq)/q from one fused
/// evaluation, once per pair, on the lists' own entries
/// ([`NeighbourList::own`]) streamed in equal pieces without padding
/// ([`NeighbourList::own_stream`]); then per particle the sum of W over all its
/// slots, each taken from where it was evaluated. The (dW/dq)/q of every
/// pair is kept for [`super::forces::forces`] beside W in the pair table
/// (one evaluation: the solver's steps pick their form by its cost,
/// [`GForm`]).
pub(crate) fn density<K: Kernel>(s: &mut State, list: &NeighbourList, params: &Params) -> f64 {
    let isa = Isa::detect();
    kernel_pass::<K>(s, list, params, isa, GForm::Gather);
    density_sums::<K>(s, list, params, isa)
}

/// Where the kernel pass leaves each pair's (dW/dq)/q for the force pass:
/// in both window lanes that list it (a window's eight then load as one
/// vector), or beside W in the pair table (the force pass gathers a
/// window's eight through its sources, [`NeighbourList::window_sources`]).
/// The same value reaches the same lane either way: the same bits. The
/// lanes are the quicker form while their table stays in a cache near the
/// core, and the stores into it cost less than the gathers; which is, is
/// the machine's (the solver picks by cost, `Sim::g_pick`). A list whose
/// table would exceed [`crate::solver::neighbours::LANE_TABLE_MAX_BYTES`]
/// has no lanes ([`NeighbourList::lane_table`]) and takes the gather.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum GForm {
    Lanes,
    Gather,
}

impl GForm {
    /// Its name in `bench`'s table: "lanes" or "pairs".
    pub(crate) fn name(self) -> &'static str {
        match self {
            GForm::Lanes => "lanes",
            GForm::Gather => "pairs",
        }
    }
}

/// The first half of [`density`], timed apart by the solver: W of every
/// own pair into the pair table, its (dW/dq)/q where `form` says (the
/// pair table where the list has no lane table); compiled for `isa`.
pub(crate) fn kernel_pass<K: Kernel>(
    s: &mut State,
    list: &NeighbourList,
    params: &Params,
    isa: Isa,
    form: GForm,
) {
    // The pair table and after it a place kept at zero that padding reads:
    // resized when a rebuild changed the number of own pairs.
    let pairs = list.own_pairs();
    if s.pair_slots != pairs {
        s.pair_slots = pairs;
        s.pair_w.resize(pairs + 1, 0.0);
        s.pair_w[pairs] = 0.0;
    }
    let n = s.x.len();
    let input = DensityIn::new((&s.x[..n], &s.y[..n]), s.n_fluid, list, params);
    let (entries, owners) = list.own_stream();
    if form == GForm::Gather || !list.lane_table() {
        // (dW/dq)/q beside W in the pair table, for the force pass to
        // gather.
        if s.pair_g.len() != pairs + 1 {
            s.pair_g.clear();
            s.pair_g.resize(pairs + 1, 0.0);
        }
        s.g_written = (list.generation(), GForm::Gather);
        (
            s.pair_w[..pairs].par_chunks_mut(STREAM_CHUNK),
            s.pair_g[..pairs].par_chunks_mut(STREAM_CHUNK),
            entries.par_chunks(STREAM_CHUNK),
            owners.par_chunks(STREAM_CHUNK),
        )
            .into_par_iter()
            .for_each(|(w, g, e, o)| pair_table_chunk_on::<K>(isa, (w, g), e, o, &input));
        return;
    }
    // The window-lane table, zeroed for each new list: a lane not listed is
    // never written and stays 0.
    if s.lane_generation != list.generation() {
        s.lane_g.clear();
        s.lane_g.resize(list.window_count() * LANES, 0.0);
        s.lane_generation = list.generation();
    }
    s.g_written = (list.generation(), GForm::Lanes);
    let lane_g = as_atomic(&mut s.lane_g);
    let lanes = list.lanes_of_pairs();
    (
        s.pair_w[..pairs].par_chunks_mut(STREAM_CHUNK),
        entries.par_chunks(STREAM_CHUNK),
        owners.par_chunks(STREAM_CHUNK),
        lanes.par_chunks(2 * STREAM_CHUNK),
    )
        .into_par_iter()
        .for_each(|(w, e, o, l)| kernel_chunk_on::<K>(isa, (w, lane_g), e, o, l, &input));
}

/// `v` as atomics, which tasks running at once may store into (each of the
/// kernel pass's lanes is written by one pair, but which pair writes where
/// is data, not something the borrow checker can split). A relaxed store
/// of an `AtomicU64` is a plain store on x86-64 and the other 64-bit
/// targets. The same cast as the standard library's unstable
/// `AtomicU64::from_mut_slice`.
fn as_atomic(v: &mut [f64]) -> &[AtomicU64] {
    const {
        assert!(size_of::<AtomicU64>() == size_of::<f64>());
        assert!(align_of::<AtomicU64>() == align_of::<f64>());
    }
    // SAFETY: AtomicU64 has the size and alignment of f64 (checked above)
    // and the in-memory representation of u64, whose every bit pattern is
    // an f64's; `v` stays borrowed exclusively for as long as the view
    // lives, so nothing else reads or writes it meanwhile.
    unsafe { &*(v as *mut [f64] as *const [AtomicU64]) }
}

/// The second half of [`density`]: the sums of W from the pair table and
/// the EOS, compiled for `isa`; the largest fluid compaction.
pub(crate) fn density_sums<K: Kernel>(
    s: &mut State,
    list: &NeighbourList,
    params: &Params,
    isa: Isa,
) -> f64 {
    let n = s.x.len();
    assert_eq!(
        s.pair_slots,
        list.own_pairs(),
        "the kernel pass ran on this list"
    );
    let input = DensityIn::new((&s.x[..n], &s.y[..n]), s.n_fluid, list, params);
    let pair_w = &s.pair_w[..];
    (
        s.rho.par_chunks_mut(CHUNK),
        s.press.par_chunks_mut(CHUNK),
        s.vol.par_chunks_mut(CHUNK),
        s.p_rho2.par_chunks_mut(CHUNK),
    )
        .into_par_iter()
        .enumerate()
        .map(|(c, out)| density_chunk_on::<K>(isa, c, out, &input, pair_w))
        .reduce(|| f64::NEG_INFINITY, f64::max)
}

/// What every task of the density pass reads.
pub(super) struct DensityIn<'a> {
    x: &'a [f64],
    y: &'a [f64],
    list: &'a NeighbourList,
    width: f64,
    params: &'a Params,
    nf: usize,
}

impl<'a> DensityIn<'a> {
    /// From the positions `xs` (every particle's), the fluid's count `nf`.
    fn new(
        xs: (&'a [f64], &'a [f64]),
        nf: usize,
        list: &'a NeighbourList,
        params: &'a Params,
    ) -> DensityIn<'a> {
        DensityIn {
            x: xs.0,
            y: xs.1,
            list,
            width: list.width(),
            params,
            nf,
        }
    }
}

/// Pairs per task of the kernel pass: whole blocks, 2048 pairs (about a
/// hundred particles' own pairs at R = 3 h).
const STREAM_CHUNK: usize = 16 * BLOCK;

/// One task's outputs of the kernel pass: its W slots, and the window-lane
/// table of (dW/dq)/q ([`NeighbourList::lanes_of_pairs`]).
pub(super) type KernelOut<'a> = (&'a mut [f64], &'a [AtomicU64]);

/// W and (dW/dq)/q of one piece of the pair table's stream, block by
/// block: W into the pair table, (dW/dq)/q into both window lanes that list
/// each pair (`lane_of`, two per pair: scattered stores, where the force
/// pass would otherwise gather each window's eight values).
#[inline(always)]
pub(super) fn kernel_chunk<K: Kernel>(
    out: KernelOut,
    entries: &[u32],
    owners: &[u32],
    lane_of: &[u32],
    input: &DensityIn,
) {
    let (w_out, lane_g) = out;
    assert!(lane_of.len() == 2 * entries.len() && !lane_g.is_empty());
    // Clamped into the table: no bounds check (a lane is in it by
    // construction of the list anyway).
    let last = lane_g.len() - 1;
    let scratch = &mut ([0.0; BLOCK], [0.0; BLOCK]);
    let mut g = [0.0; BLOCK];
    for (((e, o), w), d) in entries
        .chunks(BLOCK)
        .zip(owners.chunks(BLOCK))
        .zip(w_out.chunks_mut(BLOCK))
        .zip(lane_of.chunks(2 * BLOCK))
    {
        let m = e.len();
        pair_kernel::<K>(
            e,
            o,
            (input.x, input.y),
            input.width,
            input.params.inv_h2,
            (w, &mut g[..m]),
            scratch,
        );
        for (&g, d) in g[..m].iter().zip(d.chunks_exact(2)) {
            for &lane in d {
                lane_g[(lane as usize).min(last)].store(g.to_bits(), Ordering::Relaxed);
            }
        }
    }
}

/// W and (dW/dq)/q of one piece of the pair table's stream into the pair
/// table's places, for a list without a lane table (the force pass gathers
/// (dW/dq)/q, [`NeighbourList::lane_table`]).
#[inline(always)]
pub(super) fn pair_table_chunk<K: Kernel>(
    out: (&mut [f64], &mut [f64]),
    entries: &[u32],
    owners: &[u32],
    input: &DensityIn,
) {
    pair_kernel::<K>(
        entries,
        owners,
        (input.x, input.y),
        input.width,
        input.params.inv_h2,
        out,
        &mut ([0.0; BLOCK], [0.0; BLOCK]),
    );
}

/// One task's outputs: rho, P, m/rho, P/rho^2.
pub(super) type DensityOut<'a> = (&'a mut [f64], &'a mut [f64], &'a mut [f64], &'a mut [f64]);

/// Density and EOS for the particles of task `c`, from the kernel pass's
/// `pair_w`; returns their largest fluid compaction. Two loops over the
/// task's particles: the sums, then the EOS (its divisions in lanes, the
/// EOS's form chosen once for the loop, not per particle: a branch the
/// compiler would otherwise turn into a power for every lane), each
/// particle's operations as one loop doing both would do them.
#[inline(always)]
pub(super) fn density_chunk<K: Kernel>(
    c: usize,
    out: DensityOut,
    input: &DensityIn,
    pair_w: &[f64],
) -> f64 {
    let (rho, press, vol, p_rho2) = out;
    let params = input.params;
    let w_self = K::w(0.0);
    let base = c * CHUNK;
    let m = rho.len();
    assert!(press.len() == m && vol.len() == m && p_rho2.len() == m);
    for (k, r) in rho.iter_mut().enumerate() {
        let i = base + k;
        let run = (input.list.own_start(i), input.list.own(i) / LANES);
        let pairs = pair_gather(input.list.sources_padded(i), run, pair_w);
        let sum = w_self + pairs;
        *r = params.mass_over_h2 * sum;
    }
    if params.gamma == 1.0 {
        eos(params, rho, (press, vol, p_rho2), |ratio| ratio - 1.0);
    } else {
        eos(params, rho, (press, vol, p_rho2), |ratio| {
            ratio.powf(params.gamma) - 1.0
        });
    }
    let fluid = input.nf.saturating_sub(base).min(m);
    rho[..fluid]
        .iter()
        .fold(f64::NEG_INFINITY, |e, &r| e.max(r / params.rho0 - 1.0))
}

/// The EOS (13) over a task's densities: P, m/rho and P/rho^2, with the
/// compression (rho/rho0)^gamma minus 1 from `compression`.
#[inline(always)]
fn eos(
    params: &Params,
    rho: &[f64],
    (press, vol, p_rho2): (&mut [f64], &mut [f64], &mut [f64]),
    compression: impl Fn(f64) -> f64,
) {
    for (((&r, p_out), v), q) in rho.iter().zip(press).zip(vol).zip(p_rho2) {
        let p = params.pressure_of(compression(r / params.rho0));
        *p_out = p;
        *v = params.mass / r;
        *q = p / (r * r);
    }
}

on_isa! {
    /// [`pair_table_chunk`] compiled for the instruction set `isa`.
    pub(super) fn pair_table_chunk_on[K: Kernel] => pair_table_chunk[K](
        out: (&mut [f64], &mut [f64]),
        entries: &[u32],
        owners: &[u32],
        input: &DensityIn
    )
}

on_isa! {
    /// [`kernel_chunk`] compiled for the instruction set `isa`.
    pub(super) fn kernel_chunk_on[K: Kernel] => kernel_chunk[K](
        out: KernelOut,
        entries: &[u32],
        owners: &[u32],
        lane_of: &[u32],
        input: &DensityIn
    )
}

on_isa! {
    /// [`density_chunk`] compiled for the instruction set `isa`.
    pub(super) fn density_chunk_on[K: Kernel] => density_chunk[K](
        c: usize,
        out: DensityOut,
        input: &DensityIn,
        pair_w: &[f64]
    ) -> f64
}

/// W and (dW/dq)/q of every `q2` into `out`: the kernel's arithmetic
/// alone, as the kernel pass runs it in lanes but without the pair table.
#[inline(always)]
pub(super) fn kernel_only<K: Kernel>(q2: &[f64], out: (&mut [f64], &mut [f64])) {
    for ((&q2, w), g) in q2.iter().zip(out.0.iter_mut()).zip(out.1.iter_mut()) {
        (*w, *g) = K::w_dw_over_q_lanes(q2);
    }
}

on_isa! {
    /// [`kernel_only`] compiled for the instruction set `isa`.
    pub(super) fn kernel_only_on[K: Kernel] => kernel_only[K](
        q2: &[f64],
        out: (&mut [f64], &mut [f64])
    )
}

/// Nanoseconds per evaluation of the kernel alone on one core: the
/// kernel pass's compute roof. Every piece's constants are selected in
/// lanes, so the cost does not depend on q; the values run over the support
/// as pairs do (q^2 uniform in [0, R^2], as the area is), 1024 of them and
/// their results in the first-level cache. The best of 5 timings of a
/// loop of about 5 ms.
pub(crate) fn kernel_alone_ns<K: Kernel>() -> f64 {
    const N: usize = 1024;
    let isa = Isa::detect();
    let q2: Vec<f64> = (0..N)
        .map(|k| (k as f64 + 0.5) / N as f64 * K::SUPPORT2_CLOSED)
        .collect();
    let (mut w, mut g) = (vec![0.0; N], vec![0.0; N]);
    let mut time = |rounds: usize| {
        let start = std::time::Instant::now();
        for _ in 0..rounds {
            kernel_only_on::<K>(isa, std::hint::black_box(&q2[..]), (&mut w[..], &mut g[..]));
            std::hint::black_box((&w, &g));
        }
        start.elapsed().as_secs_f64()
    };
    // Rounds for about 5 ms, from a first timing of 16.
    let first = time(16).max(1e-9);
    let rounds = ((5e-3 / first * 16.0) as usize).clamp(16, 1 << 20);
    let best = (0..5).map(|_| time(rounds)).fold(f64::INFINITY, f64::min);
    best / (rounds * N) as f64 * 1e9
}

on_isa! {
    /// [`pair_kernel`] alone, for the test that compares instruction sets.
    #[cfg(test)]
    #[allow(clippy::too_many_arguments)]
    pub(super) fn pair_kernel_on[K: Kernel] => pair_kernel[K](
        entries: &[u32],
        owners: &[u32],
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
    pub(super) fn pair_gather_on[] => pair_gather[](
        sources: &[u32],
        run: (usize, usize),
        pair_w: &[f64]
    ) -> f64
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kernels::Morris;
    use crate::solver::step::isa::every_isa;

    /// The kernel pass's pieces write each pair's (dW/dq)/q into both its
    /// window lanes, the value the pair loop computes for the pair, and
    /// nothing else, on every instruction set; W as the pair loop does.
    #[test]
    fn each_pairs_gradient_goes_to_both_its_lanes() {
        let n = 50;
        let x: Vec<f64> = (0..n).map(|i| (i as f64 * 0.618).fract() * 4.0).collect();
        let y: Vec<f64> = (0..n).map(|i| (i as f64 * 0.377).fract() * 4.0).collect();
        // Two blocks and a part of pairs, their lanes a permutation of the
        // first 2m of a table of 2m + 20, so 20 lanes are never written.
        let m = 2 * BLOCK + 22;
        let table_len = 2 * m + 20;
        let entries: Vec<u32> = (0..m)
            .map(|p| Entry::pack((p * 7 + 3) % n, (p % 3) as i8 - 1))
            .collect();
        let owners: Vec<u32> = (0..m as u32).map(|p| p % n as u32).collect();
        // 37 shares no factor with 2m = 4 (BLOCK + 11): a permutation.
        let lane_of: Vec<u32> = (0..2 * m as u32)
            .map(|k| (k * 37 + 5) % (2 * m as u32))
            .collect();
        // Only inv_h2 matters to the kernel pass.
        let params = Params {
            inv_h2: 0.5,
            mass_over_h2: 1.0,
            mass: 1.0,
            rho0: 1.0,
            b_eos: 1.0,
            gamma: 1.0,
            allow_negative: false,
            symmetric: false,
            grad_scale: 1.0,
            av: 0.0,
            has_av: false,
            visc: 1.0,
            body: 0.0,
            mirror_walls: false,
            b: 1.0,
            beta_max: 1.0,
        };
        let list = NeighbourList::default();
        let input = DensityIn {
            x: &x,
            y: &y,
            list: &list,
            width: 4.0,
            params: &params,
            nf: n,
        };
        let isas = every_isa();
        let (mut w_want, mut g_want) = (vec![0.0; m], vec![0.0; m]);
        let scratch = &mut ([0.0; BLOCK], [0.0; BLOCK]);
        let xs = (&x[..], &y[..]);
        let out = (&mut w_want[..], &mut g_want[..]);
        pair_kernel_on::<Morris>(Isa::Base, &entries, &owners, xs, 4.0, 0.5, out, scratch);
        assert!(
            g_want.iter().filter(|&&g| g != 0.0).count() > 20,
            "pairs in reach"
        );
        for isa in isas {
            let mut w = vec![0.0; m];
            let mut table = vec![0.0; table_len];
            kernel_chunk_on::<Morris>(
                isa,
                (&mut w, as_atomic(&mut table)),
                &entries,
                &owners,
                &lane_of,
                &input,
            );
            let bits = |v: &[f64]| v.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&w), bits(&w_want), "{isa:?}");
            let mut want = vec![0.0; table_len];
            for (p, &g) in g_want.iter().enumerate() {
                want[lane_of[2 * p] as usize] = g;
                want[lane_of[2 * p + 1] as usize] = g;
            }
            assert_eq!(bits(&table), bits(&want), "{isa:?}");
        }
    }

    /// The slots of a particle's first groups name consecutive places in
    /// the pair table (its own entries): [`pair_gather`] loads those as
    /// contiguous vectors, the same bits as gathering them, on every
    /// instruction set.
    #[test]
    fn consecutive_places_load_as_the_gather_would() {
        // 37 slots, the first 19 consecutive from 5, then others, then
        // padding at the zero place 60.
        let w: Vec<f64> = (0..61)
            .map(|s| {
                if s < 60 {
                    (s as f64 * 0.731).sin() * 1e-3
                } else {
                    0.0
                }
            })
            .collect();
        let sources: Vec<u32> = (0..40u32)
            .map(|s| match s {
                0..19 => 5 + s,
                19..37 => (s * 11) % 60,
                _ => 60,
            })
            .collect();
        let isas = every_isa();
        let gathered = pair_gather_on(Isa::Base, &sources, (0, 0), &w).to_bits();
        for isa in isas {
            for whole in 0..=2 {
                let got = pair_gather_on(isa, &sources, (5, whole), &w);
                assert_eq!(got.to_bits(), gathered, "{isa:?}, {whole} groups");
            }
        }
        // A run that is not the slots' places changes the sum.
        let wrong = pair_gather_on(Isa::Base, &sources, (6, 1), &w);
        assert_ne!(wrong.to_bits(), gathered);
    }
}
