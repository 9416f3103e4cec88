//! `shearsph run` and `shearsph c0` from the outside: outputs written, an
//! existing folder kept without --force, clear errors for bad input.

use std::path::Path;
use std::process::{Command, Output};

use shearsph::kernels::KERNELS;

fn shearsph(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_shearsph"))
        .args(args)
        .output()
        .unwrap()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// A run that takes a fraction of a second.
fn quick_run(out: &Path, extra: &[&str]) -> Output {
    let mut args = vec![
        "run",
        "--n",
        "4",
        "--t-end",
        "10",
        "--quiet",
        "--out",
        out.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    shearsph(&args)
}

#[test]
fn run_writes_every_output() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("run");
    let o = quick_run(&out, &["--json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    for f in [
        "summary.json",
        "profile.csv",
        "timeseries.csv",
        "profile.svg",
        "timeseries.svg",
        "scene.toml",
    ] {
        assert!(out.join(f).is_file(), "missing {f}");
    }
    // No temporary files left behind.
    let names: Vec<_> = std::fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .collect();
    assert!(names.iter().all(|n| !n.starts_with(".tmp")), "{names:?}");

    // --json prints the summary that was written.
    let printed: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let written: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    for key in [
        "kernel",
        "n_layers",
        "particles",
        "d",
        "b",
        "u",
        "nu",
        "p",
        "t_end",
        "steps",
        "dt",
        "dt_limit",
        "c0",
        "c0_rule",
        "wall_s",
        "linf_rel_err",
        "l2_rel_err",
        "max_eps",
        "rms_v",
        "outcome",
    ] {
        assert!(written.get(key).is_some(), "summary.json lacks {key}");
    }
    assert_eq!(written["outcome"], "ok");
    assert_eq!(written["n_layers"], 4);
    assert_eq!(printed["steps"], written["steps"]);

    let profile = std::fs::read_to_string(out.join("profile.csv")).unwrap();
    let header: Vec<&str> = profile.lines().next().unwrap().split(',').collect();
    for col in ["y", "u", "u_analytic"] {
        assert!(header.contains(&col), "profile.csv header {header:?}");
    }
    // One row per fluid layer, n = -3 ..= 3.
    assert_eq!(profile.lines().count(), 1 + 7);
    let series = std::fs::read_to_string(out.join("timeseries.csv")).unwrap();
    assert!(series.starts_with("t,"));
    assert!(std::fs::read_to_string(out.join("profile.svg"))
        .unwrap()
        .contains("<svg"));

    // The scene as run reads back as a scene.
    let scene = std::fs::read_to_string(out.join("scene.toml")).unwrap();
    shearsph::scene::Scene::from_toml(&scene).unwrap();
}

#[test]
fn run_keeps_an_existing_folder_without_force() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("run");
    assert!(quick_run(&out, &[]).status.success());
    let before = std::fs::read(out.join("summary.json")).unwrap();

    let again = quick_run(&out, &["--u", "2"]);
    assert_eq!(again.status.code(), Some(1));
    assert!(stderr(&again).contains("--force"), "{}", stderr(&again));
    assert_eq!(
        std::fs::read(out.join("summary.json")).unwrap(),
        before,
        "untouched"
    );

    let forced = quick_run(&out, &["--u", "2", "--force"]);
    assert!(forced.status.success(), "{}", stderr(&forced));
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["u"], 2.0);
}

#[test]
fn bad_input_names_the_field_and_the_fix() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("never");
    let cases: &[(&[&str], &[&str])] = &[
        (&["--n", "1"], &["n_layers", "--n", ">= 3"]),
        (&["--kernel", "nope"], &["unknown kernel", "monaghan"]),
        (
            &["--kernel", "monagan"],
            &["unknown kernel", "did you mean \"monaghan\""],
        ),
        (
            &["--t-end", "1e9", "--re", "1000", "--c0", "rule10"],
            &[
                "max_run_s",
                "would take about",
                "days",
                "--max-run-s",
                "cfl",
            ],
        ),
        (&["--alpha", "2"], &["alpha", "[0, 1]"]),
        (&["--u", "-1"], &["`u`", "positive"]),
        (&["--re", "0"], &["`re`", "positive"]),
        (&["--d", "0"], &["`d`", "positive"]),
        (&["--t-end", "-5"], &["t_end", "positive"]),
        (&["--c0", "0"], &["c0", "positive"]),
        (&["--c0", "banana"], &["c0", "rule10"]),
        (&["--c0", "derived:nope"], &["c0", "models"]),
        (&["--initial", "moving"], &["initial", "rest"]),
    ];
    for (args, wanted) in cases {
        let o = quick_run(&out, args);
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(1), "{args:?}: {err}");
        for w in *wanted {
            assert!(err.contains(w), "{args:?}: {err:?} lacks {w:?}");
        }
    }
    assert!(!out.exists(), "a refused scene writes nothing");

    // Flags clap itself refuses.
    let o = quick_run(&out, &["--re", "10", "--p", "0.1"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let o = quick_run(&out, &["--bogus"]);
    assert_eq!(o.status.code(), Some(2));

    // A scene file with a misspelt field.
    let file = dir.path().join("scene.toml");
    std::fs::write(&file, "kernel = \"monaghan\"\nn_layer = 5\n").unwrap();
    let o = quick_run(&out, &["--scene", file.to_str().unwrap()]);
    assert!(
        stderr(&o).contains("n_layer") && stderr(&o).contains(file.to_str().unwrap()),
        "{}",
        stderr(&o)
    );
    // A scene file with both re and p.
    std::fs::write(&file, "re = 10\np = 0.1\n").unwrap();
    let o = quick_run(&out, &["--scene", file.to_str().unwrap()]);
    assert!(stderr(&o).contains("both `re` and `p`"), "{}", stderr(&o));
}

#[test]
fn scene_file_then_flags_override_the_builtin_scene() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("scene.toml");
    std::fs::write(&file, "n_layers = 5\np = 0.01\nalpha = 0.05\n").unwrap();
    let out = dir.path().join("run");
    let o = shearsph(&[
        "run",
        "--scene",
        file.to_str().unwrap(),
        "--alpha",
        "0.2",
        "--t-end",
        "5",
        "--quiet",
        "--json",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let s: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(s["n_layers"], 5);
    assert_eq!(s["p"], 0.01);
    assert_eq!(s["alpha"], 0.2);
    assert_eq!(s["kernel"], "monaghan", "from the built-in scene");
}

#[test]
fn failed_run_writes_outputs_and_exits_3() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("run");
    let o = shearsph(&[
        "run",
        "--n",
        "6",
        "--jitter",
        "0.05",
        "--c0",
        "0.01*rule10",
        "--quiet",
        "--json",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(3), "{}", stderr(&o));
    let s: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(s["outcome"], "failed");
    assert!(
        s["failure_reason"].as_str().unwrap().contains("compaction"),
        "{s}"
    );
    assert!(s["failure_t"].as_f64().unwrap() < s["t_end"].as_f64().unwrap());
    assert!(out.join("summary.json").is_file());
}

#[test]
fn c0_lists_every_rule_with_its_time_step() {
    let o = shearsph(&["c0", "--kernel", "monaghan", "--json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let t: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let rows = t["rows"].as_array().unwrap();
    let rules: Vec<&str> = rows.iter().map(|r| r["rule"].as_str().unwrap()).collect();
    let info = KERNELS.iter().find(|k| k.name == "monaghan").unwrap();
    for m in info.c0_models {
        assert!(
            rules.contains(&format!("derived:{}", m.name).as_str()),
            "{rules:?}"
        );
    }
    assert!(
        rules.contains(&"rule10") && rules.contains(&"table2"),
        "{rules:?}"
    );
    let rule10 = rows.iter().find(|r| r["rule"] == "rule10").unwrap();
    assert_eq!(rule10["c0"], 10.0);
    // 0.25 h / (c0 + U) with h = 1, U = 1.
    assert!((rule10["cost"]["dt_cfl"].as_f64().unwrap() - 0.25 / 11.0).abs() < 1e-15);
    assert!(rule10["cost"]["dt_limit"].is_string());

    let text = shearsph(&["c0", "--kernel", "monaghan", "--n", "12"]);
    assert!(text.status.success());
    let text = String::from_utf8(text.stdout).unwrap();
    assert!(text.contains("rule10") && text.contains("N = 12"), "{text}");
}
