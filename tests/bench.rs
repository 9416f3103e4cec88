//! `shearsph bench` from the outside: the JSON report's shape on a tiny
//! configuration, and the scene matched to PySPH's example. No timing is
//! asserted: these only check that every figure is there and sane.

use crate::common;
use common::*;

use std::process::Output;

use serde_json::Value;

fn json(o: &Output) -> Value {
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    serde_json::from_slice(&o.stdout).expect("stdout is JSON")
}

fn positive(v: &Value, key: &str) -> f64 {
    let x = v[key]
        .as_f64()
        .unwrap_or_else(|| panic!("`{key}` is a number in {v}"));
    assert!(x > 0.0 && x.is_finite(), "`{key}` = {x}");
    x
}

#[test]
fn bench_json_has_every_figure() {
    let o = shearsph(&[
        "bench",
        "--kernels",
        "monaghan,composite",
        "--particles",
        "100,300",
        "--steps",
        "3",
        "--repeats",
        "2",
        "--threads",
        "1,2",
        "--json",
        "--quiet",
    ]);
    let r = json(&o);
    let m = &r["machine"];
    for key in [
        "ghz",
        "flops_per_cycle_in_use",
        "peak_gflops_in_use",
        "flops_per_cycle_best",
        "peak_gflops_best",
    ] {
        // the clock comes from /proc/cpuinfo; elsewhere it may be missing
        if m[key].is_number() {
            positive(m, key);
        }
    }
    assert!(m["cores"].as_u64().unwrap() >= 1);
    assert!(m["isa_in_use"].is_string());

    let rows = r["rows"].as_array().unwrap();
    // 2 kernels x 2 counts x 2 thread counts
    assert_eq!(rows.len(), 8);
    for row in rows {
        assert!(row["ok"].as_bool().unwrap(), "{row}");
        assert_eq!(row["steps"].as_u64(), Some(3));
        assert_eq!(row["wall_s_all"].as_array().unwrap().len(), 2);
        let particles = row["particles"].as_u64().unwrap();
        assert!(particles >= row["target_particles"].as_u64().unwrap());
        for key in [
            "wall_s",
            "ns_per_particle_step",
            "particle_steps_per_s",
            "pairs_per_step",
            "pairs_per_s",
            "ns_per_pair",
            "listed_per_particle",
            "gflops",
            "fraction_of_peak_in_use",
            "fraction_of_peak_best",
            "bytes_per_particle",
            "kernel_pass_ns",
            "kernel_alone_ns",
            "forces_ns_per_lane",
            "lane_use",
            "core_ns_per_particle_step",
        ] {
            positive(row, key);
        }
        // the force pass's bound, and with it the floor, take the clock
        // from /proc/cpuinfo: without it they are not numbers (null)
        if m["ghz"].is_number() {
            for key in [
                "forces_lane_bound_ns",
                "floor_core_ns_per_particle_step",
                "floor_kernel_share",
            ] {
                positive(row, key);
            }
            assert!(row["floor_kernel_share"].as_f64().unwrap() < 1.0, "{row}");
        } else {
            assert!(row["floor_core_ns_per_particle_step"].is_null(), "{row}");
        }
        // the passes one by one: each timed, together within the steps
        let shares: Vec<f64> = row["pass_share"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_f64().unwrap())
            .collect();
        assert_eq!(shares.len(), 3, "{row}");
        assert!(shares.iter().all(|&s| s > 0.0), "{row}");
        // and the rebuilds, timed apart from them, within the steps too
        let rebuild = row["rebuild_share"].as_f64().unwrap();
        assert!(rebuild >= 0.0, "{row}");
        assert!(shares.iter().sum::<f64>() + rebuild <= 1.0, "{row}");
        assert_eq!(
            rebuild > 0.0,
            row["neighbour_rebuilds"].as_u64().unwrap() > 0,
            "{row}"
        );
        assert!(row["lane_use"].as_f64().unwrap() <= 1.0, "{row}");
        // small scenes: the force pass reads a window-lane table
        assert_eq!(row["force_g"].as_str(), Some("lanes"), "{row}");
        assert!(row["flops_per_pair"].as_f64().unwrap() > 0.0);
        // the listed pairs include the skin's
        assert!(
            row["listed_per_particle"].as_f64().unwrap() * particles as f64
                >= row["pairs_per_step"].as_f64().unwrap()
        );
    }
    let scaling = r["scaling"].as_array().unwrap();
    assert_eq!(scaling.len(), 4, "one fit per kernel and thread count");
    for s in scaling {
        assert!(s["exponent"].as_f64().unwrap().is_finite());
    }
}

#[test]
fn bench_table_names_the_peak() {
    let o = shearsph(&[
        "bench",
        "--kernels",
        "composite",
        "--particles",
        "100",
        "--steps",
        "2",
        "--repeats",
        "1",
        "--threads",
        "1",
        "--quiet",
    ]);
    assert!(o.status.success());
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(text.contains("flops/cycle"), "{text}");
    assert!(text.contains("composite"), "{text}");
    assert!(text.contains("pass by pass"), "{text}");
}

#[test]
fn bench_rejects_an_unknown_kernel() {
    let o = shearsph(&["bench", "--kernels", "nope", "--quiet"]);
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("monaghan"));
}

/// `--empirical` answers fixed scenes: a flag that would choose other ones
/// is refused before any run, named, and so is a repeat count out of range.
#[test]
fn bench_empirical_refuses_the_flags_it_does_not_take() {
    for (flag, value) in [
        ("--kernels", "monaghan"),
        ("--particles", "1000"),
        ("--steps", "10"),
        ("--threads", "1"),
    ] {
        let o = shearsph(&["bench", "--empirical", flag, value, "--quiet"]);
        assert!(!o.status.success(), "{flag}");
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(
            err.contains(flag) && err.contains("--empirical"),
            "{flag}: {err}"
        );
    }
    let o = shearsph(&["bench", "--empirical", "--repeats", "0", "--quiet"]);
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("--repeats"));
}

#[test]
fn pysph_matched_scene_is_matched() {
    let r = json(&shearsph(&[
        "bench",
        "--pysph-match",
        "--steps",
        "4",
        "--threads",
        "1",
    ]));
    // PySPH's example: 1440 fluid + 240 wall particles; within 5 %.
    let particles = r["particles"].as_u64().unwrap() as f64;
    assert!((particles / 1680.0 - 1.0).abs() < 0.05, "{particles}");
    assert_eq!(r["steps"].as_u64(), Some(4));
    // The viscous limit binds: 4 steps of 0.125 h^2 / nu with h / B = 1/30.
    let tau = r["tau"].as_f64().unwrap();
    assert!((tau - 4.0 * 0.125 / 900.0).abs() < 1e-12, "{tau}");
    positive(&r, "particle_steps_per_s");
    positive(&r, "linf_rel_err");
}

#[test]
fn coarser_pysph_scenes_reach_the_same_time_and_mirrored_walls_are_the_default() {
    let run = |extra: &[&str]| {
        let mut args = vec!["bench", "--pysph-match", "--steps", "400", "--threads", "1"];
        args.extend_from_slice(extra);
        json(&shearsph(&args))
    };
    let matched = run(&[]);
    assert_eq!(matched["wall_velocity"].as_str(), Some("mirrored"));
    assert_eq!(matched["layers"].as_u64(), Some(30));
    assert_eq!(matched["discretisation"].as_str(), Some("square, h = 1 d"));
    // 10 layers: steps scaled by (10/30)^2, the same t nu / B^2 up to the
    // rounding of the step count.
    let coarse = run(&["--layers", "10"]);
    assert_eq!(coarse["steps"].as_u64(), Some(44));
    assert!(coarse["particles"].as_u64().unwrap() < 400);
    let (a, b) = (
        matched["tau"].as_f64().unwrap(),
        coarse["tau"].as_f64().unwrap(),
    );
    assert!((b / a - 1.0).abs() < 0.02, "tau {a} against {b}");
    // The paper's walls at rest on request, and a coarser scene is less
    // accurate than the matched one.
    let zero = run(&["--wall-velocity", "zero"]);
    assert_eq!(zero["wall_velocity"].as_str(), Some("zero"));
    let err = |r: &serde_json::Value| r["linf_rel_err"].as_f64().unwrap();
    assert!(err(&coarse) > err(&matched));
    assert!(err(&zero) > err(&matched));
}

#[test]
fn sphinxsys_matched_scene_is_matched() {
    // The keys bench/peers/sphinxsys_poiseuille.sh reads, and the scene its
    // header fixes: Wendland C2, square lattice, h = 13/10 d, U B / nu = 7.5,
    // c0 = 10 U, B = N d, to t nu / B^2 = TAU on a strip of --columns.
    let matched = |more: &[&str]| {
        let mut args = vec![
            "bench",
            "--sphinxsys-match",
            "--layers",
            "6",
            "--tau",
            "0.02",
            "--threads",
            "1",
            "--columns",
            "12",
        ];
        args.extend_from_slice(more);
        json(&shearsph(&args))
    };
    let r = matched(&[]);
    assert!(r["code"].as_str().unwrap().starts_with("shearsph"));
    assert_eq!(r["discretisation"].as_str(), Some("square, h = 13/10 d"));
    assert_eq!(r["layers"].as_u64(), Some(6));
    assert!((r["re"].as_f64().unwrap() - 7.5).abs() < 1e-12);
    assert!((r["c0_over_u"].as_f64().unwrap() - 10.0).abs() < 1e-12);
    // 11 fluid layers and 2 x 2 wall layers (R h = 2.6 d), 12 columns.
    assert_eq!(r["n_fluid"].as_u64(), Some(11 * 12));
    assert_eq!(r["n_wall"].as_u64(), Some(4 * 12));
    assert_eq!(r["particles"].as_u64(), Some(15 * 12));
    assert_eq!(r["threads"].as_u64(), Some(1));
    // The steps reach TAU (to about one step: measured 0.02 within 1e-3).
    let tau = r["tau"].as_f64().unwrap();
    assert!((tau / 0.02 - 1.0).abs() < 0.01, "{tau}");
    assert!(r["steps"].as_u64().unwrap() > 1);
    for key in ["wall_s", "particle_steps_per_s", "t", "linf_rel_err"] {
        positive(&r, key);
    }
    // The CFL factor the peer figures were measured at, unless --cfl says
    // otherwise; `default` is the kernel's own, the factor `c0` prints for
    // the discretisation, and reaches TAU in fewer steps.
    assert_eq!(r["cfl"].as_f64(), Some(0.5));
    let own = matched(&["--cfl", "default"]);
    let c0 = json(&shearsph(&[
        "c0",
        "--kernel",
        "wendland_c2",
        "--lattice",
        "square",
        "--h-over-d",
        "13/10",
        "--json",
    ]));
    let cfl = own["cfl"].as_f64().unwrap();
    assert_eq!(Some(cfl), c0["cfl"].as_f64());
    assert!(cfl > 0.5, "{cfl}");
    assert!(own["steps"].as_u64() < r["steps"].as_u64(), "{own} {r}");
    // Its 8 steps reach TAU to within one step (measured 0.0207).
    let (tau, steps) = (own["tau"].as_f64().unwrap(), own["steps"].as_u64().unwrap());
    assert!(
        (tau / 0.02 - 1.0).abs() < 1.0 / steps as f64,
        "{tau} in {steps} steps"
    );
    // A factor outside (0, 4], not a number, or so small that the run
    // would outlast its bound is refused, naming the flag.
    for bad in ["0", "5", "nan", "half", "1e-300"] {
        let o = shearsph(&["bench", "--sphinxsys-match", "--cfl", bad]);
        assert!(!o.status.success(), "--cfl {bad}");
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(err.contains("--cfl"), "--cfl {bad}: {err}");
    }
    // Too narrow a strip is refused.
    let o = shearsph(&[
        "bench",
        "--sphinxsys-match",
        "--columns",
        "3",
        "--threads",
        "1",
    ]);
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("--columns 3"));
}

/// `bench --disordered` times a disordered state: its base ran into
/// disorder (dy_rms >= 0.1 d) without failing, and each row is that state
/// tiled, a whole number of copies of the base's particles.
#[test]
fn the_disordered_bench_tiles_a_disordered_base() {
    let o = shearsph(&[
        "bench",
        "--disordered",
        "--kernels",
        "monaghan",
        "--particles",
        "1000,3000",
        "--steps",
        "3",
        "--repeats",
        "1",
        "--threads",
        "1",
        "--no-bandwidth",
        "--json",
        "--quiet",
    ]);
    let r = json(&o);
    let bases = r["bases"].as_array().expect("the bases");
    assert_eq!(bases.len(), 1);
    let b = &bases[0];
    assert!(b["failure"].is_null(), "{b}");
    assert!(positive(b, "dy_rms") >= 0.1, "the base is disordered: {b}");
    assert!(positive(b, "t") >= 640.0, "{b}");
    let base_particles = b["particles"].as_u64().unwrap();
    let rows = r["rows"].as_array().unwrap();
    assert_eq!(rows.len(), 2);
    for (row, target) in rows.iter().zip([1000, 3000]) {
        let p = row["particles"].as_u64().unwrap();
        assert_eq!(
            p % base_particles,
            0,
            "whole copies: {p} of {base_particles}"
        );
        assert!(
            p >= target && p < target + base_particles,
            "{p} for {target}"
        );
        assert_eq!(row["n_layers"].as_u64(), Some(10));
        assert!(row["ok"].as_bool().unwrap(), "{row}");
    }
}

/// A disordered scene too large for the strip's columns is refused before
/// its base runs, naming the flag and the most particles it can tile.
#[test]
fn the_disordered_bench_refuses_more_copies_than_the_strip_holds() {
    let o = shearsph(&[
        "bench",
        "--disordered",
        "--kernels",
        "monaghan",
        "--particles",
        "2.4e6",
        "--quiet",
    ]);
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("--particles 2.4e6 with --disordered") && err.contains("at most"),
        "{err}"
    );
}
