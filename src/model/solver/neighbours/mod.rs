//! Verlet neighbour list for the periodic strip: every pair within R h +
//! skin at the last rebuild, with the periodic image it was found through.
//!
//! Layout: a padded table, `stride` slots per particle and a count, so each
//! particle's list is one contiguous slice, filled in parallel without
//! sharing. A slot is one u32: the neighbour's index and, in the top two
//! bits, the periodic image it was found through ([`Entry`]); 4 bytes per
//! listed pair. Order within a list is fixed (by distance at the rebuild, ties
//! by particle index and image), so every sum over it is the same whatever
//! the thread count. For the force pass, each list is also cut into
//! [`Window`]s, runs of LANES consecutive indices (each lane with its own
//! image): the lattice keeps its rows in index order (and the solver keeps a
//! disordered fluid's bands of y so, `State::reorder`), so a neighbour row
//! is one or two windows, loaded as contiguous vectors instead of gathered;
//! each pair's (dW/dq)/q is written where both its window lanes read it
//! ([`NeighbourList::lanes_of_pairs`]).
//!
//! Rebuild rule: a pair not in the list was more than R h + skin apart; it
//! can only have come within R h if the two displacements since the rebuild
//! differ by more than `skin`. Particles are grouped in blocks (the lattice
//! layers they started in or, once the order is lost, the bands of y the
//! solver stored them in at the rebuild: `State::reorder`), and each
//! block's displacements since the rebuild are bounded by a box. Two displacements differ by at most the diagonal of
//! the union of their blocks' boxes; only blocks that were within R h + skin
//! of each other in y at the rebuild need that check, provided no two
//! transverse displacements differ by more than `skin` either. In shear the
//! whole fluid's box grows as U t, but that of neighbouring layers only as
//! (dU/dy) (R h) t, so the list lives about B / (R h) times longer than with
//! one box for all. A disordered fluid's boxes bound the displacements from
//! a shear reference instead (x0 + u(y0) t, u the bands' profile at the
//! rebuild), against a slack that allows for how far that reference can
//! bring a pair nearer ([`Reach`]): the shear between near layers no longer
//! spends the skin by itself.

use std::sync::atomic::{AtomicU64, Ordering};

use rayon::prelude::*;

/// The largest window-lane table ([`NeighbourList::lane_table`]), 8 bytes
/// a lane and LANES lanes a window. Beyond it the table (written by two
/// scattered stores a pair in the kernel pass, read back in the force
/// pass) leaves the caches, and the force pass always gathers each
/// window's (dW/dq)/q from the pair table, which moves fewer bytes; below
/// it the solver picks the quicker of the two by their cost
/// (`step::GForm`). Both forms side by side on `bench --disordered` (1
/// thread, 2 alternating rounds on the 2-core AMD EPYC with 32 MB of
/// last-level cache, bench/peers/results/2026-12-05-force-pass-gather/):
/// the gather 0.86-0.94 times as fast at 1e3-1e4 particles, 1.03-1.06 at
/// 3e4, 1.05-1.08 at 5e4 (Monaghan's table there about 3, 9 and 15 MB;
/// the composite kernel's tables are smaller). On a 2-core Xeon with 2 MB
/// of second-level cache a core the gather ran 0.99-1.27 times as fast
/// at 1e3-3e4: the pick, not this bound, takes it there.
pub const LANE_TABLE_MAX_BYTES: usize = 8 << 20;

/// Particles per parallel task when building.
const BUILD_CHUNK: usize = 64;

#[derive(Debug, Default)]
pub struct NeighbourList {
    stride: usize,
    count: Vec<u32>,
    entries: Vec<u32>,
    /// Of each list, how many entries come first as the particle's own
    /// ([`Self::own`]): the pairs whose kernel it evaluates.
    own: Vec<u32>,
    /// For every slot, where its pair's kernel values are in the pair table
    /// (see [`Self::sources_padded`]).
    source: Vec<u32>,
    /// The pair table: every list's own entries, one stream without padding
    /// ([`Self::own_stream`]); particle i's start at `own_start[i]`, and
    /// the particle each belongs to.
    own_start: Vec<u32>,
    own_entries: Vec<u32>,
    own_owner: Vec<u32>,
    /// Every list again as windows ([`Window`]), for the force pass:
    /// particle i's are `windows[win_start[i]..win_start[i + 1]]`.
    win_start: Vec<u32>,
    windows: Vec<Window>,
    /// Each window's lanes' places in the pair table (the zero place for a
    /// lane not listed): `win_sources[w]` for `windows[w]`.
    win_sources: Vec<[u32; LANES]>,
    /// For each own pair (the pair table's place s), the two window lanes
    /// that list it, as LANES w + l: `lane_of[2 s]` and `lane_of[2 s + 1]`
    /// (empty when the list has no lane table, [`Self::lane_table`]).
    lane_of: Vec<u32>,
    /// Whether the force pass reads (dW/dq)/q from a window-lane table
    /// ([`Self::lane_table`]), and the largest table it may have (none
    /// set: [`LANE_TABLE_MAX_BYTES`]).
    lane_table: bool,
    lane_table_max: Option<usize>,
    /// Whether the next builds are of a disordered fluid
    /// ([`Self::set_disordered`]), and the form this build takes: without
    /// branches on the distances or with them ([`Forms`]).
    disordered: bool,
    branch_free: bool,
    forms: Forms,
    /// This build's number, unique among all lists' builds in the process
    /// ([`Self::generation`]).
    generation: u64,
    /// The strip's width: the images' offsets ([`Entry::offset`]).
    width: f64,
    /// Cell list ([`Grid`]): particle indices sorted by cell, and where
    /// each cell starts.
    bin_start: Vec<u32>,
    bin_items: Vec<u32>,
    /// The binned particles' positions, in the bins' order.
    bin_x: Vec<f64>,
    bin_y: Vec<f64>,
    /// For each block a, the blocks b > a within the cutoff of it in y at the
    /// rebuild: `near[near_start[a]..near_start[a + 1]]`.
    near_start: Vec<u32>,
    near: Vec<u32>,
    pub rebuilds: u64,
    /// The particles' blocks' size at the last build ([`Self::build`]).
    block: usize,
}

/// The cost of a disordered fluid's build in each form, measured, and the
/// choice between them: the form without branches on the distances first,
/// then the other once, then the cheaper of the two, the other again
/// every [`Forms::RETRY`] builds (a fluid's structure changes as it runs).
/// Both forms give the same list, so the choice changes no result, only
/// the time.
#[derive(Debug, Default)]
struct Forms {
    /// ns a particle a build, with branches and without: a running mean
    /// that halves the weight of the older builds at each new one.
    cost: [Option<f64>; 2],
    since_retry: u32,
}

impl Forms {
    const RETRY: u32 = 16;

    /// Whether the next build goes without branches on the distances.
    fn pick(&mut self) -> bool {
        match self.cost {
            [_, None] => true,
            [None, _] => false,
            [Some(with), Some(without)] => {
                let cheaper = without <= with;
                self.since_retry += 1;
                if self.since_retry >= Self::RETRY {
                    self.since_retry = 0;
                    !cheaper
                } else {
                    cheaper
                }
            }
        }
    }

    fn record(&mut self, branch_free: bool, ns: f64) {
        let cost = &mut self.cost[usize::from(branch_free)];
        *cost = Some(cost.map_or(ns, |old| 0.5 * (old + ns)));
    }
}

/// A build task's room for one list. In the lattice's form, the kept
/// candidates' keys ([`list_key`]), own first; in a disordered fluid's,
/// every candidate (as an entry) and its r^2, then each part's keys as
/// two fields for [`entry::ranks`] (r^2, and the index and image as
/// [`tie`] gives them) and their places.
#[derive(Default)]
struct Scratch {
    found: Vec<u32>,
    r2: Vec<f64>,
    keys: Vec<u128>,
    own: (Vec<f64>, Vec<f64>),
    mirrored: (Vec<f64>, Vec<f64>),
    places: Vec<u32>,
}

impl Scratch {
    /// At least `room` of each, and the ranked keys' run to whole LANES.
    fn make_room(&mut self, room: usize) {
        let ranked = padded(room);
        if self.found.len() < room {
            self.found.resize(room, 0);
            self.r2.resize(room, 0.0);
        }
        if self.places.len() < ranked {
            self.places.resize(ranked, 0);
        }
        for part in [&mut self.own, &mut self.mirrored] {
            if part.0.len() < ranked {
                part.0.resize(ranked, 0.0);
                part.1.resize(ranked, 0.0);
            }
        }
    }
}

/// Each binned candidate j's r^2 from (xi, yi) through its nearest image
/// (x_i - x_j + offset, as every pair loop computes it) and its entry: in
/// lanes, from the bins' positions and indices (`binned`: x, y, j) into
/// `out` (r^2, entry).
#[inline(always)]
fn nearest_images(
    binned: (&[f64], &[f64], &[u32]),
    (xi, yi): (f64, f64),
    width: f64,
    out: (&mut [f64], &mut [u32]),
) {
    let ((xs, ys, js), (r2s, found)) = (binned, out);
    let half = 0.5 * width;
    for ((((r2, e), &x), &y), &j) in r2s.iter_mut().zip(found).zip(xs).zip(ys).zip(js) {
        let dx0 = xi - x;
        let shift = nearest_shift(dx0, half);
        let dx = dx0 + f64::from(shift) * width;
        let dy = yi - y;
        *r2 = dx * dx + dy * dy;
        *e = Entry::pack(j as usize, shift);
    }
}

/// The image shift (-1, 0 or +1 width) that brings x_i - x_j = `dx0`
/// nearest, `half` half the strip's width: on a strip wider than twice
/// the cutoff no other image can be within it.
#[inline(always)]
fn nearest_shift(dx0: f64, half: f64) -> i8 {
    if dx0 > half {
        -1
    } else if dx0 < -half {
        1
    } else {
        0
    }
}

on_isa! {
    /// [`nearest_images`] compiled for the instruction set `isa`.
    fn nearest_images_on[] => nearest_images[](
        binned: (&[f64], &[f64], &[u32]),
        at: (f64, f64),
        width: f64,
        out: (&mut [f64], &mut [u32])
    )
}

/// The entry `e`'s index and image as one number, j 4 + image code (below
/// 2^32, so exact in an f64): ordered as (j, shift), the tie-break of
/// [`list_key`] and the order of the windows ([`NeighbourList::fill_windows`]).
#[inline(always)]
fn tie(e: u32) -> f64 {
    f64::from(((e & Entry::INDEX_MASK) << 2) | (e >> Entry::IMAGE_SHIFT))
}

/// The entry whose [`tie`] is `t`.
#[inline(always)]
fn untie(t: f64) -> u32 {
    let t = t as u32;
    (t >> 2) | ((t & 3) << Entry::IMAGE_SHIFT)
}

impl NeighbourList {
    /// Neighbours of particle i (itself excluded), as [`Entry`] codes.
    #[inline]
    pub fn of(&self, i: usize) -> &[u32] {
        let start = i * self.stride;
        &self.entries[start..start + self.count[i] as usize]
    }

    /// The width of the strip the list was built for: with
    /// [`Entry::offset`], the x offset to add to x_i - x_j.
    #[inline]
    pub fn width(&self) -> f64 {
        self.width
    }

    /// Slots per particle: no list is longer.
    pub fn stride(&self) -> usize {
        self.stride
    }

    /// How many of i's entries, at the head of its list, are its own: the
    /// pairs (i, j) with j > i, and i's own image through +W. Every other
    /// entry (j, image) is the mirror of an own entry (i, mirrored image)
    /// of j, the same pair seen from j: its q^2 is the same bits (the offset
    /// is negated exactly), so is its kernel. The density pass evaluates the
    /// kernel on own entries only, once per pair (Newton's third law).
    #[inline]
    pub fn own(&self, i: usize) -> usize {
        self.own[i] as usize
    }

    /// For each of i's padded slots, the place in the pair table (of
    /// [`Self::own_pairs`] + 1 values) holding its pair's kernel values:
    /// `own_start(i) + slot` for an own entry, the mirror's place among j's
    /// own entries for the others, and [`Self::own_pairs`] (a place kept at
    /// zero) for padding.
    #[inline]
    pub fn sources_padded(&self, i: usize) -> &[u32] {
        let start = i * self.stride;
        &self.source[start..start + padded(self.count[i] as usize)]
    }

    /// Own entries of all lists: the pairs whose kernel a step evaluates,
    /// and the index of the zero place that padding's
    /// [`Self::sources_padded`] point at.
    pub fn own_pairs(&self) -> usize {
        self.own_entries.len()
    }

    /// Where particle i's own entries start in the pair table.
    #[inline]
    pub fn own_start(&self, i: usize) -> usize {
        self.own_start[i] as usize
    }

    /// The pair table's entries and, for each, the particle whose list it
    /// is in: one stream, list after list, no padding. The kernel pass
    /// evaluates it in equal pieces whatever the lists' lengths.
    pub fn own_stream(&self) -> (&[u32], &[u32]) {
        (&self.own_entries, &self.own_owner)
    }

    /// The particles' blocks' size at the last build: a lattice layer's
    /// particle count ([`Self::build`]).
    pub fn block(&self) -> usize {
        self.block
    }

    /// Particle i's list as windows of consecutive indices ([`Window`]),
    /// in a fixed order (by index).
    #[inline]
    pub fn windows(&self, i: usize) -> &[Window] {
        &self.windows[self.win_start[i] as usize..self.win_start[i + 1] as usize]
    }

    /// Where particle i's windows start among all lists' windows: its
    /// lanes' (dW/dq)/q start at LANES times this in the window-lane table.
    #[inline]
    pub fn window_start(&self, i: usize) -> usize {
        self.win_start[i] as usize
    }

    /// Particle i's windows' lanes' places in the pair table (the zero
    /// place, [`Self::own_pairs`], for a lane not listed), window by window.
    pub fn window_sources(&self, i: usize) -> &[[u32; LANES]] {
        &self.win_sources[self.win_start[i] as usize..self.win_start[i + 1] as usize]
    }

    /// For each own pair, in the pair table's order, the two window lanes
    /// that list it (LANES w + l, w among all lists' windows): its own
    /// entry's and its mirror's (for i's own image, both in i's windows).
    /// The kernel pass writes each pair's (dW/dq)/q into both, so that the
    /// force pass loads a window's as one vector.
    pub fn lanes_of_pairs(&self) -> &[u32] {
        &self.lane_of
    }

    /// Whether the force pass may read each window's (dW/dq)/q as one
    /// vector from a window-lane table the kernel pass fills
    /// ([`Self::lanes_of_pairs`]), rather than gather it from the pair
    /// table through [`Self::window_sources`]. The same values in the same
    /// lanes, so the same bits either way; the table is contiguous loads,
    /// the gather moves fewer bytes. Beyond [`LANE_TABLE_MAX_BYTES`] the
    /// list has no table; below, the solver's steps pick the quicker form
    /// by its cost.
    pub fn lane_table(&self) -> bool {
        self.lane_table
    }

    /// The largest window-lane table the next builds may make, in bytes
    /// (0: none; for the tests that compare the two forms).
    pub fn set_lane_table_max(&mut self, bytes: usize) {
        self.lane_table_max = Some(bytes);
    }

    /// Whether the particles the next builds list are disordered (their
    /// storage order moved at the last reorder, `State::reorder`) rather
    /// than a lattice. A lattice's build takes the form with branches on
    /// the distances, which branch prediction follows there; a disordered
    /// fluid's takes whichever form its recent builds found cheaper
    /// ([`Forms`]): the one without those branches wherever its tests go
    /// either way, the other where the fluid repeats (a tiling of one
    /// state, whose pattern the predictor learns). The same list in
    /// either form; only the time differs.
    pub fn set_disordered(&mut self, disordered: bool) {
        self.disordered = disordered;
    }

    /// Whether the builds are of a disordered fluid
    /// ([`Self::set_disordered`]).
    pub fn disordered(&self) -> bool {
        self.disordered
    }

    /// This build's number: unique among every list's builds in the
    /// process, so a table filled for one build is known to be stale for
    /// any other.
    pub fn generation(&self) -> u64 {
        self.generation
    }

    /// Windows of all lists.
    pub fn window_count(&self) -> usize {
        self.windows.len()
    }

    /// Total number of listed pairs (each counted from both sides).
    pub fn pairs(&self) -> usize {
        self.count.iter().map(|&c| c as usize).sum()
    }

    /// Bytes held by the list and its bins.
    pub fn bytes(&self) -> usize {
        (self.count.capacity()
            + self.entries.capacity()
            + self.own.capacity()
            + self.source.capacity()
            + self.own_start.capacity()
            + self.own_entries.capacity()
            + self.own_owner.capacity()
            + self.bin_start.capacity()
            + self.bin_items.capacity()
            + self.near_start.capacity()
            + self.near.capacity()
            + self.win_start.capacity()
            + self.lane_of.capacity())
            * size_of::<u32>()
            + self.windows.capacity() * size_of::<Window>()
            + (self.bin_x.capacity() + self.bin_y.capacity()) * size_of::<f64>()
            + self.win_sources.capacity() * size_of::<[u32; LANES]>()
    }

    /// Rebuild for positions `x` (wrapped into [0, width)) and `y`, every pair
    /// within `cutoff` (which must be below the strip width). Particles come
    /// in blocks of `block` (for the rebuild rule, see [`Self::stale`]).
    pub fn build(&mut self, x: &[f64], y: &[f64], width: f64, cutoff: f64, block: usize) {
        assert!(
            cutoff < width,
            "cutoff {cutoff} must be below the strip width {width}"
        );
        assert!(
            block > 0 && x.len().is_multiple_of(block),
            "particles come in whole blocks"
        );
        let n = x.len();
        assert!(
            n <= Entry::MAX_PARTICLES,
            "at most {} particles",
            Entry::MAX_PARTICLES
        );
        self.width = width;
        let start = std::time::Instant::now();
        self.branch_free = self.disordered && self.forms.pick();
        self.block = block;
        self.find_near_blocks(y, cutoff, block);
        let grid = self.bin_cells(x, y, width, cutoff);
        let (bin_start, bin_items) = (&self.bin_start, &self.bin_items);
        let (bin_x, bin_y) = (&self.bin_x, &self.bin_y);
        let cutoff2 = cutoff * cutoff;

        // Every neighbour of i: the particles of the cells within one cell
        // of i's, through every image, as the keys its list is sorted by:
        // returns (o, m, together), o own entries and m mirrored ones.
        // On a strip wider than 2.5 cutoffs only a candidate's nearest
        // image is tried (`nearest_only`): the others are more than half
        // the width away, beyond the cutoff. Two forms, the same entries.
        // On a lattice the distance tests come in a pattern that repeats
        // from particle to particle, which branch prediction follows:
        // each candidate is tested (each image in turn on a narrow strip),
        // and the kept ones' keys ([`list_key`]) are all in
        // `scratch.keys[..o + m]`, own first (`together`). In a disordered
        // fluid (`self.branch_free`) the tests go either way, and a
        // mispredicted branch costs more than the work it skips: there,
        // on a wide strip, every candidate's r^2 is computed in lanes,
        // and each written and kept (counted) only if it is within the
        // cutoff, with no branch on its distance: own entries' keys as two
        // fields, r^2 and [`tie`], in `scratch.own` (the first o),
        // mirrored ones' in `scratch.mirrored` (the first m), for
        // [`entry::ranks`].
        let nearest_only = width > 2.5 * cutoff;
        let branch_free = self.branch_free && nearest_only;
        let half = 0.5 * width;
        let isa = Isa::detect();
        let visit = |i: usize, scratch: &mut Scratch| -> (usize, usize, bool) {
            let (xi, yi) = (x[i], y[i]);
            let (by, bx) = grid.cell(xi, yi);
            let rows = by.saturating_sub(1)..(by + 2).min(grid.rows);
            if !branch_free {
                let found = &mut scratch.keys;
                found.clear();
                for row in rows {
                    for k in grid.columns_near(bx) {
                        let cell = row * grid.columns + k;
                        let items =
                            &bin_items[bin_start[cell] as usize..bin_start[cell + 1] as usize];
                        for &j in items {
                            let dy = yi - y[j as usize];
                            let dy2 = dy * dy;
                            // r^2 >= dy^2 as computed (adding dx^2 >= 0
                            // rounds to no less): a particle too far in y
                            // is out through every image.
                            if dy2 > cutoff2 {
                                continue;
                            }
                            let dx0 = xi - x[j as usize];
                            // Each image tried, or on a wide strip the
                            // nearest alone.
                            let mut test = |shift: i8| {
                                if shift == 0 && j as usize == i {
                                    return;
                                }
                                let dx = dx0 + f64::from(shift) * width;
                                let r2 = dx * dx + dy2;
                                if r2 <= cutoff2 {
                                    found.push(list_key(i, j, shift, r2));
                                }
                            };
                            if nearest_only {
                                test(nearest_shift(dx0, half));
                            } else {
                                for shift in -1i8..=1 {
                                    test(shift);
                                }
                            }
                        }
                    }
                }
                // Own entries first (their keys are the smaller).
                let mut own_count = 0;
                for m in 0..found.len() {
                    if found[m] >> 96 == 0 {
                        found.swap(own_count, m);
                        own_count += 1;
                    }
                }
                return (own_count, found.len() - own_count, true);
            }
            // Each row's cells near i are one or two runs of the bins
            // (wrapped at the strip's edges), read in order with their
            // positions ([`Self::bin_cells`]).
            let runs = |row: usize| {
                grid.runs_near(row, bx)
                    .map(|(a, b)| bin_start[a] as usize..bin_start[b] as usize)
            };
            let room = rows.clone().flat_map(runs).map(|r| r.len()).sum();
            scratch.make_room(room);
            // Every candidate's r^2 through its nearest image, and its
            // entry, in lanes; then own and mirrored apart, each as its
            // keys' two fields (r^2 and the tie), written at every
            // candidate and kept by a count: within the cutoff, and not i
            // itself through no image.
            let (found, r2s) = (&mut scratch.found[..room], &mut scratch.r2[..room]);
            let mut at = 0;
            for run in rows.flat_map(runs) {
                let end = at + run.len();
                let binned = (&bin_x[run.clone()], &bin_y[run.clone()], &bin_items[run]);
                let out = (&mut r2s[at..end], &mut found[at..end]);
                nearest_images_on(isa, binned, (xi, yi), width, out);
                at = end;
            }
            let itself = Entry::pack(i, 0);
            let (mut n_own, mut n_mirrored) = (0, 0);
            let (own, mirrored) = (&mut scratch.own, &mut scratch.mirrored);
            for (&e, &r2) in found.iter().zip(r2s.iter()) {
                let kept = (r2 <= cutoff2) & (e != itself);
                let mine = is_own(i, e & Entry::INDEX_MASK, Entry::image(e) as i8 - 1);
                let t = tie(e);
                (own.0[n_own], own.1[n_own]) = (r2, t);
                (mirrored.0[n_mirrored], mirrored.1[n_mirrored]) = (r2, t);
                n_own += usize::from(kept & mine);
                n_mirrored += usize::from(kept & !mine);
            }
            for (part, m) in [(own, n_own), (mirrored, n_mirrored)] {
                part.0[m..padded(m)].fill(f64::INFINITY);
            }
            (n_own, n_mirrored, false)
        };

        // One pass with the last build's stride; a second only when some
        // list outgrew it (always at the first build).
        let mut count = std::mem::take(&mut self.count);
        count.resize(n, 0);
        let mut own = std::mem::take(&mut self.own);
        own.resize(n, 0);
        let mut stride = self.stride.max(LANES);
        loop {
            self.entries.resize(n * stride, 0);
            let longest = self
                .entries
                .par_chunks_mut(stride)
                .zip(count.par_iter_mut().zip(own.par_iter_mut()))
                .with_min_len(BUILD_CHUNK)
                .enumerate()
                .map_init(Scratch::default, |scratch, (i, (entries, (c, o)))| {
                    let (own_count, mirrored_count, together) = visit(i, scratch);
                    let len = own_count + mirrored_count;
                    *c = len as u32;
                    *o = own_count as u32;
                    if padded(len) <= stride {
                        // Own entries first ([`Self::own`]), then the
                        // mirrored ones; each nearest first: the kernels'
                        // piece tests then come in runs, which branch
                        // prediction follows, for as long as the list
                        // lives (particles move less than the skin). Ties
                        // by index and image, so that the order does not
                        // depend on the order of visiting ([`list_key`]).
                        if together {
                            let pack = |key: u128| {
                                let (j, shift) =
                                    ((key >> 2) as u32 & Entry::INDEX_MASK, (key & 3) as i8 - 1);
                                Entry::pack(j as usize, shift)
                            };
                            let (own, mirrored) = scratch.keys[..len].split_at_mut(own_count);
                            sorted_into(own, false, |k, key| entries[k] = pack(key));
                            sorted_into(mirrored, false, |k, key| {
                                entries[own_count + k] = pack(key);
                            });
                        } else {
                            for (part, m, first) in [
                                (&scratch.own, own_count, 0),
                                (&scratch.mirrored, mirrored_count, own_count),
                            ] {
                                let (primary, tie) = (&part.0[..], &part.1[..]);
                                place_ranked(
                                    isa,
                                    (primary, tie),
                                    m,
                                    &mut scratch.places,
                                    |k, a| {
                                        entries[first + k] = untie(tie[a]);
                                    },
                                );
                            }
                        }
                        for slot in &mut entries[len..padded(len)] {
                            *slot = Entry::padding(i);
                        }
                    }
                    len
                })
                .max()
                .unwrap_or(0);
            if padded(longest) <= stride {
                break;
            }
            // Room for a little compaction before the next overflow.
            stride = padded(longest + 2);
        }
        self.stride = stride;
        self.count = count;
        self.own = own;
        self.fill_own_stream();
        self.find_sources();
        self.fill_windows();
        let most = self.lane_table_max.unwrap_or(LANE_TABLE_MAX_BYTES);
        self.lane_table = self.windows.len() * LANES * size_of::<f64>() <= most;
        if self.lane_table {
            self.find_lanes();
        } else {
            self.lane_of = Vec::new();
        }
        if self.disordered {
            let ns = start.elapsed().as_secs_f64() * 1e9 / n.max(1) as f64;
            self.forms.record(self.branch_free, ns);
        }
        static BUILDS: AtomicU64 = AtomicU64::new(0);
        self.generation = BUILDS.fetch_add(1, Ordering::Relaxed) + 1;
        self.rebuilds += 1;
    }

    /// The pair table's stream ([`Self::own_stream`]): each list's own
    /// entries in turn.
    fn fill_own_stream(&mut self) {
        let n = self.count.len();
        self.own_start.clear();
        self.own_start.reserve(n + 1);
        let mut total = 0usize;
        self.own_start.push(0);
        for &o in &self.own {
            total += o as usize;
            assert!(total < u32::MAX as usize, "at most {} own pairs", u32::MAX);
            self.own_start.push(total as u32);
        }
        self.own_entries.clear();
        self.own_owner.clear();
        self.own_entries.reserve(total);
        self.own_owner.reserve(total);
        for i in 0..n {
            let start = i * self.stride;
            let own = self.own[i] as usize;
            self.own_entries
                .extend_from_slice(&self.entries[start..start + own]);
            self.own_owner.extend(std::iter::repeat_n(i as u32, own));
        }
    }
}

mod entry;
mod grid;
mod stale;
mod windows;

use super::step::Isa;
use entry::{is_own, list_key, place_ranked, sorted_into};
pub use entry::{padded, Entry, LANES};
pub use stale::{Displacements, Reach};
pub use windows::Window;

#[cfg(test)]
pub(crate) mod tests;
