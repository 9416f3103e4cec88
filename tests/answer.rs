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
