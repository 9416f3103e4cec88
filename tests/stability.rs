//! `shearsph stability`: the growth rate of perturbations of the sheared
//! lattice by the solver's own step. Its parts are checked against each
//! other where the mathematics says they must agree (a sector's rate is a
//! property of its wavenumber, not of the strip; the rate does not depend
//! on the finite difference's size), and its flags are guarded. The step's
//! Jacobian against the pressure term linearised by hand is a unit test in
//! src/model/solver/tangent.rs.

use crate::common;
use common::*;

use shearsph::config::Scene;
use shearsph::solver::tangent::Options;
use shearsph::stability::{analyse, multipliers, Request};

/// A small scene (N = 4), quick to follow, at the CFL factor 0.5. The
/// leading Floquet rate of this coarse lattice moves with the time step
/// above it (0.165, 0.160, 0.130 and 0.133 at 0.25, 0.5, 0.75 and its
/// default 0.93: `shearsph stability --n 4 --columns 5 --c0-over-u 10
/// --horizon-t 160 --warm 16 --floquet --cfl F`), and at 0.93 this test's
/// tangent gives 0.114 against the multiplier's 0.146; at N = 10 the
/// tangent's rate is 0.0349, 0.0343 and 0.0342 at 0.25, 0.5 and 0.93
/// (docs/stability.md).
fn small(columns: u32) -> Scene {
    let mut s = Scene::builtin();
    s.n_layers = 4;
    s.columns = Some(columns);
    s.cfl = Some(0.5);
    s
}

fn rate(scene: &Scene, sector: u32, eps: f64) -> f64 {
    let req = Request {
        c0_over_u: vec![10.0],
        sectors: vec![sector],
        options: Options {
            eps,
            block: 50,
            horizon: 60.0,
            warm: 10.0,
        },
        amplitude: 1e-4,
    };
    let at = analyse(scene, &req).expect("the analysis runs");
    assert_eq!(at[0].sectors.len(), 1);
    at[0].sectors[0].growth_rate
}

/// The perturbation q = 2 pi / (5 d) is sector 1 of a 5-column strip and
/// sector 2 of a 10-column one: the same mode of the same linear
/// equations, so the same rate, whatever else the wider strip admits.
#[test]
fn a_sectors_rate_is_a_property_of_its_wavenumber_not_of_the_strip() {
    let narrow = rate(&small(5), 1, 1e-7);
    let wide = rate(&small(10), 2, 1e-7);
    assert!(narrow.is_finite() && wide.is_finite());
    assert!(
        (narrow - wide).abs() <= 1e-3 * narrow.abs().max(1e-3),
        "q d = 2 pi / 5: {narrow:e} on 5 columns against {wide:e} on 10"
    );
}

/// In the linear regime the rate does not depend on the perturbation's
/// size: 1e-6 and 1e-8 agree (round-off below, nonlinearity above).
#[test]
fn the_rate_does_not_depend_on_the_finite_differences_size() {
    let scene = small(5);
    let (a, b) = (rate(&scene, 1, 1e-6), rate(&scene, 1, 1e-8));
    assert!(
        (a - b).abs() <= 0.02 * a.abs().max(1e-3),
        "eps 1e-6: {a:e}, eps 1e-8: {b:e}"
    );
}

/// The steady profile's lattice repeats after T = d N^2 / U, so the flow
/// map over T is the monodromy matrix: its largest multiplier (nalgebra's
/// eigenvalues of a Jacobian of 4 n columns, each two runs of the solver)
/// gives the leading rate that the two-copy tangent finds sector by sector
/// (N = 4: T = 16; 0.160 against 0.148 over 10 periods).
#[test]
fn the_floquet_multiplier_gives_the_tangents_leading_rate() {
    let scene = small(5);
    let req = Request {
        c0_over_u: vec![10.0],
        options: Options {
            eps: 1e-7,
            block: 50,
            horizon: 160.0,
            warm: 16.0,
        },
        ..Request::default()
    };
    let at = analyse(&scene, &req).expect("the analysis runs");
    let (tangent, period) = (at[0].growth_rate, at[0].period);
    assert_eq!(period, 16.0);
    assert!((at[0].growth_rate_per_period - tangent * period).abs() < 1e-12);
    let mu = multipliers(&scene, 10.0, period, 1e-7).expect("the multipliers");
    assert_eq!(mu.dimension % 4, 0);
    let floquet = mu.growth_rate;
    assert!(tangent > 0.0 && floquet > 0.0, "{tangent:e} {floquet:e}");
    assert!(
        (floquet - tangent).abs() <= 0.15 * tangent,
        "Floquet {floquet:e} against the tangent's {tangent:e}"
    );
}

#[test]
fn the_json_reports_the_rates_and_the_prediction() {
    let dir = tempfile::tempdir().unwrap();
    let svg = dir.path().join("mode.svg");
    let o = shearsph(&[
        "stability",
        "--mode-svg",
        svg.to_str().unwrap(),
        "--n",
        "4",
        "--columns",
        "5",
        "--c0-over-u",
        "10,20",
        "--horizon-t",
        "30",
        "--warm",
        "5",
        "--json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).expect("JSON");
    assert_eq!(v["kernel"], "monaghan");
    assert_eq!(v["columns"], 5);
    let results = v["results"].as_array().expect("results");
    assert_eq!(results.len(), 2);
    for r in results {
        let rate = r["growth_rate"].as_f64().expect("a growth rate");
        let sectors = r["sectors"].as_array().expect("sectors");
        // Sectors j = 0 ..= columns / 2, the largest of their rates the
        // reported one.
        assert_eq!(sectors.len(), 3);
        let top = sectors
            .iter()
            .map(|s| s["growth_rate"].as_f64().expect("a rate"))
            .fold(f64::NEG_INFINITY, f64::max);
        assert_eq!(rate, top);
        let mode = r["mode"].as_array().expect("the mode");
        assert!(!mode.is_empty());
        match r["t_disorder_predicted"].as_f64() {
            Some(t) => {
                assert!(rate > 0.0 && (t * rate - (0.1 * 3f64.sqrt() / 1e-4).ln()).abs() < 1e-9)
            }
            None => assert!(rate <= 0.0),
        }
        assert!(r["measured"].is_null() && r["multipliers"].is_null());
    }
    // One picture per c0, a dot per fluid particle of the mode.
    for c in ["10", "20"] {
        let text = std::fs::read_to_string(dir.path().join(format!("mode-c0-{c}.svg")))
            .expect("the mode's picture");
        let dots = text.matches("<circle").count();
        assert_eq!(dots, results[0]["mode"].as_array().unwrap().len(), "c0 {c}");
    }
    assert!(!svg.exists(), "with two c0 each file has its own name");
}

/// Each flag's bound, named in the message with the flag.
#[test]
fn bad_stability_flags_are_refused_by_name() {
    let cases: &[(&[&str], &str)] = &[
        (&["--eps", "0"], "--eps"),
        (&["--eps", "0.1"], "--eps"),
        (&["--eps", "nan"], "--eps"),
        (&["--block", "0"], "--block"),
        (&["--horizon-t", "-1"], "--horizon-t"),
        (&["--horizon-t", "inf"], "--horizon-t"),
        (&["--measure-t-end", "0"], "--measure-t-end"),
        (&["--warm", "-1"], "--warm"),
        (&["--amplitude", "0.5"], "--amplitude"),
        (&["--amplitude", "0"], "--amplitude"),
        (&["--multipliers-t", "-1"], "--multipliers-t"),
        (&["--multipliers-t", "1e9"], "--multipliers-t"),
        (&["--c0-over-u", "0"], "--c0-over-u"),
        (&["--c0-over-u", "1e9"], "--c0-over-u"),
        (&["--sectors", "99"], "--sectors"),
        (&["--n", "20", "--floquet"], "--floquet"),
    ];
    for (flags, name) in cases {
        let mut args = vec!["stability", "--n", "4"];
        args.extend_from_slice(flags);
        let o = shearsph(&args);
        assert!(!o.status.success(), "{flags:?} was accepted");
        let err = stderr(&o);
        assert!(err.contains(name), "{flags:?}: {err}");
        assert!(!err.contains("panicked"), "{flags:?}: {err}");
    }
}

/// A c0 at which the perfect lattice's own run fails is said to be that,
/// not a stable ordered state (the composite kernel, square h = d, N = 4,
/// Re = 10, 30 U: every sector's run fails).
#[test]
fn a_failed_base_is_not_called_stable() {
    let o = shearsph(&[
        "stability",
        "--kernel",
        "composite",
        "--lattice",
        "square",
        "--n",
        "4",
        "--re",
        "10",
        "--c0-over-u",
        "30",
        "--horizon-t",
        "50",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = stdout(&o);
    assert!(out.contains("every sector's run failed"), "{out}");
    assert!(!out.contains("ordered state holds"), "{out}");
}
