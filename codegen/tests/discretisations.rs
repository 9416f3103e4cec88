//! Every kernel x discretisation. A kernel whose maximum compaction
//! is not at 0.5 T derives c0 from its true maximum and `show --json` names
//! that configuration; degenerate derivations are stated facts, not panics
//! or NaN; snapshots pin the exact forms and 30-digit decimals of every
//! shipped kernel on every non-paper discretisation (the paper's are pinned
//! by `snapshots.rs`, unchanged).

use shearsph_codegen::analysis::{analyse, Analysis, DiscAnalysis, Options};
use shearsph_codegen::exact::decimal;
use shearsph_codegen::kernel::{load_dir, parse_kernel};
use shearsph_codegen::lattice::{Config, Discretisation, Lattice};
use shearsph_codegen::{discretisation, emit, show};
use std::fmt::Write;
use std::path::Path;
use std::process::Command;

/// A Wendland-type kernel C (1 - q/R)^4 (1 + 4 q/R), C = 7/(pi R^2), with
/// R = 5/2: on the paper's lattice its maximum compaction is near 0.418 T,
/// not at 0.5 T (found by trying R = 5/4, 3/2, 7/4, 17/10, 9/4, 5/2; only
/// the last has it elsewhere). Not shipped.
const OFF_HALF: &str = r#"
name = "off_half"
reference = "test kernel: Wendland-type shape with R = 5/2"
support = "5/2"
scale = "28/(25*pi)"
[[w]]
to = "5/2"
expr = "(1 - 2*q/5)^4 * (1 + 8*q/5)"
"#;

/// R = 1, (1 - q)^4 (1 + 4 q) normalised: W'(1) = 0, so the six neighbours
/// at r = d exert no force.
const R1_FLAT: &str = r#"
name = "r1_flat"
reference = "test kernel: Wendland C2 shape with R = 1"
support = 1
scale = "7/pi"
[[w]]
to = 1
expr = "(1 - q)^4 * (1 + 4*q)"
"#;

/// R = 1/3: no neighbour in reach at h = d.
const THIRD: &str = r#"
name = "third"
reference = "test kernel: support 1/3"
support = "1/3"
scale = "63/pi"
[[w]]
to = "1/3"
expr = "(1 - 3*q)^4 * (1 + 12*q)"
"#;

fn opts() -> Options {
    Options {
        digits: 30,
        check_layers: 10,
    }
}

fn root() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn analyse_src(src: &str, discs: &[Discretisation]) -> Analysis {
    let def = parse_kernel(Path::new("test.toml"), src).unwrap();
    analyse(&def, discs, opts())
}

#[test]
fn c0_comes_from_the_true_maximum_and_show_names_it() {
    let a = analyse_src(OFF_HALF, &[]);
    let p = a.paper();
    let tau = p.eps.t_max.value.to_f64();
    assert!((tau - 0.418).abs() < 1e-3, "t_max = {tau}");
    // the maximum is the searched one, above eps(0.5 T) and eps(0)
    assert!(p.eps.max.value > p.eps.half_period.value);
    assert!(p.eps.max.value > p.eps.t0.value);
    // c0 derived there: not a symmetric configuration, eps0 = the maximum
    let cc = &p.c0_config;
    assert_eq!(cc.symmetric, None);
    assert_eq!(cc.eps0.value, p.eps.max.value);
    assert!(cc.label.contains("0.418"), "{}", cc.label);
    // the models are derived at that configuration: a = eps0 K with K = G(max)
    // there, which differs from the 0.5 T configuration's G
    let field = p.models.iter().find(|m| m.model.name == "field").unwrap();
    let c = field.coefs.as_ref().unwrap();
    assert!(field.exact.is_none(), "high precision, not exact");
    let k = rug::Float::with_val(a.prec, &c.a / &cc.eps0.value);
    let g_half = p.sums_half.g.to_float(a.prec);
    assert!((k.to_f64() - g_half.to_f64()).abs() > 1e-6 * g_half.to_f64().abs());
    // every number is finite
    for m in &p.models {
        let c = m.coefs.as_ref().unwrap();
        for x in [&c.a, &c.b, &c.c, &c.s, &c.p, &c.q] {
            assert!(x.is_finite(), "{}", m.model.name);
        }
    }
    // show --json names the configuration and its time as a fraction of T
    let tmp = tempfile::tempdir().unwrap();
    std::fs::write(tmp.path().join("off_half.toml"), OFF_HALF).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_shearsph-codegen"))
        .args([
            "--kernels",
            tmp.path().to_str().unwrap(),
            "show",
            "off_half",
            "--json",
        ])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let j: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let conf = &j["c0"]["configuration"];
    let t: f64 = conf["time_over_T"].as_str().unwrap().parse().unwrap();
    assert!((t - tau).abs() < 1e-12, "{conf}");
    assert!(conf["symmetric"].is_null(), "{conf}");
    assert_eq!(conf["discretisation"], "triangular, h/d = 1");
    // and the text does not head the 0.5 T table as maximum compaction
    let text = show::text(&a);
    assert!(!text.contains("t = 0.5 T (maximum compaction)"), "{text}");
    assert!(
        text.contains("derived at maximum compaction: t = 0.418"),
        "{text}"
    );
    // emitted: the coefficients as high-precision decimals, no NaN
    let module = emit::kernel_module(&a);
    assert!(module.contains("symmetric: false"));
    assert!(!module.contains("NaN"));
}

fn assert_no_c0(a: &Analysis, why: &str) {
    for da in &a.discs {
        for m in &da.models {
            let fact = m.coefs.as_ref().expect_err("no c0");
            assert!(
                fact.starts_with("no c0:") && fact.contains(why),
                "{}: {fact}",
                da.disc.label()
            );
        }
    }
    let text = show::text(a);
    assert!(text.contains("no c0:") && !text.contains("NaN"), "{text}");
    let j = show::json(a);
    assert!(j["c0"]["models"].as_object().unwrap().is_empty());
    assert_eq!(j["c0"]["no_c0"].as_object().unwrap().len(), 4);
    // generate: no panic, and the absence is emitted as data
    let module = emit::kernel_module(a);
    assert!(module.contains("NoC0 {") && !module.contains("NaN"));
    syn::parse_file(&module).unwrap();
}

#[test]
fn a_vanishing_gradient_at_every_neighbour_is_a_stated_fact() {
    let a = analyse_src(R1_FLAT, &[]);
    assert_no_c0(&a, "exert no force");
}

#[test]
fn a_support_with_no_neighbour_is_a_stated_fact() {
    let a = analyse_src(THIRD, &[]);
    assert_no_c0(&a, "reaches no neighbour");
}

#[test]
fn the_default_set_covers_the_peers_and_the_paper_comes_first() {
    let discs = discretisation::load(&root().join("kernels")).unwrap();
    assert!(discs[0].is_paper());
    let has = |l: Lattice, h: (i64, i64)| {
        discs.contains(&Discretisation {
            lattice: l,
            h: rug::Rational::from(h),
        })
    };
    assert!(has(Lattice::Square, (1, 1)));
    assert!(has(Lattice::Square, (13, 10)));
    assert!(has(Lattice::Square, (17, 10)));
    assert!(discs
        .iter()
        .any(|d| d.lattice == Lattice::Triangular && d.h > 1));
}

/// The exact forms (or stated high-precision decimals) of one kernel on one
/// discretisation.
fn table(a: &Analysis, da: &DiscAnalysis) -> String {
    let mut out = String::new();
    let _ = writeln!(out, "kernel {} on {}", a.def.name, da.disc.label());
    let e = &da.eps;
    for (label, k) in [
        ("eps(0)", &e.t0),
        ("eps(0.5T)", &e.half_period),
        ("max eps", &e.max),
        ("t_max/T", &e.t_max),
        ("mean eps", &e.mean),
    ] {
        let _ = writeln!(
            out,
            "{label:<14} {}\n{:<14} = {}",
            k.form(),
            "",
            decimal(&k.value, k.digits.map_or(30, |d| (d as usize).min(30)))
        );
    }
    let _ = writeln!(out, "c0 at          {}", da.c0_config.label);
    for m in &da.models {
        let _ = writeln!(out, "-- model {}", m.model.name);
        match (&m.exact, &m.coefs) {
            (_, Err(fact)) => {
                let _ = writeln!(out, "{fact}");
            }
            (Some(d), Ok(c)) => {
                for (l, x, f) in [
                    ("a", d.a.to_string(), &c.a),
                    ("b", d.b.to_string(), &c.b),
                    ("c", d.c.to_string(), &c.c),
                    ("S", d.s.to_string(), &c.s),
                    ("P", d.p.to_string(), &c.p),
                    ("Q", d.q.to_string(), &c.q),
                ] {
                    let _ = writeln!(out, "{l:<14} {x}\n{:<14} = {}", "", decimal(f, 30));
                }
            }
            (None, Ok(c)) => {
                for (l, f) in [
                    ("a", &c.a),
                    ("b", &c.b),
                    ("c", &c.c),
                    ("S", &c.s),
                    ("P", &c.p),
                    ("Q", &c.q),
                ] {
                    let _ = writeln!(out, "{l:<14} (high precision) = {}", decimal(f, 30));
                }
            }
        }
    }
    out
}

#[test]
fn snapshots_of_every_kernel_on_every_discretisation() {
    let dir = root().join("kernels");
    let discs = discretisation::load(&dir).unwrap();
    for def in load_dir(&dir).unwrap() {
        let a = analyse(&def, &discs, opts());
        for da in a.discs.iter().skip(1) {
            let name = format!("{}__{}", def.name, da.disc.ident());
            insta::assert_snapshot!(name, table(&a, da));
        }
        // the paper's claims are checked on every discretisation
        for da in &a.discs {
            assert_eq!(da.claims.len(), 4, "{}", da.disc.label());
            // the sums of eps include the particle itself
            assert!(
                da.terms_t0.iter().any(|t| t.nb.is_self()),
                "{} on {}: the particle itself is in its stencil",
                def.name,
                da.disc.label()
            );
            let _ = Config::T0;
        }
    }
}
