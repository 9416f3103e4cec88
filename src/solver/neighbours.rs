//! Verlet neighbour list for the periodic strip: every pair within R h +
//! skin at the last rebuild, with the periodic image it was found through.
//!
//! Layout: a padded table, `stride` slots per particle and a count, so each
//! particle's list is one contiguous slice, filled in parallel without
//! sharing. Order within a list is fixed (bins bottom to top, particle index,
//! image), so every sum over it is the same whatever the thread count.
//!
//! Rebuild rule: a pair not in the list was more than R h + skin apart; it
//! can only have come within R h if the two displacements since the rebuild
//! differ by more than `skin`. Any two displacements differ by at most the
//! diagonal of their bounding box, so the list stays exact while that
//! diagonal is at most `skin`. (The walls never move, so the box always
//! holds the origin; in shear it grows as U t.)

use rayon::prelude::*;

/// Particles per parallel task when building.
const BUILD_CHUNK: usize = 64;

#[derive(Debug, Default)]
pub struct NeighbourList {
    stride: usize,
    count: Vec<u32>,
    index: Vec<u32>,
    /// Periodic image of the neighbour: x_j is taken as x_j - shift * width.
    shift: Vec<i8>,
    /// Cell list in y (the strip is too narrow to bin in x): particle indices
    /// sorted by bin, and where each bin starts.
    bin_start: Vec<u32>,
    bin_items: Vec<u32>,
    pub rebuilds: u64,
}

impl NeighbourList {
    /// Neighbours of particle i (itself excluded) and their image shifts.
    #[inline]
    pub fn of(&self, i: usize) -> (&[u32], &[i8]) {
        let start = i * self.stride;
        let end = start + self.count[i] as usize;
        (&self.index[start..end], &self.shift[start..end])
    }

    /// Total number of listed pairs (each counted from both sides).
    pub fn pairs(&self) -> usize {
        self.count.iter().map(|&c| c as usize).sum()
    }

    /// Rebuild for positions `x` (wrapped into [0, width)) and `y`, every pair
    /// within `cutoff` (which must be below the strip width).
    pub fn build(&mut self, x: &[f64], y: &[f64], width: f64, cutoff: f64) {
        assert!(
            cutoff < width,
            "cutoff {cutoff} must be below the strip width {width}"
        );
        let n = x.len();
        self.bin_by_y(y, cutoff);
        let (bin_start, bin_items) = (&self.bin_start, &self.bin_items);
        let ymin = y.iter().copied().fold(f64::INFINITY, f64::min);
        let n_bins = bin_start.len() - 1;
        let cutoff2 = cutoff * cutoff;

        // Visit every neighbour of i in the fixed order.
        let visit = |i: usize, f: &mut dyn FnMut(u32, i8)| {
            let (xi, yi) = (x[i], y[i]);
            let b = bin_of(yi, ymin, cutoff, n_bins);
            for bin in b.saturating_sub(1)..(b + 2).min(n_bins) {
                for &j in &bin_items[bin_start[bin] as usize..bin_start[bin + 1] as usize] {
                    let dy = yi - y[j as usize];
                    let dx0 = xi - x[j as usize];
                    for shift in -1i8..=1 {
                        if shift == 0 && j as usize == i {
                            continue;
                        }
                        let dx = dx0 + f64::from(shift) * width;
                        if dx * dx + dy * dy <= cutoff2 {
                            f(j, shift);
                        }
                    }
                }
            }
        };

        let mut count = std::mem::take(&mut self.count);
        count.resize(n, 0);
        count
            .par_iter_mut()
            .with_min_len(BUILD_CHUNK)
            .enumerate()
            .for_each(|(i, c)| {
                let mut k = 0u32;
                visit(i, &mut |_, _| k += 1);
                *c = k;
            });
        let stride = count.iter().copied().max().unwrap_or(0) as usize;
        self.stride = stride;
        self.index.resize(n * stride, 0);
        self.shift.resize(n * stride, 0);
        if stride > 0 {
            self.index
                .par_chunks_mut(stride)
                .zip(self.shift.par_chunks_mut(stride))
                .with_min_len(BUILD_CHUNK)
                .enumerate()
                .for_each(|(i, (index, shift))| {
                    let mut k = 0;
                    visit(i, &mut |j, s| {
                        index[k] = j;
                        shift[k] = s;
                        k += 1;
                    });
                });
        }
        self.count = count;
        self.rebuilds += 1;
    }

    /// Counting sort of the particles into bins of height `cutoff` in y.
    fn bin_by_y(&mut self, y: &[f64], cutoff: f64) {
        let ymin = y.iter().copied().fold(f64::INFINITY, f64::min);
        let ymax = y.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let n_bins = ((ymax - ymin) / cutoff).floor() as usize + 1;
        self.bin_start.clear();
        self.bin_start.resize(n_bins + 1, 0);
        for &yi in y {
            self.bin_start[bin_of(yi, ymin, cutoff, n_bins) + 1] += 1;
        }
        for b in 0..n_bins {
            self.bin_start[b + 1] += self.bin_start[b];
        }
        self.bin_items.resize(y.len(), 0);
        let mut fill = self.bin_start.clone();
        for (i, &yi) in y.iter().enumerate() {
            let b = bin_of(yi, ymin, cutoff, n_bins);
            self.bin_items[fill[b] as usize] = i as u32;
            fill[b] += 1;
        }
    }
}

#[inline]
fn bin_of(y: f64, ymin: f64, cutoff: f64, n_bins: usize) -> usize {
    (((y - ymin) / cutoff) as usize).min(n_bins - 1)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::solver::lattice::Lattice;

    /// Brute force over all pairs and images.
    fn brute(x: &[f64], y: &[f64], width: f64, cutoff: f64, i: usize) -> Vec<(u32, i8)> {
        let mut out = Vec::new();
        for j in 0..x.len() {
            for s in -1i8..=1 {
                if s == 0 && i == j {
                    continue;
                }
                let dx = x[i] - x[j] + f64::from(s) * width;
                let dy = y[i] - y[j];
                if dx * dx + dy * dy <= cutoff * cutoff {
                    out.push((j as u32, s));
                }
            }
        }
        out.sort();
        out
    }

    #[test]
    fn matches_brute_force_on_a_jittered_lattice() {
        let l = Lattice::new(5, 1.0, 1.0, 2.0);
        let (mut x, mut y, _) = l.positions();
        // Deterministic jitter, then wrap x into the strip.
        for i in 0..x.len() {
            let s = (i as f64 * 12.9898).sin() * 43758.5453;
            x[i] = (x[i] + 0.3 * (s - s.floor() - 0.5)).rem_euclid(l.width);
            y[i] += 0.2 * ((i as f64 * 7.31).sin());
        }
        let cutoff = 2.3;
        let mut list = NeighbourList::default();
        list.build(&x, &y, l.width, cutoff);
        for i in 0..x.len() {
            let (idx, sh) = list.of(i);
            let mut got: Vec<(u32, i8)> = idx.iter().copied().zip(sh.iter().copied()).collect();
            got.sort();
            assert_eq!(got, brute(&x, &y, l.width, cutoff, i), "particle {i}");
        }
    }
}
