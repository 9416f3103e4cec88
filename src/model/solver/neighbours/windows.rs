//! The force pass's view of a list: runs of LANES consecutive indices
//! ([`Window`]), their sources and the lanes each pair's kernel value is
//! written to.

use super::entry::sorted_into;
use super::*;

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

    /// Whether every lane's image code is 1, the particle itself rather than
    /// an image (a lane not listed has code 1): every [`Self::offset`] is
    /// then +0.
    #[inline(always)]
    pub fn unshifted(&self) -> bool {
        self.meta >> 8 == 0x5555
    }

    /// The x offset of lane l's image, as [`Entry::offset`].
    #[inline(always)]
    pub fn offset(&self, l: usize, width: f64) -> f64 {
        (f64::from(self.image(l)) - 1.0) * width
    }
}

impl NeighbourList {
    /// Fill [`Self::sources_padded`]: for each mirrored entry (j, image) of
    /// i, the place of (i, mirrored image) among j's own entries in the pair
    /// table. The lists are symmetric: j lists i through the opposite image
    /// exactly when i lists j (the same r^2 bits, and bins in reach both
    /// ways).
    pub(super) fn find_sources(&mut self) {
        let stride = self.stride;
        let slots = self.entries.len();
        let zero = self.own_entries.len() as u32;
        self.source.resize(slots, zero);
        let (entries, count, own, own_start) =
            (&self.entries, &self.count, &self.own, &self.own_start);
        let branch_free = self.branch_free;
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
                    // Among j's own entries. On a lattice the search
                    // stops at the same place list after list, which
                    // branch prediction follows; in a disordered fluid
                    // it does not, and the entries are compared LANES at
                    // a time, as a mask of the equal ones. That padded
                    // run may reach j's mirrored entries and its padding,
                    // never the mirror (an own entry of j, listed once).
                    let from = j * stride;
                    let k = if !branch_free {
                        entries[from..from + own[j] as usize]
                            .iter()
                            .position(|&m| m == mirror)
                            .expect("neighbour lists are symmetric")
                    } else {
                        entries[from..from + padded(own[j] as usize)]
                            .chunks_exact(LANES)
                            .enumerate()
                            .find_map(|(c, chunk)| {
                                let equal = chunk
                                    .iter()
                                    .enumerate()
                                    .fold(0u32, |m, (l, &e)| m | u32::from(e == mirror) << l);
                                (equal != 0).then(|| c * LANES + equal.trailing_zeros() as usize)
                            })
                            .filter(|&k| k < own[j] as usize)
                            .expect("neighbour lists are symmetric")
                    };
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
    pub(super) fn fill_windows(&mut self) {
        let n = self.count.len();
        assert!(
            n >= LANES,
            "the force pass needs at least {LANES} particles (got {n})"
        );
        let last_start = (n - LANES) as u32;
        let zero = self.own_entries.len() as u32;
        let stride = self.stride;
        let (entries, source, count, own) = (&self.entries, &self.source, &self.count, &self.own);
        let branch_free = self.branch_free;
        // Per task of BUILD_CHUNK particles, their windows in one vector
        // and each one's count: two allocations a task, not one a particle
        // (on several threads, allocations per particle contend for the
        // allocator's lock), each with room for as many windows as the
        // last build's lists of those particles had, and a little more: a
        // list that keeps its windows grows no vector.
        type Task = (Vec<u32>, Vec<Window>, Vec<[u32; LANES]>);
        type Keys = (Vec<u64>, Vec<u64>);
        let last = &self.win_start;
        let room = |particles: &std::ops::Range<usize>| {
            let had = match (last.get(particles.start), last.get(particles.end)) {
                (Some(&a), Some(&b)) if last.len() == n + 1 => (b - a) as usize,
                _ => 0,
            };
            had + had / 8 + LANES
        };
        let per: Vec<Task> = (0..n.div_ceil(BUILD_CHUNK))
            .into_par_iter()
            .map_init(Keys::default, |(slots, sorted), task| {
                let particles = task * BUILD_CHUNK..((task + 1) * BUILD_CHUNK).min(n);
                let mut counts = Vec::with_capacity(particles.len());
                let mut out: Vec<Window> = Vec::with_capacity(room(&particles));
                let mut sources: Vec<[u32; LANES]> = Vec::with_capacity(room(&particles));
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
                    // Every mirrored entry (j < i, or i's own image
                    // through -W) comes before every own one (j > i, or
                    // i through +W) in this order: each part sorts alone.
                    let o = own[i] as usize;
                    sorted.clear();
                    sorted.resize(c, 0);
                    let (own_part, mirrored_part) = slots.split_at_mut(o);
                    sorted_into(mirrored_part, branch_free, |k, key| sorted[k] = key);
                    sorted_into(own_part, branch_free, |k, key| sorted[c - o + k] = key);
                    let first = out.len();
                    for &key in sorted.iter() {
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
        // The tasks' windows joined, each task's copied by a thread of its
        // own into its place (resized, not cleared: only windows beyond
        // the last build's count are written twice).
        self.windows.resize(total, Window::new(0, 0, [1; LANES]));
        self.win_sources.resize(total, [zero; LANES]);
        let mut places = Vec::with_capacity(per.len());
        let (mut windows, mut sources) = (&mut self.windows[..], &mut self.win_sources[..]);
        for (_, w, _) in &per {
            let (here, rest) = std::mem::take(&mut windows).split_at_mut(w.len());
            let (here_src, rest_src) = std::mem::take(&mut sources).split_at_mut(w.len());
            places.push((here, here_src));
            (windows, sources) = (rest, rest_src);
        }
        places
            .into_par_iter()
            .zip(per.par_iter())
            .for_each(|((w, src), (_, from, from_src))| {
                w.copy_from_slice(from);
                src.copy_from_slice(from_src);
            });
    }

    /// Fill [`Self::lanes_of_pairs`] from the windows' sources: every own
    /// pair is listed in exactly two lanes (its entry's and its mirror's),
    /// the first met in window order at 2 s. Without branches on the
    /// lanes, whose pattern a disordered fluid's windows do not repeat: a
    /// lane not listed has the zero place for its source
    /// ([`Self::fill_windows`]) and writes to two places past the table's
    /// end, cut off after. Lanes hold the entries, two a pair, so a pair
    /// met a third time would leave another's place empty: the check at
    /// the end finds it.
    pub(super) fn find_lanes(&mut self) {
        let pairs = self.own_entries.len();
        let none = u32::MAX;
        u32::try_from(self.windows.len() * LANES).expect("window lanes fit in u32");
        self.lane_of.clear();
        self.lane_of.resize(2 * pairs + 2, none);
        for (w, (win, src)) in self.windows.iter().zip(&self.win_sources).enumerate() {
            for (l, &s) in src.iter().enumerate() {
                debug_assert!(win.mask() & (1 << l) != 0 || s as usize == pairs);
                let s = 2 * s as usize;
                let at = s + usize::from(self.lane_of[s] != none);
                self.lane_of[at] = (w * LANES + l) as u32;
            }
        }
        self.lane_of.truncate(2 * pairs);
        assert!(
            self.lane_of.iter().all(|&l| l != none),
            "every own pair is listed in two lanes"
        );
    }
}
