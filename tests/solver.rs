//! The solver against the analytic solutions, for every shipped kernel; a
//! too small c0 ends as `failed`, naming the particle; an observer's stop
//! ends a run as `interrupted`, keeping its samples; mirrored walls remove
//! the slip of walls at rest; results do not depend on the thread count.
//!
//! Tolerances are twice the measured errors (the measured value is in the
//! comment), on small scenes that finish in seconds.

use shearsph::config::{Initial, Scene, WallVelocity};
use shearsph::kernel::Lattice;
use shearsph::kernels::KERNELS;
use shearsph::solver::{Failure, Observer, Outcome, Quiet, RunResult};

/// The test scene: N = 8, Re = 10, the paper's Table 2 sound speed (10 U
/// for a kernel without a paper row), no artificial viscosity (its extra shear viscosity, about alpha c0 h / 8, is
/// a separate effect: see `artificial_viscosity_adds_dissipation`).
fn scene(kernel: &str, initial: Initial) -> Scene {
    let mut s = Scene::builtin();
    s.kernel = kernel.to_string();
    s.n_layers = 8;
    s.re = Some(10.0);
    s.alpha = 0.0;
    let has_table2 = shearsph::kernels::kernel_info(kernel).is_some_and(|k| k.printed_c0.is_some());
    s.c0 = if has_table2 { "table2" } else { "rule10" }
        .parse()
        .unwrap();
    s.initial = initial;
    s
}

fn run(scene: &Scene) -> RunResult {
    run_observed(scene, &mut Quiet)
}

fn run_observed(scene: &Scene, observer: &mut dyn Observer) -> RunResult {
    shearsph::run::run_scene(scene, observer).expect("valid scene")
}

/// Largest L_inf error of the layer means over the output times.
fn worst_linf(r: &RunResult) -> f64 {
    r.samples.iter().map(|s| s.linf_rel_err).fold(0.0, f64::max)
}

/// Tolerances per kernel: twice what was measured (release build, the scene
/// above), for the start from rest and from the steady profile. The
/// composite kernel's gradient (22b) is not dW/dq, so its Laplacian (14) is
/// off by some 10 % and its profile with it; Morris's quintic reaches three
/// wall layers held at u = 0 where the parabola would continue negative, a
/// slip of about 2 % U at N = 8 that halves as N doubles. Any sign error in
/// a force term gives errors of order 1 or a blow-up.
const MEASURED: &[(&str, f64, f64)] = &[
    // measured 0.2076 (rest), 0.2276 (steady)
    ("composite", 0.41, 0.45),
    // measured 2.98e-3 (rest), 3.26e-3 (steady)
    ("monaghan", 6.0e-3, 6.5e-3),
    // measured 2.358e-2 (rest), 2.361e-2 (steady)
    ("morris", 4.7e-2, 4.7e-2),
    // measured 1.048e-1 (rest), 1.060e-1 (steady), with c0 = 10 U (no paper
    // row): at h = d on the triangular lattice Wendland C2's lattice sum is
    // 2.9 % off (eps(0) = 0.0293), which biases the pressure; peers run it at
    // h >= 1.3 d
    ("wendland_c2", 0.21, 0.22),
];

/// A kernel added since these were measured gets a sanity bound only (the
/// profile is roughly right), and the test prints what to add here.
const UNMEASURED: f64 = 0.5;

fn tolerance(kernel: &str, initial: Initial) -> f64 {
    match MEASURED.iter().find(|m| m.0 == kernel) {
        Some(&(_, rest, steady)) => match initial {
            Initial::Rest => rest,
            Initial::Steady => steady,
        },
        None => {
            eprintln!(
                "{kernel}: no measured tolerance yet; add twice the error printed here to MEASURED"
            );
            UNMEASURED
        }
    }
}

#[test]
fn startup_from_rest_matches_the_series_for_every_kernel() {
    for info in KERNELS {
        let r = run(&scene(info.name, Initial::Rest));
        assert_eq!(r.outcome, Outcome::Ok, "{}", info.name);
        // t = 0 and 20 output times up to the decay of the slowest mode.
        assert_eq!(r.samples.len(), 21, "{}", info.name);
        let worst = worst_linf(&r);
        eprintln!(
            "{}: start-up, worst Linf / U over {} times = {worst:.4e}",
            info.name,
            r.samples.len()
        );
        assert!(
            worst <= tolerance(info.name, Initial::Rest),
            "{}: Linf {worst}",
            info.name
        );
        // The flow did start: the centre moves at nearly U by the end.
        let centre = r.last().profile.iter().find(|l| l.layer == 0).unwrap();
        assert!(centre.u > 0.5, "{}: centre u = {}", info.name, centre.u);
    }
}

#[test]
fn steady_profile_stays_steady_for_every_kernel() {
    for info in KERNELS {
        let r = run(&scene(info.name, Initial::Steady));
        assert_eq!(r.outcome, Outcome::Ok, "{}", info.name);
        let worst = worst_linf(&r);
        eprintln!("{}: steady, worst Linf / U = {worst:.4e}", info.name);
        assert!(
            worst <= tolerance(info.name, Initial::Steady),
            "{}: Linf {worst}",
            info.name
        );
    }
}

#[test]
fn artificial_viscosity_adds_dissipation() {
    // (31) acts on the shear too: the centre line is slower than (7), by
    // roughly the ratio of the added viscosity ~ alpha c0 h / 8 to nu.
    let mut s = scene("monaghan", Initial::Steady);
    s.alpha = 0.1;
    s.c0 = "rule10".parse().unwrap();
    let r = run(&s);
    let centre = r.last().profile.iter().find(|l| l.layer == 0).unwrap();
    let deficit = 1.0 - centre.u / centre.u_steady;
    eprintln!("alpha = 0.1, c0 = 10 U: centre deficit {deficit:.4e}");
    // measured 6.9e-2; alpha c0 h / 8 / nu = 0.18 for the full (31), about
    // half of which acts (approaching pairs only).
    assert!((0.035..0.14).contains(&deficit), "deficit {deficit}");
}

#[test]
fn too_small_c0_fails_with_a_reason() {
    // A perturbed lattice needs pressure to keep particles apart: with
    // c0 = 0.1 U layers pass through each other and the compaction soars;
    // with c0 = 10 U the same start runs to the end.
    let mut s = scene("monaghan", Initial::Rest);
    s.jitter = 0.05;
    s.c0 = "0.01*rule10".parse().unwrap();
    let r = run(&s);
    match &r.outcome {
        Outcome::Failed {
            failure: Failure::Compaction { eps, limit },
            t,
            step,
            particle: p,
        } => {
            assert!(eps > limit && *t < r.problem.t_end);
            assert_eq!((*t, *step), (r.t, r.steps));
            // The densest fluid particle, as it was: a fluid index, still
            // inside the channel, from a fluid layer.
            let n = r.problem.lattice.n_layers as i32;
            assert!(p.index < r.n_fluid, "{p:?}");
            assert!(p.layer.abs() < n, "{p:?}");
            assert!(p.y.abs() < r.problem.lattice.b(), "{p:?}");
            assert!((0.0..r.problem.lattice.width).contains(&p.x), "{p:?}");
            assert!(p.vx.is_finite() && p.vy.is_finite(), "{p:?}");
            // The message says when, why and which particle.
            let said = r.outcome.to_string();
            eprintln!("c0 = 0.1 U: {said}");
            for part in [
                format!("failed at t = {t:.6}, step {step}"),
                "compaction".to_string(),
                format!("fluid particle {} (started in layer {})", p.index, p.layer),
                format!("x = {:.4}, y = {:.4}", p.x, p.y),
            ] {
                assert!(said.contains(&part), "{said:?} lacks {part:?}");
            }
        }
        other => panic!("expected a compaction failure, got {other:?}"),
    }
    // The failure is in the samples too, at the time it happened.
    assert_eq!(r.last().t, r.t);

    s.c0 = "rule10".parse().unwrap();
    s.t_end = Some(r.t * 2.0);
    let control = run(&s);
    assert_eq!(control.outcome, Outcome::Ok);
}

/// Stops the run once `k` steps are done.
struct StopAfter {
    k: u64,
    steps: u64,
}

impl Observer for StopAfter {
    fn step(&mut self, _t: f64, steps: u64) {
        self.steps = steps;
    }
    fn should_stop(&self) -> bool {
        self.steps >= self.k
    }
}

#[test]
fn an_observer_stop_ends_the_run_as_interrupted_keeping_its_samples() {
    let s = scene("monaghan", Initial::Rest);
    let full = run(&s);
    assert_eq!(full.outcome, Outcome::Ok);
    // Half-way, between two output times.
    let k = full.steps / 2;
    let mut stop = StopAfter { k, steps: 0 };
    let r = run_observed(&s, &mut stop);
    assert_eq!(r.steps, k);
    match r.outcome {
        Outcome::Interrupted { t, step } => {
            assert_eq!(step, k);
            assert_eq!(t, r.t);
            assert!(t > 0.0 && t < r.problem.t_end, "t = {t}");
        }
        ref other => panic!("expected interrupted, got {other:?}"),
    }
    // Every output sample before the stop, the same as the full run's, and
    // one last sample at the time reached.
    let (last, kept) = r.samples.split_last().unwrap();
    assert_eq!((last.t, last.step), (r.t, k));
    let before: Vec<_> = full.samples.iter().filter(|x| x.t < r.t).collect();
    assert!(before.len() >= 2, "some output times passed");
    assert_eq!(kept.len(), before.len());
    for (a, b) in kept.iter().zip(before) {
        assert_eq!(
            (a.t, a.step, a.max_eps, a.linf_rel_err, a.kinetic_energy),
            (b.t, b.step, b.max_eps, b.linf_rel_err, b.kinetic_energy)
        );
    }
}

/// Runs `s` with 1 and 2 threads and asserts bitwise identical results.
fn assert_thread_count_independent(s: &Scene) {
    let in_pool = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| run(s))
    };
    let (one, two) = (in_pool(1), in_pool(2));
    assert!(
        one.n_fluid > 256,
        "the scene must span several parallel chunks"
    );
    assert_eq!(one.steps, two.steps);
    assert_eq!(one.samples.len(), two.samples.len());
    let bits = |r: &RunResult| -> Vec<u64> {
        r.samples
            .iter()
            .flat_map(|s| {
                [s.t, s.max_eps, s.mean_eps, s.rms_v, s.kinetic_energy]
                    .into_iter()
                    .chain(s.profile.iter().flat_map(|l| [l.y, l.u, l.v_rms]))
            })
            .map(f64::to_bits)
            .collect()
    };
    assert_eq!(
        bits(&one),
        bits(&two),
        "bitwise identical with 1 and 2 threads"
    );
}

#[test]
fn results_do_not_depend_on_the_thread_count() {
    // Big enough for several parallel chunks; perturbed so that every force
    // term is busy; both wall models.
    let mut s = scene("monaghan", Initial::Rest);
    s.n_layers = 30;
    s.jitter = 0.02;
    s.alpha = 0.1;
    s.c0 = "rule10".parse().unwrap();
    s.t_end = Some(20.0);
    assert_thread_count_independent(&s);
    let mut s = scene("morris", Initial::Rest);
    s.n_layers = 20;
    s.jitter = 0.02;
    s.alpha = 0.1;
    s.c0 = "rule10".parse().unwrap();
    s.t_end = Some(5.0);
    s.wall_velocity = WallVelocity::Mirrored;
    assert_thread_count_independent(&s);
}

#[test]
fn mirrored_walls_remove_the_quintic_splines_wall_slip() {
    // Morris's quintic reaches three wall layers: at rest, they leave a slip
    // (see MEASURED); mirrored through y = B (Morris, Fox and Zhu 1997), the
    // fluid's velocity goes through zero at the wall.
    let zero = run(&scene("morris", Initial::Rest));
    let mirrored = run(&Scene {
        wall_velocity: WallVelocity::Mirrored,
        ..scene("morris", Initial::Rest)
    });
    assert!(zero.outcome.is_ok() && mirrored.outcome.is_ok());
    let (e0, em) = (worst_linf(&zero), worst_linf(&mirrored));
    // measured 2.358e-2 (walls at rest), 1.697e-3 (mirrored)
    assert!(em < 3.4e-3, "mirrored walls: worst L_inf {em:.3e} U");
    assert!(
        em < 0.2 * e0,
        "mirrored walls {em:.3e} should be far below walls at rest {e0:.3e}"
    );
    // The slip shows as the layer next to the wall running fast.
    let near_wall = |r: &RunResult| {
        let last = r.last();
        let layer = last
            .profile
            .iter()
            .max_by(|a, b| a.y.abs().total_cmp(&b.y.abs()))
            .expect("layers");
        (layer.u - r.problem.flow.startup(layer.y, last.t)).abs() / r.problem.flow.u
    };
    assert!(near_wall(&mirrored) < near_wall(&zero));
}

#[test]
fn mirrored_walls_leave_a_one_layer_wall_unchanged() {
    // The composite kernel (R = 1) reaches one wall layer, at the no-slip
    // plane itself (depth 0): mirroring changes nothing, to the bit.
    let zero = Scene {
        t_end: Some(2.0),
        ..scene("composite", Initial::Rest)
    };
    let mirrored = Scene {
        wall_velocity: WallVelocity::Mirrored,
        ..zero.clone()
    };
    let (a, b) = (run(&zero), run(&mirrored));
    assert_eq!(a.steps, b.steps);
    let bits = |r: &RunResult| -> Vec<u64> {
        r.samples
            .iter()
            .flat_map(|s| s.profile.iter().map(|l| l.u.to_bits()))
            .collect()
    };
    assert_eq!(bits(&a), bits(&b));
}

#[test]
fn lattice_density_is_the_kernels_eps_at_t0() {
    // Density by summation over fluid and walls on the undisturbed lattice
    // is the derivation's eps(0 T) in every fluid layer, the wall-side ones
    // too (walls cover the support): checks the mass, the kernel's h scaling,
    // the closed support (R = 1 counts neighbours at exactly q = 1) and the
    // neighbour list with its periodic images. For every kernel on every
    // generated discretisation (lattice kind, h/d): the registry's lists, so
    // a new kernel or discretisation is checked with no edit here.
    let mut checked = 0;
    for info in KERNELS {
        for disc in info.discretisations {
            let mut s = scene(info.name, Initial::Rest);
            s.lattice = disc.lattice;
            s.h_over_d = disc.h_over_d;
            if !disc.is_papers() {
                s.c0 = "rule10".parse().unwrap();
            }
            // Only the t = 0 sample is read; a run covers at least a step.
            s.t_end = Some(1.0);
            let first = &run(&s).samples[0];
            let want = disc.eps.t0.value;
            for got in [first.max_eps, first.mean_eps] {
                assert!(
                    (got - want).abs() < 1e-13,
                    "{} on {}: eps {got}, derived {want}",
                    info.name,
                    disc.label()
                );
            }
            checked += 1;
        }
    }
    assert!(checked >= 4 * KERNELS.len(), "{checked} discretisations");
}

/// Tolerances on the square lattice (start from rest, c0 = 10 U, the scene
/// above otherwise: N = 8, Re = 10, walls at rest), per kernel and h/d:
/// twice what was measured (release build), in the comment. At fixed N a
/// larger h reaches deeper into the walls at rest, so the wall slip grows
/// with h (as for Morris on the triangular lattice).
const MEASURED_SQUARE: &[(&str, &str, f64)] = &[
    // composite at h = d: measured 1.3213. It does NOT reach the analytic
    // profile: with R h = d it sees only the four neighbours at exactly
    // q = 1 (closed support), its lattice density is 15 % above rho0
    // (eps(0) = 0.1538, `shearsph kernels`), and the viscous term has only
    // the two neighbours straight above and below. A regression guard only.
    ("composite", "1", 2.7),
    // measured 2.4589e-1, 2.8537e-1: (22b) is not dW/dq (as on the triangular lattice)
    ("composite", "13/10", 0.50),
    ("composite", "17/10", 0.58),
    // measured 3.8607e-3, 6.8328e-3, 5.2451e-2
    ("monaghan", "1", 7.8e-3),
    ("monaghan", "13/10", 1.4e-2),
    ("monaghan", "17/10", 0.105),
    // measured 1.0724e-2, 3.6429e-2, 8.5146e-2
    ("morris", "1", 2.2e-2),
    ("morris", "13/10", 7.3e-2),
    ("morris", "17/10", 0.17),
    // measured 1.0403e-1 (h = d: Wendland C2's lattice sums are off, as on
    // the triangular lattice), 5.6381e-2, 4.5209e-2
    ("wendland_c2", "1", 0.21),
    ("wendland_c2", "13/10", 0.113),
    ("wendland_c2", "17/10", 0.091),
];

#[test]
fn square_lattice_startup_matches_the_series() {
    for info in KERNELS {
        for disc in info
            .discretisations
            .iter()
            .filter(|d| d.lattice == Lattice::Square)
        {
            let mut s = scene(info.name, Initial::Rest);
            s.lattice = disc.lattice;
            s.h_over_d = disc.h_over_d;
            s.c0 = "rule10".parse().unwrap();
            // A start-up test, not a compaction test: the composite
            // kernel's lattice pulsates by 15 % at h = d, and once the
            // lattice disorders (t = 11) the largest eps of its particles
            // wanders between 0.16 and 0.2 (0.179 and 0.2003 by t = 225 on
            // two builds that differ only in rounding), so the default
            // 0.2 limit would make the outcome chance.
            s.eps_limit = 0.3;
            let r = run(&s);
            let worst = worst_linf(&r);
            eprintln!(
                "{} on {}: start-up, worst Linf / U = {worst:.4e}, outcome {:?}",
                info.name,
                disc.label(),
                r.outcome
            );
            let bound = MEASURED_SQUARE
                .iter()
                .find(|m| m.0 == info.name && m.1 == disc.h_over_d_exact)
                .map_or(UNMEASURED, |m| m.2);
            assert_eq!(r.outcome, Outcome::Ok, "{} on {}", info.name, disc.label());
            assert!(
                worst <= bound,
                "{} on {}: Linf {worst}",
                info.name,
                disc.label()
            );
        }
    }
}
