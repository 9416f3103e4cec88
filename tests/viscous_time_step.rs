//! The viscous limit dt <= F h^2 / nu: the largest F at which a kernel's
//! viscous term is stable on the perfect lattice, derived from the term's
//! fastest damping rate over the wave vectors
//! (`LatticeGeometry::viscous_stable_factor`), and the default F kept
//! below it (docs/timestep.md).

use crate::common;
use common::brute::Sites;

use shearsph::config::Scene;
use shearsph::kernel::{Kernel, KernelVisitor, Lattice};
use shearsph::kernels::{kernel_info, with_kernel, KERNELS};
use shearsph::problem::Problem;
use shearsph::solver::{Class, Quiet, RunResult};

fn scene(kernel: &str, lattice: Lattice, h_over_d: f64, viscous_dt: Option<f64>) -> Scene {
    let mut s = Scene::builtin();
    s.kernel = kernel.to_string();
    s.lattice = lattice;
    s.h_over_d = h_over_d;
    s.n_layers = 10;
    s.re = Some(1.0);
    s.c0 = "2".parse().unwrap();
    s.viscous_dt = viscous_dt;
    s
}

fn problem(s: &Scene) -> Problem {
    Problem::resolve(s, kernel_info(&s.kernel).unwrap()).expect("a valid scene")
}

/// The start-up from rest at Re = 1, c0 = 2 U: the viscous limit binds.
fn startup(kernel: &str, lattice: Lattice, h_over_d: f64, viscous_dt: Option<f64>) -> RunResult {
    shearsph::run::run_scene(&scene(kernel, lattice, h_over_d, viscous_dt), &mut Quiet)
        .expect("a valid scene")
}

/// The fastest damping rate h^2 Lambda / nu by brute force, apart from
/// the solver's code: every site within the closed support from the
/// lattice's basis, the rate on a 240 x 240 grid over the reciprocal cell.
struct BruteRate(Lattice, f64);

impl KernelVisitor for BruteRate {
    type Output = f64;
    fn visit<K: Kernel>(self) -> f64 {
        let BruteRate(lattice, h) = self;
        let lattice = Sites::new::<K>(lattice, h);
        let sites: Vec<_> = (lattice.others.iter())
            .map(|&(x, y, q2)| (x, y, -K::w_dw_over_q_lanes(q2).1))
            .collect();
        let best = (lattice.wave_vectors(240))
            .map(|(kx, ky)| {
                sites
                    .iter()
                    .map(|&(x, y, f)| f * (1.0 - (kx * x + ky * y).cos()))
                    .sum::<f64>()
            })
            .fold(0.0f64, f64::max);
        let sigma = lattice.sigma;
        2.0 * lattice.area * best / (h * h) / (sigma * sigma)
    }
}

/// The solver's factor is 1 / (the fastest rate) on every shipped kernel and
/// discretisation: at most the brute-force grid's (its maximum is at least
/// every grid point's), and within the grid's resolution of it.
#[test]
fn the_stable_factor_is_one_over_the_fastest_damping_rate() {
    for info in KERNELS {
        for disc in info.discretisations {
            let s = scene(info.name, disc.lattice, disc.h_over_d, None);
            let f = problem(&s).viscous_stable_factor();
            let brute = with_kernel(info.name, BruteRate(disc.lattice, disc.h_over_d)).unwrap();
            let ratio = f * brute;
            eprintln!(
                "{} on {}: F = {f:.6}, F x brute rate = {ratio:.9}",
                info.name,
                disc.label()
            );
            assert!(
                ratio <= 1.0 + 1e-12 && ratio > 0.999,
                "{} on {}: F = {f}, brute-force rate {brute}",
                info.name,
                disc.label()
            );
        }
    }
}

/// Below the factor the start-up runs as at 0.125 (the same class, the
/// window's mean-flow error to 1e-3 of itself); 15 % above it the lattice
/// goes unstable (docs/timestep.md measured the onset between 1 and 1.16 times
/// the factor).
#[test]
fn runs_below_the_stable_factor_keep_their_numbers_and_above_it_go_unstable() {
    for (kernel, lattice, h) in [
        ("monaghan", Lattice::Triangular, 1.0),
        ("morris", Lattice::Triangular, 1.0),
        ("wendland_c2", Lattice::Square, 1.3),
    ] {
        let f = problem(&scene(kernel, lattice, h, None)).viscous_stable_factor();
        let rules = Scene::builtin().classes();
        let base = startup(kernel, lattice, h, Some(0.125));
        let below = startup(kernel, lattice, h, Some(0.9 * f));
        let above = startup(kernel, lattice, h, Some(1.15 * f));
        let (cb, cl, ca) = (base.class(&rules), below.class(&rules), above.class(&rules));
        let (lb, ll) = (base.window.linf_stat, below.window.linf_stat);
        eprintln!("{kernel} {lattice:?} {h}: F = {f:.4}; 0.125 {cb} {lb:.6e}, 0.9 F {cl} {ll:.6e}, 1.15 F {ca}");
        assert!(matches!(cb, Class::Ok), "{kernel}: {cb} at 0.125");
        assert_eq!(cl, cb, "{kernel} at 0.9 F = {}", 0.9 * f);
        assert!(
            (ll / lb - 1.0).abs() < 1e-3,
            "{kernel}: L_inf {ll} at 0.9 F, {lb} at 0.125"
        );
        assert!(
            matches!(ca, Class::OverCompressed | Class::Failed),
            "{kernel} at 1.15 F = {}: {ca}",
            1.15 * f
        );
    }
}

/// The default is 0.85 of the stable factor on every kernel and
/// discretisation. The composite kernel at h = 1.3 d is stable only to a
/// factor of about 0.07: at 0.125 its start-up fails; its default runs it
/// through (inaccurate, as the kernel is at c0 = 2 U).
#[test]
fn the_default_factor_stays_below_the_stable_one() {
    for info in KERNELS {
        for disc in info.discretisations {
            let p = problem(&scene(info.name, disc.lattice, disc.h_over_d, None));
            let (used, f) = (p.dt_factors.viscous, p.viscous_stable_factor());
            assert!(
                f.is_finite() && f > 0.0,
                "{} on {}: stable factor {f}",
                info.name,
                disc.label()
            );
            assert_eq!(used, 0.85 * f, "{} on {}", info.name, disc.label());
        }
    }
    let rules = Scene::builtin().classes();
    let fixed = startup("composite", Lattice::Triangular, 1.3, Some(0.125));
    let default = startup("composite", Lattice::Triangular, 1.3, None);
    assert_eq!(fixed.class(&rules), Class::Failed);
    let c = default.class(&rules);
    assert!(
        !matches!(c, Class::Failed | Class::OverCompressed),
        "the composite kernel at h = 1.3 d with its default factor {}: {c}",
        default.problem.dt_factors.viscous
    );
}

/// The default factor: 0.85 of the stable factor; 0.125 where the stable
/// factor is unknown (NaN, not positive) or there is none (infinite).
#[test]
fn the_default_factor_by_the_stable_one() {
    use shearsph::problem::cost::default_viscous_dt;
    assert_eq!(default_viscous_dt(0.2), 0.85 * 0.2);
    assert_eq!(default_viscous_dt(0.1), 0.85 * 0.1);
    for unknown in [f64::NAN, f64::INFINITY, 0.0, -0.1] {
        assert_eq!(default_viscous_dt(unknown), 0.125, "{unknown}");
    }
}
