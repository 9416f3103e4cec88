//! A kernel the project does not ship, derived end to end; and definitions
//! that are malformed, each with its own clear error.

use shearsph_codegen::analysis::{analyse, Options};
use shearsph_codegen::emit;
use shearsph_codegen::kernel::{load_dir, parse_kernel, KernelError};
use std::path::Path;

/// Lucy's quartic-like kernel with a support that is not an integer:
/// W = 16/(9 pi) (1 - 4 q^2/9)^3 on [0, 3/2] (normalised in 2D for R = 3/2).
const POLY6: &str = r#"
name = "poly6"
title = "Poly6-type kernel, R = 3/2"
reference = "written for this test"
support = "3/2"
scale = "16/(9*pi)"
[[w]]
to = "3/2"
expr = "(1 - 4*q^2/9)^3"
"#;

#[test]
fn unshipped_kernel_end_to_end() {
    let def = parse_kernel(Path::new("poly6.toml"), POLY6).expect("a valid kernel");
    assert_eq!(def.support.to_string(), "3/2");
    // the paper's lattice and the same at h = 1.3 d
    let tri13 = shearsph_codegen::lattice::Discretisation {
        lattice: shearsph_codegen::lattice::Lattice::Triangular,
        h: shearsph_codegen::rug::Rational::from((13, 10)),
    };
    let a = analyse(
        &def,
        &[tri13],
        Options {
            digits: 20,
            check_layers: 6,
        },
    );
    // exact values where the mathematics is exact (even kernel: the mean too)
    assert!(a.paper().eps.t0.exact.is_some());
    assert!(a.paper().eps.half_period.exact.is_some());
    assert!(
        a.paper().eps.mean.exact.is_some(),
        "even pieces integrate exactly"
    );
    assert!(
        a.facts
            .iter()
            .find(|f| f.name.starts_with("even in q"))
            .unwrap()
            .holds
    );
    // the extremes are found, and eps(0.5 T) is never above the true maximum
    assert!(a.paper().eps.max.value >= a.paper().eps.half_period.value);
    assert!(a.paper().eps.min.value <= a.paper().eps.t0.value);
    // on the paper's lattice it never compacts (max eps < 0 at t = 0): every
    // derived model states so; at h = 1.3 d it compacts, and every model has
    // P = S^2 and finite coefficients
    assert!(a.paper().eps.max.value < 0);
    for m in &a.paper().models {
        let fact = m.coefs.as_ref().expect_err("no c0");
        assert!(fact.contains("the lattice never compacts"), "{fact}");
    }
    let at13 = &a.discs[1];
    assert!(at13.eps.max.value > 0);
    assert_eq!(at13.exact_models().len(), 4);
    for m in at13.exact_models() {
        assert_eq!(m.p, m.s.square());
        assert!(m.s.to_f64().is_finite() && m.q.to_f64().is_finite());
    }
    // and emits a module that parses as Rust
    let src = emit::kernel_module(&a);
    syn::parse_file(&src).expect("emitted module parses");
    assert!(src.contains("pub struct Poly6;"));
    // an even kernel needs no square root in W or W'/q
    let (w_at, pair_at) = (
        src.find("fn w(").unwrap(),
        src.find("fn w_dw_over_q_lanes(").unwrap(),
    );
    let impl_end = pair_at + src[pair_at..].find("\n}\n").unwrap();
    for f in [&src[w_at..pair_at], &src[pair_at..impl_end]] {
        assert!(!f.contains("sqrt"), "{f}");
    }
    let json = shearsph_codegen::show::json(&a);
    assert_eq!(json["kernel"], "poly6");
    assert!(json["eps"]["t_max"].is_string());
    assert!(json["c0"]["no_c0"]["field-av"]
        .as_str()
        .is_some_and(|f| f.starts_with("no c0: the lattice never compacts")));
    assert!(json["discretisations"][1]["c0"]["models"]["field-av"]["S"].is_string());
}

fn err(src: &str) -> KernelError {
    parse_kernel(Path::new("kernels/bad.toml"), src).expect_err("must be rejected")
}

const GOOD_HEAD: &str = "name = \"bad\"\nreference = \"test\"\n";

#[test]
fn bad_syntax_points_at_line_and_column() {
    let e = err(&format!(
        "{GOOD_HEAD}support = 2\n[[w]]\nto = 2\nexpr = \"(2 - q)^3 * \"\n"
    ));
    assert_eq!(e.field, "w[0].expr");
    assert!(e.message.contains("ends too early"), "{e}");
    assert_eq!(e.at.unwrap().0, 6, "line of the formula: {e}");
    let shown = e.to_string();
    assert!(shown.starts_with("kernels/bad.toml:6:"), "{shown}");
    assert!(shown.contains("fix:"), "{shown}");
}

#[test]
fn toml_syntax_error_names_the_file_and_line() {
    let e = err("name = \"bad\"\nsupport = = 2\n");
    assert!(e.to_string().starts_with("kernels/bad.toml:2:"), "{e}");
}

#[test]
fn not_normalised() {
    let e = err(&format!(
        "{GOOD_HEAD}support = 1\n[[w]]\nto = 1\nexpr = \"(1 - q^2)^2\"\n"
    ));
    assert_eq!(e.field, "w");
    assert!(e.message.contains("not normalised"), "{e}");
    assert!(
        e.message.contains("pi/3"),
        "the integral is given exactly: {e}"
    );
    assert!(e.fix.contains("scale"), "{e}");
}

#[test]
fn discontinuous() {
    let e = err(&format!(
        "{GOOD_HEAD}support = 2\nscale = \"15/(7*pi)\"\n[[w]]\nto = 1\nexpr = \"2/3 - q^2 + q^3/2\"\n[[w]]\nto = 2\nexpr = \"(2 - q)^3 / 5\"\n"
    ));
    assert_eq!(e.field, "w[1].expr");
    assert!(e.message.contains("discontinuous at q = 1"), "{e}");
}

#[test]
fn not_zero_at_the_support() {
    let e = err(&format!(
        "{GOOD_HEAD}support = 1\n[[w]]\nto = 1\nexpr = \"1/pi\"\n"
    ));
    assert!(e.message.contains("W(R) = 1/pi, not 0"), "{e}");
}

#[test]
fn negative_support() {
    let e = err(&format!(
        "{GOOD_HEAD}support = -2\n[[w]]\nto = 1\nexpr = \"q\"\n"
    ));
    assert_eq!(e.field, "support");
    assert!(e.message.contains("must be positive"), "{e}");
    let e = err(&format!(
        "{GOOD_HEAD}support = 0\n[[w]]\nto = 1\nexpr = \"q\"\n"
    ));
    assert!(e.message.contains("must be positive"), "{e}");
}

#[test]
fn unknown_symbol() {
    let e = err(&format!(
        "{GOOD_HEAD}support = 1\n[[w]]\nto = 1\nexpr = \"(1 - r)^2\"\n"
    ));
    assert_eq!(e.field, "w[0].expr");
    assert!(e.message.contains("unknown symbol `r`"), "{e}");
    // column of `r` inside the file: `expr = "(1 - ` is 13 characters
    assert_eq!(e.at.unwrap(), (6, 14), "{e}");
    assert!(e.fix.contains("q (= r/h)"), "{e}");
}

#[test]
fn floating_point_support_is_refused() {
    let e = err(&format!(
        "{GOOD_HEAD}support = 1.5\n[[w]]\nto = 1\nexpr = \"q\"\n"
    ));
    assert_eq!(e.field, "support");
    assert!(e.message.contains("floating-point"), "{e}");
    assert!(
        e.fix.contains("\"3/2\""),
        "the fix names the exact form: {e}"
    );
}

#[test]
fn pieces_out_of_order_are_refused() {
    let e = err(&format!(
        "{GOOD_HEAD}support = 2\n[[w]]\nto = 2\nexpr = \"q\"\n[[w]]\nto = 1\nexpr = \"q\"\n"
    ));
    assert_eq!(e.field, "w[1].to");
    assert!(e.message.contains("out of order"), "{e}");
}

#[test]
fn overlapping_pieces_are_refused() {
    // Two pieces ending at the same q: the second covers no interval.
    let e = err(&format!(
        "{GOOD_HEAD}support = 2\n[[w]]\nto = 1\nexpr = \"q\"\n[[w]]\nto = 1\nexpr = \"q\"\n[[w]]\nto = 2\nexpr = \"q\"\n"
    ));
    assert_eq!(e.field, "w[1].to");
    assert!(e.message.contains("out of order"), "{e}");
}

#[test]
fn last_piece_short_of_the_support_is_refused() {
    let e = err(&format!(
        "{GOOD_HEAD}support = 2\n[[w]]\nto = 1\nexpr = \"q\"\n"
    ));
    assert!(e.message.contains("but the support is 2"), "{e}");
}

#[test]
fn division_by_zero_is_refused() {
    let e = err(&format!(
        "{GOOD_HEAD}support = 1\n[[w]]\nto = 1\nexpr = \"1/(1 - 1)\"\n"
    ));
    assert_eq!(e.field, "w[0].expr");
    assert!(e.message.contains("division by zero"), "{e}");
}

#[test]
fn division_by_q_is_refused() {
    let e = err(&format!(
        "{GOOD_HEAD}support = 1\n[[w]]\nto = 1\nexpr = \"1/q\"\n"
    ));
    assert_eq!(e.field, "w[0].expr");
    assert!(e.message.contains("division by an expression in q"), "{e}");
}

#[test]
fn unknown_key_is_refused() {
    let e = err(&format!(
        "{GOOD_HEAD}support = 1\ncolour = 3\n[[w]]\nto = 1\nexpr = \"q\"\n"
    ));
    assert!(e.message.contains("unknown field `colour`"), "{e}");
    assert_eq!(e.field, "colour");
}

#[test]
fn support_too_large_for_the_lattice_enumeration_is_refused() {
    let e = err(&format!(
        "{GOOD_HEAD}support = 40\n[[w]]\nto = 40\nexpr = \"q\"\n"
    ));
    assert_eq!(e.field, "support");
    assert!(e.message.contains("too large"), "{e}");
}

#[test]
fn name_that_is_not_an_identifier_is_refused() {
    let e =
        err("name = \"Bad Name\"\nreference = \"x\"\nsupport = 1\n[[w]]\nto = 1\nexpr = \"q\"\n");
    assert_eq!(e.field, "name");
}

#[test]
fn duplicate_names_across_files() {
    let dir = tempfile::tempdir().unwrap();
    let shipped = Path::new(env!("CARGO_MANIFEST_DIR")).join("../kernels/monaghan.toml");
    std::fs::copy(&shipped, dir.path().join("a.toml")).unwrap();
    std::fs::copy(&shipped, dir.path().join("b.toml")).unwrap();
    let e = load_dir(dir.path()).unwrap_err();
    assert!(
        e.message.contains("duplicate kernel name `monaghan`"),
        "{e}"
    );
}
