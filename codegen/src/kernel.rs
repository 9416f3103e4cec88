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

/// Every Rust keyword, strict, reserved and edition-dependent (2015 to 2024):
/// a kernel's name becomes a module and, capitalised, a type, so none of
/// these can be one (`self`, `super`, `crate` and `Self` cannot even be raw
/// identifiers, so `r#name` is no way out).
pub const RUST_KEYWORDS: &[&str] = &[
    // strict
    "as",
    "break",
    "const",
    "continue",
    "crate",
    "else",
    "enum",
    "extern",
    "false",
    "fn",
    "for",
    "if",
    "impl",
    "in",
    "let",
    "loop",
    "match",
    "mod",
    "move",
    "mut",
    "pub",
    "ref",
    "return",
    "self",
    "static",
    "struct",
    "super",
    "trait",
    "true",
    "type",
    "unsafe",
    "use",
    "where",
    "while",
    "async",
    "await",
    "dyn",
    // reserved
    "abstract",
    "become",
    "box",
    "do",
    "final",
    "macro",
    "override",
    "priv",
    "typeof",
    "unsized",
    "virtual",
    "yield",
    "try",
    "gen",
    // weak, kept out so that the module name never reads as syntax
    "union",
    "raw",
    "safe",
    "macro_rules",
];

/// Names the generated tree or the crates that include it already use for
/// a module or file: a kernel with one of these names would shadow or
/// include it (a kernel `registry` makes `registry.rs` include itself).
/// Names of further output files are checked against the rendered tree by
/// [`check_emitted_names`].
pub const RESERVED_NAMES: &[&str] = &["registry", "kernel", "kernels", "mod", "lib", "main"];

/// Why a kernel name cannot be used, or `None` when it can.
pub fn name_problem(name: &str) -> Option<(String, String)> {
    let valid_name = name.chars().next().is_some_and(|c| c.is_ascii_lowercase())
        && name
            .chars()
            .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_');
    if !valid_name {
        return Some((
            format!("`{name}` is not a valid kernel name"),
            "use lowercase letters, digits and _, starting with a letter (it names a Rust module)"
                .into(),
        ));
    }
    if RUST_KEYWORDS.contains(&name) {
        return Some((
            format!("`{name}` is a Rust keyword, and a kernel's name becomes a Rust module"),
            format!("choose another name, e.g. `{name}_kernel`"),
        ));
    }
    if RESERVED_NAMES.contains(&name) {
        return Some((
            format!(
                "`{name}` is the name of a module or file of the generated tree or of the crate that includes it ({})",
                RESERVED_NAMES.join(", ")
            ),
            format!("choose another name, e.g. `{name}_kernel`"),
        ));
    }
    None
}

/// The identifiers in Rust source (doc strings and literals excluded).
pub fn identifiers(src: &str) -> std::collections::BTreeSet<String> {
    fn walk(ts: proc_macro2::TokenStream, out: &mut std::collections::BTreeSet<String>) {
        for t in ts {
            match t {
                proc_macro2::TokenTree::Ident(i) => {
                    out.insert(i.to_string());
                }
                proc_macro2::TokenTree::Group(g) => walk(g.stream(), out),
                _ => {}
            }
        }
    }
    let mut out = std::collections::BTreeSet::new();
    if let Ok(ts) = src.parse::<proc_macro2::TokenStream>() {
        walk(ts, &mut out);
    }
    out
}

/// The stand-in name of kernel `i` in the neutral rendering that
/// [`check_emitted_names`] compares with.
pub fn neutral_name(i: usize) -> String {
    format!("{NEUTRAL_PREFIX}{i}")
}

const NEUTRAL_PREFIX: &str = "zz_neutral_kernel_";

/// Checks that no kernel's module name, type name or file collides with
/// anything else the generator writes. `files` is the rendered tree;
/// `neutral` is the same tree rendered with kernel `i` renamed to
/// [`neutral_name`]`(i)`: every identifier and file stem in it belongs to the
/// generator itself (imports, prelude names, functions, generic
/// parameters, further output files), so a kernel named like one of them
/// would shadow it. This holds for whatever files and items a future
/// generator adds, without a list to keep in step.
pub fn check_emitted_names(
    defs: &[KernelDef],
    files: &[(PathBuf, String)],
    neutral: &[(PathBuf, String)],
) -> Result<(), KernelError> {
    let name_err = |d: &KernelDef, message: String| KernelError {
        file: d.file.clone(),
        field: "name".into(),
        at: None,
        message,
        fix: format!(
            "choose another name, e.g. `{}_kernel`, and rename the file to match",
            d.name
        ),
    };
    let mut seen: std::collections::BTreeMap<&Path, usize> = Default::default();
    for (p, _) in files {
        *seen.entry(p.as_path()).or_default() += 1;
    }
    if let Some((p, _)) = seen.iter().find(|(_, n)| **n > 1) {
        let owner = defs
            .iter()
            .find(|d| {
                p.file_stem()
                    .and_then(|s| s.to_str())
                    .is_some_and(|s| s == d.name)
            })
            .unwrap_or(&defs[0]);
        return Err(name_err(
            owner,
            format!(
                "the generator would write {} twice: two kernels' outputs share a file name",
                p.display()
            ),
        ));
    }
    // a kernel's own files are included inside its module, so its module name
    // can only collide in the shared files (the registry); its type name
    // enters every file of its own
    let mut idents = std::collections::BTreeSet::new();
    let mut shared_idents = std::collections::BTreeSet::new();
    let mut stems = std::collections::BTreeSet::new();
    for (p, src) in neutral {
        let stem = p.file_stem().and_then(|s| s.to_str()).unwrap_or("");
        let ids = identifiers(src);
        if !stem.starts_with(NEUTRAL_PREFIX) {
            shared_idents.extend(ids.iter().cloned());
        }
        idents.extend(ids);
        stems.insert(stem.to_string());
    }
    for d in defs {
        if stems.contains(&d.name) {
            return Err(name_err(
                d,
                format!(
                    "`{}` is the name of a file the generator writes ({}.rs): the kernel's module would collide with it",
                    d.name, d.name
                ),
            ));
        }
        let ty = crate::emit::type_name(&d.name);
        for (what, id, used) in [("module", &d.name, &shared_idents), ("type", &ty, &idents)] {
            if used.contains(id) {
                return Err(name_err(
                    d,
                    format!(
                        "the kernel's {what} name `{id}` is already used by the generated code (an import, a prelude name, a function or a parameter), which it would shadow"
                    ),
                ));
            }
        }
    }
    Ok(())
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

/// A polynomial with rational coefficients, lowest power first, and whether
/// it is the piece's polynomial up to a positive constant exactly (all
/// coefficients share one basis element pi^e sqrt(s) > 0) or only to the
/// stated binary precision.
fn rational_shape(p: &Poly) -> (Vec<Rational>, bool) {
    let bases: Vec<_> = p
        .coef
        .iter()
        .filter(|c| !c.is_zero())
        .map(|c| c.as_monomial().map(|(b, _)| b))
        .collect();
    let common = bases.first().copied().flatten();
    if common.is_some() && bases.iter().all(|b| *b == common) {
        let coef = p
            .coef
            .iter()
            .map(|c| c.as_monomial().map(|(_, q)| q.clone()).unwrap_or_default())
            .collect();
        (coef, true)
    } else {
        let coef = p
            .coef
            .iter()
            .map(|c| c.to_float(SIGN_PREC).to_rational().unwrap_or_default())
            .collect();
        (coef, false)
    }
}

/// Bits of the coefficients when a piece mixes basis elements.
const SIGN_PREC: u32 = 256;
/// Width to which sign changes of W are located: 2^-50 (shown to 1e-12).
const ROOT_WIDTH_BITS: u32 = 50;

fn trim(mut p: Vec<Rational>) -> Vec<Rational> {
    while p.last().is_some_and(|c| *c == 0) {
        p.pop();
    }
    p
}

fn eval_rat(p: &[Rational], x: &Rational) -> Rational {
    let mut acc = Rational::new();
    for c in p.iter().rev() {
        acc *= x;
        acc += c;
    }
    acc
}

fn rem(a: &[Rational], b: &[Rational]) -> Vec<Rational> {
    let mut r = a.to_vec();
    let lb = b.last().expect("nonzero divisor");
    while r.len() >= b.len() && !r.is_empty() {
        let shift = r.len() - b.len();
        let f = Rational::from(r.last().unwrap() / lb);
        for (i, c) in b.iter().enumerate() {
            r[shift + i] -= Rational::from(&f * c);
        }
        r.pop();
        r = trim(r);
    }
    r
}

/// p / (q - x) for a root x (synthetic division).
fn deflate(p: &[Rational], x: &Rational) -> Vec<Rational> {
    let n = p.len() - 1;
    let mut out = vec![Rational::new(); n];
    let mut carry = Rational::new();
    for k in (0..n).rev() {
        carry = Rational::from(&carry * x) + &p[k + 1];
        out[k] = carry.clone();
    }
    out
}

fn sturm(p: &[Rational]) -> Vec<Vec<Rational>> {
    let d: Vec<Rational> = trim(
        p.iter()
            .enumerate()
            .skip(1)
            .map(|(k, c)| Rational::from(c * k as u32))
            .collect(),
    );
    let mut seq = vec![p.to_vec()];
    if d.is_empty() {
        return seq;
    }
    seq.push(d);
    loop {
        let n = seq.len();
        let r: Vec<Rational> = rem(&seq[n - 2], &seq[n - 1])
            .into_iter()
            .map(|c| -c)
            .collect();
        if r.is_empty() {
            return seq;
        }
        seq.push(r);
    }
}

fn variations(seq: &[Vec<Rational>], x: &Rational) -> usize {
    let signs: Vec<std::cmp::Ordering> = seq
        .iter()
        .map(|p| eval_rat(p, x).cmp0())
        .filter(|s| *s != std::cmp::Ordering::Equal)
        .collect();
    signs.windows(2).filter(|w| w[0] != w[1]).count()
}

/// A real root of a piece: exact, or inside (lo, hi) of width < 2^-50.
#[derive(Clone, Debug)]
struct Root {
    lo: Rational,
    hi: Rational,
}

impl Root {
    fn show(&self) -> String {
        if self.lo == self.hi {
            self.lo.to_string()
        } else {
            let mid = Rational::from(&self.lo + &self.hi) / 2u32;
            format!("{:.12}", mid.to_f64())
        }
    }
}

/// The distinct real roots of p in the open interval (a, b), isolated by
/// Sturm sequences and bisection, exact where they are rational and hit.
fn roots_between(p: &[Rational], a: &Rational, b: &Rational) -> Vec<Root> {
    let mut p = trim(p.to_vec());
    let mut exact: Vec<Rational> = Vec::new();
    // roots at the ends are not inside; divide them out
    for end in [a, b] {
        while p.len() > 1 && eval_rat(&p, end) == 0 {
            p = deflate(&p, end);
        }
    }
    let width = Rational::from((1, rug::Integer::from(1) << ROOT_WIDTH_BITS));
    'restart: loop {
        if p.len() <= 1 {
            break;
        }
        let seq = sturm(&p);
        let mut found = Vec::new();
        let mut stack = vec![(a.clone(), b.clone())];
        while let Some((lo, hi)) = stack.pop() {
            let n = variations(&seq, &lo) - variations(&seq, &hi);
            if n == 0 {
                continue;
            }
            if n == 1 && Rational::from(&hi - &lo) < width {
                found.push(Root { lo, hi });
                continue;
            }
            let mid = Rational::from(&lo + &hi) / 2u32;
            if eval_rat(&p, &mid) == 0 {
                p = deflate(&p, &mid);
                while p.len() > 1 && eval_rat(&p, &mid) == 0 {
                    p = deflate(&p, &mid);
                }
                exact.push(mid);
                continue 'restart;
            }
            stack.push((mid.clone(), hi));
            stack.push((lo, mid));
        }
        let mut all: Vec<Root> = found;
        all.extend(exact.iter().map(|x| Root {
            lo: x.clone(),
            hi: x.clone(),
        }));
        all.sort_by(|x, y| x.lo.cmp(&y.lo).then(x.hi.cmp(&y.hi)));
        return all;
    }
    let mut all: Vec<Root> = exact
        .into_iter()
        .map(|x| Root {
            lo: x.clone(),
            hi: x,
        })
        .collect();
    all.sort_by(|x, y| x.lo.cmp(&y.lo));
    all
}

/// The stretches of (from, to) where a piece is negative, as (left, right)
/// descriptions; exact ends are rationals, located ones decimals to 1e-12.
fn negative_stretches(piece: &Piece) -> (Vec<(String, String)>, bool) {
    // roots at the piece's ends (W(R) = 0 always) are divided out exactly
    // first, so that rounded coefficients cannot move one inside
    let mut poly = piece.poly.clone();
    for end in [&piece.from, &piece.to] {
        while poly.degree() > 0 && poly.eval_rational(end).is_zero() {
            poly = deflate_exact(&poly, end);
        }
    }
    if poly.is_zero() {
        return (Vec::new(), true);
    }
    let (p, exact) = rational_shape(&poly);
    let roots = roots_between(&trim(p), &piece.from, &piece.to);
    // the sign between two roots, from W itself (exact where W's value is
    // rational up to a positive factor, else to 256 bits)
    let negative_at = |x: &Rational| piece.poly.eval_rational(x).to_float(SIGN_PREC) < 0;
    let mut out = Vec::new();
    let mut left = (piece.from.clone(), piece.from.to_string());
    let ends: Vec<(Rational, Rational, String)> = roots
        .iter()
        .map(|r| (r.lo.clone(), r.hi.clone(), r.show()))
        .chain(std::iter::once((
            piece.to.clone(),
            piece.to.clone(),
            piece.to.to_string(),
        )))
        .collect();
    for (lo, hi, shown) in ends {
        let sample = Rational::from(&left.0 + &lo) / 2u32;
        if negative_at(&sample) {
            out.push((left.1.clone(), shown.clone()));
        }
        left = (hi, shown);
    }
    (out, exact)
}

/// p / (q - x) for a root x of p, exactly.
fn deflate_exact(p: &Poly, x: &Rational) -> Poly {
    let n = p.coef.len() - 1;
    let mut out = vec![Exact::zero(); n];
    let mut carry = Exact::zero();
    let xe = Exact::rational(x.clone());
    for k in (0..n).rev() {
        carry = &(&carry * &xe) + &p.coef[k + 1];
        out[k] = carry.clone();
    }
    Poly { coef: out }
}

/// Facts about the shape of W that make a kernel questionable but not
/// unusable, found exactly: where W < 0 on [0, R] (Sturm sequences on each
/// piece, sign changes located to 1e-12), and whether W'(0) = 0.
pub fn shape_facts(def: &KernelDef) -> Vec<crate::analysis::Fact> {
    let mut stretches: Vec<(String, String)> = Vec::new();
    let mut all_exact = true;
    for piece in &def.w.pieces {
        let (s, exact) = negative_stretches(piece);
        all_exact &= exact;
        for (l, r) in s {
            // W is continuous: a stretch that reaches a joint goes on in the next piece
            match stretches.last_mut() {
                Some(last) if last.1 == l && l == piece.from.to_string() => last.1 = r,
                _ => stretches.push((l, r)),
            }
        }
    }
    let how = if all_exact {
        "Sturm sequences on each piece, exact; sign changes located to 1e-12"
    } else {
        "Sturm sequences on each piece, coefficients to 256 bits; sign changes located to 1e-12"
    };
    let negative = crate::analysis::Fact {
        name: "W >= 0 on [0, R]".into(),
        holds: stretches.is_empty(),
        detail: if stretches.is_empty() {
            format!("W is nowhere negative ({how})")
        } else {
            let list: Vec<String> = stretches
                .iter()
                .map(|(l, r)| format!("({l}, {r})"))
                .collect();
            format!(
                "W < 0 for q in {} ({how}); a negative weight lowers the density a neighbour there adds",
                list.join(" and ")
            )
        },
    };
    let first = &def.dw.pieces[0];
    let dw0 = first.poly.eval_rational(&Rational::new());
    let origin = crate::analysis::Fact {
        name: "gradient vanishes at the origin".into(),
        holds: dw0.is_zero(),
        detail: if dw0.is_zero() {
            "W'(0) = 0 (exact)".into()
        } else {
            format!("W'(0) = {dw0} (exact), not 0: W has a cusp at q = 0 and the force between close particles does not vanish as they meet")
        },
    };
    vec![negative, origin]
}
