//! A list's slot: a neighbour's index and the periodic image it was found
//! through, in one u32, and the key a list is sorted by.

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
    pub(super) const IMAGE_SHIFT: u32 = 30;
    pub(super) const INDEX_MASK: u32 = (1 << Self::IMAGE_SHIFT) - 1;
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

/// Whether the entry (j, image `shift`) of i's list is i's own
/// ([`NeighbourList::own`]).
#[inline]
pub(super) fn is_own(i: usize, j: u32, shift: i8) -> bool {
    let j = j as usize;
    j > i || (j == i && shift == 1)
}

/// The entry (j, image `shift`) of i's list at squared distance `r2` as
/// the key its list is sorted by: one integer whose order is that of the
/// tuple (not own, r^2, j, shift), so a sort compares integers. The own
/// flag in bit 96, r^2's bits in bits 32-95 (r^2 >= 0 orders as its bits),
/// j in bits 2-31, shift + 1 in bits 0-1.
#[inline]
pub(super) fn list_key(i: usize, j: u32, shift: i8, r2: f64) -> u128 {
    debug_assert!(r2 >= 0.0 && (j as usize) < Entry::MAX_PARTICLES);
    (u128::from(!is_own(i, j, shift)) << 96)
        | (u128::from(r2.to_bits()) << 32)
        | (u128::from(j) << 2)
        | u128::from((shift + 1) as u8)
}

/// The longest list part [`sorted_into`] ranks without branches; a longer
/// one is sorted (its n^2 comparisons would cost more than a sort's
/// mispredicted branches).
const RANK_MAX: usize = 24;

/// `keys` in ascending order: `put(k, key)` for the k-th smallest, every k
/// once (equal keys, which the callers' integer keys cannot tell apart,
/// in some order: the sort is not stable). With `branch_free`, a
/// short slice is ranked without branches on the keys: each key's place is
/// the number of keys below it, so a disordered fluid's keys, whose
/// comparisons go either way, cost no mispredicted branch. Otherwise (and
/// for a long slice) `keys` is sorted in place: a lattice's keys come in a
/// pattern that repeats from list to list, which a sort's branches follow.
#[inline]
pub(super) fn sorted_into<T: Ord + Copy>(
    keys: &mut [T],
    branch_free: bool,
    mut put: impl FnMut(usize, T),
) {
    if branch_free && keys.len() <= RANK_MAX {
        for (a, &key) in keys.iter().enumerate() {
            let below = keys[..a].iter().filter(|&&k| k <= key).count()
                + keys[a + 1..].iter().filter(|&&k| k < key).count();
            put(below, key);
        }
    } else {
        keys.sort_unstable();
        for (k, &key) in keys.iter().enumerate() {
            put(k, key);
        }
    }
}
