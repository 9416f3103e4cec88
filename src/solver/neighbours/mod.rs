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
//! image): the lattice keeps its rows in index order, so a neighbour row is
//! one or two windows, loaded as contiguous vectors instead of gathered;
//! each pair's (dW/dq)/q is written where both its window lanes read it
//! ([`NeighbourList::lanes_of_pairs`]).
//!
//! Rebuild rule: a pair not in the list was more than R h + skin apart; it
//! can only have come within R h if the two displacements since the rebuild
//! differ by more than `skin`. Particles are grouped in blocks (the lattice
//! layers they started in), and each block's displacements since the rebuild
//! are bounded by a box. Two displacements differ by at most the diagonal of
//! the union of their blocks' boxes; only blocks that were within R h + skin
//! of each other in y at the rebuild need that check, provided no two
//! transverse displacements differ by more than `skin` either. In shear the
//! whole fluid's box grows as U t, but that of neighbouring layers only as
//! (dU/dy) (R h) t, so the list lives about B / (R h) times longer than with
//! one box for all.

use std::sync::atomic::{AtomicU64, Ordering};

use rayon::prelude::*;

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
    /// that list it, as LANES w + l: `lane_of[2 s]` and `lane_of[2 s + 1]`.
    lane_of: Vec<u32>,
    /// This build's number, unique among all lists' builds in the process
    /// ([`Self::generation`]).
    generation: u64,
    /// The strip's width: the images' offsets ([`Entry::offset`]).
    width: f64,
    /// Cell list ([`Grid`]): particle indices sorted by cell, and where
    /// each cell starts.
    bin_start: Vec<u32>,
    bin_items: Vec<u32>,
    /// For each block a, the blocks b > a within the cutoff of it in y at the
    /// rebuild: `near[near_start[a]..near_start[a + 1]]`.
    near_start: Vec<u32>,
    near: Vec<u32>,
    pub rebuilds: u64,
}

/// Lists are padded to a multiple of this many entries (with
/// [`Entry::padding`]) so the pair loops run in whole groups of lanes.
pub const LANES: usize = 8;

/// `n` rounded up to whole groups of [`LANES`].
#[inline(always)]
pub fn padded(n: usize) -> usize {
    n.div_ceil(LANES) * LANES
}

/// A listed neighbour j of i: its index, and the image it was found through
/// as a code 0, 1, 2 for the offset -W, 0, +W added to x_i - x_j
/// ([`Entry::offset`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Entry;

impl Entry {
    const IMAGE_SHIFT: u32 = 30;
    const INDEX_MASK: u32 = (1 << Self::IMAGE_SHIFT) - 1;
    /// Most particles a list can index.
    pub const MAX_PARTICLES: usize = 1 << Self::IMAGE_SHIFT;

    #[inline(always)]
    pub fn pack(j: usize, shift: i8) -> u32 {
        j as u32 | (((shift + 1) as u32) << Self::IMAGE_SHIFT)
    }

    /// A padding entry: particle i itself seen through image code 3, whose
    /// offset 2W ([`Entry::offset`]) puts the pair out of every kernel's
    /// support: W = 0, (dW/dq)/q = 0, and so every force term 0.
    #[inline(always)]
    pub fn padding(i: usize) -> u32 {
        i as u32 | (3 << Self::IMAGE_SHIFT)
    }

    /// The x offset of the entry's image in a strip `width` wide: -W, 0,
    /// +W for codes 0, 1, 2, and 2W for padding (code 3): beyond every
    /// support, as the cutoff is below the width. Arithmetic, not a table
    /// lookup: in the vector loops a lookup is one more gather.
    #[inline(always)]
    pub fn offset(e: u32, width: f64) -> f64 {
        (f64::from(e >> Self::IMAGE_SHIFT) - 1.0) * width
    }

    /// The index, clamped to `last`: in the pair loops, an index that is
    /// below the arrays' length whatever the entry, with no bounds check.
    /// Clamped in 32 bits, so that the vector loops gather with 32-bit
    /// indices.
    #[inline(always)]
    pub fn index_below(e: u32, last: usize) -> usize {
        (e & Self::INDEX_MASK).min(u32::try_from(last).unwrap_or(u32::MAX)) as usize
    }

    #[inline(always)]
    pub fn index(e: u32) -> usize {
        (e & Self::INDEX_MASK) as usize
    }

    /// The image code (0 to 3).
    #[inline(always)]
    pub fn image(e: u32) -> usize {
        (e >> Self::IMAGE_SHIFT) as usize
    }
}

/// A piece of a list as LANES consecutive particle indices: the listed
/// neighbours j in `start..start + LANES`, as bits of the mask (bit l for
/// j = start + l), each with the image it was found through. Its lanes'
/// (dW/dq)/q are LANES consecutive values of the window-lane table the
/// kernel pass fills ([`NeighbourList::lanes_of_pairs`]; 0 in a lane not
/// listed). The lattice keeps its rows in index order, so a row
/// of i's neighbours is a few consecutive indices: one window, or two where
/// it holds more than LANES or crosses the strip's edge on a wide strip (a
/// whole row of a narrow strip, wrapped through two images, is one): the
/// force pass
/// loads a window's positions, velocities, pressures, volumes and kernel
/// values as contiguous vectors, without a gather. A lane holds
/// one entry: a particle listed through two images (a strip narrower than
/// twice the cutoff with the skin) is in two windows.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(C)]
pub struct Window {
    pub start: u32,
    /// The lanes listed (bits 0-7) and each lane's image code (bits 8 + 2 l
    /// and 9 + 2 l, as [`Entry::image`]).
    meta: u32,
}

impl Window {
    /// A window at `start` with the lanes `mask` (bits 0-7) listed, lane l
    /// found through the image code `images[l]` (0 to 2, as
    /// [`Entry::image`]).
    pub fn new(start: u32, mask: u8, images: [u32; LANES]) -> Window {
        assert!(images.iter().all(|&c| c <= 2), "image codes are 0, 1 and 2");
        let codes = images
            .iter()
            .enumerate()
            .fold(0u32, |m, (l, &c)| m | c << (8 + 2 * l));
        Window {
            start,
            meta: u32::from(mask) | codes,
        }
    }

    /// The lanes listed, bit l for particle `start + l`.
    #[inline(always)]
    pub fn mask(&self) -> u32 {
        self.meta & 0xff
    }

    /// The image code (0 to 2) of lane l.
    #[inline(always)]
    pub fn image(&self, l: usize) -> u32 {
        (self.meta >> (8 + 2 * l)) & 3
    }

    /// The x offset of lane l's image, as [`Entry::offset`].
    #[inline(always)]
    pub fn offset(&self, l: usize, width: f64) -> f64 {
        (f64::from(self.image(l)) - 1.0) * width
    }
}

/// The box bounding the displacements of a block of particles since the
/// last rebuild.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Displacements {
    pub dx_min: f64,
    pub dx_max: f64,
    pub dy_min: f64,
    pub dy_max: f64,
}

impl Displacements {
    /// No displacement yet: add some.
    pub const EMPTY: Displacements = Displacements {
        dx_min: f64::INFINITY,
        dx_max: f64::NEG_INFINITY,
        dy_min: f64::INFINITY,
        dy_max: f64::NEG_INFINITY,
    };

    /// Particles that never moved (the walls).
    pub const ZERO: Displacements = Displacements {
        dx_min: 0.0,
        dx_max: 0.0,
        dy_min: 0.0,
        dy_max: 0.0,
    };

    #[inline]
    pub fn add(&mut self, dx: f64, dy: f64) {
        self.dx_min = self.dx_min.min(dx);
        self.dx_max = self.dx_max.max(dx);
        self.dy_min = self.dy_min.min(dy);
        self.dy_max = self.dy_max.max(dy);
    }

    pub fn union(self, o: Displacements) -> Displacements {
        Displacements {
            dx_min: self.dx_min.min(o.dx_min),
            dx_max: self.dx_max.max(o.dx_max),
            dy_min: self.dy_min.min(o.dy_min),
            dy_max: self.dy_max.max(o.dy_max),
        }
    }

    /// Whether two displacements in the box can differ by more than
    /// `skin`: its diagonal against `skin`, squared (no square root: the
    /// rebuild test runs every step over every pair of near blocks).
    #[inline]
    pub fn wider_than(&self, skin: f64) -> bool {
        let (w, h) = (self.dx_max - self.dx_min, self.dy_max - self.dy_min);
        w * w + h * h > skin * skin
    }
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
        self.find_near_blocks(y, cutoff, block);
        let grid = self.bin_cells(x, y, width, cutoff);
        let (bin_start, bin_items) = (&self.bin_start, &self.bin_items);
        let cutoff2 = cutoff * cutoff;

        // Every neighbour of i: the particles of the cells within one cell
        // of i's, through every image, into `found` as the keys its list
        // is sorted by ([`list_key`]).
        let visit = |i: usize, found: &mut Vec<u128>| {
            let (xi, yi) = (x[i], y[i]);
            let (by, bx) = grid.cell(xi, yi);
            for row in by.saturating_sub(1)..(by + 2).min(grid.rows) {
                for k in grid.columns_near(bx) {
                    let cell = row * grid.columns + k;
                    let items = &bin_items[bin_start[cell] as usize..bin_start[cell + 1] as usize];
                    for &j in items {
                        let dy = yi - y[j as usize];
                        let dy2 = dy * dy;
                        // r^2 >= dy^2 as computed (adding dx^2 >= 0 rounds
                        // to no less): a particle too far in y is out
                        // through every image.
                        if dy2 > cutoff2 {
                            continue;
                        }
                        let dx0 = xi - x[j as usize];
                        for shift in -1i8..=1 {
                            if shift == 0 && j as usize == i {
                                continue;
                            }
                            let dx = dx0 + f64::from(shift) * width;
                            let r2 = dx * dx + dy2;
                            if r2 <= cutoff2 {
                                found.push(list_key(i, j, shift, r2));
                            }
                        }
                    }
                }
            }
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
                .map_init(Vec::new, |found, (i, (entries, (c, o)))| {
                    found.clear();
                    visit(i, found);
                    *c = found.len() as u32;
                    *o = found.iter().filter(|&&key| key >> 96 == 0).count() as u32;
                    if padded(found.len()) <= stride {
                        // Own entries first ([`Self::own`]), then the
                        // mirrored ones; each nearest first: the kernels'
                        // piece tests then come in runs, which branch
                        // prediction follows, for as long as the list lives
                        // (particles move less than the skin). Ties by
                        // index and image, so that the order does not
                        // depend on the order of visiting ([`list_key`]).
                        found.sort_unstable();
                        for (slot, &key) in entries.iter_mut().zip(found.iter()) {
                            let (j, shift) =
                                ((key >> 2) as u32 & Entry::INDEX_MASK, (key & 3) as i8 - 1);
                            *slot = Entry::pack(j as usize, shift);
                        }
                        for slot in &mut entries[found.len()..padded(found.len())] {
                            *slot = Entry::padding(i);
                        }
                    }
                    found.len()
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
        self.find_lanes();
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

    /// Fill [`Self::sources_padded`]: for each mirrored entry (j, image) of
    /// i, the place of (i, mirrored image) among j's own entries in the pair
    /// table. The lists are symmetric: j lists i through the opposite image
    /// exactly when i lists j (the same r^2 bits, and bins in reach both
    /// ways).
    fn find_sources(&mut self) {
        let stride = self.stride;
        let slots = self.entries.len();
        let zero = self.own_entries.len() as u32;
        self.source.resize(slots, zero);
        let (entries, count, own, own_start) =
            (&self.entries, &self.count, &self.own, &self.own_start);
        self.source
            .par_chunks_mut(stride)
            .with_min_len(BUILD_CHUNK)
            .enumerate()
            .for_each(|(i, source)| {
                let base = i * stride;
                let (c, o) = (count[i] as usize, own[i] as usize);
                let first = own_start[i];
                for (slot, src) in source.iter_mut().enumerate().take(o) {
                    *src = first + slot as u32;
                }
                for (src, &e) in source[o..c].iter_mut().zip(&entries[base + o..base + c]) {
                    let j = Entry::index(e);
                    let mirror = Entry::pack(i, 1 - Entry::image(e) as i8);
                    let from = j * stride;
                    let k = entries[from..from + own[j] as usize]
                        .iter()
                        .position(|&m| m == mirror)
                        .expect("neighbour lists are symmetric");
                    *src = own_start[j] + k as u32;
                }
                for src in &mut source[c..] {
                    *src = zero;
                }
            });
    }

    /// Cut every list into [`Window`]s: its entries ordered by index, each
    /// window starting at the first entry not yet in one and taking every
    /// later entry below its start + LANES, whatever its image.
    /// A window that would run past the last particle starts LANES before
    /// the end instead (its lanes shift with it), so every window's
    /// particles exist: a list needs at least LANES particles.
    fn fill_windows(&mut self) {
        let n = self.count.len();
        assert!(
            n >= LANES,
            "the force pass needs at least {LANES} particles (got {n})"
        );
        let last_start = (n - LANES) as u32;
        let zero = self.own_entries.len() as u32;
        let stride = self.stride;
        let (entries, source, count) = (&self.entries, &self.source, &self.count);
        // Per task of BUILD_CHUNK particles, their windows in one vector
        // and each one's count: two allocations a task, not one a particle
        // (on several threads, allocations per particle contend for the
        // allocator's lock).
        type Task = (Vec<u32>, Vec<Window>, Vec<[u32; LANES]>);
        let per: Vec<Task> = (0..n.div_ceil(BUILD_CHUNK))
            .into_par_iter()
            .map_init(Vec::new, |slots, task| {
                let particles = task * BUILD_CHUNK..((task + 1) * BUILD_CHUNK).min(n);
                let mut counts = Vec::with_capacity(particles.len());
                let mut out: Vec<Window> = Vec::new();
                let mut sources: Vec<[u32; LANES]> = Vec::new();
                for i in particles {
                    let base = i * stride;
                    let c = count[i] as usize;
                    slots.clear();
                    // (j, image, source) as one integer in that order.
                    slots.extend(
                        entries[base..base + c]
                            .iter()
                            .zip(&source[base..base + c])
                            .map(|(&e, &src)| {
                                (u64::from(Entry::index(e) as u32) << 34)
                                    | (Entry::image(e) as u64) << 32
                                    | u64::from(src)
                            }),
                    );
                    slots.sort_unstable();
                    let first = out.len();
                    for &key in slots.iter() {
                        let (j, image, src) =
                            ((key >> 34) as u32, (key >> 32) as u32 & 3, key as u32);
                        // A lane holds one entry: j seen through two images (a
                        // strip narrower than two cutoffs with the skin) takes
                        // a second window.
                        let fits = out.len() > first
                            && out.last().is_some_and(|w: &Window| {
                                j < w.start + LANES as u32 && w.mask() & (1 << (j - w.start)) == 0
                            });
                        if !fits {
                            let start = j.min(last_start);
                            out.push(Window::new(start, 0, [1; LANES]));
                            sources.push([zero; LANES]);
                        }
                        let w = out.last_mut().expect("a window was just pushed");
                        let lane = (j - w.start) as usize;
                        w.meta |= 1 << lane;
                        w.meta = (w.meta & !(3 << (8 + 2 * lane))) | image << (8 + 2 * lane);
                        sources.last_mut().expect("pushed with its window")[lane] = src;
                    }
                    counts.push((out.len() - first) as u32);
                }
                (counts, out, sources)
            })
            .collect();
        self.win_start.clear();
        self.win_start.reserve(n + 1);
        self.win_start.push(0);
        let mut total = 0usize;
        for &c in per.iter().flat_map(|(counts, _, _)| counts) {
            total += c as usize;
            self.win_start
                .push(u32::try_from(total).expect("windows fit in u32"));
        }
        self.windows.clear();
        self.windows.reserve(total);
        self.win_sources.clear();
        self.win_sources.reserve(total);
        for (_, w, src) in per {
            self.windows.extend_from_slice(&w);
            self.win_sources.extend_from_slice(&src);
        }
    }

    /// Fill [`Self::lanes_of_pairs`] from the windows' sources: every own
    /// pair is listed in exactly two lanes (its entry's and its mirror's).
    fn find_lanes(&mut self) {
        let pairs = self.own_entries.len();
        let none = u32::MAX;
        self.lane_of.clear();
        self.lane_of.resize(2 * pairs, none);
        for (w, (win, src)) in self.windows.iter().zip(&self.win_sources).enumerate() {
            for (l, &s) in src.iter().enumerate() {
                if win.mask() & (1 << l) == 0 {
                    continue;
                }
                let lane = u32::try_from(w * LANES + l).expect("window lanes fit in u32");
                let s = s as usize;
                let at = if self.lane_of[2 * s] == none {
                    2 * s
                } else {
                    2 * s + 1
                };
                assert_eq!(self.lane_of[at], none, "a pair is listed in two lanes only");
                self.lane_of[at] = lane;
            }
        }
        assert!(
            self.lane_of.iter().all(|&l| l != none),
            "every own pair is listed in two lanes"
        );
    }

    /// Whether the list may miss a pair within `cutoff - skin`, given each
    /// block's displacement box.
    pub fn stale(&self, box_of: impl Fn(usize) -> Displacements, skin: f64) -> bool {
        let n_blocks = self.near_start.len() - 1;
        let all = (0..n_blocks).fold(Displacements::EMPTY, |acc, b| acc.union(box_of(b)));
        if all.dy_max - all.dy_min > skin {
            return true;
        }
        (0..n_blocks).any(|a| {
            let box_a = box_of(a);
            box_a.wider_than(skin)
                || self.near[self.near_start[a] as usize..self.near_start[a + 1] as usize]
                    .iter()
                    .any(|&b| box_a.union(box_of(b as usize)).wider_than(skin))
        })
    }

    /// The pairs of blocks within `cutoff` of each other in y.
    fn find_near_blocks(&mut self, y: &[f64], cutoff: f64, block: usize) {
        let ranges = block_ranges(y, block);
        self.near_start.clear();
        self.near.clear();
        self.near_start.push(0);
        let near = |(lo_a, hi_a): (f64, f64), (lo_b, hi_b): (f64, f64)| {
            (lo_b - hi_a).max(lo_a - hi_b) <= cutoff
        };
        if !ranges.iter().all(|r| r.0.is_finite() && r.1.is_finite()) {
            // A state that is not finite (about to be reported): every
            // pair of blocks tested.
            for (a, &ra) in ranges.iter().enumerate() {
                for (b, &rb) in ranges.iter().enumerate().skip(a + 1) {
                    if near(ra, rb) {
                        self.near.push(b as u32);
                    }
                }
                self.near_start.push(self.near.len() as u32);
            }
            return;
        }
        // The blocks by their lowest y: a block b within the cutoff of a
        // has its lowest y within [lo_a - cutoff - H, hi_a + cutoff], H the
        // tallest block's height. Only those are tested, in a window
        // widened by a margin far above the rounding of the test, which
        // decides: the same pairs as testing all, in O(blocks log blocks)
        // for the usual few neighbours (a tall narrow strip has tens of
        // thousands of blocks).
        let tallest = ranges.iter().fold(0.0f64, |t, r| t.max(r.1 - r.0));
        let scale = ranges
            .iter()
            .fold(cutoff + tallest, |m, r| m.max(r.0.abs()).max(r.1.abs()));
        let margin = 1e-9 * scale;
        let mut order: Vec<u32> = (0..ranges.len() as u32).collect();
        order.sort_by(|&a, &b| ranges[a as usize].0.total_cmp(&ranges[b as usize].0));
        let lows: Vec<f64> = order.iter().map(|&b| ranges[b as usize].0).collect();
        let mut found: Vec<u32> = Vec::new();
        for (a, &ra) in ranges.iter().enumerate() {
            let from = lows.partition_point(|&lo| lo < ra.0 - cutoff - tallest - margin);
            let to = lows.partition_point(|&lo| lo <= ra.1 + cutoff + margin);
            found.clear();
            found.extend(
                order[from..to.max(from)]
                    .iter()
                    .copied()
                    .filter(|&b| b as usize > a && near(ra, ranges[b as usize])),
            );
            found.sort_unstable();
            self.near.extend_from_slice(&found);
            self.near_start.push(self.near.len() as u32);
        }
    }

    /// Counting sort of the particles into cells: rows of height `cutoff`
    /// in y from the lowest particle and, when the strip is at least three
    /// cutoffs wide, columns at least `cutoff` wide in x (periodic);
    /// otherwise one column (a narrow strip: every image of every particle
    /// in the rows near is tested). Within a cell, particles by index.
    fn bin_cells(&mut self, x: &[f64], y: &[f64], width: f64, cutoff: f64) -> Grid {
        let ymin = y.iter().copied().fold(f64::INFINITY, f64::min);
        let ymax = y.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        // Rows of height `cutoff` from the lowest particle; no more rows than
        // particles (the last one takes the rest), and one for a span that is
        // not finite (a blown-up state, about to be reported).
        let span = ymax - ymin;
        let rows = if span.is_finite() {
            (span / cutoff).floor().min(y.len() as f64) as usize + 1
        } else {
            1
        };
        let fit = (width / cutoff).floor();
        let columns = if fit >= 3.0 {
            (fit as usize).min(y.len())
        } else {
            1
        };
        let grid = Grid {
            ymin,
            cutoff,
            rows,
            columns,
            column_width: width / columns as f64,
        };
        let cells = rows * columns;
        self.bin_start.clear();
        self.bin_start.resize(cells + 1, 0);
        let cell_of = |i: usize| {
            let (r, c) = grid.cell(x[i], y[i]);
            r * columns + c
        };
        for i in 0..y.len() {
            self.bin_start[cell_of(i) + 1] += 1;
        }
        for b in 0..cells {
            self.bin_start[b + 1] += self.bin_start[b];
        }
        self.bin_items.resize(y.len(), 0);
        let mut fill = self.bin_start.clone();
        for i in 0..y.len() {
            let b = cell_of(i);
            self.bin_items[fill[b] as usize] = i as u32;
            fill[b] += 1;
        }
        grid
    }
}

/// The cells of [`NeighbourList::bin_cells`].
#[derive(Debug, Clone, Copy)]
struct Grid {
    ymin: f64,
    cutoff: f64,
    rows: usize,
    columns: usize,
    column_width: f64,
}

impl Grid {
    /// The (row, column) of a particle at (x, y), x in [0, width) (a
    /// position outside, or NaN, is put in the nearest cell).
    #[inline]
    fn cell(&self, x: f64, y: f64) -> (usize, usize) {
        let row = (((y - self.ymin) / self.cutoff) as usize).min(self.rows - 1);
        let column = ((x / self.column_width) as usize).min(self.columns - 1);
        (row, column)
    }

    /// The columns within one of column `c`, periodic: all (one) of a
    /// narrow strip, else `c - 1`, `c`, `c + 1` (three distinct columns).
    #[inline]
    fn columns_near(&self, c: usize) -> impl Iterator<Item = usize> {
        let n = self.columns;
        let (first, count) = if n == 1 { (0, 1) } else { (c + n - 1, 3) };
        (0..count).map(move |k| (first + k) % n)
    }
}

/// Each block's lowest and highest y (infinite both for a block of NaN).
fn block_ranges(y: &[f64], block: usize) -> Vec<(f64, f64)> {
    y.chunks(block)
        .map(|c| {
            c.iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| {
                    (lo.min(v), hi.max(v))
                })
        })
        .collect()
}

/// Whether the entry (j, image `shift`) of i's list is i's own
/// ([`NeighbourList::own`]).
#[inline]
fn is_own(i: usize, j: u32, shift: i8) -> bool {
    let j = j as usize;
    j > i || (j == i && shift == 1)
}

/// The entry (j, image `shift`) of i's list at squared distance `r2` as
/// the key its list is sorted by: one integer whose order is that of the
/// tuple (not own, r^2, j, shift), so a sort compares integers. The own
/// flag in bit 96, r^2's bits in bits 32-95 (r^2 >= 0 orders as its bits),
/// j in bits 2-31, shift + 1 in bits 0-1.
#[inline]
fn list_key(i: usize, j: u32, shift: i8, r2: f64) -> u128 {
    debug_assert!(r2 >= 0.0 && (j as usize) < Entry::MAX_PARTICLES);
    (u128::from(!is_own(i, j, shift)) << 96)
        | (u128::from(r2.to_bits()) << 32)
        | (u128::from(j) << 2)
        | u128::from((shift + 1) as u8)
}

#[cfg(test)]
mod tests;
