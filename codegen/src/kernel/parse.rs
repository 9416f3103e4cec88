//! Reading a kernel file: TOML with spans, every field guarded with an error
//! naming the file, field and fix; a folder of them.

use super::names::name_problem;
use super::{
    denominator_problem, normalisation, KernelDef, KernelError, PaperValues, Piece, Radial,
    MAX_DENOMINATOR, MAX_SUPPORT,
};
use crate::exact::Exact;
use crate::poly::{parse_poly, parse_rational, Poly};
use rug::Rational;
use serde::Deserialize;
use std::path::{Path, PathBuf};
use toml::Spanned;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct KernelFile {
    name: Spanned<String>,
    title: Option<String>,
    reference: Spanned<String>,
    support: Spanned<toml::Value>,
    scale: Option<Spanned<String>>,
    w: Spanned<Vec<PieceFile>>,
    dw_scale: Option<Spanned<String>>,
    dw: Option<Spanned<Vec<PieceFile>>>,
    paper: Option<PaperValues>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct PieceFile {
    to: Spanned<toml::Value>,
    expr: Spanned<String>,
}

/// The 1-based line and column (in characters) of a byte offset: where an
/// error in a TOML file of `kernels/` points.
pub(crate) fn line_col(src: &str, byte: usize) -> (usize, usize) {
    let before = &src[..byte.min(src.len())];
    let line = before.matches('\n').count() + 1;
    let col = before
        .rsplit('\n')
        .next()
        .map(|s| s.chars().count())
        .unwrap_or(0)
        + 1;
    (line, col)
}

/// A formula as quoted in a message: whole when short, else its start.
fn shorten(s: &str) -> String {
    const SHOWN: usize = 60;
    if s.chars().count() <= SHOWN {
        s.to_string()
    } else {
        let head: String = s.chars().take(SHOWN).collect();
        format!("{head}... ({} characters)", s.chars().count())
    }
}

struct Ctx<'a> {
    file: &'a Path,
    src: &'a str,
}

impl Ctx<'_> {
    fn err(
        &self,
        field: &str,
        span: Option<std::ops::Range<usize>>,
        message: String,
        fix: &str,
    ) -> KernelError {
        KernelError {
            file: self.file.to_path_buf(),
            field: field.to_string(),
            at: span.map(|s| line_col(self.src, s.start)),
            message,
            fix: fix.to_string(),
        }
    }

    /// A formula inside a TOML string: the error column points into the file.
    fn formula(&self, field: &str, s: &Spanned<String>) -> Result<Poly, KernelError> {
        parse_poly(s.get_ref()).map_err(|e| {
            // span covers the quotes; the formula starts one byte in.
            let at = line_col(self.src, s.span().start + 1);
            KernelError {
                file: self.file.to_path_buf(),
                field: field.to_string(),
                at: Some((at.0, at.1 + e.column - 1)),
                message: format!("{} (in `{}`)", e.message, shorten(s.get_ref())),
                fix: e.fix,
            }
        })
    }

    fn rational(&self, field: &str, v: &Spanned<toml::Value>) -> Result<Rational, KernelError> {
        let bad = |msg: String| {
            self.err(
                field,
                Some(v.span()),
                msg,
                "write an exact number: an integer (2) or a string (\"3/2\", \"1.5\")",
            )
        };
        let q = match v.get_ref() {
            toml::Value::Integer(i) => Rational::from(*i),
            toml::Value::String(s) => {
                parse_rational(s).ok_or_else(|| bad(format!("`{s}` is not an exact number")))?
            }
            toml::Value::Float(x) => {
                return Err(bad(format!(
                    "{x} is a floating-point number; supports and piece ends must be exact"
                )))
            }
            other => {
                return Err(bad(format!(
                    "expected a number, found {}",
                    other.type_str()
                )))
            }
        };
        // the same bound as h/d's in discretisations.toml: these are lengths
        // of the lattice geometry too
        match denominator_problem(&q, field) {
            Some(message) => Err(self.err(
                field,
                Some(v.span()),
                message,
                &format!(
                    "write it with a denominator of at most {MAX_DENOMINATOR} (e.g. \"3/2\", \"1.25\"; three decimals at most)"
                ),
            )),
            None => Ok(q),
        }
    }

    fn pieces(
        &self,
        field: &str,
        list: &Spanned<Vec<PieceFile>>,
        scale: &Option<Spanned<String>>,
        scale_field: &str,
        support: &Rational,
    ) -> Result<Radial, KernelError> {
        let factor = match scale {
            Some(s) => self.formula(scale_field, s)?,
            None => Poly::constant(Exact::one()),
        };
        if list.get_ref().is_empty() {
            return Err(self.err(
                field,
                Some(list.span()),
                "no pieces".into(),
                "give at least one [[w]] table with `to` and `expr`",
            ));
        }
        let mut pieces = Vec::new();
        let mut from = Rational::new();
        for (i, p) in list.get_ref().iter().enumerate() {
            let to = self.rational(&format!("{field}[{i}].to"), &p.to)?;
            if to <= from {
                return Err(self.err(
                    &format!("{field}[{i}].to"),
                    Some(p.to.span()),
                    format!("piece ends at {to}, not after the previous end {from}: pieces out of order or overlapping"),
                    "list the pieces in increasing order of q, each `to` larger than the one before",
                ));
            }
            let poly = self
                .formula(&format!("{field}[{i}].expr"), &p.expr)?
                .mul(&factor);
            pieces.push(Piece {
                from: from.clone(),
                to: to.clone(),
                poly,
            });
            from = to;
        }
        if &from != support {
            let last = list.get_ref().last().unwrap();
            return Err(self.err(
                &format!("{field}[{}].to", list.get_ref().len() - 1),
                Some(last.to.span()),
                format!("the last piece ends at {from}, but the support is {support}"),
                "end the last piece at the support R (W is zero beyond it)",
            ));
        }
        Ok(Radial { pieces })
    }
}

/// Reads and validates one definition. Everything that makes a kernel
/// unusable is an error; everything else is a [`Fact`] (see [`super::shape_facts`]).
pub fn parse_kernel(file: &Path, src: &str) -> Result<KernelDef, KernelError> {
    let ctx = Ctx { file, src };
    let raw: KernelFile = toml::from_str(src).map_err(|e| {
        let span = e.span();
        KernelError {
            file: file.to_path_buf(),
            field: field_from_toml_error(e.message()),
            at: span.map(|s| line_col(src, s.start)),
            message: e.message().trim().to_string(),
            fix: "see README.md, \"Kernel definitions\", for the format".into(),
        }
    })?;
    let name = raw.name.get_ref().clone();
    if let Some((message, fix)) = name_problem(&name) {
        return Err(ctx.err("name", Some(raw.name.span()), message, &fix));
    }
    let support = ctx.rational("support", &raw.support)?;
    if support <= 0 {
        return Err(ctx.err(
            "support",
            Some(raw.support.span()),
            format!("the support must be positive, found {support}"),
            "give the support radius R in units of h, e.g. 2",
        ));
    }
    if support > MAX_SUPPORT {
        return Err(ctx.err(
            "support",
            Some(raw.support.span()),
            format!("a support of {support} h is too large: the lattice enumeration and time searches would be unreasonable (limit {MAX_SUPPORT})"),
            "rescale the kernel so that R <= 12 (e.g. express it in a larger h)",
        ));
    }
    let w = ctx.pieces("w", &raw.w, &raw.scale, "scale", &support)?;
    let (dw, dw_given) = match &raw.dw {
        Some(list) => (
            ctx.pieces("dw", list, &raw.dw_scale, "dw_scale", &support)?,
            true,
        ),
        None => {
            if let Some(s) = &raw.dw_scale {
                return Err(ctx.err(
                    "dw_scale",
                    Some(s.span()),
                    "`dw_scale` without `dw` pieces".into(),
                    "remove dw_scale, or give the gradient as [[dw]] pieces",
                ));
            }
            (w.derivative(), false)
        }
    };
    let def = KernelDef {
        name,
        title: raw.title.unwrap_or_else(|| raw.name.get_ref().clone()),
        reference: raw.reference.get_ref().clone(),
        file: file.to_path_buf(),
        support,
        w,
        dw,
        dw_given,
        paper: raw.paper,
    };
    // Unusable: discontinuous W, W(R) != 0, not normalised.
    for (i, pair) in def.w.pieces.windows(2).enumerate() {
        let left = pair[0].poly.eval_rational(&pair[0].to);
        let right = pair[1].poly.eval_rational(&pair[0].to);
        if left != right {
            return Err(ctx.err(
                &format!("w[{}].expr", i + 1),
                Some(raw.w.get_ref()[i + 1].expr.span()),
                format!(
                    "W is discontinuous at q = {}: {} from the left, {} from the right",
                    pair[0].to, left, right
                ),
                "make neighbouring pieces agree at their joint",
            ));
        }
    }
    let last = def.w.pieces.last().unwrap();
    let at_r = last.poly.eval_rational(&def.support);
    if !at_r.is_zero() {
        return Err(ctx.err(
            &format!("w[{}].expr", def.w.pieces.len() - 1),
            Some(raw.w.get_ref().last().unwrap().expr.span()),
            format!("W(R) = {at_r}, not 0: the kernel would jump to zero at the support"),
            "make the last piece vanish at q = R",
        ));
    }
    let norm = normalisation(&def.w);
    if norm != Exact::one() {
        return Err(ctx.err(
            "w",
            Some(raw.w.span()),
            format!(
                "not normalised: the integral of W over the plane is {} = {:.12}, not 1",
                norm,
                norm.to_f64()
            ),
            "multiply W by the inverse of that integral (the `scale` field is the place for it)",
        ));
    }
    Ok(def)
}

fn field_from_toml_error(msg: &str) -> String {
    // toml's messages name unknown/missing fields in backquotes.
    for key in ["unknown field `", "missing field `"] {
        if let Some(i) = msg.find(key) {
            let rest = &msg[i + key.len()..];
            if let Some(j) = rest.find('`') {
                return rest[..j].to_string();
            }
        }
    }
    "(file)".into()
}

/// Reads every `*.toml` in a folder, sorted by file name; a duplicate
/// kernel name is an error naming both files.
pub fn load_dir(dir: &Path) -> Result<Vec<KernelDef>, KernelError> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .map_err(|e| KernelError {
            file: dir.to_path_buf(),
            field: "(folder)".into(),
            at: None,
            message: format!("cannot read the kernels folder: {e}"),
            fix: "run from the repository root, or pass --kernels DIR".into(),
        })?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        // the discretisations file sits beside the kernels; it is not one
        .filter(|p| {
            p.file_name()
                .is_none_or(|n| n != crate::discretisation::FILE)
        })
        .collect();
    files.sort();
    let mut out: Vec<KernelDef> = Vec::new();
    for f in files {
        let src = read_kernel_file(&f)?;
        let def = parse_kernel(&f, &src)?;
        if let Some(other) = out.iter().find(|k| k.name == def.name) {
            return Err(KernelError {
                file: f.clone(),
                field: "name".into(),
                at: None,
                message: format!(
                    "duplicate kernel name `{}`, also in {}",
                    def.name,
                    other.file.display()
                ),
                fix: "give every kernel its own name".into(),
            });
        }
        // the type name is derived (`my_k2` -> `MyK2`): two names may meet in one
        let ty = crate::emit::type_name(&def.name);
        if let Some(other) = out.iter().find(|k| crate::emit::type_name(&k.name) == ty) {
            return Err(KernelError {
                file: f.clone(),
                field: "name".into(),
                at: None,
                message: format!(
                    "kernel name `{}` gives the Rust type name `{ty}`, as does `{}` in {}",
                    def.name,
                    other.name,
                    other.file.display()
                ),
                fix: "choose names that differ by more than underscores before digits or doubled underscores".into(),
            });
        }
        out.push(def);
    }
    Ok(out)
}

/// Reads a kernel file, with an error of its own for each way that fails:
/// missing, a folder, no permission, not UTF-8 (with the byte offset and
/// line), anything else with the system's words.
pub fn read_kernel_file(f: &Path) -> Result<String, KernelError> {
    let fail = |message: String, fix: &str| KernelError {
        file: f.to_path_buf(),
        field: "(file)".into(),
        at: None,
        message,
        fix: fix.into(),
    };
    if f.is_dir() {
        return Err(fail(
            "is a folder, not a kernel definition".into(),
            "rename the folder so that it does not end in .toml, or move it out of the kernels folder",
        ));
    }
    let bytes = std::fs::read(f).map_err(|e| match e.kind() {
        std::io::ErrorKind::NotFound => fail(
            "does not exist (or is a broken symbolic link)".into(),
            "check the path; a symbolic link must point to an existing file",
        ),
        std::io::ErrorKind::PermissionDenied => fail(
            format!("cannot be read: permission denied ({e})"),
            "make the file readable (chmod u+r FILE)",
        ),
        _ => fail(
            format!("cannot be read: {e}"),
            "check the file and the disk it is on",
        ),
    })?;
    String::from_utf8(bytes).map_err(|e| {
        let at = e.utf8_error().valid_up_to();
        let valid = std::str::from_utf8(&e.as_bytes()[..at]).unwrap_or("");
        let (line, col) = line_col(valid, valid.len());
        KernelError {
            file: f.to_path_buf(),
            field: "(file)".into(),
            at: Some((line, col)),
            message: format!(
                "is not UTF-8 text: invalid byte 0x{:02x} at byte offset {at}",
                e.as_bytes()[at]
            ),
            fix: "save the file as UTF-8 (TOML files must be UTF-8)".into(),
        }
    })
}
