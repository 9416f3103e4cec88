//! `shearsph run` and `shearsph c0` from the outside: outputs written, an
//! existing folder kept without --force, clear errors for bad input (one
//! test per kind), a failed run naming its particle, Ctrl-C keeping the
//! outputs so far.

use crate::common;
use common::*;

use std::io::{BufRead, BufReader, Read};
use std::path::Path;
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use shearsph::kernels::KERNELS;

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
    shearsph::config::Scene::from_toml(&scene).unwrap();
}

#[test]
fn run_keeps_an_existing_folder_without_force() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("run");
    assert!(quick_run(&out, &[]).status.success());
    let before = std::fs::read(out.join("summary.json")).unwrap();

    let again = quick_run(&out, &["--u", "2"]);
    assert_eq!(again.status.code(), Some(1));
    let err = stderr(&again);
    for w in [
        out.to_str().unwrap(),
        "already exists",
        "--force",
        "another with --out",
    ] {
        assert!(err.contains(w), "{err:?} lacks {w:?}");
    }
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

/// A scene `shearsph run` refuses before writing anything: exit status 1, an
/// error that holds every one of `wanted` (the field, the flag, the fix).
fn assert_refused(args: &[&str], wanted: &[&str]) {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("never");
    let o = quick_run(&out, args);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{args:?}: {err}");
    for w in wanted {
        assert!(err.contains(w), "{args:?}: {err:?} lacks {w:?}");
    }
    assert!(!out.exists(), "{args:?}: a refused scene writes nothing");
}

#[test]
fn n_too_small_for_the_support_is_refused() {
    assert_refused(
        &["--n", "1"],
        &["`n_layers`", "--n", "support R = 2", ">= 3"],
    );
    // The bound follows the kernel's support.
    assert_refused(
        &["--kernel", "morris", "--n", "3"],
        &["`n_layers`", "--n", "support R = 3", "use n_layers >= 4"],
    );
}

#[test]
fn non_positive_u_is_refused() {
    assert_refused(
        &["--u", "-1"],
        &["`u`", "--u", "must be a positive finite number"],
    );
    assert_refused(
        &["--u", "0"],
        &["`u`", "--u", "must be a positive finite number"],
    );
}

#[test]
fn non_positive_re_is_refused() {
    assert_refused(
        &["--re", "0"],
        &["`re`", "--re", "must be a positive finite number"],
    );
    assert_refused(
        &["--re", "-3"],
        &["`re`", "--re", "must be a positive finite number"],
    );
}

#[test]
fn non_positive_d_is_refused() {
    assert_refused(
        &["--d", "0"],
        &["`d`", "--d", "must be a positive finite number"],
    );
}

#[test]
fn non_positive_c0_is_refused() {
    for c0 in ["0", "-2"] {
        assert_refused(
            &["--c0", c0],
            &[
                "`c0`",
                "--c0",
                "not a positive sound speed",
                "give a positive number or another rule",
            ],
        );
    }
    // Not a number nor a rule: the rules are listed.
    assert_refused(&["--c0", "banana"], &["c0", "rule10"]);
    assert_refused(&["--c0", "derived:nope"], &["c0", "models"]);
}

#[test]
fn non_positive_end_time_is_refused() {
    assert_refused(
        &["--t-end", "-5"],
        &["`t_end`", "--t-end", "must be a positive finite number"],
    );
    assert_refused(
        &["--t-end", "0"],
        &["`t_end`", "--t-end", "must be a positive finite number"],
    );
}

#[test]
fn alpha_outside_0_1_is_refused() {
    for alpha in ["2", "-0.1"] {
        assert_refused(
            &["--alpha", alpha],
            &["`alpha`", "--alpha", "outside [0, 1]"],
        );
    }
}

#[test]
fn unknown_kernel_lists_the_known_ones_and_suggests_the_nearest() {
    let mut wanted = vec!["unknown kernel \"nope\"", "--kernel", "known kernels:"];
    wanted.extend(KERNELS.iter().map(|k| k.name));
    assert_refused(&["--kernel", "nope"], &wanted);
    assert_refused(
        &["--kernel", "monagan"],
        &["unknown kernel", "did you mean \"monaghan\""],
    );
}

#[test]
fn too_long_a_run_says_how_long_and_how_to_change_the_bound() {
    assert_refused(
        &["--t-end", "1e9", "--re", "1000", "--c0", "rule10"],
        &[
            "`max_run_s`",
            "would take about",
            "days",
            "bound by the cfl limit",
            "raise it (--max-run-s)",
            "shorten t_end",
        ],
    );
}

#[test]
fn unknown_scene_file_key_is_refused_naming_file_and_key() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("scene.toml");
    std::fs::write(&file, "kernel = \"monaghan\"\nn_layer = 5\n").unwrap();
    assert_refused(
        &["--scene", file.to_str().unwrap()],
        &[
            file.to_str().unwrap(),
            "unknown field `n_layer`",
            "expected one of",
            "`n_layers`",
        ],
    );
    // A scene file with both re and p.
    std::fs::write(&file, "re = 10\np = 0.1\n").unwrap();
    assert_refused(&["--scene", file.to_str().unwrap()], &["both `re` and `p`"]);
}

#[test]
fn other_bad_flags_are_refused() {
    assert_refused(&["--initial", "moving"], &["initial", "rest"]);
    // Flags clap itself refuses: bad input, exit 1 like every other.
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("never");
    let o = quick_run(&out, &["--re", "10", "--p", "0.1"]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(stderr(&o).contains("cannot be used with"), "{}", stderr(&o));
    let o = quick_run(&out, &["--bogus"]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("--bogus"), "{}", stderr(&o));
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
    let written: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(written, s);

    // The particle that triggered it: which one, where, how fast.
    let p = &s["failure_particle"];
    let index = p["index"].as_u64().unwrap();
    assert!(index < s["fluid_particles"].as_u64().unwrap(), "{p}");
    let (x, y) = (p["x"].as_f64().unwrap(), p["y"].as_f64().unwrap());
    assert!(y.abs() < s["b"].as_f64().unwrap(), "{p}");
    for key in ["layer", "vx", "vy"] {
        assert!(p[key].is_number(), "{p}");
    }
    // And stderr says it in words.
    let err = stderr(&o);
    for part in [
        format!(
            "class: failed at t = {:.6}",
            s["failure_t"].as_f64().unwrap()
        ),
        format!("step {}", s["failure_step"]),
        format!("fluid particle {index} (started in layer {})", p["layer"]),
        format!("x = {x:.4}, y = {y:.4}"),
    ] {
        assert!(err.contains(&part), "{err:?} lacks {part:?}");
    }

    // The text summary too.
    let text = shearsph(&[
        "run",
        "--n",
        "6",
        "--jitter",
        "0.05",
        "--c0",
        "0.01*rule10",
        "--quiet",
        "--force",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(text.status.code(), Some(3));
    let text = String::from_utf8(text.stdout).unwrap();
    assert!(
        text.contains(&format!("fluid particle {index} ")) && text.contains("compaction"),
        "{text}"
    );
}

/// SIGINT to a running `shearsph run`: it ends at the next step, writes
/// every output up to there (summary `interrupted`, the partial time series,
/// profile, charts), says where it stopped and exits with status 130.
#[test]
fn ctrl_c_stops_a_run_and_keeps_its_outputs_so_far() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("run");
    // Minutes of work if it ran to the end; outputs every unit of time.
    let mut child = Command::new(env!("CARGO_BIN_EXE_shearsph"))
        .args([
            "run",
            "--n",
            "30",
            "--t-end",
            "100000",
            "--output-interval",
            "1",
            "--json",
            "--out",
            out.to_str().unwrap(),
        ])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // The run says it started once its Ctrl-C handler is in place.
    let mut err = BufReader::new(child.stderr.take().unwrap());
    let mut first = String::new();
    err.read_line(&mut first).unwrap();
    assert!(first.contains("Ctrl-C stops"), "{first:?}");
    // Let it pass a few output times (not asserted: any stop point is fine).
    let start = Instant::now();
    while start.elapsed() < Duration::from_millis(300) {
        assert!(child.try_wait().unwrap().is_none(), "ended by itself");
        std::thread::sleep(Duration::from_millis(10));
    }
    let signalled = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(signalled.success());
    let mut rest = String::new();
    err.read_to_string(&mut rest).unwrap();
    let o = child.wait_with_output().unwrap();
    assert_eq!(o.status.code(), Some(130), "{rest}");

    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(s["outcome"], "interrupted");
    assert_eq!(
        s,
        serde_json::from_slice::<serde_json::Value>(&o.stdout).unwrap()
    );
    let (t, steps) = (s["t"].as_f64().unwrap(), s["steps"].as_u64().unwrap());
    assert!(t > 0.0 && t < s["t_end"].as_f64().unwrap(), "t = {t}");
    assert!(
        rest.contains(&format!("interrupted at t = {t:.6}, step {steps}")),
        "{rest}"
    );
    assert!(rest.contains(out.to_str().unwrap()), "{rest}");

    // The time series: t = 0, every output time passed (1, 2, ...), and
    // the time reached.
    let series = std::fs::read_to_string(out.join("timeseries.csv")).unwrap();
    let rows: Vec<(f64, u64)> = series
        .lines()
        .skip(1)
        .map(|l| {
            let mut f = l.split(',');
            (
                f.next().unwrap().parse().unwrap(),
                f.next().unwrap().parse().unwrap(),
            )
        })
        .collect();
    let (last, passed) = rows.split_last().unwrap();
    assert_eq!(*last, (t, steps));
    let want: Vec<f64> = (0..).map(f64::from).take_while(|&k| k < t).collect();
    let got: Vec<f64> = passed.iter().map(|r| r.0).collect();
    assert_eq!(got, want);
    for f in ["profile.csv", "profile.svg", "timeseries.svg", "scene.toml"] {
        assert!(out.join(f).is_file(), "missing {f}");
    }
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
    // cfl h / (c0 + U) with h = 1, U = 1 and the default cfl: half the
    // factor at which the kernel's pressure term is stable, at most 1.
    let (cfl, stable) = (
        t["cfl"].as_f64().unwrap(),
        t["cfl_stable"].as_f64().unwrap(),
    );
    assert!(stable > 1.8 && stable < 1.9, "{stable}");
    assert_eq!(cfl, (0.5 * stable).min(1.0));
    assert!((rule10["cost"]["dt_cfl"].as_f64().unwrap() - cfl / 11.0).abs() < 1e-15);
    assert!(rule10["cost"]["dt_limit"].is_string());

    let text = shearsph(&["c0", "--kernel", "monaghan", "--n", "12"]);
    assert!(text.status.success());
    let text = String::from_utf8(text.stdout).unwrap();
    assert!(text.contains("rule10") && text.contains("N = 12"), "{text}");
}

#[test]
fn c0_on_a_square_lattice_with_h_13_10_is_that_discretisations() {
    let args = [
        "c0",
        "--kernel",
        "monaghan",
        "--n",
        "10",
        "--re",
        "10",
        "--lattice",
        "square",
        "--h-over-d",
        "13/10",
    ];
    let o = shearsph(&args);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = String::from_utf8(o.stdout).unwrap();
    assert!(text.contains("square lattice, h = 13/10 d"), "{text}");
    let mut json_args = args.to_vec();
    json_args.push("--json");
    let o = shearsph(&json_args);
    assert!(o.status.success(), "{}", stderr(&o));
    let t: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(t["lattice"], "square");
    assert_eq!(t["h_over_d"], "13/10");
    assert_eq!(t["discretisation"], "square, h = 13/10 d");
    // The derived c0 is the square h = 13/10 d discretisation's model on this
    // scene: B = N d, p = 2 U^2 / (Re B) = 0.02, A = p d N^4 / U^2 = 200.
    let info = KERNELS.iter().find(|k| k.name == "monaghan").unwrap();
    let disc = info
        .discretisation(shearsph::kernel::Lattice::Square, 1.3)
        .expect("square 13/10 is generated");
    let p = t["p"].as_f64().unwrap();
    assert!((p - 0.02).abs() < 1e-15, "p {p}");
    let row = |rule: &str| {
        t["rows"]
            .as_array()
            .unwrap()
            .iter()
            .find(|r| r["rule"] == rule)
            .unwrap_or_else(|| panic!("row {rule}"))["c0"]
            .as_f64()
            .unwrap()
    };
    for m in disc.c0_models {
        let want = m.c0(1.0, 10.0, p, 1.0, 0.1);
        let got = row(&format!("derived:{}", m.name));
        assert!(
            (got - want).abs() <= 1e-14 * want.abs(),
            "{}: {got} against {want}",
            m.name
        );
    }
    // ... and not the paper's discretisation's (h/d is not ignored), and no
    // Table 2 row (the paper's table is for its own discretisation).
    let paper = shearsph(&[
        "c0", "--kernel", "monaghan", "--n", "10", "--re", "10", "--json",
    ]);
    let paper: serde_json::Value = serde_json::from_slice(&paper.stdout).unwrap();
    let paper_c0 = paper["rows"][0]["c0"].as_f64().unwrap();
    assert!(
        (row("derived:field-av") - paper_c0).abs() > 0.01,
        "{paper_c0}"
    );
    assert!(t["rows"]
        .as_array()
        .unwrap()
        .iter()
        .all(|r| r["rule"] != "table2"));
    // A number finds the same discretisation.
    let mut num = json_args.clone();
    num[10] = "1.3";
    let o = shearsph(&num);
    let n: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(n["rows"], t["rows"]);
}

#[test]
fn an_ungenerated_discretisation_names_the_line_to_add() {
    for cmd in ["c0", "run"] {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("out");
        let mut args = vec![cmd, "--lattice", "square", "--h-over-d", "3/2"];
        if cmd == "run" {
            args.extend(["--quiet", "--out", out.to_str().unwrap()]);
        }
        let o = shearsph(&args);
        assert_eq!(o.status.code(), Some(1), "{cmd}");
        let e = stderr(&o);
        for want in [
            "--h-over-d",
            "kernels/discretisations.toml",
            "[[discretisation]]\nlattice = \"square\"\nh_over_d = \"3/2\"",
            "cargo run -p shearsph-codegen -- generate",
        ] {
            assert!(e.contains(want), "{cmd}: no {want:?} in {e}");
        }
        assert!(!out.exists(), "{cmd} wrote before refusing");
    }
    // Not a number nor a rational: bad input like any other, exit 1.
    let o = shearsph(&["c0", "--h-over-d", "13/x"]);
    assert_eq!(o.status.code(), Some(1));
    assert!(
        stderr(&o).contains("neither a number nor a rational"),
        "{}",
        stderr(&o)
    );
    // The same lookup for a scene file's fields.
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("scene.toml");
    std::fs::write(&file, "lattice = \"square\"\nh_over_d = \"7/4\"\n").unwrap();
    let o = shearsph(&["c0", "--scene", file.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("h_over_d = \"7/4\""), "{}", stderr(&o));
    std::fs::write(&file, "lattice = \"hexagonal\"\n").unwrap();
    let o = shearsph(&["c0", "--scene", file.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("lattice"), "{}", stderr(&o));
}

/// docs/c0-rules.md's table is the registry's (`config::RULES`): every
/// rule's name, c0 and source, in its order; and `--help` says each.
#[test]
fn the_rules_table_and_help_are_the_registry() {
    let page =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/docs/c0-rules.md")).unwrap();
    let rows: Vec<&str> = page
        .lines()
        .skip_while(|l| !l.starts_with("| rule | c0 | source |"))
        .skip(2)
        .take_while(|l| l.starts_with('|'))
        .collect();
    let want: Vec<String> = shearsph::config::RULES
        .iter()
        .map(|e| {
            let names: Vec<String> = e.syntax.split(", ").map(|n| format!("`{n}`")).collect();
            format!("| {} | {} | {} |", names.join(", "), e.formula, e.source)
        })
        .collect();
    assert_eq!(rows, want, "docs/c0-rules.md's table against config::RULES");
    let help = Command::new(env!("CARGO_BIN_EXE_shearsph"))
        .args(["run", "--help"])
        .output()
        .unwrap();
    let help = String::from_utf8_lossy(&help.stdout).replace(char::is_whitespace, "");
    for e in shearsph::config::RULES {
        let said = format!("{}:{}", e.syntax, e.formula.replace("\\|", "|"));
        assert!(
            help.contains(&said.replace(char::is_whitespace, "")),
            "--help lacks {said}"
        );
    }
}

/// A time-step factor above the kernel's stable one is run as asked, with
/// a warning naming the factor, the bound and the flag, from `run` and
/// from `c0`; at the defaults neither warns.
#[test]
fn factors_above_the_stable_ones_are_warned_about() {
    let dir = tempfile::tempdir().unwrap();
    let o = quick_run(
        &dir.path().join("above"),
        &["--cfl", "2", "--viscous-dt", "0.5"],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let err = stderr(&o);
    for wanted in [
        "warning: cfl = 2 is above 1.8597",
        "pressure term is stable on the perfect lattice",
        "(--cfl)",
        "warning: viscous_dt = 0.5 is above 0.1866",
        "(--viscous-dt)",
    ] {
        assert!(err.contains(wanted), "{wanted:?} not in {err}");
    }
    let c0 = shearsph(&["c0", "--kernel", "monaghan", "--cfl", "2"]);
    assert!(c0.status.success(), "{}", stderr(&c0));
    assert!(stderr(&c0).contains("warning: cfl = 2 is above 1.8597"));
    assert!(stdout(&c0).contains("stable on the perfect lattice up to cfl = 1.8597"));
    let plain = quick_run(&dir.path().join("plain"), &[]);
    assert!(plain.status.success() && !stderr(&plain).contains("warning"));
}
