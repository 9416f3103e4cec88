//! The formula language of kernel definitions (grammar in [`super`]): a
//! lexer, exact decimals and rationals, and a recursive-descent parser with
//! errors at 1-based columns.

use super::Poly;
use crate::exact::Exact;
use rug::Rational;
use std::fmt;

/// A formula that could not be read: 1-based column within the formula.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ParseError {
    pub column: usize,
    pub message: String,
    pub fix: String,
}

impl fmt::Display for ParseError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "column {}: {}", self.column, self.message)
    }
}

#[derive(Debug, Clone, PartialEq)]
enum Tok {
    Num(Rational),
    Ident(String),
    Op(char),
}

fn lex(src: &str) -> Result<Vec<(usize, Tok)>, ParseError> {
    let chars: Vec<char> = src.chars().collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        let col = i + 1;
        if c.is_whitespace() {
            i += 1;
        } else if c.is_ascii_digit() || c == '.' {
            let start = i;
            while i < chars.len() && (chars[i].is_ascii_digit() || chars[i] == '.') {
                i += 1;
            }
            let text: String = chars[start..i].iter().collect();
            let q = parse_decimal(&text).ok_or_else(|| ParseError {
                column: col,
                message: format!("`{text}` is not a number"),
                fix: "write numbers as 12, 3.25 or 13/4".into(),
            })?;
            out.push((col, Tok::Num(q)));
        } else if c.is_alphabetic() || c == '_' {
            let start = i;
            while i < chars.len() && (chars[i].is_alphanumeric() || chars[i] == '_') {
                i += 1;
            }
            out.push((col, Tok::Ident(chars[start..i].iter().collect())));
        } else if "+-*/^()".contains(c) {
            out.push((col, Tok::Op(c)));
            i += 1;
        } else {
            return Err(ParseError {
                column: col,
                message: format!("unexpected character `{c}`"),
                fix: "use numbers, q, pi, sqrt(..), + - * / ^ and parentheses".into(),
            });
        }
    }
    Ok(out)
}

/// An exact rational from a decimal literal such as `12`, `0.125`, `2.`.
pub fn parse_decimal(text: &str) -> Option<Rational> {
    let (int, frac) = match text.split_once('.') {
        Some((a, b)) => (a, b),
        None => (text, ""),
    };
    if (int.is_empty() && frac.is_empty()) || frac.contains('.') {
        return None;
    }
    let digits = format!("{int}{frac}");
    let num: rug::Integer = digits.parse().ok()?;
    let den = rug::Integer::from(10).pow_ref_u(frac.len() as u32);
    Some(Rational::from((num, den)))
}

trait PowRefU {
    fn pow_ref_u(self, e: u32) -> rug::Integer;
}
impl PowRefU for rug::Integer {
    fn pow_ref_u(self, e: u32) -> rug::Integer {
        use rug::ops::Pow;
        self.pow(e)
    }
}

/// An exact rational from `3`, `-3/2`, `0.75`.
pub fn parse_rational(text: &str) -> Option<Rational> {
    let t = text.trim();
    let (neg, t) = match t.strip_prefix('-') {
        Some(rest) => (true, rest.trim()),
        None => (false, t),
    };
    let q = match t.split_once('/') {
        Some((a, b)) => {
            let a = parse_decimal(a.trim())?;
            let b = parse_decimal(b.trim())?;
            if b == 0 {
                return None;
            }
            a / b
        }
        None => parse_decimal(t)?,
    };
    Some(if neg { -q } else { q })
}

struct Parser {
    toks: Vec<(usize, Tok)>,
    pos: usize,
    end_col: usize,
    /// How deep the recursive descent is: every nesting (parentheses,
    /// `sqrt(..)`, a sign before a sign) goes one level down.
    depth: usize,
}

/// The deepest nesting a formula may have. The parser recurses once per
/// level; this keeps it far from the stack's end (a kernel piece needs a
/// handful of levels).
pub const MAX_NESTING: usize = 100;

/// The largest degree in q a formula may reach.
pub const MAX_DEGREE: usize = 64;

const GRAMMAR_FIX: &str =
    "write a polynomial in q with numbers, pi, sqrt(..), + - * / ^ and parentheses, e.g. 15/(7*pi) * (2 - q)^3 / 6";

impl Parser {
    fn peek(&self) -> Option<&Tok> {
        self.toks.get(self.pos).map(|(_, t)| t)
    }
    fn col(&self) -> usize {
        self.toks
            .get(self.pos)
            .map(|(c, _)| *c)
            .unwrap_or(self.end_col)
    }
    /// Goes one nesting level down, refusing past [`MAX_NESTING`].
    fn descend(&mut self) -> Result<(), ParseError> {
        self.depth += 1;
        if self.depth > MAX_NESTING {
            return Err(ParseError {
                column: self.col(),
                message: format!(
                    "nested more than {MAX_NESTING} levels deep (parentheses, sqrt(..) or signs)"
                ),
                fix: "write the formula with less nesting: multiply out, or drop repeated signs"
                    .into(),
            });
        }
        Ok(())
    }

    fn err(&self, message: String) -> ParseError {
        ParseError {
            column: self.col(),
            message,
            fix: GRAMMAR_FIX.into(),
        }
    }

    fn expr(&mut self) -> Result<Poly, ParseError> {
        let mut acc = self.term()?;
        while let Some(Tok::Op(c @ ('+' | '-'))) = self.peek().cloned() {
            self.pos += 1;
            let rhs = self.term()?;
            acc = if c == '+' {
                acc.add(&rhs)
            } else {
                acc.sub(&rhs)
            };
        }
        Ok(acc)
    }

    fn term(&mut self) -> Result<Poly, ParseError> {
        let mut acc = self.unary()?;
        while let Some(Tok::Op(c @ ('*' | '/'))) = self.peek().cloned() {
            let col = self.col();
            self.pos += 1;
            let rhs = self.unary()?;
            if c == '*' {
                acc = acc.mul(&rhs);
            } else {
                let den = rhs.as_constant().ok_or_else(|| ParseError {
                    column: col,
                    message: "division by an expression in q".into(),
                    fix: "divide only by constants; multiply the pieces out instead".into(),
                })?;
                if den.is_zero() {
                    return Err(ParseError {
                        column: col,
                        message: "division by zero".into(),
                        fix: "remove the division or correct the divisor".into(),
                    });
                }
                let mut out = Poly::default();
                for (k, a) in acc.coef.iter().enumerate() {
                    let v = a.div_monomial(&den).ok_or_else(|| ParseError {
                        column: col,
                        message: format!("division by `{den}`, which is not a single term"),
                        fix:
                            "divide only by a rational times a power of pi (and sqrt of a rational)"
                                .into(),
                    })?;
                    let mut mono = vec![Exact::zero(); k + 1];
                    mono[k] = v;
                    out = out.add(&Poly { coef: mono });
                }
                acc = out;
            }
        }
        Ok(acc)
    }

    fn unary(&mut self) -> Result<Poly, ParseError> {
        match self.peek() {
            Some(Tok::Op(c @ ('-' | '+'))) => {
                let neg = *c == '-';
                self.pos += 1;
                self.descend()?;
                let inner = self.unary()?;
                self.depth -= 1;
                Ok(if neg { inner.neg() } else { inner })
            }
            _ => self.power(),
        }
    }

    fn power(&mut self) -> Result<Poly, ParseError> {
        let base = self.atom()?;
        if let Some(Tok::Op('^')) = self.peek() {
            self.pos += 1;
            let col = self.col();
            match self.peek().cloned() {
                Some(Tok::Num(n)) if n.denom() == &1 && *n.numer() >= 0 && *n.numer() <= 64 => {
                    self.pos += 1;
                    let e = n.numer().to_u32().unwrap();
                    if base.degree() * e as usize > MAX_DEGREE {
                        return Err(ParseError {
                            column: col,
                            message: format!("a degree above {MAX_DEGREE} in q"),
                            fix: "kernel pieces are polynomials of modest degree; check the exponents".into(),
                        });
                    }
                    Ok(base.pow(e))
                }
                _ => Err(ParseError {
                    column: col,
                    message: "an exponent must be a whole number from 0 to 64".into(),
                    fix: "write powers as q^3 or (2 - q)^5".into(),
                }),
            }
        } else {
            Ok(base)
        }
    }

    fn atom(&mut self) -> Result<Poly, ParseError> {
        let col = self.col();
        match self.peek().cloned() {
            Some(Tok::Num(n)) => {
                self.pos += 1;
                Ok(Poly::constant(Exact::rational(n)))
            }
            Some(Tok::Ident(name)) => {
                self.pos += 1;
                match name.as_str() {
                    "q" => Ok(Poly::q()),
                    "pi" => Ok(Poly::constant(Exact::pi_pow(1))),
                    "sqrt" => {
                        self.expect('(')?;
                        self.descend()?;
                        let inner = self.expr()?;
                        self.depth -= 1;
                        self.expect(')')?;
                        let r = inner
                            .as_constant()
                            .and_then(|c| c.as_rational())
                            .filter(|r| *r >= 0)
                            // square-free reduction is by trial division: keep it quick
                            .filter(|r| {
                                r.numer().significant_bits() <= 40
                                    && r.denom().significant_bits() <= 40
                            })
                            .ok_or_else(|| ParseError {
                                column: col,
                                message: "sqrt of something other than a non-negative rational below 2^40"
                                    .into(),
                                fix: "use sqrt only on numbers, e.g. sqrt(3)".into(),
                            })?;
                        Ok(Poly::constant(Exact::sqrt_rational(&r)))
                    }
                    other => Err(ParseError {
                        column: col,
                        message: format!("unknown symbol `{other}`"),
                        fix: "the variable is q (= r/h); the only named constant is pi".into(),
                    }),
                }
            }
            Some(Tok::Op('(')) => {
                self.pos += 1;
                self.descend()?;
                let e = self.expr()?;
                self.depth -= 1;
                self.expect(')')?;
                Ok(e)
            }
            Some(Tok::Op(c)) => Err(self.err(format!("unexpected `{c}`"))),
            None => Err(self.err("the formula ends too early".into())),
        }
    }

    fn expect(&mut self, c: char) -> Result<(), ParseError> {
        match self.peek() {
            Some(Tok::Op(x)) if *x == c => {
                self.pos += 1;
                Ok(())
            }
            Some(t) => {
                let shown = match t {
                    Tok::Num(n) => n.to_string(),
                    Tok::Ident(s) => s.clone(),
                    Tok::Op(o) => o.to_string(),
                };
                Err(self.err(format!("expected `{c}`, found `{shown}`")))
            }
            None => Err(self.err(format!("expected `{c}` before the end"))),
        }
    }
}

/// Parses a formula into an exact polynomial in q.
pub fn parse_poly(src: &str) -> Result<Poly, ParseError> {
    let toks = lex(src)?;
    let mut p = Parser {
        toks,
        pos: 0,
        end_col: src.chars().count() + 1,
        depth: 0,
    };
    if p.toks.is_empty() {
        return Err(p.err("the formula is empty".into()));
    }
    let out = p.expr()?;
    if p.pos < p.toks.len() {
        return Err(p.err("unexpected text after the formula (a missing operator?)".into()));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn powers_bind_tighter_than_minus_and_division() {
        let p = parse_poly("-q^2 + q^3/2").unwrap();
        assert_eq!(p.to_string(), "(-1)*q^2 + (1/2)*q^3");
        let c = parse_poly("(2 - q)^3/6").unwrap();
        assert_eq!(
            c.eval_rational(&Rational::from(1)).as_rational(),
            Some(Rational::from((1, 6)))
        );
    }

    #[test]
    fn pi_and_decimals_are_exact() {
        let p = parse_poly("15/(7*pi) * 0.5").unwrap();
        assert_eq!(p.as_constant().unwrap().to_string(), "15/(14*pi)");
    }

    #[test]
    fn errors_point_at_columns() {
        let e = parse_poly("1 - x^2").unwrap_err();
        assert_eq!(e.column, 5);
        assert!(e.message.contains("unknown symbol `x`"));
        let e = parse_poly("1 / (1 - q)").unwrap_err();
        assert!(e.message.contains("division by an expression in q"));
        let e = parse_poly("(1 - q").unwrap_err();
        assert!(e.message.contains("expected `)`"));
        let e = parse_poly("1/0").unwrap_err();
        assert!(e.message.contains("division by zero"));
    }

    #[test]
    fn odd_powers_carry_the_root() {
        let p = parse_poly("q^3").unwrap();
        let v = p.eval_sqrt(&Rational::from((3, 4)));
        assert_eq!(v.to_string(), "3*sqrt(3)/8");
    }
}
