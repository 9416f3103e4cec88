//! Bounds and outcomes, one test per class (counts with no
//! bound, a second signal, one exit code per kind, meaningless results,
//! Slurm's resubmitted task and incomplete merge, messages naming the
//! field and where it came from), and a property test over the count
//! flags.

use crate::common;
use common::*;

use std::path::Path;
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use clap::Parser;
use proptest::prelude::*;
use shearsph::config::bounds;

/// Run `cmd` to its end, failing the test (and killing it) if it has not
/// ended within `limit`: a refused count must not hang. Not a timing
/// assertion: the limit is minutes above what any refusal takes.
fn ends_within(mut cmd: Command, limit: Duration) -> Output {
    let mut child = cmd
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the binary runs");
    let start = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed() > limit {
            let _ = child.kill();
            panic!("{cmd:?} had not ended after {limit:?}");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.wait_with_output().unwrap()
}

fn shearsph(args: &[&str]) -> Output {
    let mut c = bin();
    c.args(args);
    ends_within(c, Duration::from_secs(120))
}

/// `args` is refused as bad input: exit 1, every one of `says` in stderr.
fn refused(args: &[&str], says: &[&str]) -> String {
    let o = shearsph(args);
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{args:?}: {e}");
    for s in says {
        assert!(e.contains(s), "{args:?}: {e:?} lacks {s:?}");
    }
    e
}

/// Send `signal` to the child `times` times, and wait for it.
fn signal(mut child: std::process::Child, signal: &str, times: usize) -> Output {
    for _ in 0..times {
        let _ = Command::new("kill")
            .args([&format!("-{signal}"), &child.id().to_string()])
            .status();
    }
    let start = Instant::now();
    while child.try_wait().unwrap().is_none() {
        assert!(
            start.elapsed() < Duration::from_secs(180),
            "not stopped by {signal}"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
    child.wait_with_output().unwrap()
}

fn spawn(args: &[&str]) -> std::process::Child {
    bin()
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap()
}

/// Item 2: every count has a bound that says why, checked before any work
/// (a count of 1e9 is refused at once, nothing written).
#[test]
fn every_count_is_bounded_before_any_work() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("s");
    let out = out.to_str().unwrap();
    let one = [
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
        "--c0",
        "rule10",
    ];
    let with = |extra: &[&'static str]| -> Vec<&str> {
        let mut v = one.to_vec();
        v.extend_from_slice(extra);
        v
    };
    for (extra, says) in [
        (
            &["--jitter", "0.05", "--seeds", "1000000000"][..],
            &[
                "--seeds = 1000000000",
                "above the bound of 1000",
                "each seed",
            ][..],
        ),
        (
            &["--threads-per-scene", "100000"],
            &["--threads-per-scene = 100000", "8 per core"],
        ),
        (&["--jobs", "100000"], &["--jobs = 100000", "8 per core"]),
        (&["--jobs", "0"], &["--jobs = 0", "give at least 1"]),
        (
            &["--threads-per-scene", "0"],
            &["--threads-per-scene = 0", "give at least 1"],
        ),
    ] {
        refused(&with(extra), says);
        assert!(
            !Path::new(out).exists(),
            "{extra:?}: a refused sweep writes nothing"
        );
    }
    // 11 N x 20 Re x 10 c0 x 3 amplitudes x 1000 seeds: 6.6e6 points,
    // refused before a point is built.
    refused(
        &[
            "sweep",
            "--quiet",
            "--out",
            out,
            "--kernel",
            "monaghan",
            "--n",
            "10,11,12,13,14,15,16,17,18,19,20",
            "--re",
            "1,2,3,4,5,6,7,8,9,10,11,12,13,14,15,16,17,18,19,20",
            "--c0-over-u",
            "1,2,3,4,5,6,7,8,9,10",
            "--jitter",
            "0.01,0.02,0.03",
            "--seeds",
            "1000",
        ],
        &["the grid's points", "6600000", "above the bound of 1000000"],
    );
    // The same bound for a value from the sweep file, named as the file's.
    let file = tmp.path().join("grid.toml");
    std::fs::write(&file, "jitter = [0.05]\nseeds = 1000000000\n").unwrap();
    let f = file.to_str().unwrap();
    refused(
        &["sweep", "--quiet", "--sweep", f, "--out", out],
        &[
            "sweep file",
            "field `seeds` = 1000000000",
            "above the bound of 1000",
        ],
    );
    // bench's counts: threads, repeats, steps (by its time), columns (by memory).
    for (extra, says) in [
        (
            &["--threads", "100000"][..],
            &["--threads = 100000", "8 per core"][..],
        ),
        (
            &["--repeats", "1000000"],
            &["--repeats = 1000000", "above the bound of 100"],
        ),
        (
            &["--steps", "1000000000000"],
            &[
                "--steps 1000000000000",
                "would take about",
                "over the bound of 60.0 min",
            ],
        ),
        (
            &["--pysph-match", "--steps", "1000000000000"],
            &["--steps 1000000000000", "over the bound of 60.0 min"],
        ),
        (
            &["--pysph-match", "--columns", "4000000000"],
            &["--columns 4000000000", "of memory, over the bound"],
        ),
        (
            &["--pysph-match", "--threads", "100000"],
            &["--threads = 100000"],
        ),
    ] {
        let mut args = vec!["bench", "--quiet"];
        args.extend_from_slice(extra);
        refused(&args, says);
    }
    // report --jobs, and the report config's counts (before any scene runs).
    refused(
        &["report", "--quick", "--jobs", "0", "--out", out],
        &["--jobs = 0", "give at least 1"],
    );
    assert!(!Path::new(out).exists());
}

/// Item 5b/5c: one behaviour for every command on SIGTERM (and SIGINT,
/// SIGHUP): exit 130, keeping what it computed; a second signal never
/// loses it.
#[test]
fn every_command_exits_130_on_a_signal_and_a_second_keeps_the_outputs() {
    // Commands with nothing to keep end at once with 130 (not 143).
    for args in [
        // seconds of bisection at N = 20, every run to its end
        &["c0", "--empirical", "--quiet", "--n", "20"][..],
        &["bench", "--quiet", "--particles", "1e5", "--no-bandwidth"],
    ] {
        let child = spawn(args);
        std::thread::sleep(Duration::from_millis(1500));
        let o = signal(child, "TERM", 1);
        assert_eq!(o.status.code(), Some(130), "{args:?}: {}", stderr(&o));
        assert!(stderr(&o).contains("interrupted"), "{}", stderr(&o));
    }
    let tmp = tempfile::tempdir().unwrap();

    // The law keeps its finished points and says it was interrupted.
    let law = tmp.path().join("law");
    let child = spawn(&["law", "--quiet", "--out", law.to_str().unwrap()]);
    std::thread::sleep(Duration::from_millis(3000));
    let o = signal(child, "TERM", 1);
    assert_eq!(o.status.code(), Some(130), "{}", stderr(&o));
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(law.join("law.json")).unwrap()).unwrap();
    assert_eq!(v["interrupted"], true);
    let planned = v["points_planned"].as_u64().unwrap();
    assert!((v["points"].as_array().unwrap().len() as u64) < planned);
    let csv = std::fs::read_to_string(law.join("law.csv")).unwrap();
    assert_eq!(
        csv.lines().count() - 1,
        v["points"].as_array().unwrap().len()
    );

    // A run sent SIGHUP twice (as `timeout` delivers it) keeps every output
    // up to where it stopped, and leaves no staging folder.
    let run = tmp.path().join("run");
    let child = spawn(&[
        "run",
        "--n",
        "30",
        "--max-run-s",
        "1e6",
        "--output-interval",
        "1e-2",
        "--quiet",
        "--out",
        run.to_str().unwrap(),
    ]);
    std::thread::sleep(Duration::from_millis(1500));
    let o = signal(child, "HUP", 2);
    assert_eq!(o.status.code(), Some(130), "{}", stderr(&o));
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(run.join("summary.json")).unwrap()).unwrap();
    assert_eq!(s["outcome"], "interrupted");
    // its own word, not "failed"
    assert_eq!(s["class"], "interrupted");
    assert!(
        stdout(&o).contains("class: interrupted: stopped at t = "),
        "{}",
        stdout(&o)
    );
    let staging = |d: &Path| {
        std::fs::read_dir(d)
            .unwrap()
            .filter(|e| {
                e.as_ref()
                    .unwrap()
                    .file_name()
                    .to_string_lossy()
                    .starts_with(".shearsph-staging-")
            })
            .count()
    };
    assert_eq!(staging(&run), 0);

    // A staging folder a killed run left (its PID gone) is removed by the
    // next run into the folder, with --force or into one holding only it.
    let dead = run.join(".shearsph-staging-4194305-0");
    std::fs::create_dir(&dead).unwrap();
    std::fs::write(dead.join("summary.json"), "{}").unwrap();
    let o = shearsph(&[
        "run",
        "--quiet",
        "--force",
        "--t-end",
        "1",
        "--out",
        run.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(staging(&run), 0);
    let only = tmp.path().join("only");
    std::fs::create_dir_all(only.join(".shearsph-staging-4194305-1")).unwrap();
    let o = shearsph(&[
        "run",
        "--quiet",
        "--t-end",
        "1",
        "--out",
        only.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(staging(&only), 0);
}

/// Item 6: a result that would mean nothing is refused as bad input
/// (exit 1) before any run, not a grid of failed rows with exit 0.
#[test]
fn meaningless_results_are_refused_before_any_run() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("s");
    let o = out.to_str().unwrap();
    refused(
        &[
            "sweep",
            "--quiet",
            "--kernel",
            "monaghan",
            "--c0",
            "empirical",
            "--out",
            o,
        ],
        &[
            "flag --c0",
            "the solver's own search",
            "shearsph c0 --empirical",
        ],
    );
    // Scene-wide values invalid for every point: one error before the grid.
    for (grid, says) in [
        (
            "kernels = [\"monaghan\"]\nn = [10]\nre = [10.0]\nc0 = [\"rule10\"]\n[scene]\noutput_interval = 1e-9\n",
            &["sweep point monaghan/n=10", "invalid `output_interval`", "field `scene.output_interval`"][..],
        ),
        (
            "kernels = [\"monaghan\"]\nn = [100000]\nre = [10.0]\nc0 = [\"rule10\"]\n",
            &["sweep point monaghan/n=100000", "invalid `n_layers`", "field `n`"],
        ),
        (
            "n = [10]\nre = [1.0, 10.0]\nc0 = [\"rule10\"]\n[scene]\nt_end = 1e-300\n",
            &["and 7 more of the 8 points", "invalid `t_end`", "shorter than one time step"],
        ),
    ] {
        let file = tmp.path().join("grid.toml");
        std::fs::write(&file, grid).unwrap();
        refused(
            &["sweep", "--quiet", "--sweep", file.to_str().unwrap(), "--out", o],
            says,
        );
        assert!(!out.exists(), "{grid}: nothing written");
    }
    // A rule with no c0 at a point stays that point's row (a finding).
    let ok = shearsph(&[
        "sweep",
        "--quiet",
        "--no-charts",
        "--kernel",
        "morris",
        "--n",
        "10",
        "--re",
        "10",
        "--c0",
        "derived",
        "--t-end",
        "1",
        "--out",
        o,
    ]);
    assert!(ok.status.success(), "{}", stderr(&ok));
    // A run that covers no time.
    let run = tmp.path().join("run");
    refused(
        &["run", "--t-end", "1e-300", "--out", run.to_str().unwrap()],
        &[
            "invalid `t_end` (flag --t-end)",
            "shorter than one time step",
            "t_end >= 0.184",
        ],
    );
    assert!(!run.exists());
    // The report's config: maps.n = 0 and a value twice, at once.
    let quick = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("src/studies/report/quick.toml"),
    )
    .unwrap();
    for (from, to, says) in [
        ("[maps]\nn = 6", "[maps]\nn = 0", "maps.n = 0"),
        (
            "c0_over_u = [0.1, 1.0, 10.0]",
            "c0_over_u = [0.1, 1.0, 1.0]",
            "maps.c0_over_u gives 1.0 twice",
        ),
    ] {
        assert!(quick.contains(from), "{from}");
        let file = tmp.path().join("report.toml");
        std::fs::write(&file, quick.replace(from, to)).unwrap();
        refused(
            &[
                "report",
                "--config",
                file.to_str().unwrap(),
                "--out",
                run.to_str().unwrap(),
            ],
            &[says],
        );
        assert!(!run.exists());
    }
    // The law's and the bench's lists refuse a value twice, as a sweep's.
    let law = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("src/studies/law/quick.toml"),
    )
    .unwrap();
    let file = tmp.path().join("law.toml");
    std::fs::write(&file, law.replace("n = [6]", "n = [6, 6]")).unwrap();
    refused(
        &[
            "law",
            "--config",
            file.to_str().unwrap(),
            "--out",
            run.to_str().unwrap(),
        ],
        &["`n` gives 6 twice"],
    );
    refused(
        &["bench", "--quiet", "--particles", "1e3,1000"],
        &["--particles gives 1000 twice"],
    );
}

/// Item 7: `sweep merge` of an incomplete set fails unless --partial; a
/// task resubmitted alone (`--array=1`) keeps its shard; a lone task with
/// no record is refused rather than run as the whole grid.
#[test]
fn a_resubmitted_task_keeps_its_shard_and_an_incomplete_merge_fails() {
    let tmp = tempfile::tempdir().unwrap();
    let grid = tmp.path().join("grid.toml");
    std::fs::write(
        &grid,
        "kernels = [\"monaghan\"]\nn = [6]\nre = [1.0, 10.0]\nc0_over_u = [10.0, 20.0]\n[scene]\nt_end = 1.0\n",
    )
    .unwrap();
    let task = |dir: &Path, id: &str, count: &str, min: &str| {
        let mut c = bin();
        c.args([
            "sweep",
            "--quiet",
            "--no-charts",
            "--shard",
            "auto",
            "--sweep",
        ])
        .arg(&grid)
        .arg("--out")
        .arg(dir)
        .env("SLURM_ARRAY_TASK_ID", id)
        .env("SLURM_ARRAY_TASK_COUNT", count)
        .env("SLURM_ARRAY_TASK_MIN", min)
        .env_remove("SLURM_ARRAY_TASK_STEP");
        ends_within(c, Duration::from_secs(120))
    };
    let s1 = tmp.path().join("s1");
    let o = task(&s1, "1", "4", "0");
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stdout(&o).contains("1 points in"), "{}", stdout(&o));
    // Resubmitted alone: Slurm says task 1 of 1 from 1; the folder's 1/4 is kept.
    let o = task(&s1, "1", "1", "1");
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("keeping 1/4"), "{}", stderr(&o));
    assert!(
        stdout(&o).contains("1 points in") && stdout(&o).contains("ran 0 now"),
        "{}",
        stdout(&o)
    );
    // The same lone task with no folder yet: refused, not the whole grid.
    let fresh = tmp.path().join("fresh");
    let o = task(&fresh, "1", "1", "1");
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(stderr(&o).contains("give --shard K/N"), "{}", stderr(&o));
    // Bad Slurm variables are bad input, exit 1.
    let o = task(&fresh, "x1", "4", "0");
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("SLURM_ARRAY_TASK_ID=\"x1\""),
        "{}",
        stderr(&o)
    );
    assert!(!fresh.join("sweep.toml").exists());
    // An explicit other shard into the folder is refused.
    let o = shearsph(&[
        "sweep",
        "--quiet",
        "--shard",
        "2/8",
        "--sweep",
        grid.to_str().unwrap(),
        "--out",
        s1.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("is shard 1/4"), "{}", stderr(&o));

    // Merge: shards 1 and 3 of 4 only.
    let s3 = tmp.path().join("s3");
    assert!(task(&s3, "3", "4", "0").status.success());
    let merged = tmp.path().join("merged");
    let args = |partial: bool| {
        let mut v = vec![
            "sweep".to_string(),
            "merge".into(),
            s1.display().to_string(),
            s3.display().to_string(),
            "--no-charts".into(),
            "--out".into(),
            merged.display().to_string(),
        ];
        if partial {
            v.push("--partial".into());
        }
        v
    };
    let a = args(false);
    let e = refused(
        &a.iter().map(String::as_str).collect::<Vec<_>>(),
        &[
            "hold 2 of the grid's 4 points",
            "no folder given for shards 0/4, 2/4",
            "--partial",
        ],
    );
    assert!(!merged.exists(), "{e}");
    let a = args(true);
    let o = shearsph(&a.iter().map(String::as_str).collect::<Vec<_>>());
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stdout(&o).contains("2 of 4 points finished"),
        "{}",
        stdout(&o)
    );
    // --force starts a folder over, forgetting its shard.
    let o = shearsph(&[
        "sweep",
        "--quiet",
        "--no-charts",
        "--force",
        "--sweep",
        grid.to_str().unwrap(),
        "--out",
        s1.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(!s1.join("shard.toml").exists());
    assert!(stdout(&o).contains("4 points in"), "{}", stdout(&o));
}

/// Item 8: parse errors exit 1 like other bad input; a value is named by
/// where it came from; a far too long run names the input that made it.
#[test]
fn messages_name_the_field_and_where_it_came_from() {
    for args in [
        &["run", "--n", "nan"][..],
        &["sweep", "--shard", "5/3"],
        &["run", "--h-over-d", "13/0"],
        &["run", "--bogus"],
    ] {
        refused(args, &["error:"]);
    }
    // --help is not an error.
    assert_eq!(shearsph(&["run", "--help"]).status.code(), Some(0));
    let tmp = tempfile::tempdir().unwrap();
    let scene = tmp.path().join("scene.toml");
    std::fs::write(&scene, "n_layers = 2\n").unwrap();
    let out = tmp.path().join("x");
    let e = refused(
        &[
            "run",
            "--scene",
            scene.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ],
        &["invalid `n_layers` (scene file"],
    );
    assert!(!e.contains("flag --n"), "{e}");
    // The flag, when a flag gave it.
    refused(
        &["run", "--n", "2", "--out", out.to_str().unwrap()],
        &["invalid `n_layers` (flag --n)"],
    );
    // A sweep's base scene: the field itself, from the sweep file.
    let grid = tmp.path().join("grid.toml");
    std::fs::write(&grid, "[scene]\ngamma = -1\n").unwrap();
    let e = refused(
        &[
            "sweep",
            "--quiet",
            "--sweep",
            grid.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ],
        &["invalid `gamma`", "field `scene.gamma`"],
    );
    assert!(!e.contains("classes"), "{e}");
    // 1e300 in t_end, --margin, the law's hi_over_u, --tau: each named.
    refused(
        &["run", "--t-end", "1e300", "--out", out.to_str().unwrap()],
        &[
            "invalid `t_end` (flag --t-end)",
            "far too long for any bound",
        ],
    );
    let e = refused(
        &["c0", "--empirical", "--margin", "1e300", "--quiet"],
        &["--margin = 1e300"],
    );
    assert!(!e.starts_with("error: invalid `max_run_s`"), "{e}");
    let law = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("src/studies/law/quick.toml"),
    )
    .unwrap();
    let file = tmp.path().join("law.toml");
    std::fs::write(&file, law.replace("hi_over_u = 100.0", "hi_over_u = 1e300")).unwrap();
    refused(
        &[
            "law",
            "--config",
            file.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ],
        &["`hi_over_u` = 1e300"],
    );
    refused(
        &["bench", "--sphinxsys-match", "--tau", "1e300"],
        &["--tau 1e300"],
    );
    // One statement of the run's class, never "outcome: ok" beside another.
    let o = shearsph(&[
        "run",
        "--n",
        "6",
        "--c0",
        "1e3",
        "--quiet",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(4));
    let text = stdout(&o);
    assert!(!text.contains("outcome:"), "{text}");
    assert!(
        text.contains("class: inaccurate: its window's mean-flow error"),
        "{text}"
    );
}

#[derive(Parser)]
struct SweepCli {
    #[command(flatten)]
    a: shearsph::cli::sweep::RunSweepArgs,
}

#[derive(Parser)]
struct BenchCli {
    #[command(flatten)]
    a: shearsph::cli::bench::BenchArgs,
}

/// Counts: the ends of each bound and beyond, small, powers of two, any.
fn any_count(max: u64) -> impl Strategy<Value = u64> {
    prop_oneof![
        0u64..4,
        Just(max),
        Just(max + 1),
        (0u32..64).prop_map(|e| 1u64 << e),
        (0u64..(2 * max + 2)),
        any::<u64>(),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, failure_persistence: None, ..ProptestConfig::default() })]

    /// Every count flag of `sweep` and `bench`: accepted exactly within
    /// its bound (the time bound's estimate for --steps), else refused
    /// naming the flag; never a panic. (A value beyond the flag's type is
    /// clap's error, naming the flag too.)
    #[test]
    fn every_count_flag_is_accepted_exactly_within_its_bound(
        which in 0usize..6,
        v in any_count(1_000),
        w in any_count(bounds::threads().max),
    ) {
        let threads = bounds::threads().max;
        let sweep = |extra: &[String]| {
            let mut args: Vec<String> = ["sweep", "--kernel", "monaghan", "--n", "10", "--re", "10", "--c0", "rule10"]
                .iter().map(|s| s.to_string()).collect();
            args.extend_from_slice(extra);
            SweepCli::try_parse_from(args)
        };
        let bench = |extra: &[String]| {
            let mut args: Vec<String> = ["bench", "--kernels", "monaghan", "--particles", "1e3", "--threads", "1"]
                .iter().map(|s| s.to_string()).collect();
            args.extend_from_slice(extra);
            BenchCli::try_parse_from(args)
        };
        let (flag, value, within, result): (&str, u64, bool, Result<(), String>) = match which {
            0 => {
                let p = sweep(&["--jitter".into(), "0.05".into(), "--seeds".into(), v.to_string()]);
                let r = match p {
                    Ok(c) => c.a.grid.spec().map(|_| ()).map_err(|e| format!("{e:#}")),
                    Err(e) => Err(e.to_string()),
                };
                ("--seeds", v, (1..=1_000).contains(&v), r)
            }
            1 | 2 => {
                let flag = if which == 1 { "--jobs" } else { "--threads-per-scene" };
                let r = match sweep(&[flag.into(), w.to_string()]) {
                    Ok(c) => c.a.parallel().map(|_| ()).map_err(|e| format!("{e:#}")),
                    Err(e) => Err(e.to_string()),
                };
                (flag, w, (1..=threads).contains(&w), r)
            }
            3 => {
                // bench --threads replaces the default list
                let args = vec!["bench".to_string(), "--kernels".into(), "monaghan".into(), "--particles".into(), "1e3".into(), "--threads".into(), w.to_string()];
                let r = match BenchCli::try_parse_from(args) {
                    Ok(c) => c.a.options().map(|_| ()).map_err(|e| format!("{e:#}")),
                    Err(e) => Err(e.to_string()),
                };
                ("--threads", w, (1..=threads).contains(&w), r)
            }
            4 => {
                let r = match bench(&["--repeats".into(), v.to_string()]) {
                    Ok(c) => c.a.options().map(|_| ()).map_err(|e| format!("{e:#}")),
                    Err(e) => Err(e.to_string()),
                };
                ("--repeats", v, (1..=100).contains(&v), r)
            }
            _ => {
                let steps = v.saturating_mul(1 << (w % 40));
                let r = match bench(&["--steps".into(), steps.to_string()]) {
                    Ok(c) => c.a.options().map(|_| ()).map_err(|e| format!("{e:#}")),
                    Err(e) => Err(e.to_string()),
                };
                let opts = shearsph::bench::Options {
                    kernels: vec!["monaghan".into()],
                    particles: vec![1000],
                    steps: Some(steps),
                    threads: vec![1],
                    ..shearsph::bench::Options::defaults()
                };
                let est = shearsph::bench::estimated_seconds(&opts).unwrap();
                ("--steps", steps, steps >= 1 && est <= shearsph::bench::MAX_BENCH_S, r)
            }
        };
        match result {
            Ok(()) => prop_assert!(within, "{flag} {value} accepted"),
            Err(e) => {
                prop_assert!(!within, "{flag} {value} refused: {e}");
                prop_assert!(e.contains(flag), "{flag} {value}: {e}");
            }
        }
    }
}
