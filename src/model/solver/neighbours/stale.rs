//! When the list must be rebuilt: each block's displacement box since the
//! rebuild, and the pairs of blocks near enough in y to need the check.

use super::*;

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
    pub(super) fn find_near_blocks(&mut self, y: &[f64], cutoff: f64, block: usize) {
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
}

/// Each block's lowest and highest y (infinite both for a block of NaN).
pub(super) fn block_ranges(y: &[f64], block: usize) -> Vec<(f64, f64)> {
    y.chunks(block)
        .map(|c| {
            c.iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| {
                    (lo.min(v), hi.max(v))
                })
        })
        .collect()
}
