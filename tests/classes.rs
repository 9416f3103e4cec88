//! One classification everywhere: `shearsph run` gives a scene the class
//! the sweep gives the same scene, with the same bounds, and its exit status
//! tells the classes apart.

use std::process::Command;
use std::sync::atomic::AtomicBool;

use serde_json::Value;
use shearsph::config::Scene;
use shearsph::sweep::{run_point, Class, ClassRules, Point, PointC0};

/// `shearsph run` on the built-in scene with `args`: its summary and exit code.
fn run_cli(args: &[&str]) -> (Value, Option<i32>) {
    let dir = tempfile::tempdir().unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_shearsph"))
        .args(["run", "--quiet", "--json", "--out"])
        .arg(dir.path().join("run"))
        .args(args)
        .output()
        .unwrap();
    let summary: Value = serde_json::from_slice(&out.stdout)
        .unwrap_or_else(|e| panic!("{e}: {}", String::from_utf8_lossy(&out.stderr)));
    (summary, out.status.code())
}

/// The sweep's row for the built-in scene at N = `n` with sound speed `c0`.
fn sweep_class(n: u32, c0: &str, rules: &ClassRules) -> Class {
    let scene = Scene::builtin();
    let point = Point {
        at: Default::default(),
        disc: Default::default(),
        start: Default::default(),
        index: 0,
        kernel: scene.kernel.clone(),
        n,
        re: scene.re.unwrap(),
        alpha: scene.alpha,
        c0: PointC0::Spec(c0.parse().unwrap()),
    };
    run_point(
        &point,
        &toml::Table::new(),
        rules,
        &AtomicBool::new(false),
        None,
    )
    .unwrap()
    .class
}

#[test]
fn run_classes_a_scene_as_the_sweep_does_and_says_so_in_its_exit_code() {
    // c0 = 1000 U at N = 6: the run reaches t_end, but the artificial
    // viscosity's shear (about alpha c0 h / 8) is far larger than nu, so the
    // profile is wrong by most of U.
    let (summary, code) = run_cli(&["--n", "6", "--c0", "1e3"]);
    let sweep = sweep_class(6, "1e3", &ClassRules::default());
    assert_eq!(summary["outcome"], "ok");
    assert_eq!(summary["class"], "inaccurate");
    assert_eq!(summary["class"], sweep.name());
    assert_eq!(code, Some(4));

    // The bounds are the scene's: loosened past the error, the same run is ok
    // for both, and exits 0.
    let loose = ClassRules {
        linf_bound: 2.0,
        ..ClassRules::default()
    };
    let (summary, code) = run_cli(&["--n", "6", "--c0", "1e3", "--linf-bound", "2"]);
    assert_eq!(summary["class"], "ok");
    assert_eq!(sweep_class(6, "1e3", &loose), Class::Ok);
    assert_eq!(code, Some(0));
}
