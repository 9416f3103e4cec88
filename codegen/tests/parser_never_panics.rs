//! Property tests: the formula parser and the kernel reader never panic on
//! arbitrary input; they return a value or an error with a position.

use proptest::prelude::*;
use shearsph_codegen::kernel::parse_kernel;
use shearsph_codegen::poly::parse_poly;
use std::path::Path;

proptest! {
    #![proptest_config(ProptestConfig { cases: 2000, ..ProptestConfig::default() })]

    #[test]
    fn formula_parser_total(src in "[ q0-9pi.+*/^()sqrt-]{0,40}") {
        match parse_poly(&src) {
            Ok(_) => {}
            Err(e) => prop_assert!(e.column >= 1 && e.column <= src.chars().count() + 1),
        }
    }

    #[test]
    fn formula_parser_total_on_any_text(src in "\\PC{0,30}") {
        let _ = parse_poly(&src);
    }

    #[test]
    fn kernel_reader_total(
        support in "[-0-9./\"]{0,6}",
        to in "[-0-9./\"]{0,6}",
        expr in "[ q0-9pi.+*/^()-]{0,30}",
    ) {
        let src = format!("name = \"k\"\nreference = \"r\"\nsupport = {support}\n[[w]]\nto = {to}\nexpr = \"{expr}\"\n");
        match parse_kernel(Path::new("k.toml"), &src) {
            Ok(def) => prop_assert!(def.support > 0),
            Err(e) => prop_assert!(!e.message.is_empty() && !e.fix.is_empty()),
        }
    }

    #[test]
    fn kernel_reader_total_on_any_text(src in "\\PC{0,120}") {
        let _ = parse_kernel(Path::new("k.toml"), &src);
    }
}

#[test]
fn pathological_formulas_are_refused_quickly() {
    let e = parse_poly("((q^64)^64)^64").unwrap_err();
    assert!(e.message.contains("degree above 64"), "{e}");
    let e = parse_poly("sqrt(1000000000000000000000000000001)").unwrap_err();
    assert!(e.message.contains("below 2^40"), "{e}");
}
