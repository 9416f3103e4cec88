//! Polynomials in q with exact coefficients, and the small formula language a
//! kernel definition is written in:
//!
//! ```text
//! expr  := term (('+' | '-') term)*
//! term  := unary (('*' | '/') unary)*
//! unary := ('-' | '+') unary | power
//! power := atom ('^' INTEGER)?
//! atom  := NUMBER | 'q' | 'pi' | 'sqrt' '(' expr ')' | '(' expr ')'
//! ```
//!
//! Numbers are exact: `0.5` is 1/2. `^` binds tighter than unary minus
//! (`-q^2` is `-(q^2)`). Division is by constants that are monomials
//! (`/(7*pi)`, `/6`); `sqrt` takes a non-negative rational constant.
//!
//! Here the polynomials; [`parse`] the formula language.

mod parse;

pub use parse::{parse_decimal, parse_poly, parse_rational, ParseError, MAX_DEGREE, MAX_NESTING};

use crate::exact::Exact;
use rug::Rational;
use std::fmt;

/// `sum_k coef[k] q^k`, no trailing zeros.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Poly {
    pub coef: Vec<Exact>,
}

impl Poly {
    pub fn constant(c: Exact) -> Self {
        Poly { coef: vec![c] }.trimmed()
    }

    pub fn q() -> Self {
        Poly {
            coef: vec![Exact::zero(), Exact::one()],
        }
    }

    fn trimmed(mut self) -> Self {
        while self.coef.last().is_some_and(|c| c.is_zero()) {
            self.coef.pop();
        }
        self
    }

    pub fn is_zero(&self) -> bool {
        self.coef.is_empty()
    }

    pub fn degree(&self) -> usize {
        self.coef.len().saturating_sub(1)
    }

    pub fn as_constant(&self) -> Option<Exact> {
        match self.coef.len() {
            0 => Some(Exact::zero()),
            1 => Some(self.coef[0].clone()),
            _ => None,
        }
    }

    pub fn add(&self, o: &Poly) -> Poly {
        let n = self.coef.len().max(o.coef.len());
        let z = Exact::zero();
        Poly {
            coef: (0..n)
                .map(|k| self.coef.get(k).unwrap_or(&z) + o.coef.get(k).unwrap_or(&z))
                .collect(),
        }
        .trimmed()
    }

    pub fn neg(&self) -> Poly {
        Poly {
            coef: self.coef.iter().map(|c| -c).collect(),
        }
    }

    pub fn sub(&self, o: &Poly) -> Poly {
        self.add(&o.neg())
    }

    pub fn mul(&self, o: &Poly) -> Poly {
        if self.is_zero() || o.is_zero() {
            return Poly::default();
        }
        let mut coef = vec![Exact::zero(); self.coef.len() + o.coef.len() - 1];
        for (i, a) in self.coef.iter().enumerate() {
            for (j, b) in o.coef.iter().enumerate() {
                coef[i + j] = &coef[i + j] + &(a * b);
            }
        }
        Poly { coef }.trimmed()
    }

    pub fn scale(&self, c: &Exact) -> Poly {
        Poly {
            coef: self.coef.iter().map(|a| a * c).collect(),
        }
        .trimmed()
    }

    pub fn pow(&self, n: u32) -> Poly {
        let mut out = Poly::constant(Exact::one());
        for _ in 0..n {
            out = out.mul(self);
        }
        out
    }

    /// d/dq.
    pub fn derivative(&self) -> Poly {
        Poly {
            coef: self
                .coef
                .iter()
                .enumerate()
                .skip(1)
                .map(|(k, c)| c * &Exact::int(k as i64))
                .collect(),
        }
        .trimmed()
    }

    /// Value at a rational q.
    pub fn eval_rational(&self, q: &Rational) -> Exact {
        let mut acc = Exact::zero();
        for c in self.coef.iter().rev() {
            acc = &(&acc * &Exact::rational(q.clone())) + c;
        }
        acc
    }

    /// Value at q = sqrt(q2), q2 a non-negative rational: even powers are
    /// rational, odd ones carry sqrt(q2).
    pub fn eval_sqrt(&self, q2: &Rational) -> Exact {
        let root = Exact::sqrt_rational(q2);
        let mut even = Exact::zero();
        let mut odd = Exact::zero();
        let mut pow = Exact::one(); // q2^(k/2)
        for (k, c) in self.coef.iter().enumerate() {
            if k > 0 && k % 2 == 0 {
                pow = &pow * &Exact::rational(q2.clone());
            }
            if k % 2 == 0 {
                even = &even + &(c * &pow);
            } else {
                odd = &odd + &(c * &pow);
            }
        }
        &even + &(&odd * &root)
    }

    /// `int_a^b p(q) q^m dq`, exactly (a, b rational).
    pub fn integral_times_power(&self, m: u32, a: &Rational, b: &Rational) -> Exact {
        let mut acc = Exact::zero();
        for (k, c) in self.coef.iter().enumerate() {
            let e = k as u32 + m + 1;
            let diff = b.clone().pow_int(e) - a.clone().pow_int(e);
            acc = &acc + &(c * &Exact::rational(diff / Rational::from(e)));
        }
        acc
    }

    pub fn is_odd(&self) -> bool {
        self.coef.iter().step_by(2).all(|c| c.is_zero())
    }

    pub fn is_even(&self) -> bool {
        self.coef.iter().skip(1).step_by(2).all(|c| c.is_zero())
    }
}

trait PowInt {
    fn pow_int(self, e: u32) -> Rational;
}
impl PowInt for Rational {
    fn pow_int(self, e: u32) -> Rational {
        let mut out = Rational::from(1);
        for _ in 0..e {
            out *= &self;
        }
        out
    }
}

impl fmt::Display for Poly {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.is_zero() {
            return write!(f, "0");
        }
        let mut first = true;
        for (k, c) in self.coef.iter().enumerate() {
            if c.is_zero() {
                continue;
            }
            if !first {
                write!(f, " + ")?;
            }
            first = false;
            match k {
                0 => write!(f, "({c})")?,
                1 => write!(f, "({c})*q")?,
                _ => write!(f, "({c})*q^{k}")?,
            }
        }
        Ok(())
    }
}
