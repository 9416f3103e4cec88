//! A list's slot: a neighbour's index and the periodic image it was found
//! through, in one u32, and the key a list is sorted by.

use super::super::step::Isa;

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

/// The longest list part [`sorted_into`] and [`ranks`] rank without
/// branches; a longer one is sorted (its n^2 comparisons would cost more
/// than a sort's mispredicted branches).
pub(super) const RANK_MAX: usize = 24;

/// The place of each of `m` keys in ascending order: `places[a]` = the
/// number of keys below key a, each key the pair (`primary[a]`,
/// `tie[a]`) compared field by field, as f64. Without branches on the keys,
/// LANES keys compared at a time: a disordered fluid's comparisons go
/// either way. The keys must be distinct and not NaN; `primary` and `tie`
/// run on to a whole number of LANES ([`padded`]`(m)`), `primary` +inf past
/// m (never below a key), and `places` has room for as many.
#[inline(always)]
pub(super) fn ranks(primary: &[f64], tie: &[f64], m: usize, places: &mut [u32]) {
    let lanes = padded(m);
    let (primary, tie, places) = (&primary[..lanes], &tie[..lanes], &mut places[..lanes]);
    places.fill(0);
    // Key b against every key a at once: a vector of places.
    for (&p, &t) in primary[..m].iter().zip(tie) {
        for ((place, &pa), &ta) in places.iter_mut().zip(primary).zip(tie) {
            *place += u32::from((p < pa) | ((p == pa) & (t < ta)));
        }
    }
}

/// `put(k, a)` for key a the k-th smallest of `m` keys given as [`ranks`]
/// takes them (`primary` and `tie` run on to [`padded`]`(m)`, `primary`
/// +inf past m; `places` room for as many): ranked without branches up to
/// [`RANK_MAX`], sorted beyond (a primary field >= 0, whose order is that
/// of its bits, and a tie a whole number below 2^32).
#[inline]
pub(super) fn place_ranked(
    isa: Isa,
    (primary, tie): (&[f64], &[f64]),
    m: usize,
    places: &mut [u32],
    mut put: impl FnMut(usize, usize),
) {
    if m <= RANK_MAX {
        ranks_on(isa, primary, tie, m, places);
        for (a, &k) in places[..m].iter().enumerate() {
            put(k as usize, a);
        }
    } else {
        let mut keys: Vec<u128> = primary[..m]
            .iter()
            .zip(tie)
            .enumerate()
            .map(|(a, (&p, &t))| {
                u128::from(p.to_bits()) << 64 | u128::from(t as u32) << 32 | a as u128
            })
            .collect();
        keys.sort_unstable();
        for (k, &key) in keys.iter().enumerate() {
            put(k, key as u32 as usize);
        }
    }
}

on_isa! {
    /// [`ranks`] compiled for the instruction set `isa`.
    pub(super) fn ranks_on[] => ranks[](
        primary: &[f64],
        tie: &[f64],
        m: usize,
        places: &mut [u32]
    )
}

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
