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

/// A formula nested `depth` times with a mix of the parser's recursive paths
/// (parentheses, sqrt, sign chains, powers).
fn nested(kinds: &[u8], depth: usize) -> String {
    let mut open = String::new();
    let mut close = String::new();
    for i in 0..depth {
        match kinds[i % kinds.len()] % 4 {
            0 => {
                open.push('(');
                close.insert(0, ')');
            }
            1 => {
                open.push_str("sqrt(");
                close.insert(0, ')');
            }
            2 => open.push('-'),
            _ => {
                open.push('(');
                close.insert_str(0, ")^1");
            }
        }
    }
    format!("{open}4{close}")
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    /// Deep inputs never overflow the stack: up to 20,000 levels of any mix
    /// of the recursive paths give a value or the nesting error.
    #[test]
    fn deep_formulas_never_overflow(
        kinds in proptest::collection::vec(0u8..4, 1..6),
        depth in 0usize..20_000,
    ) {
        let src = nested(&kinds, depth);
        match parse_poly(&src) {
            Ok(_) => prop_assert!(depth <= shearsph_codegen::poly::MAX_NESTING),
            Err(e) => prop_assert!(
                e.message.contains("nested more than") || e.message.contains("sqrt of"),
                "{}", e.message
            ),
        }
    }
}

#[test]
fn deep_toml_never_overflows() {
    for depth in [100, 1_000, 10_000] {
        let arrays = format!("x = {}{}\n", "[".repeat(depth), "]".repeat(depth));
        let tables = format!("x = {}{}\n", "{ a = ".repeat(depth), "1 }".repeat(depth));
        for src in [arrays, tables] {
            let src = format!("name = \"k\"\nreference = \"r\"\nsupport = 2\n{src}");
            let e = parse_kernel(Path::new("k.toml"), &src).unwrap_err();
            assert!(!e.message.is_empty(), "depth {depth}");
        }
    }
    for depth in [1_000, 10_000] {
        let expr = format!("{}q{}", "(".repeat(depth), ")".repeat(depth));
        let e = parse_poly(&expr).unwrap_err();
        assert!(e.message.contains("nested more than 100 levels"), "{e}");
        let e = parse_poly(&"-".repeat(depth)).unwrap_err();
        assert!(e.message.contains("nested more than 100 levels"), "{e}");
    }
}
