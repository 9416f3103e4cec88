//! Kernel definitions (`kernels/*.toml`): reading, and exact validation.
//!
//! A definition gives W as pieces of polynomials in q = r/h on consecutive
//! intervals (0, to_1], (to_1, to_2], ..., the last ending at the support R;
//! W = 0 beyond R. The support is closed: a neighbour at exactly q = R counts
//! (this matters only for a gradient that does not vanish at R, like the
//! composite kernel's (22b)). An optional separate gradient `dw` has the same
//! shape; without it the gradient is dW/dq.

use crate::exact::Exact;
use crate::poly::{parse_poly, parse_rational, Poly};
use rug::Rational;
use serde::Deserialize;
use std::fmt;
use std::path::{Path, PathBuf};
use toml::Spanned;

/// The largest support accepted: the lattice enumeration and the time
/// searches grow with R^2 and R^3; beyond this they stop being reasonable.
pub const MAX_SUPPORT: i64 = 12;

/// A definition that cannot be used, with where and how to fix it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct KernelError {
    pub file: PathBuf,
    pub field: String,
    /// 1-based line and column in the file, when known.
    pub at: Option<(usize, usize)>,
    pub message: String,
    pub fix: String,
}

impl fmt::Display for KernelError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.file.display())?;
        if let Some((l, c)) = self.at {
            write!(f, ":{l}:{c}")?;
        }
        write!(
            f,
            ": field `{}`: {}\n  fix: {}",
            self.field, self.message, self.fix
        )
    }
}

impl std::error::Error for KernelError {}

/// One polynomial piece on (from, to].
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Piece {
    pub from: Rational,
    pub to: Rational,
    pub poly: Poly,
}

/// A piecewise polynomial radial function on [0, R], zero beyond.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Radial {
    pub pieces: Vec<Piece>,
}

impl Radial {
    pub fn support(&self) -> &Rational {
        &self.pieces.last().expect("at least one piece").to
    }

    /// The piece that holds q, given q^2 (closed on the right; the first
    /// piece also holds q = 0); `None` beyond the support.
    pub fn piece_for_q2(&self, q2: &Rational) -> Option<&Piece> {
        self.pieces
            .iter()
            .find(|p| *q2 <= Rational::from(&p.to * &p.to))
    }

    /// The exact value at q = sqrt(q2).
    pub fn eval_q2(&self, q2: &Rational) -> Exact {
        match self.piece_for_q2(q2) {
            Some(p) => p.poly.eval_sqrt(q2),
            None => Exact::zero(),
        }
    }

    pub fn derivative(&self) -> Radial {
        Radial {
            pieces: self
                .pieces
                .iter()
                .map(|p| Piece {
                    from: p.from.clone(),
                    to: p.to.clone(),
                    poly: p.poly.derivative(),
                })
                .collect(),
        }
    }

    /// Whether every piece is even in q (then no square root is needed).
    pub fn is_even(&self) -> bool {
        self.pieces.iter().all(|p| p.poly.is_even())
    }
}

/// The paper's printed values for a kernel, kept as printed (strings), so a
/// comparison knows the printed precision.
#[derive(Clone, Debug, Deserialize, PartialEq, Eq)]
#[serde(deny_unknown_fields)]
pub struct PaperValues {
    /// Equation number(s) of the definition in the paper.
    pub equation: String,
    pub table1: PrintedTable1,
    pub table2: Option<PrintedTable2>,
}

#[derive(Clone, Debug, Deserialize, PartialEq, Eq)]
#[serde(deny_unknown_fields)]
pub struct PrintedTable1 {
    pub t0: String,
    pub half_period: String,
    pub mean: String,
}

/// c0 = factor U (sqrt(P alpha^2 + Q A) - S alpha) / N^2 as printed.
#[derive(Clone, Debug, Deserialize, PartialEq, Eq)]
#[serde(deny_unknown_fields)]
pub struct PrintedTable2 {
    pub eps0: String,
    pub factor: String,
    #[serde(rename = "S")]
    pub s: String,
    #[serde(rename = "P")]
    pub p: String,
    #[serde(rename = "Q")]
    pub q: String,
}

/// A validated kernel definition.
#[derive(Clone, Debug)]
pub struct KernelDef {
    pub name: String,
    pub title: String,
    pub reference: String,
    pub file: PathBuf,
    pub support: Rational,
    pub w: Radial,
    /// The gradient dW/dq used by the SPH approximations: given, or derived.
    pub dw: Radial,
    pub dw_given: bool,
    pub paper: Option<PaperValues>,
}

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

fn line_col(src: &str, byte: usize) -> (usize, usize) {
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
                message: format!("{} (in `{}`)", e.message, s.get_ref()),
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
        match v.get_ref() {
            toml::Value::Integer(i) => Ok(Rational::from(*i)),
            toml::Value::String(s) => {
                parse_rational(s).ok_or_else(|| bad(format!("`{s}` is not an exact number")))
            }
            toml::Value::Float(x) => Err(bad(format!(
                "{x} is a floating-point number; supports and piece ends must be exact"
            ))),
            other => Err(bad(format!(
                "expected a number, found {}",
                other.type_str()
            ))),
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
/// unusable is an error; everything else is a [`Fact`] (see [`facts`]).
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
    let valid_name = name.chars().next().is_some_and(|c| c.is_ascii_lowercase())
        && name
            .chars()
            .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_');
    if !valid_name {
        return Err(ctx.err(
            "name",
            Some(raw.name.span()),
            format!("`{name}` is not a valid kernel name"),
            "use lowercase letters, digits and _, starting with a letter (it names a Rust module)",
        ));
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

/// The 2D integral of W over the plane, 2 pi int_0^R W(q) q dq, exactly.
pub fn normalisation(w: &Radial) -> Exact {
    let mut acc = Exact::zero();
    for p in &w.pieces {
        acc = &acc + &p.poly.integral_times_power(1, &p.from, &p.to);
    }
    &acc * &Exact::monomial(Rational::from(2), 1, 1)
}

/// The continuum first moment of the gradient, pi int_0^R W'(q) q^2 dq,
/// which is -1 for the derivative of a normalised W that vanishes at R.
pub fn gradient_moment(dw: &Radial) -> Exact {
    let mut acc = Exact::zero();
    for p in &dw.pieces {
        acc = &acc + &p.poly.integral_times_power(2, &p.from, &p.to);
    }
    &acc * &Exact::pi_pow(1)
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
        let src = std::fs::read_to_string(&f).map_err(|e| KernelError {
            file: f.clone(),
            field: "(file)".into(),
            at: None,
            message: format!("cannot read: {e}"),
            fix: "check the file's permissions".into(),
        })?;
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
        out.push(def);
    }
    Ok(out)
}
