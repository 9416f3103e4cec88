//! Facts about the shape of W, found exactly: where W < 0 (Sturm sequences),
//! and whether W'(0) = 0.

use super::{KernelDef, Piece};
use crate::exact::Exact;
use crate::poly::Poly;
use rug::Rational;

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
