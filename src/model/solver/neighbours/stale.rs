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
    /// `slack`: its diagonal against `slack`, squared (no square root: the
    /// rebuild test runs every step over every pair of near blocks).
    #[inline]
    pub fn wider_than(&self, slack: f64) -> bool {
        let (w, h) = (self.dx_max - self.dx_min, self.dy_max - self.dy_min);
        w * w + h * h > slack * slack
    }
}

/// What the rebuild rule weighs the blocks' boxes against: the skin, the
/// cutoff the list was built with (R h + skin) and how far the shear
/// reference has parted particles from where the list was built, per unit
/// of their distance in y (`parting`: the reference profile's Lipschitz
/// constant times the time from the positions listed, [`crate::solver::step`]'s
/// `State::shear_reference`; 0 without a reference). A list built at the
/// rebuild's positions takes the time since the rebuild; one built ahead
/// along the reference, at the positions it reaches at tau
/// (`State::ahead`), |t - tau|: the same bound, from there.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Reach {
    pub skin: f64,
    pub cutoff: f64,
    pub parting: f64,
}

impl Reach {
    /// How much two particles' displacements from their references may
    /// differ (the diagonal of their blocks' boxes) before the list may
    /// miss a pair within R h = cutoff - skin; the skin itself without a
    /// reference. Each displacement is the reference's, (u(y0) t, 0), plus
    /// the rest the boxes bound. A pair not listed was r0 = (a, b) apart
    /// where the list was built, |r0| > C = cutoff; the references move it
    /// from there along x by at most
    /// L = `parting` times |b|, which brings it no nearer than
    /// min over |b| <= C of sqrt((sqrt(C^2 - b^2) - L |b|)^2 + b^2)
    /// = C (sqrt(1 + L^2/4) - L/2) (at b = C sin(theta), the minimum of
    /// C^2 (1 - L sin 2 theta + L^2 sin^2 theta) over theta; a pair with
    /// |b| > C is as far as it was anyway). The rest moves it by at most
    /// the diagonal, so the pair stays beyond R h while the diagonal is
    /// below that nearest distance less R h (less 1e-9 C for the rounding
    /// of the references). Negative when no diagonal is safe.
    pub fn slack(&self) -> f64 {
        if self.parting == 0.0 {
            return self.skin;
        }
        let (c, l) = (self.cutoff, self.parting);
        let nearest = c * ((1.0 + 0.25 * l * l).sqrt() - 0.5 * l);
        nearest - (c - self.skin) - 1e-9 * c
    }
}

impl NeighbourList {
    /// Whether the list may miss a pair within `cutoff - skin`, given each
    /// block's box of displacements from the shear reference (x0 + u t,
    /// y0) and how far that reference has parted the particles
    /// ([`Reach`]). Blocks near in y at the rebuild are checked pair by
    /// pair against [`Reach::slack`]; the others were more than the
    /// cutoff apart in y, which the reference does not change (it moves
    /// along x only): they need no two y displacements of the fluid to
    /// differ by more than the skin.
    pub fn stale(&self, box_of: impl Fn(usize) -> Displacements, reach: Reach) -> bool {
        self.stale_each(box_of, [reach])[0]
    }

    /// [`Self::stale`] for each of `reaches` on the same boxes (a list and
    /// the one another rebuild would have built, `Listing` in the solver):
    /// each box and union formed once, the same answer as each alone.
    pub fn stale_each<const K: usize>(
        &self,
        box_of: impl Fn(usize) -> Displacements,
        reaches: [Reach; K],
    ) -> [bool; K] {
        // No room, or none known (a time or profile that is not finite):
        // rebuild.
        let slack = reaches.map(|r| r.slack());
        let mut stale = slack.map(|s| s.is_nan() || s <= 0.0);
        if stale.iter().all(|&s| s) {
            return stale;
        }
        let n_blocks = self.near_start.len() - 1;
        let all = (0..n_blocks).fold(Displacements::EMPTY, |acc, b| acc.union(box_of(b)));
        for (s, r) in stale.iter_mut().zip(&reaches) {
            *s |= all.dy_max - all.dy_min > r.skin;
        }
        let mut weigh = |d: Displacements| {
            for (s, &slack) in stale.iter_mut().zip(&slack) {
                *s = *s || d.wider_than(slack);
            }
            stale.iter().all(|&s| s)
        };
        for a in 0..n_blocks {
            let box_a = box_of(a);
            if weigh(box_a)
                || self.near[self.near_start[a] as usize..self.near_start[a + 1] as usize]
                    .iter()
                    .any(|&b| weigh(box_a.union(box_of(b as usize))))
            {
                break;
            }
        }
        stale
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
