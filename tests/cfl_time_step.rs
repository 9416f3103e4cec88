//! The CFL limit dt <= cfl h / (c0 + |v|max): the largest factor at which a
//! kernel's pressure term is stable on the perfect lattice, derived from
//! the fastest sound wave over the wave vectors
//! (`LatticeGeometry::acoustic_stable_factor`), checked against a
//! brute-force count apart from the solver's code and against runs
//! (docs/timestep.md).

use crate::common;
use common::brute::Sites;

use shearsph::config::{PressureForm, Scene};
use shearsph::kernel::{Kernel, KernelVisitor, Lattice};
use shearsph::kernels::{kernel_info, with_kernel, KERNELS};
use shearsph::problem::Problem;
use shearsph::solver::{Class, Quiet, RunResult};

fn scene(kernel: &str, lattice: Lattice, h_over_d: f64) -> Scene {
    let mut s = Scene::builtin();
    s.kernel = kernel.to_string();
    s.lattice = lattice;
    s.h_over_d = h_over_d;
    s.n_layers = 10;
    s.c0 = "10".parse().unwrap();
    s
}

fn problem(s: &Scene) -> Problem {
    Problem::resolve(s, kernel_info(&s.kernel).unwrap()).expect("a valid scene")
}

/// The fastest sound wave's h omega / c0 by brute force, apart from the
/// solver's code: every site within the closed support from the lattice's
/// basis; the pressure term's force on a particle as a function of its
/// neighbours' places, differentiated in x and y by central differences
/// of grad W itself (not of (dW/dq)/q in q^2), one-sided inside the
/// support for a neighbour at its edge; the summation density's response
/// likewise; the largest eigenvalue of the 2 x 2 dynamical matrix on a
/// 200 x 200 grid over the reciprocal cell. Equation of state (13) with
/// gamma = 1, pressure clamped at 0, the paper's form.
struct BruteOmega(Lattice, f64);

impl KernelVisitor for BruteOmega {
    type Output = f64;
    fn visit<K: Kernel>(self) -> f64 {
        let BruteOmega(lattice, h) = self;
        let lattice = Sites::new::<K>(lattice, h);
        // grad W at (x, y), zero beyond the closed support.
        let grad = |x: f64, y: f64| {
            let q2 = (x * x + y * y) / (h * h);
            if q2 > K::SUPPORT2_CLOSED {
                return [0.0, 0.0];
            }
            let f = K::w_dw_over_q_lanes(q2).1 / h.powi(4);
            [f * x, f * y]
        };
        // (x, y, grad W, its Jacobian) of every other site.
        let sites: Vec<_> = (lattice.others.iter())
            .map(|&(x, y, _)| {
                let e = 1e-6 * h;
                let r = (x * x + y * y).sqrt();
                let (ux, uy) = (x / r, y / r);
                // At the support's edge, the derivative from inside: each
                // direction's difference taken toward the particle.
                let at_edge = ((x + e).powi(2) + (y + e).powi(2)) / (h * h) > K::SUPPORT2_CLOSED
                    || ((x - e).powi(2) + (y - e).powi(2)) / (h * h) > K::SUPPORT2_CLOSED;
                let jac = |dx: f64, dy: f64| -> [f64; 2] {
                    if at_edge {
                        // Second-order one-sided: from the site inward.
                        let s = if dx * ux + dy * uy > 0.0 { -1.0 } else { 1.0 };
                        let (g0, g1, g2) = (
                            grad(x, y),
                            grad(x + s * dx, y + s * dy),
                            grad(x + 2.0 * s * dx, y + 2.0 * s * dy),
                        );
                        let sc = s * 2.0 * (dx + dy);
                        [
                            (-3.0 * g0[0] + 4.0 * g1[0] - g2[0]) / sc,
                            (-3.0 * g0[1] + 4.0 * g1[1] - g2[1]) / sc,
                        ]
                    } else {
                        let (gp, gm) = (grad(x + dx, y + dy), grad(x - dx, y - dy));
                        let sc = 2.0 * (dx + dy);
                        [(gp[0] - gm[0]) / sc, (gp[1] - gm[1]) / sc]
                    }
                };
                let (jx, jy) = (jac(e, 0.0), jac(0.0, e));
                (x, y, grad(x, y), [[jx[0], jy[0]], [jx[1], jy[1]]])
            })
            .collect();
        // gamma = 1, clamped: P = max(sigma - 1, 0), slope 1 (rho0 = c0 = 1).
        let rho = lattice.sigma;
        let (p, slope, m) = ((rho - 1.0).max(0.0), 1.0, lattice.area);
        let best = (lattice.wave_vectors(200))
            .map(|(kx, ky)| {
                let (mut g, mut hm) = ([0.0; 2], [[0.0; 2]; 2]);
                for &(x, y, gw, jac) in &sites {
                    let ph = kx * x + ky * y;
                    for a in 0..2 {
                        g[a] += gw[a] * ph.sin();
                        for b in 0..2 {
                            hm[a][b] += jac[a][b] * (1.0 - ph.cos());
                        }
                    }
                }
                let c = m / (rho * rho);
                let d = |a: usize, b: usize| c * (m * slope * g[a] * g[b] + 2.0 * p * hm[a][b]);
                let off = 0.5 * (d(0, 1) + d(1, 0));
                let (mean, half) = (0.5 * (d(0, 0) + d(1, 1)), 0.5 * (d(0, 0) - d(1, 1)));
                mean + (half * half + off * off).sqrt()
            })
            .fold(0.0f64, f64::max);
        h * best.sqrt()
    }
}

/// The solver's factor is 2 / (the fastest wave's h omega / c0) on every
/// shipped kernel and discretisation: at most the brute-force grid's (its
/// maximum is at least every grid point's, up to the differences' error),
/// and within the grid's resolution of it.
#[test]
fn the_stable_factor_is_two_over_the_fastest_sound_wave() {
    for info in KERNELS {
        for disc in info.discretisations {
            let f =
                problem(&scene(info.name, disc.lattice, disc.h_over_d)).acoustic_stable_factor();
            let brute = with_kernel(info.name, BruteOmega(disc.lattice, disc.h_over_d)).unwrap();
            let ratio = f * brute / 2.0;
            eprintln!(
                "{} on {}: cfl* = {f:.6}, cfl* x brute omega / 2 = {ratio:.9}",
                info.name,
                disc.label()
            );
            assert!(
                ratio <= 1.0 + 1e-6 && ratio > 0.999,
                "{} on {}: cfl* = {f}, brute-force h omega / c0 = {brute}",
                info.name,
                disc.label()
            );
        }
    }
}

/// The perfect lattice from rest at Re = 30, c0 = 100 U (the CFL limit
/// binds, |v| about 1 % of c0) to t = 40, about 2,000 steps, at `factor`
/// times the derived stable factor.
fn at_factor(kernel: &str, lattice: Lattice, h: f64, factor: f64) -> RunResult {
    let mut s = scene(kernel, lattice, h);
    s.re = Some(30.0);
    s.c0 = "100".parse().unwrap();
    s.t_end = Some(40.0);
    s.cfl = Some(factor * problem(&s).acoustic_stable_factor());
    shearsph::run::run_scene(&s, &mut Quiet).expect("a valid scene")
}

/// Below the factor the perfect lattice keeps its compaction; a little
/// above it a sound wave grows (docs/timestep.md measured the onset
/// between 0.97 and 1.03 times the factor on these discretisations).
#[test]
fn runs_below_the_stable_factor_stay_ordered_and_above_it_go_unstable() {
    for (kernel, lattice, h) in [
        ("monaghan", Lattice::Square, 1.0),
        ("morris", Lattice::Square, 1.0),
    ] {
        let below = at_factor(kernel, lattice, h, 0.9);
        let above = at_factor(kernel, lattice, h, 1.1);
        let (eb, ea) = (below.max_eps_run, above.max_eps_run);
        eprintln!("{kernel} {lattice:?} {h}: max eps {eb:.3e} at 0.9, {ea:.3e} at 1.1");
        let rules = Scene::builtin().classes();
        assert_ne!(below.class(&rules), Class::Failed, "{kernel} at 0.9");
        assert!(eb < 2e-3, "{kernel} at 0.9: max eps {eb}");
        assert!(ea > 10.0 * eb, "{kernel}: max eps {ea} at 1.1, {eb} at 0.9");
    }
}

/// The equation of state moves the factor: Wendland C2 on the triangular
/// lattice at h = d sums above rho0 (its pressure at rest P > 0), so the
/// symmetric form (whose density wave's slope is P' - 2 P / rho) is
/// stable to a larger factor than the paper's, and gamma = 7 (P' = sigma^6)
/// to a smaller one; Monaghan's kernel there sums below rho0, where the
/// clamp leaves it no pressure at rest and negative pressures give it one.
#[test]
fn the_factor_follows_the_equation_of_state() {
    let base = scene("wendland_c2", Lattice::Triangular, 1.0);
    let f = problem(&base).acoustic_stable_factor();
    let mut sym = base.clone();
    sym.pressure_form = PressureForm::Symmetric;
    let mut g7 = base.clone();
    g7.gamma = 7.0;
    let (fs, f7) = (
        problem(&sym).acoustic_stable_factor(),
        problem(&g7).acoustic_stable_factor(),
    );
    eprintln!("wendland_c2 triangular h = d: paper {f:.4}, symmetric {fs:.4}, gamma 7 {f7:.4}");
    assert!(fs > f && f7 < f, "paper {f}, symmetric {fs}, gamma 7 {f7}");
    let clamped = problem(&scene("monaghan", Lattice::Triangular, 1.0)).acoustic_stable_factor();
    let mut neg = scene("monaghan", Lattice::Triangular, 1.0);
    neg.allow_negative_pressure = true;
    let negative = problem(&neg).acoustic_stable_factor();
    eprintln!("monaghan triangular h = d: clamped {clamped:.4}, negative pressures {negative:.4}");
    assert!(clamped.is_finite() && negative.is_finite() && negative != clamped);
}

/// The default factor: half the stable factor, at most 1; 0.5 where the
/// stable factor is unknown (NaN, not positive) or there is none
/// (infinite). A scene that gives no `cfl` runs at its kernel's default on
/// its lattice and equation of state; one that gives it runs at it.
#[test]
fn the_default_factor_by_the_stable_one() {
    use shearsph::problem::cost::default_cfl;
    assert_eq!(default_cfl(1.8597), 0.5 * 1.8597);
    assert_eq!(default_cfl(1.9), 0.95);
    assert_eq!(default_cfl(2.31), 1.0);
    for unknown in [f64::NAN, f64::INFINITY, 0.0, -0.1] {
        assert_eq!(default_cfl(unknown), 0.5, "{unknown}");
    }
    let mut cases = vec![];
    for (kernel, lattice, h) in [
        ("monaghan", Lattice::Triangular, 1.0),
        ("morris", Lattice::Square, 1.7),
        ("composite", Lattice::Triangular, 1.3),
    ] {
        cases.push(scene(kernel, lattice, h));
    }
    let mut g7 = scene("wendland_c2", Lattice::Triangular, 1.0);
    g7.gamma = 7.0;
    cases.push(g7);
    for s in &cases {
        let p = problem(s);
        let stable = p.acoustic_stable_factor();
        assert_eq!(p.dt_factors.cfl, default_cfl(stable), "{}", s.kernel);
        let mut given = s.clone();
        given.cfl = Some(0.3);
        assert_eq!(problem(&given).dt_factors.cfl, 0.3);
    }
}
