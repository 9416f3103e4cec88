//! The neighbour lists' tests.

/// Uniform numbers in [0, 1) from `seed` (a 64-bit LCG), for the tests'
/// random pairs: the same sequence on every machine.
pub(crate) fn uniform(seed: u64) -> impl FnMut() -> f64 {
    let mut state = seed;
    move || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    }
}

mod lists {
    use super::super::*;
    use crate::problem::lattice::LatticeGeometry;

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

    /// A deterministic jitter of up to `ax` / 2 in x and `ay` in y, then x
    /// wrapped into the strip.
    fn jitter(x: &mut [f64], y: &mut [f64], width: f64, ax: f64, ay: f64) {
        for i in 0..x.len() {
            let s = (i as f64 * 12.9898).sin() * 43758.5453;
            x[i] = (x[i] + ax * (s - s.floor() - 0.5)).rem_euclid(width);
            y[i] += ay * ((i as f64 * 7.31).sin());
        }
    }

    /// Every list is brute force's, and its windows hold it.
    fn check_lists(list: &NeighbourList, x: &[f64], y: &[f64], width: f64, cutoff: f64) {
        for i in 0..x.len() {
            assert_eq!(
                listed(list, i),
                brute(x, y, width, cutoff, i),
                "particle {i}"
            );
        }
        check_windows(list, x.len());
    }

    /// Particle i's list as (index, image shift), sorted: what [`brute`]
    /// returns.
    fn listed(list: &NeighbourList, i: usize) -> Vec<(u32, i8)> {
        let mut got: Vec<(u32, i8)> = list
            .of(i)
            .iter()
            .map(|&e| (Entry::index(e) as u32, Entry::image(e) as i8 - 1))
            .collect();
        got.sort();
        got
    }

    /// The windows hold every entry once, at its index's lane, with its
    /// image and its slot's source, and nothing else: a lane not listed
    /// points at the zero place; every window lies inside the arrays. Each
    /// own pair's two lanes ([`NeighbourList::lanes_of_pairs`]) are the
    /// two listed lanes whose source it is, the first in window order
    /// first, and every listed lane is one pair's. A window is unshifted
    /// exactly when no lane's image is another, and its offsets are then +0.
    fn check_windows(list: &NeighbourList, n: usize) {
        let mut listed = Vec::new();
        for i in 0..n {
            let mut want: Vec<(usize, usize, u32)> = list
                .of(i)
                .iter()
                .zip(list.sources_padded(i))
                .map(|(&e, &src)| (Entry::image(e), Entry::index(e), src))
                .collect();
            want.sort();
            let mut got = Vec::new();
            let first = list.window_start(i);
            for (k, (w, src)) in list
                .windows(i)
                .iter()
                .zip(list.window_sources(i))
                .enumerate()
            {
                assert!(w.start as usize + LANES <= n, "particle {i}");
                // A window through no image is one the force pass adds +0
                // to (Window::unshifted).
                assert_eq!(
                    w.unshifted(),
                    (0..LANES).all(|l| w.image(l) == 1),
                    "particle {i}"
                );
                if w.unshifted() {
                    assert!((0..LANES).all(|l| w.offset(l, list.width()).to_bits() == 0));
                }
                for (l, &src) in src.iter().enumerate() {
                    if w.mask() & (1 << l) != 0 {
                        got.push((w.image(l) as usize, w.start as usize + l, src));
                        listed.push(((first + k) * LANES + l, src));
                    } else {
                        assert_eq!(src as usize, list.own_pairs());
                    }
                }
            }
            got.sort();
            assert_eq!(got, want, "particle {i}");
        }
        let lanes = list.lanes_of_pairs();
        assert_eq!(lanes.len(), 2 * list.own_pairs());
        assert!(
            lanes.chunks_exact(2).all(|p| p[0] < p[1]),
            "each pair's first lane in window order comes first"
        );
        let mut from_pairs: Vec<(usize, u32)> = lanes
            .iter()
            .enumerate()
            .map(|(k, &lane)| (lane as usize, (k / 2) as u32))
            .collect();
        from_pairs.sort();
        listed.sort();
        assert_eq!(
            from_pairs, listed,
            "each listed lane is one pair's, each pair in two"
        );
    }

    /// A strip narrower than two cutoffs lists some neighbours through two
    /// images: each is in two windows, and the lists are still complete.
    #[test]
    fn a_narrow_strip_lists_some_neighbours_twice() {
        let l = LatticeGeometry::new(crate::kernel::Lattice::Square, 4, 1.0, 1.0, 2.0);
        let (x, y, _) = l.positions();
        let cutoff = 0.9 * l.width;
        let mut list = NeighbourList::default();
        list.build(&x, &y, l.width, cutoff, l.columns as usize);
        let twice = (0..x.len()).any(|i| {
            let mut js: Vec<usize> = list.of(i).iter().map(|&e| Entry::index(e)).collect();
            js.sort();
            js.windows(2).any(|p| p[0] == p[1])
        });
        assert!(twice, "some particle is listed through two images");
        check_lists(&list, &x, &y, l.width, cutoff);
    }

    /// A strip many cutoffs wide is binned in x too (periodic columns of
    /// cells): the lists are still every pair within the cutoff, through
    /// the right image, in the documented order (own first, then by r^2,
    /// index and image), whatever the cells.
    #[test]
    fn a_wide_strip_binned_in_x_matches_brute_force() {
        let mut l = LatticeGeometry::new(crate::kernel::Lattice::Square, 4, 1.0, 1.3, 2.0);
        l.columns = 40;
        l.width = 40.0;
        let (mut x, mut y, _) = l.positions();
        jitter(&mut x, &mut y, l.width, 0.4, 0.3);
        let cutoff = 3.0;
        let mut list = NeighbourList::default();
        list.build(&x, &y, l.width, cutoff, l.columns as usize);
        for i in 0..x.len() {
            let key = |e: u32| {
                let j = Entry::index(e);
                let dx = x[i] - x[j] + Entry::offset(e, l.width);
                let dy = y[i] - y[j];
                let own = j > i || (j == i && Entry::image(e) == 2);
                (!own, (dx * dx + dy * dy).to_bits(), j, Entry::image(e))
            };
            let keys: Vec<_> = list.of(i).iter().map(|&e| key(e)).collect();
            assert!(keys.is_sorted(), "particle {i}: the list's order");
        }
        check_lists(&list, &x, &y, l.width, cutoff);
    }

    /// Every number of cell columns, from one (a narrow strip) to six:
    /// the lists are brute force's, and a particle on a column's edge or
    /// the strip's finds its neighbours through the right image.
    #[test]
    fn every_column_count_matches_brute_force() {
        for columns in [3u32, 5, 7, 8, 9, 10, 12, 14] {
            let mut l = LatticeGeometry::new(crate::kernel::Lattice::Triangular, 3, 1.0, 1.0, 2.0);
            l.columns = columns;
            l.width = f64::from(columns);
            let (mut x, mut y, _) = l.positions();
            jitter(&mut x, &mut y, l.width, 0.45, 0.3);
            // On the edges: the first column's edge, the strip's.
            x[0] = 0.0;
            x[1] = l.width * (1.0 - f64::EPSILON);
            let cutoff = 2.3;
            let mut list = NeighbourList::default();
            list.build(&x, &y, l.width, cutoff, l.columns as usize);
            check_lists(&list, &x, &y, l.width, cutoff);
        }
    }

    /// The two forms of a build (a lattice's, with branches on the
    /// distances; a disordered fluid's, without) give the same list, entry
    /// for entry: the same order, sources, windows and lanes. On narrow
    /// strips (every image tried), strips binned in x (the nearest image
    /// alone), and with particles on the columns' and the strip's edges.
    #[test]
    fn both_forms_of_a_build_give_the_same_list() {
        for (columns, cutoff) in [
            (3u32, 2.3),
            (5, 2.3),
            (6, 2.3),
            (7, 2.3),
            (12, 2.3),
            (40, 3.0),
        ] {
            let mut l = LatticeGeometry::new(crate::kernel::Lattice::Triangular, 3, 1.0, 1.0, 2.0);
            l.columns = columns;
            l.width = f64::from(columns);
            let (mut x, mut y, _) = l.positions();
            jitter(&mut x, &mut y, l.width, 0.9, 0.45);
            x[0] = 0.0;
            x[1] = l.width * (1.0 - f64::EPSILON);
            x[2] = 0.5 * l.width;
            let build = |disordered: bool| {
                let mut list = NeighbourList::default();
                list.set_disordered(disordered);
                list.build(&x, &y, l.width, cutoff, l.columns as usize);
                list
            };
            let (a, b) = (build(false), build(true));
            for i in 0..x.len() {
                assert_eq!(a.of(i), b.of(i), "{columns} columns, particle {i}");
                assert_eq!(a.own(i), b.own(i));
                assert_eq!(a.sources_padded(i), b.sources_padded(i));
                assert_eq!(a.windows(i), b.windows(i));
                assert_eq!(a.window_sources(i), b.window_sources(i));
            }
            assert_eq!(a.lanes_of_pairs(), b.lanes_of_pairs());
            check_lists(&b, &x, &y, l.width, cutoff);
            // The widest reaches have parts too long to rank: sorted
            // instead ([`entry::place_ranked`]); the others, ranked.
            let longest = (0..x.len())
                .map(|i| b.own(i).max(b.of(i).len() - b.own(i)))
                .max()
                .unwrap_or(0);
            assert_eq!(
                longest > entry::RANK_MAX,
                cutoff >= 3.0,
                "{columns} columns: {longest}"
            );
        }
    }

    /// A disordered fluid's build tries the branch-free form, then the
    /// other, then keeps the cheaper, trying the other again every
    /// [`Forms::RETRY`] builds.
    #[test]
    fn the_cheaper_form_is_kept_and_the_other_retried() {
        let mut forms = Forms::default();
        assert!(forms.pick(), "the branch-free form first");
        forms.record(true, 100.0);
        assert!(!forms.pick(), "then the other");
        forms.record(false, 300.0);
        let picks: Vec<bool> = (0..2 * Forms::RETRY).map(|_| forms.pick()).collect();
        // The cheaper (branch-free) form, but the other at every RETRY-th.
        let retried: Vec<usize> = (0..picks.len()).filter(|&k| !picks[k]).collect();
        let r = Forms::RETRY as usize;
        assert_eq!(retried, vec![r - 1, 2 * r - 1], "{picks:?}");
        // The costs are running means: cheaper builds of the other form
        // tip the choice once its mean is below (300 -> 155 -> 82.5).
        forms.record(false, 10.0);
        assert!(forms.pick(), "155 ns is still above 100");
        forms.record(false, 10.0);
        assert!(!forms.pick(), "82.5 ns is below 100");
    }

    /// Both forms of [`entry::sorted_into`] put every key once, in order;
    /// short slices and long, distinct keys and repeated ones.
    #[test]
    fn sorted_into_puts_the_keys_in_order() {
        for len in [0usize, 1, 2, 7, 24, 25, 40] {
            let keys: Vec<(u32, usize)> = (0..len).map(|k| (((k * 7919) % 11) as u32, k)).collect();
            let mut want = keys.clone();
            want.sort();
            for branch_free in [false, true] {
                let mut got = vec![None; len];
                let mut work = keys.clone();
                entry::sorted_into(&mut work, branch_free, |k, key| {
                    assert!(got[k].replace(key).is_none(), "place {k} put twice");
                });
                let got: Vec<_> = got
                    .into_iter()
                    .map(|k| k.expect("every place put"))
                    .collect();
                assert_eq!(got, want, "{len} keys, branch_free {branch_free}");
                // Repeated keys (the first fields alone): each place gets
                // the key a sort puts there.
                let firsts: Vec<u32> = keys.iter().map(|k| k.0).collect();
                let mut firsts_sorted = firsts.clone();
                firsts_sorted.sort();
                let mut only: Vec<u32> = firsts.clone();
                entry::sorted_into(&mut only, branch_free, |k, key| {
                    assert_eq!(key, firsts_sorted[k]);
                });
            }
        }
    }

    /// [`entry::place_ranked`] puts every key once, in the order of
    /// (primary, tie): primaries repeated (ties decide), ranked up to
    /// RANK_MAX keys and sorted beyond, on every instruction set.
    #[test]
    fn place_ranked_puts_the_keys_in_order() {
        for len in [0usize, 1, 7, 8, 9, 24, 25, 40] {
            let keys: Vec<(f64, f64)> = (0..len)
                .map(|k| (((k * 7919) % 5) as f64 * 0.25, ((k * 104_729) % 61) as f64))
                .collect();
            let mut want = keys.clone();
            want.sort_by(|a, b| a.partial_cmp(b).expect("no NaN"));
            let lanes = padded(len);
            let mut primary: Vec<f64> = keys.iter().map(|k| k.0).collect();
            primary.resize(lanes, f64::INFINITY);
            let mut tie: Vec<f64> = keys.iter().map(|k| k.1).collect();
            tie.resize(lanes, 0.0);
            for isa in crate::solver::step::every_isa() {
                let mut places = vec![0u32; lanes];
                let mut got = vec![None; len];
                entry::place_ranked(isa, (&primary, &tie), len, &mut places, |k, a| {
                    assert!(got[k].replace(keys[a]).is_none(), "place {k} put twice");
                });
                let got: Vec<_> = got
                    .into_iter()
                    .map(|k| k.expect("every place put"))
                    .collect();
                assert_eq!(got, want, "{len} keys, {isa:?}");
            }
        }
    }

    #[test]
    fn matches_brute_force_on_a_jittered_lattice() {
        let l = LatticeGeometry::new(crate::kernel::Lattice::Triangular, 5, 1.0, 1.0, 2.0);
        let (mut x, mut y, _) = l.positions();
        jitter(&mut x, &mut y, l.width, 0.3, 0.2);
        let cutoff = 2.3;
        let mut list = NeighbourList::default();
        list.build(&x, &y, l.width, cutoff, l.columns as usize);
        for i in 0..x.len() {
            let mut got: Vec<(u32, i8)> = list
                .of(i)
                .iter()
                .map(|&e| {
                    let off = Entry::offset(e, list.width());
                    (Entry::index(e) as u32, (off / l.width).round() as i8)
                })
                .collect();
            got.sort();
            assert_eq!(got, brute(&x, &y, l.width, cutoff, i), "particle {i}");
        }
        // Own entries first, and in the pair table's stream in turn; every
        // other one's source is its mirror, an own entry of its neighbour;
        // padding's the zero place.
        let (stream, owners) = list.own_stream();
        for i in 0..x.len() {
            let at = list.own_start(i);
            assert_eq!(&stream[at..at + list.own(i)], &list.of(i)[..list.own(i)]);
            assert!(owners[at..at + list.own(i)]
                .iter()
                .all(|&o| o as usize == i));
        }
        assert_eq!(
            list.own_start(x.len() - 1) + list.own(x.len() - 1),
            list.own_pairs()
        );
        for i in 0..x.len() {
            let (own, count) = (list.own(i), list.of(i).len());
            assert!(list.of(i)[..own].iter().all(|&e| {
                let j = Entry::index(e);
                j > i || (j == i && Entry::image(e) == 2)
            }));
            for (slot, &src) in list.sources_padded(i).iter().enumerate() {
                let src = src as usize;
                if slot < own {
                    assert_eq!(src, list.own_start(i) + slot);
                } else if slot < count {
                    let e = list.of(i)[slot];
                    let j = Entry::index(e);
                    let k = src.wrapping_sub(list.own_start(j));
                    assert!(k < list.own(j), "particle {i} slot {slot}");
                    let m = list.of(j)[k];
                    assert_eq!(Entry::index(m), i);
                    assert_eq!(Entry::image(m), 2 - Entry::image(e));
                } else {
                    assert_eq!(src, list.own_pairs());
                }
            }
        }
        check_windows(&list, x.len());
        assert!(list.window_count() * 2 < list.pairs(), "rows come in runs");
    }
}

mod stale_tests {
    use super::super::stale::block_ranges;
    use super::super::*;
    use crate::problem::lattice::LatticeGeometry;

    #[test]
    fn shear_between_near_layers_triggers_a_rebuild() {
        let l = LatticeGeometry::new(crate::kernel::Lattice::Triangular, 6, 1.0, 1.0, 2.0);
        let (x, y, layer) = l.positions();
        let mut list = NeighbourList::default();
        list.build(&x, &y, l.width, 2.3, l.columns as usize);
        let n_blocks = x.len() / l.columns as usize;
        // Every block moves along x by the steady profile's speed times t.
        let moved = |t: f64| -> Vec<Displacements> {
            (0..n_blocks)
                .map(|b| {
                    let n = layer[b * l.columns as usize];
                    let u = if n.abs() < 6 {
                        1.0 - (n as f64 / 6.0).powi(2)
                    } else {
                        0.0
                    };
                    let mut d = Displacements::EMPTY;
                    d.add(u * t, 0.0);
                    d
                })
                .collect()
        };
        // Blocks within reach are at most 2 layers apart (3 dy > 2.3); the
        // fastest relative motion among them is layer 4 (u = 20/36) against
        // the wall layer 6.
        let v = 20.0 / 36.0;
        let reach = Reach {
            skin: 0.3,
            cutoff: 2.3,
            parting: 0.0,
        };
        let stale = |b: &[Displacements]| list.stale(|k| b[k], reach);
        assert!(!stale(&moved(0.29 / v)));
        assert!(stale(&moved(0.31 / v)));
        // A transverse spread over the skin always does.
        let mut b = vec![Displacements::ZERO; n_blocks];
        b[0] = Displacements::EMPTY;
        b[0].add(0.0, 0.31);
        assert!(stale(&b));
        // Several reaches weighed together on the same boxes
        // ([`NeighbourList::stale_each`]) answer as each alone, in either
        // order: stale, not, and one of each.
        let mut mixed = false;
        for boxes in [0.1, 0.29 / v, 0.31 / v, 1.0]
            .map(moved)
            .into_iter()
            .chain([b])
        {
            for parting in [0.0, 0.05, 0.2, 0.3, f64::NAN] {
                let other = Reach { parting, ..reach };
                let alone = [
                    list.stale(|k| boxes[k], reach),
                    list.stale(|k| boxes[k], other),
                ];
                mixed |= alone[0] != alone[1];
                assert_eq!(list.stale_each(|k| boxes[k], [reach, other]), alone);
                assert_eq!(
                    list.stale_each(|k| boxes[k], [other, reach]),
                    [alone[1], alone[0]]
                );
            }
        }
        assert!(mixed, "some boxes stale for one reach and not the other");
    }

    /// [`Reach::slack`] is the bound it says and no looser: a pair more
    /// than the cutoff C apart at the rebuild, parted along x by the
    /// reference by at most L |dy| and moved by the rest by at most the
    /// slack, stays beyond R h = C - skin, over random pairs; at the worst
    /// angle, moved straight in by 2e-9 C more than the slack, it comes
    /// within R h.
    #[test]
    fn the_slack_holds_every_unlisted_pair_beyond_the_support_and_no_more() {
        let (skin, cutoff) = (0.3, 2.3);
        let reach_h = cutoff - skin;
        let mut uniform = super::uniform(0x9e37_79b9_7f4a_7c15);
        for parting in [0.0, 1e-3, 0.05, 0.1, 0.2, 0.26] {
            let slack = Reach {
                skin,
                cutoff,
                parting,
            }
            .slack();
            assert!(slack > 0.0 && slack <= skin, "{parting}: {slack}");
            for _ in 0..20_000 {
                // At the rebuild: beyond the cutoff, at any angle.
                let (r0, theta) = (cutoff * (1.0 + 1e-6 + 0.2 * uniform()), uniform() * 6.3);
                let (a, b) = (r0 * theta.cos(), r0 * theta.sin());
                // The reference's parting toward the other, at most L |b|,
                // and the rest in any direction, at most the slack.
                let along = -(parting * b.abs() * uniform()).copysign(a);
                let (rest, phi) = (slack * uniform(), uniform() * 6.3);
                let (x, y) = (a + along + rest * phi.cos(), b + rest * phi.sin());
                assert!(x.hypot(y) > reach_h, "{parting}: reached {}", x.hypot(y));
            }
            // The worst pair: at the angle where the parting brings it
            // nearest, moved in by the parting and then straight in.
            let worst = if parting > 0.0 {
                0.5 * (2.0 / parting).atan()
            } else {
                0.0
            };
            let (a, b) = (cutoff * worst.cos(), cutoff * worst.sin());
            let (x, y) = (a - parting * b, b);
            let r = x.hypot(y);
            let inward = (slack + 2e-9 * cutoff) / r;
            let reached = (x * (1.0 - inward)).hypot(y * (1.0 - inward));
            assert!(reached < reach_h, "{parting}: {reached} is a looser bound");
        }
        // A parting that leaves no room: stale whatever the boxes.
        let none = Reach {
            skin,
            cutoff,
            parting: 0.3,
        };
        assert!(none.slack() < 0.0);
        // A parting that is not finite is no room either.
        let list = NeighbourList::default();
        for parting in [0.3, f64::NAN, f64::INFINITY] {
            let reach = Reach {
                skin,
                cutoff,
                parting,
            };
            assert!(list.stale(|_| Displacements::ZERO, reach), "{parting}");
        }
    }

    /// The blocks near each block, by testing every pair: what
    /// [`NeighbourList::find_near_blocks`] must give.
    fn near_by_brute_force(y: &[f64], cutoff: f64, block: usize) -> Vec<Vec<u32>> {
        let ranges = block_ranges(y, block);
        (0..ranges.len())
            .map(|a| {
                (a + 1..ranges.len())
                    .filter(|&b| {
                        let ((lo_a, hi_a), (lo_b, hi_b)) = (ranges[a], ranges[b]);
                        (lo_b - hi_a).max(lo_a - hi_b) <= cutoff
                    })
                    .map(|b| b as u32)
                    .collect()
            })
            .collect()
    }

    fn near_of(list: &NeighbourList) -> Vec<Vec<u32>> {
        (0..list.near_start.len() - 1)
            .map(|a| {
                list.near[list.near_start[a] as usize..list.near_start[a + 1] as usize].to_vec()
            })
            .collect()
    }

    #[test]
    fn near_blocks_are_those_of_testing_every_pair() {
        // A tall strip (the walls' layers stored after the fluid's, so the
        // blocks are not in order of y), on the lattice (layers exactly
        // one cutoff apart at cutoff 1) and jittered in y by up to a third
        // of the spacing.
        let l = LatticeGeometry::new(crate::kernel::Lattice::Square, 60, 1.0, 1.0, 2.0);
        let (x, mut y, _) = l.positions();
        let block = l.columns as usize;
        let check = |y: &[f64], cutoff: f64| {
            assert!(cutoff < l.width);
            let mut list = NeighbourList::default();
            list.build(&x, y, l.width, cutoff, block);
            assert_eq!(
                near_of(&list),
                near_by_brute_force(y, cutoff, block),
                "cutoff {cutoff}"
            );
        };
        check(&y, 1.0);
        for (i, y) in y.iter_mut().enumerate() {
            *y += 0.33 * ((i as f64 * 7.31).sin());
        }
        for cutoff in [0.5, 1.0, 2.3, 4.0] {
            check(&y, cutoff);
        }
        // A state that is not finite takes the pairwise test itself.
        y[3] = f64::NAN;
        y[block * 5] = f64::INFINITY;
        check(&y, 2.3);
    }
}
