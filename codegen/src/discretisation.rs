//! `kernels/discretisations.toml`: the set of discretisations (lattice kind,
//! h/d) every kernel is derived for. User-extendable; the paper's
//! (triangular, h = d) is always derived, listed or not.
//!
//! ```toml
//! [[discretisation]]
//! lattice = "square"      # a kind of shearsph-lattice: "triangular" or "square"
//! h_over_d = "13/10"      # a positive rational up to 4: an integer or a string "13/10", "1.3";
//!                         # denominator at most 1000 (kernel::MAX_DENOMINATOR)
//! note = "SPHinXsys"      # optional, for the reader
//! ```

use crate::kernel::{denominator_problem, line_col, KernelError, MAX_DENOMINATOR};
use crate::lattice::{Discretisation, Lattice};
use crate::poly::parse_rational;
use rug::Rational;
use serde::Deserialize;
use std::path::Path;
use toml::Spanned;

/// The file's name inside the kernels folder.
pub const FILE: &str = "discretisations.toml";

/// The largest h/d accepted: the stencils grow with (R h/d)^2 and the
/// searches with (R h/d)^3.
pub const MAX_H_OVER_D: i64 = 4;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct DiscFile {
    discretisation: Vec<Entry>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Entry {
    lattice: Spanned<String>,
    h_over_d: Spanned<toml::Value>,
    #[allow(dead_code)]
    note: Option<String>,
}

/// Every lattice kind by name, with the paper's marked and its geometry:
/// `"triangular" (the paper's: dy = ...) or "square" (dy = d)`.
fn kinds_with_geometry() -> String {
    Lattice::listed(" or ", |l| {
        let papers = if l.is_papers() { "the paper's: " } else { "" };
        format!("{:?} ({papers}{})", l.name(), l.kind().geometry)
    })
}

/// Reads and validates the file's text; the paper's discretisation comes
/// first, then the file's in order, duplicates removed.
pub fn parse(file: &Path, src: &str) -> Result<Vec<Discretisation>, KernelError> {
    let err = |field: String, span: Option<std::ops::Range<usize>>, message: String, fix: &str| {
        KernelError {
            file: file.to_path_buf(),
            field,
            at: span.map(|s| line_col(src, s.start)),
            message,
            fix: fix.to_string(),
        }
    };
    let raw: DiscFile = toml::from_str(src).map_err(|e| {
        err(
            "discretisation".into(),
            e.span(),
            e.message().trim().to_string(),
            &format!(
                "write [[discretisation]] tables with `lattice` ({}) and `h_over_d` (e.g. \"13/10\"), and an optional `note`",
                Lattice::listed(" or ", |l| format!("{:?}", l.name()))
            ),
        )
    })?;
    let mut out = vec![Discretisation::paper()];
    for (i, e) in raw.discretisation.iter().enumerate() {
        let lattice = Lattice::parse(e.lattice.get_ref()).ok_or_else(|| {
            err(
                format!("discretisation[{i}].lattice"),
                Some(e.lattice.span()),
                format!("unknown lattice `{}`", e.lattice.get_ref()),
                &format!("write {}", kinds_with_geometry()),
            )
        })?;
        let field = format!("discretisation[{i}].h_over_d");
        let fix = "write h/d as an exact positive number: an integer (1) or a string (\"13/10\", \"1.3\"), at most 4, with a denominator of at most 1000";
        let h = match e.h_over_d.get_ref() {
            toml::Value::Integer(n) => Some(Rational::from(*n)),
            toml::Value::String(s) => parse_rational(s),
            _ => None,
        }
        .ok_or_else(|| {
            err(
                field.clone(),
                Some(e.h_over_d.span()),
                format!("`{}` is not an exact number", e.h_over_d.get_ref()),
                fix,
            )
        })?;
        if h <= 0 || h > MAX_H_OVER_D {
            return Err(err(
                field,
                Some(e.h_over_d.span()),
                format!("h/d = {h} is out of range (0, {MAX_H_OVER_D}]"),
                fix,
            ));
        }
        if let Some(message) = denominator_problem(&h, "h/d") {
            return Err(err(
                field,
                Some(e.h_over_d.span()),
                message,
                &format!("write h/d with a denominator of at most {MAX_DENOMINATOR}: three decimals at most (\"1.697\") or a fraction such as \"1697/1000\""),
            ));
        }
        let d = Discretisation { lattice, h };
        if !out.contains(&d) {
            out.push(d);
        }
    }
    Ok(out)
}

/// The discretisations of a kernels folder: its `discretisations.toml`, or
/// the paper's alone when the folder has none.
pub fn load(dir: &Path) -> Result<Vec<Discretisation>, KernelError> {
    let path = dir.join(FILE);
    if !path.exists() {
        return Ok(vec![Discretisation::paper()]);
    }
    let src = std::fs::read_to_string(&path).map_err(|e| KernelError {
        file: path.clone(),
        field: "(file)".into(),
        at: None,
        message: format!("cannot read: {e}"),
        fix: "check the file's permissions".into(),
    })?;
    parse(&path, &src)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(src: &str) -> Result<Vec<Discretisation>, KernelError> {
        parse(Path::new("kernels/discretisations.toml"), src)
    }

    #[test]
    fn paper_first_duplicates_removed() {
        let d = p("[[discretisation]]\nlattice = \"square\"\nh_over_d = \"13/10\"\n[[discretisation]]\nlattice = \"triangular\"\nh_over_d = 1\n[[discretisation]]\nlattice = \"square\"\nh_over_d = \"1.3\"\n").unwrap();
        assert_eq!(d.len(), 2);
        assert!(d[0].is_paper());
        assert_eq!(d[1].h, Rational::from((13, 10)));
    }

    #[test]
    fn bad_input_names_file_field_and_fix() {
        let e = p("[[discretisation]]\nlattice = \"hexagonal\"\nh_over_d = 1\n").unwrap_err();
        assert_eq!(e.field, "discretisation[0].lattice");
        assert_eq!(e.at, Some((2, 11)));
        assert!(e.fix.contains("square"));
        for bad in ["0", "\"-1\"", "\"x\"", "1.5", "5"] {
            let e = p(&format!(
                "[[discretisation]]\nlattice = \"square\"\nh_over_d = {bad}\n"
            ))
            .unwrap_err();
            assert_eq!(e.field, "discretisation[0].h_over_d", "{bad}");
            assert!(e.to_string().contains("discretisations.toml"));
        }
        let e = p("[[discretisation]]\nlattice = \"square\"\nh = 1\n").unwrap_err();
        assert!(e.message.contains("unknown field"), "{}", e.message);
    }
}
