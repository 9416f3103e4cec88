//! Kernel definitions (`kernels/*.toml`): reading, and exact validation.
//!
//! A definition gives W as pieces of polynomials in q = r/h on consecutive
//! intervals (0, to_1], (to_1, to_2], ..., the last ending at the support R;
//! W = 0 beyond R. The support is closed: a neighbour at exactly q = R counts
//! (this matters only for a gradient that does not vanish at R, like the
//! composite kernel's (22b)). An optional separate gradient `dw` has the same
//! shape; without it the gradient is dW/dq.
//!
//! Here the definition's types and its integrals; [`parse`] reads a file and
//! guards every field, [`names`] guards the name against Rust and against
//! what the generator emits, [`shape`] finds the facts of W's shape.

mod names;
mod parse;
mod shape;

pub use names::{
    check_emitted_names, identifiers, name_problem, neutral_name, RESERVED_NAMES, RUST_KEYWORDS,
};
pub(crate) use parse::line_col;
pub use parse::{load_dir, parse_kernel, read_kernel_file};
pub use shape::shape_facts;

use crate::exact::Exact;
use crate::poly::Poly;
use rug::Rational;
use serde::Deserialize;
use std::fmt;
use std::path::PathBuf;

/// The largest support accepted: the lattice enumeration and the time
/// searches grow with R^2 and R^3; beyond this they stop being reasonable.
pub const MAX_SUPPORT: i64 = 12;

/// The largest denominator of an exact length of the lattice geometry: h/d
/// (`discretisations.toml`), the support and every piece's end (`support`,
/// `w[i].to`, `dw[i].to`). The derivation takes exact square roots of the
/// lattice distances in h and of a piece's end squared minus a row's
/// height, reduced to a square-free radicand by factoring; those radicands
/// grow as the fourth power of the denominators (up to about 1e16 here), so
/// a larger one would make `generate` run without end. Three decimals
/// ("1.697") fit.
pub const MAX_DENOMINATOR: u32 = 1000;

/// Why an exact length is refused for its denominator, if it is.
pub fn denominator_problem(q: &Rational, what: &str) -> Option<String> {
    (*q.denom() > MAX_DENOMINATOR).then(|| {
        format!(
            "{what} = {q} has the denominator {}, above {MAX_DENOMINATOR}: the exact derivation \
             factors square roots whose radicands grow as the fourth power of the denominators \
             of h/d, the support and the piece ends, and would not finish",
            q.denom()
        )
    })
}

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
