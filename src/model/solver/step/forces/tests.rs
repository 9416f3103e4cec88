//! The force pass's tests: every instruction set against the scalar pair.

use super::super::density::{pair_gather_on, pair_kernel_on};
use super::super::isa::{every_isa, BLOCK};
use super::*;
use crate::kernels::Morris;
use crate::solver::neighbours::Entry;

/// Positions, velocities and windows over 200 particles for the pair
/// loops' tests, and where each window lane's pair is in a table of 40
/// (dW/dq)/q.
struct Fixture {
    x: Vec<f64>,
    y: Vec<f64>,
    v: Vec<f64>,
    windows: Vec<Window>,
    sources: Vec<[u32; LANES]>,
    width: f64,
}

impl Fixture {
    fn new() -> Fixture {
        let n = 200;
        // Windows over the particles: starts anywhere (the last one at
        // the end of the arrays), some lanes listed, every image.
        let (windows, sources) = (0..6u32)
            .map(|k| {
                let start = if k == 5 { n as u32 - 8 } else { k * 31 % 150 };
                let mask = [0xff, 0x5a, 0x01, 0x80, 0x3c, 0xe7][k as usize];
                let src: [u32; 8] = std::array::from_fn(|l| (k * 8 + l as u32) % 40);
                let images: [u32; 8] = std::array::from_fn(|l| (k + l as u32) % 3);
                (Window::new(start, mask, images), src)
            })
            .unzip();
        Fixture {
            x: (0..n).map(|i| (i as f64 * 0.618).fract() * 7.0).collect(),
            y: (0..n).map(|i| (i as f64 * 0.377).fract() * 7.0).collect(),
            v: (0..n).map(|i| (i as f64 * 0.123).sin()).collect(),
            windows,
            sources,
            width: 7.0,
        }
    }

    /// The windows' lanes' (dW/dq)/q from the table `pg`, as the
    /// kernel pass leaves them: 0 in a lane not listed.
    fn lane_g(&self, pg: &[f64]) -> Vec<f64> {
        self.windows
            .iter()
            .zip(&self.sources)
            .flat_map(|(w, src)| {
                (0..LANES).map(move |l| {
                    if w.mask() & (1 << l) != 0 {
                        pg[src[l] as usize]
                    } else {
                        0.0
                    }
                })
            })
            .collect()
    }

    /// The windows' sources as the list gives them to the gathering form:
    /// the zero place `zero` for a lane not listed.
    fn gather_sources(&self, zero: u32) -> Vec<[u32; LANES]> {
        self.windows
            .iter()
            .zip(&self.sources)
            .map(|(w, src)| {
                std::array::from_fn(|l| {
                    if w.mask() & (1 << l) != 0 {
                        src[l]
                    } else {
                        zero
                    }
                })
            })
            .collect()
    }

    /// Particle 0's force inputs with the windows' (dW/dq)/q `g`, its y
    /// as the walls' depths (>= 0).
    fn args<'a>(&'a self, g: WindowG<'a>, scales: Scales) -> ForceArgs<'a> {
        ForceArgs {
            i: 0,
            windows: &self.windows[..],
            g,
            xs: (&self.x[..], &self.y[..]),
            vs: (&self.v[..], &self.v[..]),
            pressure_term: &self.v[..],
            vol: &self.x[..],
            depth: &self.y[..],
            width: self.width,
            scales,
        }
    }
}

fn test_scales(inv_gap: f64, beta_max: f64) -> Scales {
    Scales {
        pressure: 0.7,
        av: 0.3,
        visc: 0.2,
        inv_gap,
        beta_max,
    }
}

/// The pair loops give the same bits whatever instructions they were
/// compiled for: the vector builds only run the same operations in the
/// same order in lanes.
#[test]
fn pair_loops_give_the_same_bits_on_every_isa() {
    let f = Fixture::new();
    let n = f.x.len();
    // 37 neighbours (four whole lane groups and a part) and padding.
    let mut entries: Vec<u32> = (1..38)
        .map(|j| Entry::pack(j * 5 % n, (j % 3) as i8 - 1))
        .collect();
    entries.resize(40, Entry::padding(0));
    // Where each slot's kernel values come from: a permutation of the
    // evaluated slots, and for the padding the zero slot after them.
    let sources: Vec<u32> = (0..entries.len() as u32)
        .map(|s| if s < 37 { (s * 7 + 3) % 37 } else { 40 })
        .collect();
    let run = |isa: Isa| {
        let mut w = vec![0.0; entries.len() + 1];
        let mut pg = vec![0.0; entries.len() + 1];
        let scratch = &mut ([0.0; BLOCK], [0.0; BLOCK]);
        let owners = vec![0u32; entries.len()];
        let xs = (&f.x[..], &f.y[..]);
        let out = (&mut w[..40], &mut pg[..40]);
        pair_kernel_on::<Morris>(isa, &entries, &owners, xs, f.width, 0.5, out, scratch);
        let w_sum = pair_gather_on(isa, &sources, (0, 0), &w);
        let lane_g = f.lane_g(&pg);
        let scales = test_scales(0.9, 3.0);
        let force =
            pair_forces_on::<true, true, false>(isa, f.args(WindowG::Lanes(&lane_g), scales));
        // The gathering form: the same values in the same lanes.
        let sources = f.gather_sources(40);
        let gather = WindowG::Gather {
            sources: &sources,
            pair_g: &pg,
        };
        let gathered = pair_forces_on::<true, true, true>(isa, f.args(gather, scales));
        assert_eq!(
            (gathered.0.to_bits(), gathered.1.to_bits()),
            (force.0.to_bits(), force.1.to_bits()),
            "{isa:?}: gathered as the lane table"
        );
        let mut bits: Vec<u64> = w.iter().chain(&pg).map(|v| v.to_bits()).collect();
        bits.extend([w_sum.to_bits(), force.0.to_bits(), force.1.to_bits()]);
        bits
    };
    let base = run(Isa::Base);
    assert!(
        f64::from_bits(base[base.len() - 3]) > 0.0,
        "some pairs are in reach"
    );
    let detected = Isa::detect();
    assert_eq!(run(detected), base, "{detected:?} against the base build");
    #[cfg(target_arch = "x86_64")]
    if detected == Isa::Avx512 {
        assert_eq!(run(Isa::Avx2), base, "AVX2 against the base build");
    }
}

/// A window whose lanes all have g = 0 is skipped ([`pair_forces`]):
/// the same bits as without it, on every instruction set and loop; a
/// window with one lane's g not 0 is not.
#[test]
fn windows_whose_every_g_is_zero_add_nothing() {
    let f = Fixture::new();
    let pg: Vec<f64> = (0..41)
        .map(|s| if s < 40 { (s as f64 * 0.37).sin() } else { 0.0 })
        .collect();
    let lane_g = f.lane_g(&pg);
    let extra = Window::new(60, 0xff, [1; LANES]);
    let mut one = [0.0; LANES];
    one[3] = pg[7];
    let bits = |(a, b): (f64, f64)| (a.to_bits(), b.to_bits());
    // The fixture's windows with `extra` third, its lanes' g `g`.
    let with = |g: [f64; LANES]| {
        let mut w = f.windows.clone();
        w.insert(2, extra);
        let mut lg = lane_g.clone();
        lg.splice(2 * LANES..2 * LANES, g);
        (w, lg)
    };
    let (with_zero, with_live) = (with([0.0; LANES]), with(one));
    let isas = every_isa();
    for isa in isas {
        let scales = test_scales(0.9, 3.0);
        let run = |(windows, lane_g): (&[Window], &[f64])| {
            let args = ForceArgs {
                windows,
                ..f.args(WindowG::Lanes(lane_g), scales)
            };
            [
                bits(pair_forces_on::<false, false, false>(isa, args)),
                bits(pair_forces_on::<true, true, false>(isa, args)),
            ]
        };
        let base = run((&f.windows, &lane_g));
        assert_eq!(run((&with_zero.0, &with_zero.1)), base, "{isa:?}");
        let changed = run((&with_live.0, &with_live.1));
        assert!(changed.iter().zip(&base).all(|(c, b)| c != b), "{isa:?}");
    }
}

/// Without the artificial viscosity, walls that are not mirrored run the
/// loop with the walls' factor at inv_gap = 0 ([`forces`]): the same bits
/// as the loop without the factor, on every instruction set, whatever
/// the cap; and the factor acts where the gap is not 0.
#[test]
fn the_walls_factor_at_zero_inverse_gap_is_the_loop_without_it() {
    let f = Fixture::new();
    // (dW/dq)/q of 40 slots, and the zero place after them.
    let pg: Vec<f64> = (0..41)
        .map(|s| if s < 40 { (s as f64 * 0.37).sin() } else { 0.0 })
        .collect();
    let lg = f.lane_g(&pg);
    let bits = |(a, b): (f64, f64)| (a.to_bits(), b.to_bits());
    let isas = every_isa();
    for isa in isas {
        for beta_max in [1.0, 3.0] {
            let lanes = WindowG::Lanes(&lg);
            let without = pair_forces_on::<false, false, false>(
                isa,
                f.args(lanes, test_scales(0.9, beta_max)),
            );
            let at_zero = pair_forces_on::<false, true, false>(
                isa,
                f.args(lanes, test_scales(0.0, beta_max)),
            );
            assert_eq!(bits(at_zero), bits(without), "{isa:?}, beta_max {beta_max}");
            let mirrored = pair_forces_on::<false, true, false>(
                isa,
                f.args(lanes, test_scales(0.9, beta_max)),
            );
            assert_eq!(
                bits(mirrored) == bits(without),
                beta_max == 1.0,
                "{isa:?}: the factor is 1 only where its cap is"
            );
        }
    }
}
