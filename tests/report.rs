//! `shearsph report --quick`: the page references every figure and table it
//! promises, and each chart is checked by the CSV behind it (Figure 4
//! against the generated eps_at, one map row per grid point, Pareto flags,
//! the tables against the generated KernelInfo).

use std::collections::{BTreeMap, BTreeSet};
use std::path::PathBuf;
use std::process::Command;
use std::sync::OnceLock;

use shearsph::charts::pareto_flags;
use shearsph::kernels::{self, KERNELS};
use shearsph::report::ReportConfig;
use shearsph::sweep::Class;

/// The quick report, made once for every test here.
fn report_dir() -> PathBuf {
    static DIR: OnceLock<tempfile::TempDir> = OnceLock::new();
    DIR.get_or_init(|| {
        let tmp = tempfile::tempdir().unwrap();
        let out = Command::new(env!("CARGO_BIN_EXE_shearsph"))
            .args(["report", "--quick", "--out"])
            .arg(tmp.path().join("r"))
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        tmp
    })
    .path()
    .join("r")
}

/// A kernel's discretisation in the quick report's square case (its second
/// `[[case]]`).
fn square_case_of(
    info: &'static shearsph::kernel::KernelInfo,
) -> Option<&'static shearsph::kernel::DiscretisationInfo> {
    let config = ReportConfig::quick();
    assert_eq!(config.case[1].id, "square");
    let case = config.cases().into_iter().find(|c| c.disc.index == 1)?;
    case.disc.of(info).map(|(_, on)| on)
}

/// A CSV file as maps from column name to value (fields here hold no
/// quoted commas but the `reason` and `id` ones, which are not read).
fn csv(name: &str) -> Vec<BTreeMap<String, String>> {
    let text = std::fs::read_to_string(report_dir().join(name)).unwrap();
    let mut lines = text.lines();
    let header: Vec<String> = lines
        .next()
        .unwrap()
        .split(',')
        .map(str::to_string)
        .collect();
    lines
        .map(|l| {
            let cells = split_csv(l);
            assert_eq!(cells.len(), header.len(), "{name}: {l}");
            header.iter().cloned().zip(cells).collect()
        })
        .collect()
}

fn split_csv(line: &str) -> Vec<String> {
    let mut out = vec![String::new()];
    let mut quoted = false;
    let mut chars = line.chars().peekable();
    while let Some(c) = chars.next() {
        match (c, quoted) {
            ('"', true) if chars.peek() == Some(&'"') => {
                chars.next();
                out.last_mut().unwrap().push('"');
            }
            ('"', _) => quoted = !quoted,
            (',', false) => out.push(String::new()),
            (c, _) => out.last_mut().unwrap().push(c),
        }
    }
    out
}

/// A row of the paper's discretisation from the perfect lattice (runs.csv:
/// seed 0; the report's tables: start "perfect").
fn paper_perfect(r: &BTreeMap<String, String>) -> bool {
    r["lattice"] == "triangular"
        && r["h_over_d"] == "1"
        && r.get("seed").is_none_or(|s| s == "0")
        && r.get("start").is_none_or(|s| s == "perfect")
}

fn f(v: &str) -> f64 {
    v.parse().unwrap_or_else(|_| panic!("not a number: {v:?}"))
}

#[test]
fn index_references_every_figure_and_table() {
    let dir = report_dir();
    let html = std::fs::read_to_string(dir.join("index.html")).unwrap();
    let mut promised = vec![
        "figure4.svg",
        "figure4.csv",
        "figure4_square.svg",
        "figure4_square.csv",
        "speed_accuracy.svg",
        "speed_accuracy_work.svg",
        "speed_accuracy.csv",
        "table1.csv",
        "table2.csv",
        "c0_compare.csv",
        "empirical_c0.csv",
        "empirical_c0_trials.csv",
        "runs.csv",
        "ordered_lattice.json",
        "growth_map.json",
        "verdicts.json",
        "report.toml",
    ]
    .into_iter()
    .map(str::to_string)
    .collect::<Vec<_>>();
    for k in KERNELS {
        for case in ["", "_perturbed", "_square", "_square_perturbed"] {
            promised.push(format!("stability_{}{case}.svg", k.name));
            promised.push(format!("stability_{}{case}.csv", k.name));
        }
        promised.push(format!("answer_{}.svg", k.name));
        promised.push(format!("answer_{}.csv", k.name));
        // the two regimes in time, at the search's first probe
        promised.push(format!("history_{}.svg", k.name));
    }
    // Where the method fails, when some run of a map failed in the solver.
    for entry in std::fs::read_dir(&dir).unwrap() {
        let name = entry.unwrap().file_name().to_string_lossy().to_string();
        if name.starts_with("failure_") && name.ends_with(".svg") {
            promised.push(name);
        }
    }
    for file in &promised {
        assert!(
            html.contains(&format!("href=\"{file}\"")),
            "index.html does not link {file}"
        );
        assert!(dir.join(file).is_file(), "{file} is missing");
    }
    // Every link points at a file that exists.
    for part in html.split("href=\"").skip(1) {
        let target = part.split('"').next().unwrap();
        if !target.starts_with('#') {
            assert!(dir.join(target).is_file(), "broken link {target}");
        }
    }
    // Sections, and the figures inline: one <svg> per figure file.
    for id in [
        "answer",
        "history",
        "verdicts",
        "table1",
        "table2",
        "c0",
        "square",
        "figure4",
        "speed",
        "maps",
        "empirical",
        "method",
        "files",
    ] {
        assert!(html.contains(&format!("id=\"{id}\"")), "no section {id}");
    }
    let svgs = promised.iter().filter(|f| f.ends_with(".svg")).count();
    assert_eq!(html.matches("<svg").count(), svgs);
    // Self-contained: no scripts, nothing from the network.
    assert!(!html.contains("<script"));
    assert!(!html.contains("src=\"http"));
    // The square-lattice analysis names each kernel's square discretisation
    // (h = 13/10 d where generated), and every c0 model's row or fact.
    for k in KERNELS {
        let disc = square_case_of(k).expect("a square discretisation");
        assert!(
            html.contains(&disc.label()),
            "{}: no {}",
            k.name,
            disc.label()
        );
        if disc.h_over_d_exact != "13/10" {
            assert!(k
                .discretisations
                .iter()
                .all(|d| d.lattice != shearsph::kernel::Lattice::Square
                    || d.h_over_d_exact != "13/10"));
        }
    }
    assert!(html.contains("the paper's discretisation: triangular, h = d"));
    // A verdict per kernel, named.
    for k in KERNELS {
        assert!(
            html.contains(&format!("<h3>{}</h3>", k.name)),
            "no verdict for {}",
            k.name
        );
    }
}

#[test]
fn figure4_csv_is_the_generated_eps_at_and_the_solver_agrees() {
    let rows = csv("figure4.csv");
    let mut curves = BTreeSet::new();
    for r in &rows {
        let info = kernels::kernel_info(&r["kernel"]).unwrap();
        let (n, big_n, t) = (
            r["n"].parse::<u32>().unwrap(),
            r["n_layers"].parse::<u32>().unwrap(),
            f(&r["t_over_T"]),
        );
        let model = f(&r["eps_model"]);
        assert_eq!(model, (info.eps_at)(t, n, Some(big_n)), "{r:?}");
        // The solver's density summation under ideal shear: the same sum in
        // another order.
        assert!((f(&r["eps_solver"]) - model).abs() < 1e-12, "{r:?}");
        assert_eq!(f(&r["eps_mean"]), info.eps.mean.value);
        curves.insert((r["kernel"].clone(), n));
    }
    // Layers 0, N - R and N - 1 of every kernel.
    let big_n = ReportConfig::quick().figure4.n;
    for k in KERNELS {
        let r = k.support.ceil() as u32;
        for n in [0, big_n - r, big_n - 1] {
            assert!(
                curves.contains(&(k.name.to_string(), n)),
                "{} n = {n}",
                k.name
            );
        }
    }
}

#[test]
fn figure4_square_is_each_kernels_square_eps_at_and_the_solver_agrees() {
    // The same as Figure 4 on the square discretisation the report picks per
    // kernel: the solver's density summation on the square lattice under
    // ideal shear is that discretisation's eps_at.
    let rows = csv("figure4_square.csv");
    let mut kernels_seen = BTreeSet::new();
    for r in &rows {
        let info = kernels::kernel_info(&r["kernel"]).unwrap();
        let disc = square_case_of(info).unwrap();
        let (n, big_n, t) = (
            r["n"].parse::<u32>().unwrap(),
            r["n_layers"].parse::<u32>().unwrap(),
            f(&r["t_over_T"]),
        );
        let model = f(&r["eps_model"]);
        assert_eq!(model, (disc.eps_at)(t, n, Some(big_n)), "{r:?}");
        assert!((f(&r["eps_solver"]) - model).abs() < 1e-12, "{r:?}");
        assert_eq!(f(&r["eps_mean"]), disc.eps.mean.value);
        kernels_seen.insert(r["kernel"].clone());
    }
    assert_eq!(kernels_seen.len(), KERNELS.len());
}

#[test]
fn each_stability_map_has_one_valid_row_per_grid_point() {
    let maps = ReportConfig::quick().maps;
    for k in KERNELS {
        let rows = csv(&format!("stability_{}.csv", k.name));
        let mut seen = BTreeSet::new();
        for r in &rows {
            assert!(Class::parse(&r["class"]).is_some(), "{r:?}");
            assert!(
                seen.insert((r["re"].clone(), r["c0_over_u"].clone())),
                "duplicate {r:?}"
            );
            assert_eq!(r["kernel"], k.name);
        }
        assert_eq!(
            rows.len(),
            maps.re.len() * maps.c0_over_u.len(),
            "{}",
            k.name
        );
        for re in &maps.re {
            for c in &maps.c0_over_u {
                assert!(
                    seen.contains(&(re.to_string(), c.to_string())),
                    "{} Re {re} c0 {c}",
                    k.name
                );
            }
        }
        // The lines behind the map: one per rule, every derived model with a
        // positive value where the model's own formula gives one.
        let lines = csv(&format!("stability_{}_lines.csv", k.name));
        for m in k.c0_models {
            let mine: Vec<_> = lines
                .iter()
                .filter(|l| l["line"].starts_with(&format!("derived:{}", m.name)))
                .collect();
            assert!(!mine.is_empty(), "no line for {}", m.name);
            for l in mine.iter().filter(|l| !l["re"].is_empty()) {
                assert!(f(&l["c0_over_u"]) > 0.0);
            }
        }
    }
}

#[test]
fn pareto_flags_are_right() {
    // (cost, error): a beats b when no worse in both and better in one.
    let pts = [
        (1.0, 0.5),      // front: cheapest
        (2.0, 0.1),      // front
        (3.0, 0.1),      // beaten by (2, 0.1)
        (2.5, 0.05),     // front
        (10.0, 0.05),    // beaten by (2.5, 0.05)
        (10.0, 0.01),    // front: most accurate
        (1.0, 0.6),      // beaten by (1, 0.5)
        (f64::NAN, 0.0), // never on it
    ];
    assert_eq!(
        pareto_flags(&pts),
        vec![true, true, false, true, false, true, false, false]
    );
    // Equal points do not beat each other.
    assert_eq!(pareto_flags(&[(1.0, 1.0), (1.0, 1.0)]), vec![true, true]);

    // The report's speed chart data carries flags that agree with its own
    // points, per Re.
    let rows = csv("speed_accuracy.csv");
    assert!(!rows.is_empty());
    let res: BTreeSet<String> = rows.iter().map(|r| r["re"].clone()).collect();
    for re in res {
        let here: Vec<_> = rows.iter().filter(|r| r["re"] == re).collect();
        for (cost, flag) in [
            ("wall_s", "pareto_wall"),
            ("particle_steps", "pareto_particle_steps"),
        ] {
            let xy: Vec<(f64, f64)> = here
                .iter()
                .map(|r| (f(&r[cost]).max(1e-4), f(&r["linf_max"])))
                .collect();
            let want = pareto_flags(&xy);
            let got: Vec<bool> = here.iter().map(|r| r[flag] == "true").collect();
            assert_eq!(got, want, "Re {re}, {cost}");
        }
    }
}

#[test]
fn tables_are_the_generated_values_beside_the_print() {
    let t1 = csv("table1.csv");
    for k in KERNELS {
        let mine: Vec<_> = t1.iter().filter(|r| r["kernel"] == k.name).collect();
        assert_eq!(mine.len(), 3);
        let ours: Vec<f64> = mine.iter().map(|r| f(&r["ours"])).collect();
        assert_eq!(
            ours,
            vec![k.eps.t0.value, k.eps.half_period.value, k.eps.mean.value]
        );
        if let Some(p) = k.printed_eps {
            for (r, printed) in mine.iter().zip([p.t0, p.half_period, p.mean]) {
                assert_eq!(r["printed"], printed);
                // Agreement: ours rounded to the printed places is the print.
                let places = printed.split('.').nth(1).map_or(0, str::len);
                let rounded = format!("{:.*}", places, f(&r["ours"]));
                let agrees = f(&rounded) == f(printed);
                assert_eq!(
                    r["agrees_at_printed_precision"],
                    agrees.to_string(),
                    "{r:?}"
                );
            }
        }
    }
    let t2 = csv("table2.csv");
    for k in KERNELS {
        for m in k.c0_models {
            let r = t2
                .iter()
                .find(|r| {
                    r["kernel"] == k.name
                        && r["source"] == "ours"
                        && r["model"].trim_end_matches(" (default)") == m.name
                })
                .unwrap();
            assert_eq!(f(&r["S"]), m.s.value);
            assert_eq!(f(&r["P"]), m.p.value);
            assert_eq!(f(&r["Q"]), m.q.value);
            assert_eq!(
                r["no_positive_root"],
                (m.q.value <= 0.0 && m.s.value >= 0.0).to_string()
            );
        }
        if let Some(p) = k.printed_c0 {
            let r = t2
                .iter()
                .find(|r| r["kernel"] == k.name && r["source"] == "printed")
                .unwrap();
            assert_eq!(f(&r["S"]), p.factor * p.s);
            assert_eq!(f(&r["Q"]), p.factor * p.factor * p.q);
        }
    }
}

#[test]
fn verdicts_and_empirical_c0_follow_from_the_runs() {
    let config = ReportConfig::quick();
    let runs = csv("runs.csv");
    let compare = csv("c0_compare.csv");
    let verdicts: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(report_dir().join("verdicts.json")).unwrap())
            .unwrap();
    for k in KERNELS {
        let v = verdicts
            .as_array()
            .unwrap()
            .iter()
            .find(|v| v["kernel"] == k.name)
            .unwrap();
        for a in v["at_re"].as_array().unwrap() {
            let re = a["re"].as_f64().unwrap();
            // The derived c0 is the default model's for the scene, or none.
            let row = compare
                .iter()
                .find(|c| {
                    c["kernel"] == k.name
                        && f(&c["re"]) == re
                        && c["default_model"] == "true"
                        && paper_perfect(c)
                })
                .unwrap();
            let c0 = f(&row["c0_over_u"]);
            match a["derived_c0_over_u"].as_f64() {
                Some(d) => assert_eq!(d, c0),
                None => assert!(
                    c0.is_nan() || c0 <= 0.0,
                    "{} Re {re}: derived c0 {c0} not shown",
                    k.name
                ),
            }
            // Its class is the class of the run at that c0 ("derived"), on
            // the stationary horizon (the speed section's runs at the same
            // c0 have a fixed horizon and are another measurement).
            if let Some(class) = a["derived_class"].as_str() {
                let run = runs
                    .iter()
                    .find(|r| {
                        r["kernel"] == k.name
                            && f(&r["re"]) == re
                            && r["n"] == config.maps.n.to_string()
                            && r["c0_spec"] == "derived"
                            && r["horizon"] == "stationary"
                            && paper_perfect(r)
                    })
                    .unwrap();
                assert_eq!(run["class"], class);
            }
        }
    }
    // The empirical c0 was ok, the value below it over-compressed (or
    // failed), by the trials' own classes, within the tolerance.
    let trials = csv("empirical_c0_trials.csv");
    for e in csv("empirical_c0.csv") {
        if e["c0_over_u"].is_empty() {
            continue;
        }
        let perturbed = e["start"] == "perturbed";
        let class_at = |c0: f64| {
            let t = trials
                .iter()
                .find(|t| {
                    t["kernel"] == e["kernel"]
                        && t["re"] == e["re"]
                        && t["lattice"] == e["lattice"]
                        && t["h_over_d"] == e["h_over_d"]
                        && f(&t["c0_over_u"]) == c0
                })
                .unwrap_or_else(|| panic!("no trial at c0 = {c0} for {e:?}"));
            let key = if perturbed {
                "pooled_class"
            } else {
                "perfect_class"
            };
            Class::parse(&t[key]).unwrap_or_else(|| panic!("{key} at {c0}: {t:?}"))
        };
        let c0 = f(&e["c0_over_u"]);
        assert_eq!(class_at(c0), Class::Ok, "{e:?}");
        if !e["below_c0_over_u"].is_empty() {
            let below = f(&e["below_c0_over_u"]);
            assert!(
                matches!(class_at(below), Class::OverCompressed | Class::Failed),
                "{e:?}"
            );
            assert!(c0 / below <= 1.0 + f(&e["rel_tol"]) + 1e-12, "{e:?}");
        }
    }
}

/// The report's empirical c0 is `c0 --empirical`'s answer for the same
/// scene: one engine, one search, one horizon.
#[test]
fn the_report_and_c0_empirical_give_the_same_answer() {
    let config = ReportConfig::quick();
    let e = csv("empirical_c0.csv")
        .into_iter()
        .find(|e| {
            e["kernel"] == "monaghan" && e["start"] == "perturbed" && e["lattice"] == "triangular"
        })
        .expect("monaghan's answer in the quick report");
    let span = config.scene["horizon_span"].as_float().unwrap().to_string();
    let out = Command::new(env!("CARGO_BIN_EXE_shearsph"))
        .args(["c0", "--empirical", "--no-rules", "--json", "--quiet"])
        .args(["--kernel", "monaghan", "--n", &config.maps.n.to_string()])
        .args(["--re", &e["re"], "--alpha", &config.maps.alpha.to_string()])
        .args(["--horizon-span", &span])
        .args(["--seeds", &config.perturbed.seeds.to_string()])
        .args(["--amplitude", &config.perturbed.jitter.to_string()])
        .args(["--rel-tol", &config.empirical.rel_tol.to_string()])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let c0 = v["c0_min_ok"]
        .as_f64()
        .map(|c| c / v["u"].as_f64().unwrap());
    let report = (!e["c0_over_u"].is_empty()).then(|| f(&e["c0_over_u"]));
    assert_eq!(c0, report, "c0 --empirical against the report's {e:?}");
    assert!(!v["trials"].as_array().unwrap().is_empty());
}

#[test]
fn an_existing_report_is_kept_without_force() {
    let dir = report_dir();
    let before = std::fs::read(dir.join("index.html")).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_shearsph"))
        .args(["report", "--quick", "--out"])
        .arg(&dir)
        .output()
        .unwrap();
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("--force"));
    assert_eq!(std::fs::read(dir.join("index.html")).unwrap(), before);
}

/// The ordered lattice beside the answer: per kernel and verdict Re, the
/// growth of perturbations of the perfect sheared lattice at the derived
/// and rule10 c0 (the quick config's Re 1 and 10), in the data and in the
/// first screen's words.
#[test]
fn the_answer_says_how_long_the_ordered_lattice_lasts() {
    let dir = report_dir();
    let rows: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("ordered_lattice.json")).unwrap())
            .unwrap();
    let rows = rows.as_array().expect("rows");
    // Every kernel with the paper's discretisation generated.
    let kernels = KERNELS
        .iter()
        .filter(|k| shearsph::report::papers(k).is_some())
        .count();
    assert_eq!(rows.len(), kernels * 2 * 2);
    for r in rows {
        let rule = r["rule"].as_str().unwrap();
        assert!(rule == "derived" || rule == "rule10", "{rule}");
        if rule == "rule10" {
            assert_eq!(r["c0_over_u"].as_f64(), Some(10.0));
        }
        match (r["c0_over_u"].as_f64(), r["growth_rate"].as_f64()) {
            // A rate, and where it is positive the time a 1e-4 d jitter
            // takes at it.
            (Some(_), Some(g)) => {
                let t = r["t_disorder"].as_f64();
                assert_eq!(t.is_some(), g > 0.0, "{r}");
                if let Some(t) = t {
                    assert!(
                        (t * g - (0.1 * 3f64.sqrt() / 1e-4).ln()).abs() < 1e-9,
                        "{r}"
                    );
                }
            }
            // No c0, or a base that does not last: said why.
            _ => assert!(r["note"].as_str().is_some_and(|n| !n.is_empty()), "{r}"),
        }
    }
    let html = std::fs::read_to_string(dir.join("index.html")).unwrap();
    let said = html
        .matches("The ordered lattice the derived rules assume")
        .count();
    assert_eq!(
        said,
        KERNELS.len() * 2,
        "one sentence per kernel and verdict Re"
    );
}

/// The growth map: a cell for every kernel on each discretisation it has
/// generated, every Re and c0 of `[growth]` (the quick config's), each with
/// a rate or the reason it has none, and its time to disorder exactly where
/// the rate is positive; the page shows it as a table, one row per kernel,
/// discretisation and Re.
#[test]
fn the_growth_map_covers_every_kernel_discretisation_re_and_c0() {
    let dir = report_dir();
    let config = shearsph::report::ReportConfig::quick();
    let g = &config.growth;
    let cells: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("growth_map.json")).unwrap())
            .unwrap();
    let cells = cells.as_array().expect("cells");
    let discs: usize = KERNELS
        .iter()
        .map(|k| {
            usize::from(shearsph::report::papers(k).is_some())
                + usize::from(square_case_of(k).is_some())
        })
        .sum();
    assert!(discs >= KERNELS.len(), "every kernel has a discretisation");
    assert_eq!(cells.len(), discs * g.re.len() * g.c0_over_u.len());
    for c in cells {
        assert!(g.re.contains(&c["re"].as_f64().unwrap()), "{c}");
        assert!(
            g.c0_over_u.contains(&c["c0_over_u"].as_f64().unwrap()),
            "{c}"
        );
        match c["growth_rate"].as_f64() {
            Some(rate) => {
                assert_eq!(c["t_disorder"].as_f64().is_some(), rate > 0.0, "{c}");
                assert!(c["growth_rate_per_period"].as_f64().is_some(), "{c}");
            }
            None => assert!(c["note"].as_str().is_some_and(|n| !n.is_empty()), "{c}"),
        }
    }
    let html = std::fs::read_to_string(dir.join("index.html")).unwrap();
    let start = html
        .find("id=\"growth\"")
        .expect("the growth map's section");
    let table = &html[start..start + html[start..].find("</table>").unwrap()];
    assert_eq!(
        table.matches("<tr><td").count(),
        discs * g.re.len(),
        "one row per kernel, discretisation and Re"
    );
}

/// The config the report writes beside its page reads back as a config
/// (its `[[case]]` entries included) and is the one the report ran.
#[test]
fn the_written_config_reads_back() {
    let dir = report_dir();
    let text = std::fs::read_to_string(dir.join("report.toml")).unwrap();
    let read = ReportConfig::parse(&text, "report.toml")
        .unwrap_or_else(|e| panic!("the written report.toml: {e:#}"));
    let quick = ReportConfig::quick();
    assert_eq!(read.case.len(), quick.case.len());
    for (a, b) in read.case.iter().zip(&quick.case) {
        assert_eq!(
            (a.id.as_str(), a.discretisation()),
            (b.id.as_str(), b.discretisation())
        );
    }
}
