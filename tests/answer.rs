//! `shearsph c0 --empirical`: the answer's JSON schema, and a too-small c0
//! is not ok on a perturbed lattice even where the perfect lattice hides it.

use std::process::Command;

use indicatif::ProgressBar;
use serde_json::Value;
use shearsph::answer::{trial, Search};
use shearsph::config::Scene;
use shearsph::solver::Class;

#[test]
fn a_too_small_c0_is_not_ok_on_a_perturbed_lattice() {
    // The built-in scene (Monaghan, N = 10, Re = 10) at c0 = 0.1 U, about
    // its derived c0: pure shear on the perfect lattice needs no pressure,
    // so it runs ok there; jittered by 0.05 d it is not.
    let scene = Scene::builtin();
    let search = Search {
        seeds: 2,
        ..Search::default()
    };
    let t = trial(&scene, 0.1 * scene.u, &search, &ProgressBar::hidden()).unwrap();
    assert_eq!(t.outcome_perfect, Class::Ok, "{t:?}");
    assert_ne!(t.outcome_perturbed, Class::Ok, "{t:?}");
    assert!(!t.ok());
}

#[test]
fn the_empirical_answer_has_its_schema() {
    let out = Command::new(env!("CARGO_BIN_EXE_shearsph"))
        .args([
            "c0",
            "--empirical",
            "--json",
            "--quiet",
            "--n",
            "6",
            "--re",
            "10",
            "--t-end",
            "3",
            "--seeds",
            "1",
            "--rel-tol",
            "0.5",
        ])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert!(v["recommended"].is_number() || v["recommended"].is_null());
    let rules = v["rules"].as_array().unwrap();
    assert!(rules.len() >= 10, "every rule: {rules:?}");
    for r in rules {
        for key in [
            "name",
            "c0",
            "outcome_perfect",
            "outcome_perturbed",
            "linf",
            "steps",
            "wall_s",
        ] {
            assert!(r.get(key).is_some(), "rule {r} lacks {key}");
        }
    }
    let names: Vec<&str> = rules.iter().map(|r| r["name"].as_str().unwrap()).collect();
    for rule in [
        "rule10",
        "morris1997",
        "gpusph",
        "dualsphysics",
        "trixi",
        "derived-eps",
    ] {
        assert!(names.contains(&rule), "{rule} missing from {names:?}");
    }
    for r in rules {
        if let Some(c) = r["outcome_perfect"].as_str() {
            assert!(["ok", "inaccurate", "over-compressed", "failed"].contains(&c));
        }
    }
}

#[test]
fn empirical_as_a_c0_rule_runs_the_bisection_first() {
    // `run --c0 empirical`: the bisection for the scene, said on stdout,
    // then the run itself at that c0 (its summary's c0 is the number said).
    let dir = tempfile::tempdir().unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_shearsph"))
        .args([
            "run",
            "--quiet",
            "--no-particles",
            "--n",
            "6",
            "--re",
            "10",
            "--t-end",
            "3",
        ])
        .args(["--c0", "empirical", "--out"])
        .arg(dir.path())
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        stdout.starts_with("c0 = empirical = "),
        "{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let said: f64 = stdout["c0 = empirical = ".len()..]
        .split_whitespace()
        .next()
        .unwrap()
        .parse()
        .unwrap();
    let summary: Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("summary.json")).unwrap())
            .unwrap();
    let c0 = summary["c0"]
        .as_f64()
        .unwrap_or_else(|| summary["problem"]["c0"].as_f64().unwrap());
    assert!((c0 - said).abs() <= 1e-6 * said, "{c0} vs {said}");
    // and the same search the c0 command's answer makes: its recommendation
    let ans = Command::new(env!("CARGO_BIN_EXE_shearsph"))
        .args([
            "c0", "--json", "--quiet", "--n", "6", "--re", "10", "--t-end", "3",
        ])
        .args(["--c0", "empirical"])
        .output()
        .unwrap();
    let v: Value = serde_json::from_slice(&ans.stdout).unwrap();
    let rec = v["recommended"].as_f64().unwrap();
    assert!((rec - said).abs() <= 1e-6 * said, "{rec} vs {said}");
}

#[test]
fn the_quick_law_writes_its_points_fits_and_chart() {
    let dir = tempfile::tempdir().unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_shearsph"))
        .args(["law", "--quick", "--quiet", "--force", "--out"])
        .arg(dir.path())
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let csv = std::fs::read_to_string(dir.path().join("law.csv")).unwrap();
    // a header and one row per point of src/law/quick.toml (2 N x 2 Re x 2 alpha)
    assert_eq!(csv.lines().count(), 1 + 8, "{csv}");
    assert!(csv.starts_with("kernel,n,re,alpha,c0_min_over_u,below_over_u"));
    let v: Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("law.json")).unwrap())
            .unwrap();
    let law = &v["laws"][0];
    assert_eq!(law["kernel"], "monaghan");
    let fitted = law["fitted"].as_u64().unwrap() as usize;
    assert_eq!(fitted + law["unfitted"].as_array().unwrap().len(), 8);
    let svg = std::fs::read_to_string(dir.path().join("law_monaghan.svg")).unwrap();
    assert!(svg.contains("<svg") && svg.contains("Re = 1"));
}
