//! Exact numbers: finite rational combinations of `pi^e * sqrt(s)` with `e` an
//! integer and `s` a square-free positive integer. Every kernel value at a
//! lattice distance (where r^2 is rational) is one of these, and so is every
//! lattice sum of the c0 derivation. They form a ring; division is offered
//! only by monomials (a rational times `pi^e * sqrt(s)`), which is all the
//! derivation needs — quotients of general elements are kept as [`Ratio`].

use rug::{ops::Pow, Float, Integer, Rational};
use std::collections::BTreeMap;
use std::fmt;
use std::ops::{Add, Mul, Neg, Sub};

/// The basis element `pi^pi_pow * sqrt(root)`, `root` square-free (of any
/// size: a product of radicands never overflows).
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Basis {
    pub pi_pow: i32,
    pub root: Integer,
}

/// A rational combination of basis elements; zero coefficients never stored.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Exact {
    terms: BTreeMap<Basis, Rational>,
}

/// Splits a positive integer into `(outside, inside)` with
/// `n = outside^2 * inside` and `inside` square-free. Trial division runs
/// only while p^3 <= rest: what is left then has every prime factor above
/// its cube root, so it is 1, a prime, a product of two distinct primes
/// (square-free as it stands) or the square of a prime (a perfect square).
/// The cost is at most n^(1/3) divisions, and stops as soon as the rest is
/// a perfect square; the inputs' sizes are bounded where they are read
/// (`kernel::MAX_DENOMINATOR`).
fn square_free(n: &Integer) -> (Integer, Integer) {
    let mut rest = n.clone();
    let mut outside = Integer::from(1);
    let mut inside = Integer::from(1);
    let mut p = 2u32;
    let mut changed = true;
    loop {
        if changed && rest.is_perfect_square() {
            outside *= rest.sqrt();
            return (outside, inside);
        }
        changed = false;
        let cube = Integer::from(p).pow(3);
        if cube > rest {
            break;
        }
        let mut count = 0u32;
        while rest.is_divisible_u(p) {
            rest.div_exact_u_mut(p);
            count += 1;
        }
        if count > 0 {
            changed = true;
            outside *= Integer::from(p).pow(count / 2);
            if count % 2 == 1 {
                inside *= p;
            }
        }
        // the inputs are bounded far below (2^32)^3
        p = p
            .checked_add(if p == 2 { 1 } else { 2 })
            .expect("square-free reduction of a number below 2^96");
    }
    inside *= rest;
    (outside, inside)
}

impl Exact {
    pub fn zero() -> Self {
        Self::default()
    }

    pub fn one() -> Self {
        Self::rational(Rational::from(1))
    }

    pub fn rational(q: impl Into<Rational>) -> Self {
        Self::monomial(q.into(), 0, 1)
    }

    pub fn int(n: i64) -> Self {
        Self::rational(Rational::from(n))
    }

    /// `q * pi^pi_pow * sqrt(root)` (root need not be square-free).
    pub fn monomial(q: Rational, pi_pow: i32, root: impl Into<Integer>) -> Self {
        let mut out = Self::zero();
        if q == 0 {
            return out;
        }
        let root: Integer = root.into();
        assert!(root > 0, "sqrt of zero is not a basis element");
        let (o, root) = square_free(&root);
        let q = q * Rational::from(o);
        out.terms.insert(Basis { pi_pow, root }, q);
        out
    }

    /// `q * pi^pi_pow * sqrt(root)` for a `root` known square-free.
    fn monomial_square_free(q: Rational, pi_pow: i32, root: Integer) -> Self {
        let mut out = Self::zero();
        if q != 0 {
            out.terms.insert(Basis { pi_pow, root }, q);
        }
        out
    }

    /// `pi^e`.
    pub fn pi_pow(e: i32) -> Self {
        Self::monomial(Rational::from(1), e, 1)
    }

    /// The exact square root of a non-negative rational, `sqrt(a/b) =
    /// sqrt(a b)/b`, reduced to a square-free radicand.
    pub fn sqrt_rational(x: &Rational) -> Self {
        assert!(*x >= 0, "sqrt of a negative rational");
        if *x == 0 {
            return Self::zero();
        }
        // sqrt(a/b) = sqrt(a b)/b, with a and b reduced apart (each is
        // smaller than a b): a = oa^2 ia, b = ob^2 ib, and ia ib = g^2 (ia ib/g^2)
        // with g = gcd(ia, ib), the last factor square-free
        let (num, den) = x.clone().into_numer_denom();
        let (oa, ia) = square_free(&num);
        let (ob, ib) = square_free(&den);
        let g = Integer::from(ia.gcd_ref(&ib));
        let root = Integer::from(&ia * &ib) / Integer::from(&g * &g);
        let coef = Rational::from((oa * ob * g, den));
        Self::monomial_square_free(coef, 0, root)
    }

    pub fn is_zero(&self) -> bool {
        self.terms.is_empty()
    }

    /// The value as a rational, when it is one.
    pub fn as_rational(&self) -> Option<Rational> {
        match self.terms.len() {
            0 => Some(Rational::new()),
            1 => {
                let (b, q) = self.terms.iter().next().unwrap();
                (b.pi_pow == 0 && b.root == 1).then(|| q.clone())
            }
            _ => None,
        }
    }

    /// The single term, when this is a monomial.
    pub fn as_monomial(&self) -> Option<(&Basis, &Rational)> {
        if self.terms.len() == 1 {
            let (b, q) = self.terms.iter().next().unwrap();
            Some((b, q))
        } else {
            None
        }
    }

    pub fn terms(&self) -> impl Iterator<Item = (&Basis, &Rational)> {
        self.terms.iter()
    }

    fn add_term(&mut self, b: Basis, q: Rational) {
        if q == 0 {
            return;
        }
        let entry = self.terms.entry(b.clone()).or_default();
        *entry += q;
        if *entry == 0 {
            self.terms.remove(&b);
        }
    }

    /// Divides by a monomial; `None` when `den` is zero or not a monomial.
    pub fn div_monomial(&self, den: &Exact) -> Option<Exact> {
        let (b, q) = den.as_monomial()?;
        // 1/(q pi^e sqrt(s)) = sqrt(s) / (q s) * pi^-e
        let inv = Exact::monomial_square_free(
            Rational::from(1) / (q.clone() * Rational::from(&b.root)),
            -b.pi_pow,
            b.root.clone(),
        );
        Some(self * &inv)
    }

    pub fn pow(&self, n: u32) -> Exact {
        let mut out = Exact::one();
        for _ in 0..n {
            out = &out * self;
        }
        out
    }

    /// The value rounded to `prec` bits (pi and square roots at that
    /// precision; the result is good to a few ulps of `prec`).
    pub fn to_float(&self, prec: u32) -> Float {
        let work = prec + 32;
        let pi = Float::with_val(work, rug::float::Constant::Pi);
        let mut sum = Float::with_val(work, 0);
        for (b, q) in &self.terms {
            let mut t = Float::with_val(work, q);
            if b.root != 1 {
                t *= Float::with_val(work, &b.root).sqrt();
            }
            if b.pi_pow != 0 {
                t *= Float::with_val(work, pi.clone().pow(b.pi_pow));
            }
            sum += t;
        }
        Float::with_val(prec, sum)
    }

    /// Correctly rounded f64 (via a 200-bit evaluation).
    pub fn to_f64(&self) -> f64 {
        self.to_float(200).to_f64()
    }
}

impl From<i64> for Exact {
    fn from(n: i64) -> Self {
        Exact::int(n)
    }
}

impl From<Rational> for Exact {
    fn from(q: Rational) -> Self {
        Exact::rational(q)
    }
}

impl Add<&Exact> for &Exact {
    type Output = Exact;
    fn add(self, rhs: &Exact) -> Exact {
        let mut out = self.clone();
        for (b, q) in &rhs.terms {
            out.add_term(b.clone(), q.clone());
        }
        out
    }
}

impl Sub<&Exact> for &Exact {
    type Output = Exact;
    fn sub(self, rhs: &Exact) -> Exact {
        let mut out = self.clone();
        for (b, q) in &rhs.terms {
            out.add_term(b.clone(), -q.clone());
        }
        out
    }
}

impl Mul<&Exact> for &Exact {
    type Output = Exact;
    fn mul(self, rhs: &Exact) -> Exact {
        let mut out = Exact::zero();
        for (b1, q1) in &self.terms {
            for (b2, q2) in &rhs.terms {
                // sqrt(s1) sqrt(s2) = g sqrt(s1 s2 / g^2), g = gcd(s1, s2)
                let g = Integer::from(b1.root.gcd_ref(&b2.root));
                let inside = Integer::from(&b1.root * &b2.root) / (&g * &g).complete();
                let q = Rational::from(q1 * q2) * Rational::from(g);
                out.add_term(
                    Basis {
                        pi_pow: b1.pi_pow + b2.pi_pow,
                        root: inside,
                    },
                    q,
                );
            }
        }
        out
    }
}

impl Neg for &Exact {
    type Output = Exact;
    fn neg(self) -> Exact {
        let mut out = self.clone();
        for q in out.terms.values_mut() {
            *q = -q.clone();
        }
        out
    }
}

macro_rules! forward_owned {
    ($tr:ident, $m:ident) => {
        impl $tr<Exact> for Exact {
            type Output = Exact;
            fn $m(self, rhs: Exact) -> Exact {
                (&self).$m(&rhs)
            }
        }
        impl $tr<&Exact> for Exact {
            type Output = Exact;
            fn $m(self, rhs: &Exact) -> Exact {
                (&self).$m(rhs)
            }
        }
        impl $tr<Exact> for &Exact {
            type Output = Exact;
            fn $m(self, rhs: Exact) -> Exact {
                self.$m(&rhs)
            }
        }
    };
}
forward_owned!(Add, add);
forward_owned!(Sub, sub);
forward_owned!(Mul, mul);

impl Neg for Exact {
    type Output = Exact;
    fn neg(self) -> Exact {
        -&self
    }
}

use rug::Complete;

impl fmt::Display for Exact {
    /// A form a person (and a calculator) can read: `-3/4 + 15/(7*pi) +
    /// 5*sqrt(3)/(2*pi^2)`. Terms ordered by pi power, then radicand.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.terms.is_empty() {
            return write!(f, "0");
        }
        // Order: rational part first, then increasing powers of 1/pi.
        let mut keys: Vec<&Basis> = self.terms.keys().collect();
        keys.sort_by_key(|b| (-b.pi_pow, &b.root));
        for (i, b) in keys.iter().enumerate() {
            let q = &self.terms[b];
            let neg = *q < 0;
            if i == 0 {
                if neg {
                    write!(f, "-")?;
                }
            } else {
                write!(f, " {} ", if neg { "-" } else { "+" })?;
            }
            let q = Rational::from(q.abs_ref());
            let (num, den) = (q.numer().clone(), q.denom().clone());
            let mut top: Vec<String> = Vec::new();
            if num != 1 || (b.root == 1 && b.pi_pow <= 0) {
                top.push(num.to_string());
            }
            if b.root != 1 {
                top.push(format!("sqrt({})", b.root));
            }
            if b.pi_pow > 0 {
                top.push(if b.pi_pow == 1 {
                    "pi".to_string()
                } else {
                    format!("pi^{}", b.pi_pow)
                });
            }
            let mut bottom: Vec<String> = Vec::new();
            if den != 1 {
                bottom.push(den.to_string());
            }
            if b.pi_pow < 0 {
                bottom.push(if b.pi_pow == -1 {
                    "pi".to_string()
                } else {
                    format!("pi^{}", -b.pi_pow)
                });
            }
            write!(f, "{}", top.join("*"))?;
            match bottom.len() {
                0 => {}
                1 => write!(f, "/{}", bottom[0])?,
                _ => write!(f, "/({})", bottom.join("*"))?,
            }
        }
        Ok(())
    }
}

/// A quotient of two exact numbers, kept unevaluated (the ring has no general
/// inverse: pi is transcendental). Used for S = b/(2a) and Q = -c/a.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Ratio {
    pub num: Exact,
    pub den: Exact,
}

impl Ratio {
    /// `num/den`, simplified to a ring element when `den` is a monomial.
    pub fn new(num: Exact, den: Exact) -> Self {
        match num.div_monomial(&den) {
            Some(q) => Ratio {
                num: q,
                den: Exact::one(),
            },
            None => Ratio { num, den },
        }
    }

    pub fn to_float(&self, prec: u32) -> Float {
        let n = self.num.to_float(prec + 64);
        let d = self.den.to_float(prec + 64);
        Float::with_val(prec, n / d)
    }

    pub fn to_f64(&self) -> f64 {
        self.to_float(200).to_f64()
    }

    /// `self^2` as a ratio.
    pub fn square(&self) -> Ratio {
        Ratio::new(&self.num * &self.num, &self.den * &self.den)
    }
}

impl fmt::Display for Ratio {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.den == Exact::one() {
            write!(f, "{}", self.num)
        } else {
            write!(f, "({}) / ({})", self.num, self.den)
        }
    }
}

/// A decimal string of `digits` significant digits, positional (no
/// exponent), correctly rounded from `x`.
pub fn decimal(x: &Float, digits: usize) -> String {
    if x.is_zero() {
        return "0".to_string();
    }
    if !x.is_finite() {
        return x.to_string();
    }
    let s = x.to_string_radix(10, Some(digits.max(1)));
    // rug gives e.g. "-5.9568e-2" or "1.25" or "1.2e1"
    let (mant, exp) = match s.find('e') {
        Some(i) => (&s[..i], s[i + 1..].parse::<i64>().unwrap()),
        None => (s.as_str(), 0),
    };
    let neg = mant.starts_with('-');
    let mant = mant.trim_start_matches('-');
    let (int_part, frac_part) = match mant.find('.') {
        Some(i) => (&mant[..i], &mant[i + 1..]),
        None => (mant, ""),
    };
    let all: String = format!("{int_part}{frac_part}");
    let point = int_part.len() as i64 + exp; // digits before the point
    let mut out = String::new();
    if neg {
        out.push('-');
    }
    if point <= 0 {
        out.push_str("0.");
        out.push_str(&"0".repeat((-point) as usize));
        out.push_str(&all);
    } else if point as usize >= all.len() {
        out.push_str(&all);
        out.push_str(&"0".repeat(point as usize - all.len()));
    } else {
        out.push_str(&all[..point as usize]);
        out.push('.');
        out.push_str(&all[point as usize..]);
    }
    out
}

/// Bits of working precision for `digits` decimal digits, with guard bits.
pub fn bits_for_digits(digits: usize) -> u32 {
    ((digits as f64) * std::f64::consts::LOG2_10).ceil() as u32 + 64
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sqrt_reduces_to_square_free() {
        let x = Exact::sqrt_rational(&Rational::from((12, 1)));
        assert_eq!(x.to_string(), "2*sqrt(3)");
        let y = Exact::sqrt_rational(&Rational::from((3, 4)));
        assert_eq!(y.to_string(), "sqrt(3)/2");
        let z = &y * &y;
        assert_eq!(z.as_rational(), Some(Rational::from((3, 4))));
    }

    /// The cube-root bound loses nothing: every n up to 20000 against a
    /// direct reduction, and large primes, their squares and products.
    #[test]
    fn square_free_parts_are_exact() {
        let direct = |n: u64| {
            let (mut outside, mut inside, mut rest, mut p) = (1u64, 1u64, n, 2u64);
            while p * p <= rest {
                while rest % (p * p) == 0 {
                    rest /= p * p;
                    outside *= p;
                }
                if rest % p == 0 {
                    rest /= p;
                    inside *= p;
                }
                p += 1;
            }
            (outside, inside * rest)
        };
        for n in 1..20000u64 {
            let (o, i) = square_free(&Integer::from(n));
            assert_eq!((o.to_u64().unwrap(), i.to_u64().unwrap()), direct(n), "{n}");
        }
        let (p, q) = (Integer::from(99990001u32), Integer::from(1099511627689u64));
        for (n, o, i) in [
            (
                Integer::from(&p * &p) * 12u32,
                Integer::from(&p * 2u32),
                Integer::from(3),
            ),
            (
                Integer::from(&p * &q),
                Integer::from(1),
                Integer::from(&p * &q),
            ),
            (Integer::from(&q * &q) * 7u32, q.clone(), Integer::from(7)),
        ] {
            assert_eq!(square_free(&n), (o, i), "{n}");
        }
        // a product of radicands beyond u64 stays exact
        let big =
            &Exact::sqrt_rational(&Rational::from(&q)) * &Exact::sqrt_rational(&Rational::from(&p));
        assert_eq!(big.to_string(), format!("sqrt({})", Integer::from(&p * &q)));
    }

    #[test]
    fn ring_operations_and_display() {
        let a = &Exact::int(2) + &Exact::monomial(Rational::from((15, 7)), -1, 1);
        let b = &a - &Exact::int(2);
        assert_eq!(b.to_string(), "15/(7*pi)");
        let c = b.div_monomial(&Exact::pi_pow(-1)).unwrap();
        assert_eq!(c.as_rational(), Some(Rational::from((15, 7))));
        let v = a.to_float(100).to_f64();
        assert!((v - (2.0 + 15.0 / 7.0 / std::f64::consts::PI)).abs() < 1e-15);
        let s6 =
            &Exact::sqrt_rational(&Rational::from(2)) * &Exact::sqrt_rational(&Rational::from(3));
        assert_eq!(s6.to_string(), "sqrt(6)");
    }

    #[test]
    fn decimals_are_positional() {
        let x = Float::with_val(200, -0.0595);
        assert_eq!(decimal(&x, 3), "-0.0595");
        let y = Float::with_val(200, 1234.5);
        assert_eq!(decimal(&y, 5), "1234.5");
        assert_eq!(decimal(&Float::with_val(200, 1200), 2), "1200");
    }
}
