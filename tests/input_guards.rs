//! Bad input and bad luck: no hang, no panic, no meaningless "ok", nothing
//! lost. One test per class of input, each asserting what the message says,
//! and a property test over every numeric scene field.

use crate::common;
use common::*;

use std::process::{Command, Output};

use proptest::prelude::*;
use shearsph::config::{C0Spec, Scene};
use shearsph::problem::{cost, Problem};

/// The error of the built-in scene edited by `edit`.
fn resolve_err(edit: impl Fn(&mut Scene)) -> String {
    let mut scene = Scene::builtin();
    edit(&mut scene);
    let info = scene.kernel_info().unwrap();
    match Problem::resolve(&scene, info) {
        Ok(p) => panic!("resolved: c0 {} t_end {}", p.c0, p.t_end),
        Err(e) => e.to_string(),
    }
}

type Edit = Box<dyn Fn(&mut Scene)>;

#[test]
fn derived_quantities_name_the_input() {
    let cases: Vec<(Edit, &str, &str)> = vec![
        (Box::new(|s| s.d = 1e300), "d", "1e300"),
        (Box::new(|s| s.d = 1e-300), "d", "1e-300"),
        (Box::new(|s| s.decay_tol = 10.0), "decay_tol", "10"),
        (Box::new(|s| s.decay_tol = 1.5), "decay_tol", "1.5"),
        (Box::new(|s| s.re = Some(1e308)), "re", "1e308"),
        (Box::new(|s| s.u = 1e-300), "u", "1e-300"),
        (Box::new(|s| s.u = 1e300), "u", "1e300"),
        (
            Box::new(|s| {
                s.re = None;
                s.p = Some(1e-320)
            }),
            "p",
            "1e-320",
        ),
        (Box::new(|s| s.rho0 = 1e-320), "rho0", "1e-320"),
        (Box::new(|s| s.rho0 = 1e200), "rho0", "1e200"),
        (Box::new(|s| s.c0 = C0Spec::Value(1e-300)), "c0", "1e-300"),
        (Box::new(|s| s.h_over_d = 1e-300), "h_over_d", "1e-300"),
        (Box::new(|s| s.gamma = 1e308), "gamma", "1e308"),
        // Far too long for any bound: the input that made it is named.
        (Box::new(|s| s.t_end = Some(1e300)), "t_end", "days"),
        (Box::new(|s| s.max_run_s = f64::NAN), "max_run_s", "NaN"),
    ];
    for (edit, field, shown) in cases {
        let err = resolve_err(edit);
        assert!(err.contains(&format!("`{field}`")), "{field}: {err}");
        assert!(err.contains(shown), "{field}: {err}");
        // Numbers are echoed short, never as hundreds of digits.
        assert!(!err.contains("0000000000"), "{err}");
    }
}

#[test]
fn memory_and_size_are_estimated_before_running() {
    let err = resolve_err(|s| s.output_interval = Some(1e-4));
    assert!(
        err.contains("`output_interval`") && err.contains("GB of memory"),
        "{err}"
    );
    assert!(
        err.contains("samples kept") && err.contains("--output-interval"),
        "{err}"
    );
    // h/d is a generated discretisation's (at most 4), so a huge one is
    // refused by that guard before any estimate
    let err = resolve_err(|s| s.h_over_d = 1e10);
    assert!(
        err.contains("`h_over_d`") && err.contains("1e10 is outside (0, 4]"),
        "{err}"
    );
    let err = resolve_err(|s| s.n_layers = 4_000_000_000);
    assert!(
        err.contains("`n_layers`") && err.contains("lower --n"),
        "{err}"
    );
    for count in ["1e10", "1e8"] {
        let o = shearsph(&["bench", "--quiet", "--particles", count]);
        assert!(!o.status.success());
        let e = stderr(&o);
        assert!(
            e.contains(&format!("--particles {count}")) && e.contains("GB of memory"),
            "{e}"
        );
    }
    // What passes the guard is within it.
    let scene = Scene {
        output_interval: Some(1e-3),
        ..Scene::builtin()
    };
    let p = Problem::resolve(&scene, scene.kernel_info().unwrap()).unwrap();
    assert!(p.t_end / p.output_interval < 1e6);
    assert!(cost::MAX_RUN_BYTES <= 4.0 * 1024f64.powi(3));
    // The run-time guard counts the scene's skin (the cost follows it): a
    // bound between the estimates at skin 0.3 h and 1.5 h passes the first
    // and refuses the second, naming the neighbours it counted.
    let estimate = |skin: f64| {
        let scene = Scene {
            skin,
            ..Scene::builtin()
        };
        let info = scene.kernel_info().unwrap();
        let p = Problem::resolve(&scene, info).unwrap();
        cost::Estimate::new(&p.channel(), p.c0, p.t_end).seconds(&p.channel(), info.support, skin)
    };
    let (thin, thick) = (estimate(0.3), estimate(1.5));
    assert!(thick > 2.0 * thin, "{thin} s at skin 0.3, {thick} s at 1.5");
    let bound = (thin * thick).sqrt();
    let err = resolve_err(|s| {
        s.skin = 1.5;
        s.max_run_s = bound;
    });
    assert!(
        err.contains("`max_run_s`") && err.contains("neighbours each"),
        "{err}"
    );
    let scene = Scene {
        max_run_s: bound,
        ..Scene::builtin()
    };
    assert!(Problem::resolve(&scene, scene.kernel_info().unwrap()).is_ok());
}

#[test]
fn output_folder_is_probed_and_sigterm_keeps_outputs() {
    let tmp = tempfile::tempdir().unwrap();
    let ro = tmp.path().join("ro");
    std::fs::create_dir(&ro).unwrap();
    use std::os::unix::fs::PermissionsExt;
    std::fs::set_permissions(&ro, std::fs::Permissions::from_mode(0o555)).unwrap();
    if std::fs::File::create(ro.join("x")).is_ok() {
        eprintln!("running as root: a read-only folder is writable, probe case skipped");
    } else {
        let err = shearsph::output::prepare_dir(&ro, true).unwrap_err();
        assert!(format!("{err:#}").contains("not writable"), "{err:#}");
    }
    // SIGTERM as SIGINT: exit 130, the outputs so far written.
    let out = tmp.path().join("run");
    let mut child = Command::new(env!("CARGO_BIN_EXE_shearsph"))
        .args(["run", "--quiet", "--n", "90", "--max-run-s", "1e6", "--out"])
        .arg(&out)
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(std::time::Duration::from_millis(1500));
    let _ = Command::new("kill")
        .arg("-TERM")
        .arg(child.id().to_string())
        .status();
    let status = child.wait().unwrap();
    assert_eq!(status.code(), Some(130));
    let summary = std::fs::read_to_string(out.join("summary.json")).unwrap();
    assert!(summary.contains("\"interrupted\""), "{summary}");
}

/// `sweep` of a one-point grid (a short scene) into `out`, with `extra`.
fn one_point_sweep(out: &str, extra: &[&str]) -> Output {
    let mut args = vec![
        "sweep",
        "--quiet",
        "--no-charts",
        "--out",
        out,
        "--kernel",
        "monaghan",
        "--n",
        "10",
        "--re",
        "10",
        "--alpha",
        "0.1",
        "--c0",
        "rule10",
        "--t-end",
        "0.1",
    ];
    args.extend_from_slice(extra);
    shearsph(&args)
}

#[test]
fn sweep_lock_and_grid_values() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("sw");
    let _held = shearsph::sweep::store::lock(&dir).unwrap();
    let err = shearsph::sweep::store::lock(&dir).unwrap_err();
    assert!(err.to_string().contains("in use by another sweep"), "{err}");
    let out = tmp.path().join("grid");
    let out = out.to_str().unwrap();
    for (flags, says) in [
        (&["--n", "0"][..], "flag --n: 0 is not a number of layers"),
        (&["--linf-bound", "nan"], "--linf-bound"),
        (&["--linf-bound", "-1"], "--linf-bound"),
        (&["--eps-margin", "-1"], "--eps-margin"),
        (&["--eps-margin", "inf"], "--eps-margin"),
        (&["--n", "10,10"], "twice"),
        (&["--alpha", "0.1,0.1"], "twice"),
        (&["--shard", "-1/2"], "bad shard \"-1/2\""),
    ] {
        let mut args = vec!["sweep", "--quiet", "--no-charts", "--out", out];
        args.extend_from_slice(flags);
        let o = shearsph(&args);
        assert!(!o.status.success(), "{flags:?}");
        let e = stderr(&o);
        assert!(e.contains(says), "{flags:?}: {e}");
        assert!(!e.contains("unexpected argument"), "{e}");
    }
    let o = one_point_sweep(out, &["--shard", "99/100"]);
    assert!(
        stderr(&o).contains("shard 99/100 gets no point of the 1-point grid"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn bench_flags_at_zero_are_refused() {
    for (flags, says) in [
        (&["--steps", "0"][..], "--steps must be at least 1"),
        (&["--repeats", "0"], "--repeats must be at least 1"),
        (&["--threads", "0"], "--threads must be at least 1"),
        (&["--particles", "0"], "--particles"),
        (&["--steps", "-1"], "--steps"),
        (
            &["--pysph-match", "--layers", "0"],
            "--layers must be at least 1",
        ),
    ] {
        let mut args = vec!["bench", "--quiet"];
        args.extend_from_slice(flags);
        let o = shearsph(&args);
        assert!(!o.status.success(), "{flags:?}");
        assert!(stderr(&o).contains(says), "{flags:?}: {}", stderr(&o));
    }
}

#[test]
fn messages_name_the_field_and_flag_typed() {
    let tmp = tempfile::tempdir().unwrap();
    for bad in ["true", "false", "[1]", "{ a = 1 }"] {
        let f = tmp.path().join("s.toml");
        std::fs::write(&f, format!("c0 = {bad}\n")).unwrap();
        let err = Scene::load(Some(&f), toml::Table::new())
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("a number or a rule name") && err.contains("`c0`"),
            "{bad}: {err}"
        );
        assert!(!err.contains("untagged"), "{err}");
    }
    // A flag's own name in bench's message (--layers sets n_layers).
    let o = shearsph(&["bench", "--quiet", "--pysph-match", "--layers", "2"]);
    let e = stderr(&o);
    assert!(
        e.contains("flag --layers") && !e.contains("flag --n)"),
        "{e}"
    );
    // Factors and times echoed short.
    let err = resolve_err(|s| s.c0 = "1e300*rule10".parse().unwrap());
    assert!(!err.contains("0000000000"), "{err}");
    assert_eq!(shearsph::format::fmt_value(1e300), "1e300");
}

/// Finite, non-finite, huge and tiny values.
fn any_number() -> impl Strategy<Value = f64> {
    prop_oneof![
        any::<f64>(),
        Just(f64::NAN),
        Just(f64::INFINITY),
        Just(f64::NEG_INFINITY),
        Just(0.0),
        Just(-0.0),
        Just(f64::MIN_POSITIVE),
        Just(5e-324),
        Just(f64::MAX),
        (-320i32..309).prop_map(|e| 10f64.powi(e)),
        -10.0..10.0f64,
    ]
}

const FIELDS: [&str; 16] = [
    "d",
    "h_over_d",
    "u",
    "re",
    "p",
    "rho0",
    "alpha",
    "c0",
    "t_end",
    "decay_tol",
    "output_interval",
    "gamma",
    "eps_limit",
    "jitter",
    "skin",
    "max_run_s",
];

fn set(scene: &mut Scene, field: &str, v: f64) {
    match field {
        "d" => scene.d = v,
        "h_over_d" => scene.h_over_d = v,
        "u" => scene.u = v,
        "re" => scene.re = Some(v),
        "p" => {
            scene.re = None;
            scene.p = Some(v)
        }
        "rho0" => scene.rho0 = v,
        "alpha" => scene.alpha = v,
        "c0" => scene.c0 = C0Spec::Value(v),
        "t_end" => scene.t_end = Some(v),
        "decay_tol" => scene.decay_tol = v,
        "output_interval" => scene.output_interval = Some(v),
        "gamma" => scene.gamma = v,
        "eps_limit" => scene.eps_limit = v,
        "jitter" => scene.jitter = v,
        "skin" => scene.skin = v,
        "max_run_s" => scene.max_run_s = v,
        _ => unreachable!(),
    }
}

/// Two inputs the property below once found: a c0 or a t_end that the
/// scene did not give (a rule's c0, t_end from the decay) is not blamed
/// for what its inputs made of it; the field that made it is named.
#[test]
fn a_derived_c0_or_t_end_blames_the_field_it_came_from() {
    let cases: [(&[(&str, f64)], &str); 3] = [
        (
            &[
                ("rho0", 9.999999999999998e-77),
                ("u", 9.999999999999997e-116),
            ],
            "u",
        ),
        (&[("p", 8.9383870817114e-265), ("c0", 1e43)], "p"),
        (&[("rho0", 1e-200), ("u", 1e-60)], "rho0"),
    ];
    for (fields, blamed) in cases {
        let mut scene = Scene::builtin();
        for &(f, v) in fields {
            set(&mut scene, f, v);
        }
        let msg = Problem::resolve(&scene, scene.kernel_info().unwrap())
            .err()
            .unwrap_or_else(|| panic!("{fields:?} should not resolve"))
            .to_string();
        assert!(
            msg.contains(&format!("invalid `{blamed}`")),
            "{fields:?}: {msg}"
        );
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 2000, failure_persistence: None, ..ProptestConfig::default() })]

    /// Any value of any numeric field (and two at once, and N): a problem
    /// within the stated bounds, or an error naming the field changed (or
    /// the run-time / memory guard, whose fix names the flags). Never a
    /// panic.
    #[test]
    fn any_number_resolves_or_names_the_field(
        a in 0..FIELDS.len(), va in any_number(),
        b in 0..FIELDS.len(), vb in any_number(),
        two in any::<bool>(),
        n in prop_oneof![Just(10u32), 0u32..100, any::<u32>()],
    ) {
        let mut scene = Scene::builtin();
        scene.n_layers = n;
        set(&mut scene, FIELDS[a], va);
        if two {
            set(&mut scene, FIELDS[b], vb);
        }
        let info = scene.kernel_info().unwrap();
        match Problem::resolve(&scene, info) {
            Ok(p) => {
                for (name, v) in [
                    ("c0", p.c0), ("t_end", p.t_end), ("output_interval", p.output_interval),
                    ("nu", p.flow.nu), ("p", p.flow.p), ("b", p.flow.b), ("re", p.re),
                    ("mass", p.mass), ("mu", p.mu),
                ] {
                    prop_assert!(v > 0.0 && v.is_normal(), "{name} = {v}");
                }
                let est = cost::Estimate::new(&p.channel(), p.c0, p.t_end);
                prop_assert!(est.time_step.dt > 0.0 && est.steps.is_finite());
                prop_assert!(est.seconds(&p.channel(), info.support, scene.skin) <= scene.max_run_s);
                prop_assert!(p.t_end / p.output_interval < 1e8);
                prop_assert!((p.lattice.n_particles() as f64) <= cost::MAX_PARTICLES);
            }
            Err(e) => {
                let msg = e.to_string();
                let named = |f: &str| msg.contains(&format!("`{f}`"));
                let guard = named("max_run_s") || named("n_layers") || named("output_interval");
                let changed = named(FIELDS[a]) || (two && named(FIELDS[b]))
                    || (FIELDS[a] == "p" || (two && FIELDS[b] == "p")) && named("re");
                prop_assert!(changed || guard, "{} = {va:e}, {} = {vb:e} ({two}), n = {n}: {msg}", FIELDS[a], FIELDS[b]);
            }
        }
    }
}

/// The files directly in `dir`, by name, with their bytes.
fn folder(dir: &std::path::Path) -> std::collections::BTreeMap<String, Vec<u8>> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap())
        .map(|e| {
            let name = e.file_name().to_string_lossy().into_owned();
            let bytes = if e.file_type().unwrap().is_file() {
                std::fs::read(e.path()).unwrap()
            } else {
                b"<folder>".to_vec()
            };
            (name, bytes)
        })
        .collect()
}

/// Item 5, `--force` atomic as a set: a disk that fills while a run's
/// outputs are written over an earlier run's leaves the earlier set byte
/// for byte, the user's own file in the folder, and nothing else (no
/// staging folder, no temporary file); once there is room, the new set
/// replaces the old one whole (the old particle series gone with
/// `--no-particles`) and the user's file is still there. Needs a small
/// tmpfs (root in a container that may mount); says so and returns
/// otherwise.
#[test]
fn force_over_an_earlier_run_is_atomic_as_a_set() {
    let mnt = tempfile::tempdir().unwrap();
    let ok = Command::new("mount")
        .args(["-t", "tmpfs", "-o", "size=4m", "tmpfs"])
        .arg(mnt.path())
        .status()
        .is_ok_and(|s| s.success());
    if !ok {
        eprintln!("cannot mount a small tmpfs here (not root?): full-disk case not run");
        return;
    }
    // Unmounted however the test ends.
    struct Unmount<'a>(&'a std::path::Path);
    impl Drop for Unmount<'_> {
        fn drop(&mut self) {
            let _ = Command::new("umount").arg(self.0).status();
        }
    }
    let _unmount = Unmount(mnt.path());
    let out = mnt.path().join("run");
    let out_s = out.to_str().unwrap();
    let run = |extra: &[&str]| {
        let mut args = vec![
            "run", "--quiet", "--n", "10", "--t-end", "0.5", "--out", out_s,
        ];
        args.extend_from_slice(extra);
        shearsph(&args)
    };
    let first = run(&["--re", "10"]);
    assert!(first.status.success(), "{}", stderr(&first));
    let old = folder(&out);
    for f in [
        "summary.json",
        "profile.svg",
        "timeseries.csv",
        "particles.pvd",
    ] {
        assert!(
            old.contains_key(f),
            "{f} missing from the first run: {old:?}"
        );
    }
    let set_bytes: usize = old.values().map(Vec::len).sum();
    std::fs::write(out.join("notes.txt"), "the user's own file").unwrap();

    // Fill the disk, then free about half the set: room for part of it only.
    let filler = mnt.path().join("filler");
    {
        use std::io::Write;
        let mut f = std::fs::File::create(&filler).unwrap();
        let chunk = vec![7u8; 64 * 1024];
        while f.write_all(&chunk).is_ok() {}
        let _ = f.flush();
        let len = f.metadata().unwrap().len();
        f.set_len(len.saturating_sub(set_bytes as u64 / 2)).unwrap();
    }
    let full = run(&["--re", "20", "--force"]);
    let err = stderr(&full);
    assert!(!full.status.success(), "a full disk is an error: {err}");
    assert!(err.contains("No space left on device"), "{err}");
    assert!(err.contains("keeps its earlier files"), "{err}");
    let mut expected = old.clone();
    expected.insert("notes.txt".into(), b"the user's own file".to_vec());
    let after = folder(&out);
    assert_eq!(
        after.keys().collect::<Vec<_>>(),
        expected.keys().collect::<Vec<_>>(),
        "files added or lost"
    );
    assert!(after == expected, "a file of the earlier set changed");

    // With room again: the new set, whole; the old series gone; notes kept.
    std::fs::remove_file(&filler).unwrap();
    let again = run(&["--re", "20", "--force", "--no-particles"]);
    assert!(again.status.success(), "{}", stderr(&again));
    let new = folder(&out);
    assert_ne!(new["summary.json"], old["summary.json"]);
    assert_eq!(new["notes.txt"], b"the user's own file");
    assert!(
        !new.keys()
            .any(|f| f.starts_with("particles_") || f == "particles.pvd"),
        "a stale file of the earlier set is left: {:?}",
        new.keys()
    );
    assert!(
        !new.keys()
            .any(|f| f.contains("staging") || f.contains(".tmp")),
        "{:?}",
        new.keys()
    );
    let summary = String::from_utf8_lossy(&new["summary.json"]).into_owned();
    assert!(summary.contains("\"re\": 20.0"), "{summary}");
}

/// Item 6: a results.jsonl row whose id is not a point of the grid is
/// skipped when the sweep resumes, and when its folder is merged: not
/// counted, not in the CSV, and the resume says so.
#[test]
fn a_row_not_in_the_grid_is_skipped() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("sw");
    let dir_s = dir.to_str().unwrap();
    let sweep = || one_point_sweep(dir_s, &[]);
    let first = sweep();
    assert!(first.status.success(), "{}", stderr(&first));
    let jsonl = dir.join("results.jsonl");
    let text = std::fs::read_to_string(&jsonl).unwrap();
    let mut row: serde_json::Value = serde_json::from_str(text.lines().next().unwrap()).unwrap();
    let stray = "monaghan/n=77/re=10/alpha=0.1/c0=rule10";
    row["id"] = stray.into();
    row["n_layers"] = 77.into();
    std::fs::write(&jsonl, format!("{text}{row}\n")).unwrap();

    let resumed = sweep();
    assert!(resumed.status.success(), "{}", stderr(&resumed));
    let err = stderr(&resumed);
    assert!(
        err.contains("1 row(s) of")
            && err.contains(
                "have an id that is not a point of this sweep's grid: skipped \
                             (not counted, not written to results.csv)"
            ),
        "{err}"
    );
    let said = String::from_utf8_lossy(&resumed.stdout).into_owned();
    assert!(
        said.contains("1 points in") && said.contains("ran 0 now, 1 were done before"),
        "{said}"
    );
    let (ok, rest) = said.split_once("rows: ").unwrap();
    let counts: usize = rest
        .split(", ")
        .filter_map(|c| c.split_whitespace().next()?.parse::<usize>().ok())
        .sum();
    assert_eq!(counts, 1, "{ok}{rest}");
    let csv = std::fs::read_to_string(dir.join("results.csv")).unwrap();
    assert_eq!(csv.lines().count(), 2, "{csv}");
    assert!(!csv.contains("n=77"), "{csv}");

    let merged = tmp.path().join("merged");
    let m = shearsph(&[
        "sweep",
        "merge",
        dir_s,
        "--no-charts",
        "--out",
        merged.to_str().unwrap(),
    ]);
    assert!(m.status.success(), "{}", stderr(&m));
    assert!(
        stderr(&m).contains("not a point of this sweep's grid: skipped"),
        "{}",
        stderr(&m)
    );
    let said = String::from_utf8_lossy(&m.stdout).into_owned();
    assert!(said.contains("1 of 1 points finished"), "{said}");
    let csv = std::fs::read_to_string(merged.join("results.csv")).unwrap();
    assert!(!csv.contains("n=77"), "{csv}");
}
