//! The empirical answer (`shearsph c0 --empirical`, one engine for every
//! command): it does not depend on the horizon nor on the jitter's
//! amplitude once the flow is stationary, `run --c0 empirical` runs at its
//! recommendation, and its JSON has the schema programs read.

use std::process::Command;
use std::sync::atomic::AtomicBool;

use indicatif::ProgressBar;
use serde_json::Value;
use shearsph::config::Scene;
use shearsph::empirical::{answer, queue, Extras, Priority, RunQueue, Search, Starts};
use shearsph::solver::Class;

fn scene(fields: &[(&str, toml::Value)]) -> Scene {
    let mut t = toml::Table::new();
    for (k, v) in fields {
        t.insert(k.to_string(), v.clone());
    }
    Scene::load(None, t).unwrap()
}

/// N = 6 at Re = 1 with a first checkpoint 8 shear times after the
/// start-up: runs of a second or so.
fn short_scene() -> Scene {
    scene(&[
        ("n_layers", 6.into()),
        ("re", 1.0.into()),
        ("horizon_span", 8.0.into()),
    ])
}

/// The answer's c0 and its relative statistical uncertainty.
fn c0_min(scene: &Scene, search: &Search) -> (f64, f64) {
    let a = answer(
        scene,
        search,
        Extras::default(),
        &AtomicBool::new(false),
        &ProgressBar::hidden(),
    )
    .unwrap();
    let c = a
        .c0_min_ok
        .unwrap_or_else(|| panic!("an answer: {:?}", a.disordered));
    (c, a.c0_rel_uncertainty.expect("seeds to tell the spread"))
}

/// The answer at horizon H (64 shear times after the start-up) and 2H, and
/// from a jitter five times smaller, agree within the bisection's
/// tolerance and twice their combined statistical uncertainty (the seeds'
/// spread: the disordered state's compaction fluctuates by about 15 %
/// between windows of 500 t, so a window of 32 shear times carries that
/// noise; docs/stationary.md).
#[test]
fn the_answer_holds_for_twice_the_horizon_and_a_smaller_jitter() {
    let base = |span: f64| {
        scene(&[
            ("n_layers", 6.into()),
            ("re", 1.0.into()),
            ("horizon_span", span.into()),
        ])
    };
    let search = Search::default();
    let small_jitter = Search {
        amplitude: 0.01,
        ..search
    };
    // The three answers at once: each search waits on its probes' runs in
    // turn, and the others' runs fill the cores meanwhile (an answer does
    // not depend on how many run beside it:
    // `the_number_of_workers_changes_no_trial`).
    let (h, h2, small) = std::thread::scope(|s| {
        let h2 = s.spawn(|| c0_min(&base(128.0), &search));
        let small = s.spawn(|| c0_min(&base(64.0), &small_jitter));
        let h = c0_min(&base(64.0), &search);
        (h, h2.join().unwrap(), small.join().unwrap())
    });
    for (what, c) in [("2H", h2), ("a 0.01 d jitter", small)] {
        let off = (c.0 / h.0).ln().abs();
        let allowed = (1.0 + search.rel_tol).ln() + 2.0 * (c.1 * c.1 + h.1 * h.1).sqrt();
        assert!(
            off <= allowed,
            "H: {h:?}, {what}: {c:?} (c0, relative uncertainty): ln ratio {off} above {allowed}"
        );
    }
}

#[test]
fn a_too_small_c0_is_ok_on_the_perfect_lattice_but_not_disordered() {
    // The built-in scene (Monaghan, N = 10, Re = 10) at c0 = 0.2 U, above
    // its derived c0: the perfect lattice keeps its order and runs ok, the
    // jittered start disorders and fails by compaction.
    let s = Scene::builtin();
    let search = Search {
        seeds: 1,
        ..Search::default()
    };
    let t = queue::trials(
        &s,
        &search,
        &[0.2 * s.u],
        Starts::Both,
        &AtomicBool::new(false),
        &ProgressBar::hidden(),
    )
    .unwrap()
    .remove(0);
    let perfect = t.perfect.as_ref().unwrap();
    assert_eq!(perfect.class, Class::Ok, "{t:?}");
    assert!(perfect.stationary, "{t:?}");
    assert_eq!(t.pooled.as_ref().unwrap().class, Class::Failed, "{t:?}");
}

/// The queue's workers change no run: the trials made by one worker and
/// by three (the runs then share the cores, in another order) are the same
/// bits.
#[test]
fn the_number_of_workers_changes_no_trial() {
    let s = short_scene();
    let search = Search {
        seeds: 2,
        ..Search::default()
    };
    let c0s = [3.0 * s.u, 10.0 * s.u];
    let made = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            queue::trials(
                &s,
                &search,
                &c0s,
                Starts::Both,
                &AtomicBool::new(false),
                &ProgressBar::hidden(),
            )
        })
        .unwrap()
    };
    let bits = |trials: &[shearsph::empirical::Trial]| -> Vec<(u32, u64, u64, u64, u64)> {
        trials
            .iter()
            .flat_map(|t| t.perfect.iter().chain(&t.seeds))
            .map(|r| {
                (
                    r.seed,
                    r.eps_stat.to_bits(),
                    r.linf_stat.to_bits(),
                    r.t.to_bits(),
                    r.steps,
                )
            })
            .collect()
    };
    let (one, three) = (made(1), made(3));
    assert_eq!(
        bits(&one).len(),
        6,
        "two c0 on the perfect lattice and two seeds"
    );
    assert_eq!(bits(&one), bits(&three));
}

/// A run the answer's queue makes at another alpha (the diagnosis's check,
/// queued beside the answer's own runs) is the run of the scene with that
/// alpha, bit for bit, and not the scene's own run at that c0 and start.
#[test]
fn a_run_at_another_alpha_is_that_scenes_run() {
    let s = short_scene();
    let search = Search {
        seeds: 1,
        ..Search::default()
    };
    let (c0, alpha) = (10.0 * s.u, 0.5 * s.alpha);
    let (stop, bar) = (AtomicBool::new(false), ProgressBar::hidden());
    let q = RunQueue::new(&s, &search, &stop, &bar);
    let (at, own) = queue::with_workers(&q, || {
        let other = q.runs_at(alpha, &[c0], Starts::Seeds);
        let mine = q.runs_of(&[c0], Starts::Seeds);
        assert_ne!(other, mine);
        q.wait(&other, Priority::Ordered)?;
        assert!(
            q.collect(&[c0])?[0].pooled.is_none(),
            "the scene's own run is another"
        );
        q.wait(&mine, Priority::Ordered)?;
        Ok::<_, anyhow::Error>((q.collect_at(alpha, &[c0])?, q.collect(&[c0])?))
    })
    .unwrap();
    let mut s2 = s.clone();
    s2.alpha = alpha;
    let alone = queue::trials(&s2, &search, &[c0], Starts::Seeds, &stop, &bar).unwrap();
    let bits = |t: &[shearsph::empirical::Trial]| -> Vec<(u64, u64, u64)> {
        t.iter()
            .flat_map(|t| &t.seeds)
            .map(|r| (r.eps_stat.to_bits(), r.linf_stat.to_bits(), r.steps))
            .collect()
    };
    assert_eq!(bits(&at).len(), 1);
    assert_eq!(bits(&at), bits(&alone));
    assert_ne!(bits(&at), bits(&own), "alpha changes the run");
}

/// A cheap scene for the CLI's plumbing: a short horizon and one seed.
const CHEAP: [&str; 8] = [
    "--n",
    "6",
    "--re",
    "1",
    "--horizon-span",
    "8",
    "--seeds",
    "1",
];

/// `shearsph c0 --empirical --json --quiet ARGS`: it succeeds, and its JSON.
fn c0_empirical_json(args: &[&str]) -> Value {
    let out = Command::new(env!("CARGO_BIN_EXE_shearsph"))
        .args(["c0", "--empirical", "--json", "--quiet"])
        .args(args)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).unwrap()
}

#[test]
fn the_empirical_answer_has_its_schema() {
    let v = c0_empirical_json(&[&["--rel-tol", "0.5"][..], &CHEAP].concat());
    assert!(v["recommended"].is_number() || v["recommended"].is_null());
    // The recommendation is a c0 whose own disordered run was ok, inside
    // the band above the smallest ok c0.
    if let Some(rec) = v["recommended"].as_f64() {
        let band = &v["band"];
        assert_eq!(band["lo"], v["c0_min_ok"], "{band}");
        assert!(band["lo"].as_f64().unwrap() <= rec && rec <= band["hi_ok"].as_f64().unwrap());
        let t = v["trials"]
            .as_array()
            .unwrap()
            .iter()
            .find(|t| t["c0"].as_f64() == Some(rec))
            .expect("the recommended c0 was run");
        assert_eq!(t["pooled"]["class"], "ok", "{t}");
        assert!(
            t["perfect"].is_object(),
            "run on the perfect lattice too: {t}"
        );
    } else {
        assert!(v["band"].is_null());
    }
    for key in [
        "t_startup",
        "shear_time",
        "first",
        "cap",
        "runs",
        "stationary",
    ] {
        assert!(
            v["horizon"][key].is_number(),
            "horizon.{key}: {}",
            v["horizon"]
        );
    }
    for key in ["disordered", "ordered", "trials", "search"] {
        assert!(!v[key].is_null(), "{key}");
    }
    let rules = v["rules"].as_array().unwrap();
    for r in rules {
        for key in [
            "name",
            "c0",
            "ordered",
            "disordered",
            "eps_stat",
            "linf_stat",
            "not_applicable",
        ] {
            assert!(r.get(key).is_some(), "rule {r} lacks {key}");
        }
        for key in ["ordered", "disordered"] {
            if let Some(c) = r[key].as_str() {
                assert!(["ok", "inaccurate", "over-compressed", "failed"].contains(&c));
            }
        }
    }
    let names: Vec<&str> = rules.iter().map(|r| r["name"].as_str().unwrap()).collect();
    // Every code's rule of the registry, and the derivation with a
    // technical eps0.
    let codes = shearsph::config::RULES.iter().filter_map(|e| match e.kind {
        shearsph::config::RuleKind::Code { .. } => Some(e.syntax),
        _ => None,
    });
    for rule in codes.chain(["derived-eps"]) {
        assert!(names.contains(&rule), "{rule} missing from {names:?}");
    }
}

/// `--tolerance`: the disordered law's c0 for a density tolerance, said to
/// be extrapolated exactly when it lies outside the c0 of the trials the
/// law was fitted on (here delta = 0.001 puts it above them: a short
/// horizon, one seed, no rules, so that the law is fitted cheaply).
#[test]
fn the_tolerance_says_when_the_law_is_extrapolated() {
    let args =
        "--no-rules --rel-tol 0.5 --tolerance 0.001 --n 6 --re 1 --horizon-span 32 --seeds 1";
    let v = c0_empirical_json(&args.split(' ').collect::<Vec<_>>());
    let tol = &v["tolerance"];
    assert_eq!(tol["delta"], 0.001, "{tol}");
    let c = tol["law_c0_over_u"]
        .as_f64()
        .unwrap_or_else(|| panic!("a law fitted: {}", v["law"]));
    let xs: Vec<f64> = v["law"]["points"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p[0].as_f64().unwrap())
        .collect();
    let (lo, hi) = xs
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
            (a.min(x), b.max(x))
        });
    assert!(c > hi, "the law's c0 {c} U within its trials' {lo}..{hi} U");
    assert_eq!(tol["law_extrapolated"], true, "{tol}");
}

#[test]
fn empirical_as_a_c0_rule_runs_the_search_first() {
    // `run --c0 empirical`: the search for the scene, said on stdout, then
    // the run itself at that c0 (its summary's c0 is the number said), the
    // same as `c0 --c0 empirical` recommends.
    let dir = tempfile::tempdir().unwrap();
    let span = ["--n", "6", "--re", "1", "--horizon-span", "8"];
    let out = Command::new(env!("CARGO_BIN_EXE_shearsph"))
        .args(["run", "--quiet", "--no-particles"])
        .args(span)
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
    let c0 = summary["c0"].as_f64().unwrap();
    assert!((c0 - said).abs() <= 1e-6 * said, "{c0} vs {said}");
    let ans = Command::new(env!("CARGO_BIN_EXE_shearsph"))
        .args(["c0", "--json", "--quiet", "--no-rules"])
        .args(span)
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
    // a header and one row per point of src/studies/law/quick.toml (1 N x 2 Re x 1 alpha)
    assert_eq!(csv.lines().count(), 1 + 2, "{csv}");
    assert!(csv.starts_with("kernel,n,re,alpha,c0_min_over_u,below_over_u,law_k,law_m"));
    let v: Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("law.json")).unwrap())
            .unwrap();
    let law = &v["laws"][0];
    assert_eq!(law["kernel"], "monaghan");
    let fitted = law["fitted"].as_u64().unwrap() as usize;
    assert_eq!(fitted + law["unfitted"].as_array().unwrap().len(), 2);
    let svg = std::fs::read_to_string(dir.path().join("law_monaghan.svg")).unwrap();
    assert!(svg.contains("<svg") && svg.contains("Re = 1"));
}

/// The answer runs on every shipped discretisation, not only the paper's:
/// a rule that gives no c0 there (no compaction, no positive root, the
/// paper's Table 2 off its lattice) is listed as not applicable, with why,
/// never fatal. A tiny search (one seed, a wide tolerance, the shortest
/// horizon, N at the support's least) per kernel x discretisation.
#[test]
fn the_answer_runs_on_every_shipped_discretisation() {
    let out = Command::new(env!("CARGO_BIN_EXE_shearsph"))
        .args(["kernels", "--json"])
        .output()
        .unwrap();
    assert!(out.status.success());
    let kernels: Value = serde_json::from_slice(&out.stdout).unwrap();
    let mut cases = Vec::new();
    for k in kernels.as_array().unwrap() {
        let support = k["support"].as_f64().unwrap();
        for d in k["discretisations"].as_array().unwrap() {
            let h = d["h_over_d"].as_f64().unwrap();
            // The fewest layers the support allows: ceil(R h / d) + 1.
            let n = ((support * h - 1e-9).ceil() as u32 + 1).max(4);
            cases.push((
                k["kernel"].as_str().unwrap().to_string(),
                d["lattice"].as_str().unwrap().to_string(),
                d["h_over_d_exact"].as_str().unwrap().to_string(),
                n,
            ));
        }
    }
    assert!(
        cases.len() >= 20,
        "every kernel x discretisation: {cases:?}"
    );
    let run = |(kernel, lattice, h, n): &(String, String, String, u32)| {
        let out = Command::new(env!("CARGO_BIN_EXE_shearsph"))
            .args(["c0", "--empirical", "--json", "--quiet", "--kernel", kernel])
            .args(["--lattice", lattice, "--h-over-d", h, "--n", &n.to_string()])
            .args(["--re", "1", "--horizon-span", "8", "--seeds", "1"])
            .args(["--rel-tol", "10", "--first-over-u", "10"])
            .args(["--lo-over-u", "5", "--hi-over-u", "20"])
            .output()
            .unwrap();
        let case = format!("{kernel} {lattice} {h} N = {n}");
        assert!(
            out.status.success(),
            "{case}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        let v: Value = serde_json::from_slice(&out.stdout).unwrap();
        let rules = v["rules"].as_array().unwrap();
        assert!(rules.len() >= 6, "{case}: every rule listed");
        for r in rules {
            let na = r["not_applicable"].as_str();
            assert!(
                r["c0"].is_number() != na.is_some(),
                "{case}: {} has a c0 or says why not: {r}",
                r["name"]
            );
            assert!(na.is_none_or(|w| !w.is_empty()), "{case}: {r}");
        }
    };
    // Two at a time: the machine's cores.
    let (a, b) = cases.split_at(cases.len() / 2);
    std::thread::scope(|s| {
        s.spawn(|| a.iter().for_each(run));
        b.iter().for_each(run);
    });
}
