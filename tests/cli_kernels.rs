//! `shearsph kernels` prints every generated kernel, as a table and as JSON,
//! with the generated constants.

use crate::common;
use common::*;

use shearsph::kernels::KERNELS;

/// serde_json's default float parsing is within an ulp, not always exact.
fn close(a: &serde_json::Value, b: f64) -> bool {
    let a = a.as_f64().unwrap();
    (a - b).abs() <= 1e-15 * b.abs()
}

#[test]
fn kernels_json_lists_every_kernel_with_its_constants() {
    let out = shearsph(&["kernels", "--json"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let list = v.as_array().unwrap();
    assert_eq!(list.len(), KERNELS.len());
    for (j, k) in list.iter().zip(KERNELS) {
        assert_eq!(j["kernel"], k.name);
        assert!(close(&j["support"], k.support));
        assert!(close(
            &j["eps"]["half_period"]["value"],
            k.eps.half_period.value
        ));
        assert!(close(&j["eps"]["t_max"]["value"], k.eps.t_max.value));
        assert_eq!(j["c0"]["default"], k.c0_default);
        let m = k.default_c0_model();
        assert!(close(&j["c0"]["models"][m.name]["S"], m.s.value));
        // Every discretisation, with its eps and models or no-c0 facts.
        let ds = j["discretisations"].as_array().unwrap();
        assert_eq!(ds.len(), k.discretisations.len());
        for (jd, d) in ds.iter().zip(k.discretisations) {
            assert_eq!(jd["lattice"], d.lattice.name());
            assert_eq!(jd["h_over_d_exact"], d.h_over_d_exact);
            assert!(close(&jd["eps"]["t0"]["value"], d.eps.t0.value));
            assert!(close(&jd["eps"]["max"]["value"], d.eps.max.value));
            for m in d.c0_models {
                assert!(close(&jd["c0"]["models"][m.name]["Q"], m.q.value));
            }
            for m in d.no_c0 {
                assert_eq!(jd["c0"]["no_c0"][m.model], m.fact);
            }
        }
    }
}

#[test]
fn kernels_table_names_every_kernel_and_flags_missing_roots() {
    let out = shearsph(&["kernels", "--models"]);
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    for k in KERNELS {
        assert!(text.contains(k.name), "{text}");
        for d in k.discretisations {
            let row = |model: &str| {
                text.lines()
                    .find(|l| {
                        let w: Vec<&str> = l.split_whitespace().collect();
                        w.len() > 3
                            && w[0] == k.name
                            && w[1] == d.lattice.name()
                            && w[2] == d.h_over_d_exact
                            && w[3] == model
                    })
                    .unwrap_or_else(|| panic!("row for {} {} {model}", k.name, d.label()))
            };
            for m in d.c0_models {
                let no_root = m.q.value <= 0.0 && m.s.value >= 0.0;
                let line = row(m.name);
                assert_eq!(line.contains("no positive root"), no_root, "{line}");
            }
            for m in d.no_c0 {
                assert!(row(m.model).contains(m.fact));
            }
        }
    }
}

/// Where the generator states "no c0" for a derived model
/// (the maximum compaction at t = 0, a lattice that never compacts), `c0`
/// lists the fact in that model's row, and `run --c0 derived:MODEL` (and
/// derived-eps for the default model's) is refused with it, exit 1, before
/// any step: every such model on every shipped discretisation.
#[test]
fn a_derived_model_without_c0_is_refused_with_the_generators_fact() {
    let mut cases = 0;
    for k in KERNELS {
        for d in k.discretisations {
            if d.no_c0.is_empty() {
                continue;
            }
            let h = d.h_over_d_exact;
            let scene = [
                "--kernel",
                k.name,
                "--n",
                "10",
                "--re",
                "10",
                "--lattice",
                d.lattice.name(),
                "--h-over-d",
                h,
            ];
            let mut args = vec!["c0"];
            args.extend(scene);
            let o = shearsph(&args);
            assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
            let table = String::from_utf8(o.stdout).unwrap();
            let dir = tempfile::tempdir().unwrap();
            for m in d.no_c0 {
                let rule = format!("derived:{}", m.model);
                let line = table
                    .lines()
                    .find(|l| l.split_whitespace().next() == Some(rule.as_str()))
                    .unwrap_or_else(|| panic!("{rule} in {table}"));
                assert!(line.contains(m.fact), "{line}");
                let mut rules = vec![rule];
                if m.model == k.c0_default {
                    rules.push("derived-eps".into());
                }
                for rule in rules {
                    let out = dir.path().join(rule.replace(':', "_"));
                    let mut args = vec!["run"];
                    args.extend(scene);
                    args.extend(["--c0", &rule, "--out", out.to_str().unwrap()]);
                    let o = shearsph(&args);
                    let err = String::from_utf8_lossy(&o.stderr);
                    assert_eq!(
                        o.status.code(),
                        Some(1),
                        "{} {} {rule}: {err}",
                        k.name,
                        d.label()
                    );
                    assert!(err.contains(m.fact), "{err}");
                    assert!(!out.join("profile.csv").exists());
                    cases += 1;
                }
            }
        }
    }
    // the cases are among them
    let morris = KERNELS.iter().find(|k| k.name == "morris").unwrap();
    let sq17 = morris
        .discretisation(shearsph::kernel::Lattice::Square, 1.7)
        .unwrap();
    assert!(sq17.no_c0_fact("field").is_some());
    let composite = KERNELS.iter().find(|k| k.name == "composite").unwrap();
    let tri13 = composite
        .discretisation(shearsph::kernel::Lattice::Triangular, 1.3)
        .unwrap();
    assert!(tri13
        .no_c0_fact("field-av")
        .unwrap()
        .contains("never compacts"));
    assert!(cases >= 8, "{cases}");
}
