//! Pins, for every shipped kernel, the exact forms and 30-digit decimals of
//! eps(0), eps(0.5 T), the c0 polynomial's coefficients and S, P, Q for every
//! model (one source of truth: a change in the derivation shows up here).

use shearsph_codegen::analysis::{analyse, Options};
use shearsph_codegen::emit;
use shearsph_codegen::exact::{decimal, Exact, Ratio};
use shearsph_codegen::kernel::load_dir;
use std::fmt::Write;
use std::path::Path;

fn table(name: &str) -> String {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../kernels");
    let defs = load_dir(&dir).unwrap();
    let def = defs.iter().find(|k| k.name == name).unwrap();
    let a = analyse(
        def,
        &[],
        Options {
            digits: 30,
            check_layers: 10,
        },
    );
    let mut out = String::new();
    let ex = |out: &mut String, label: &str, e: &Exact| {
        let _ = writeln!(
            out,
            "{label:<14} {}\n{:<14} = {}",
            e,
            "",
            decimal(&e.to_float(a.prec), 30)
        );
    };
    let ra = |out: &mut String, label: &str, r: &Ratio| {
        let _ = writeln!(
            out,
            "{label:<14} {}\n{:<14} = {}",
            r,
            "",
            decimal(&r.to_float(a.prec), 30)
        );
    };
    ex(&mut out, "eps(0)", a.paper().eps.t0.exact.as_ref().unwrap());
    ex(
        &mut out,
        "eps(0.5T)",
        a.paper().eps.half_period.exact.as_ref().unwrap(),
    );
    for m in a.paper().exact_models() {
        let _ = writeln!(out, "-- model {}", m.model.name);
        ex(&mut out, "a", &m.a);
        ex(&mut out, "b", &m.b);
        ex(&mut out, "c", &m.c);
        ra(&mut out, "S", &m.s);
        ra(&mut out, "P", &m.p);
        ra(&mut out, "Q", &m.q);
    }
    out
}

#[test]
fn composite() {
    insta::assert_snapshot!(table("composite"));
}

#[test]
fn monaghan() {
    insta::assert_snapshot!(table("monaghan"));
}

#[test]
fn morris() {
    insta::assert_snapshot!(table("morris"));
}

#[test]
fn emitted_module_monaghan() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../kernels");
    let defs = load_dir(&dir).unwrap();
    let def = defs.iter().find(|k| k.name == "monaghan").unwrap();
    let a = analyse(def, &[], Options::default());
    insta::assert_snapshot!(emit::kernel_module(&a));
}
