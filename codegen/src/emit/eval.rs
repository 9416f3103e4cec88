//! The kernel's functions as Rust: each piece of W and W' as a Horner
//! polynomial in a variable shifted to the piece's right end — `u = q^2 -
//! b^2` when the piece is even in q (no square root), `s = q - b` otherwise —
//! so values near the end of the support, where W has a high-order zero, keep
//! full relative accuracy. What the solver calls: W alone (branches), and
//! the pair (W, (dW/dq)/q) without branches (lanes) or, for a kernel of one
//! piece or with W' on other joints than W, with them (fused).

use super::lit;
use crate::exact::Exact;
use crate::kernel::{Piece, Radial};
use crate::poly::Poly;
use proc_macro2::TokenStream;
use quote::{format_ident, quote};
use rug::Rational;

/// p(q) rewritten in s = q - b.
fn shift_q(p: &Poly, b: &Rational) -> Poly {
    let sb = Poly {
        coef: vec![Exact::rational(b.clone()), Exact::one()],
    };
    let mut out = Poly::default();
    for (k, c) in p.coef.iter().enumerate() {
        out = out.add(&sb.pow(k as u32).scale(c));
    }
    out
}

/// An even p(q) = sum c_2m (q^2)^m rewritten in u = q^2 - b^2.
fn shift_q2(p: &Poly, b: &Rational) -> Poly {
    let b2 = Rational::from(b * b);
    let ub = Poly {
        coef: vec![Exact::rational(b2), Exact::one()],
    };
    let mut out = Poly::default();
    for (k, c) in p.coef.iter().enumerate().step_by(2) {
        out = out.add(&ub.pow((k / 2) as u32).scale(c));
    }
    out
}

/// q^-1 p(q) for p with p(0) = 0.
fn div_q(p: &Poly) -> Poly {
    Poly {
        coef: p.coef.iter().skip(1).cloned().collect(),
    }
}

/// Horner form `((c_n * v + c_{n-1}) * v + ...) + c_0`, zero coefficients
/// skipped (a factor v^m for the lowest m), and its flop count.
fn horner(var: &TokenStream, p: &Poly) -> (TokenStream, u32) {
    let coefs: Vec<f64> = p.coef.iter().map(|c| c.to_f64()).collect();
    let Some(low) = coefs.iter().position(|c| *c != 0.0) else {
        return (quote!(0.0), 0);
    };
    let mut acc = {
        let c = lit(*coefs.last().unwrap());
        quote!(#c)
    };
    // whether `acc` is a sum (then it needs parentheses before `* v`)
    let mut is_sum = false;
    let mut flops = 0;
    let times = |acc: &TokenStream, is_sum: bool| {
        if is_sum {
            quote!((#acc) * #var)
        } else {
            quote!(#acc * #var)
        }
    };
    for c in coefs[low..].iter().rev().skip(1) {
        let prod = times(&acc, is_sum);
        if *c == 0.0 {
            acc = prod;
            is_sum = false;
            flops += 1;
        } else {
            let c = lit(*c);
            acc = quote!(#prod + #c);
            is_sum = true;
            flops += 2;
        }
    }
    for _ in 0..low {
        acc = times(&acc, is_sum);
        is_sum = false;
        flops += 1;
    }
    (acc, flops)
}

/// One branch body for a piece: tokens and flops (sqrt counted as one).
///
/// W: Horner in u if even, else in s. (dW/dq)/q: when W'(0) = 0 the
/// division by q is done exactly on the polynomial (no cancellation near
/// q = 0), then as W; only a gradient with W'(0) != 0 divides at run time.
fn piece_body(p: &Piece, what: Which) -> (TokenStream, u32) {
    let b = &p.to;
    let b2 = lit(Rational::from(b * b).to_f64());
    let bl = lit(Exact::rational(b.clone()).to_f64());
    let in_u = |poly: &Poly| horner(&quote!(u), &shift_q2(poly, b));
    let in_s = |poly: &Poly| horner(&quote!(s), &shift_q(poly, b));
    // Where the piece vanishes at its end, s = q - b is formed as
    // (q2 - b^2)/(q + b): q2 - b^2 is exact there, so s keeps full relative
    // accuracy instead of inheriting the rounding of sqrt (W ~ s^k near R).
    let vanishes_at_end = |poly: &Poly| poly.eval_rational(b).is_zero();
    let s_of_q = |poly: &Poly, q: TokenStream| -> (TokenStream, u32) {
        if vanishes_at_end(poly) {
            (quote! { let s = (q2 - #b2) / (#q + #bl); }, 3)
        } else {
            (quote! { let s = #q - #bl; }, 1)
        }
    };
    let plain = |poly: &Poly| -> (TokenStream, u32) {
        if poly.is_even() {
            let (h, f) = in_u(poly);
            (quote! { let u = q2 - #b2; #h }, f + 1)
        } else {
            let (h, f) = in_s(poly);
            let (sd, fs) = s_of_q(poly, quote!(q2.sqrt()));
            (quote! { #sd #h }, f + fs + 1)
        }
    };
    match what {
        Which::W => plain(&p.poly),
        Which::DwOverQ => {
            if p.poly.coef.first().is_none_or(|c| c.is_zero()) {
                plain(&div_q(&p.poly))
            } else {
                let (h, f) = in_s(&p.poly);
                if vanishes_at_end(&p.poly) {
                    // one division for both s = (q2 - b^2)/(q + b) and 1/q
                    (
                        quote! {
                            let q = q2.sqrt();
                            let qb = q + #bl;
                            let t = 1.0 / (q * qb);
                            let s = (q2 - #b2) * q * t;
                            (#h) * qb * t
                        },
                        f + 9,
                    )
                } else {
                    (
                        quote! { let q = q2.sqrt(); let s = q - #bl; (#h) / q },
                        f + 4,
                    )
                }
            }
        }
    }
}

/// How a fused piece reaches its shifted variable.
#[derive(Clone, Copy, PartialEq)]
enum Var {
    /// u = q2 - b^2 (even polynomial, no square root)
    U,
    /// s = q - b
    Sub,
    /// s = q - b formed without cancellation where the piece vanishes at b
    Vanishing,
}

/// What the (dW/dq)/q part of a fused piece does after its Horner form.
#[derive(Clone, Copy, PartialEq)]
enum Post {
    /// nothing: q^-1 was divided exactly on the polynomial
    None,
    /// `/ q`
    DivQ,
    /// `* qb * t`, t = 1/(q (q + b)): one division serves s and 1/q
    QbT,
}

/// One branch of the fused (W, (dW/dq)/q) for pieces of W and W' on the same
/// interval: one square root, one shifted variable and at most one division
/// for both, each part as accurate as its own function's (same forms).
fn fused_piece(pw: &Piece, pd: &Piece) -> (TokenStream, u32) {
    let b = &pw.to;
    let b2 = lit(Rational::from(b * b).to_f64());
    let bl = lit(Exact::rational(b.clone()).to_f64());
    let vanishes = |poly: &Poly| poly.eval_rational(b).is_zero();
    let s_var = |poly: &Poly| {
        if vanishes(poly) {
            Var::Vanishing
        } else {
            Var::Sub
        }
    };
    let (w_poly, w_var) = if pw.poly.is_even() {
        (shift_q2(&pw.poly, b), Var::U)
    } else {
        (shift_q(&pw.poly, b), s_var(&pw.poly))
    };
    let exact_div = pd.poly.coef.first().is_none_or(|c| c.is_zero());
    let (g_poly, g_var, post) = if exact_div {
        let g = div_q(&pd.poly);
        if g.is_even() {
            (shift_q2(&g, b), Var::U, Post::None)
        } else {
            let v = s_var(&g);
            (shift_q(&g, b), v, Post::None)
        }
    } else {
        let v = s_var(&pd.poly);
        let post = if v == Var::Vanishing {
            Post::QbT
        } else {
            Post::DivQ
        };
        (shift_q(&pd.poly, b), v, post)
    };
    let uses = |v: Var| w_var == v || g_var == v;
    let both_s = uses(Var::Sub) && uses(Var::Vanishing);
    let name = |v: Var| match v {
        Var::U => quote!(u),
        Var::Vanishing if both_s => quote!(sv),
        _ => quote!(s),
    };
    let mut lets = TokenStream::new();
    let mut flops = 0;
    if uses(Var::U) {
        lets.extend(quote! { let u = q2 - #b2; });
        flops += 1;
    }
    if uses(Var::Sub) || uses(Var::Vanishing) {
        lets.extend(quote! { let q = q2.sqrt(); });
        flops += 1;
    }
    if post == Post::QbT {
        lets.extend(quote! { let qb = q + #bl; let t = 1.0 / (q * qb); });
        flops += 3;
    }
    if uses(Var::Sub) {
        lets.extend(quote! { let s = q - #bl; });
        flops += 1;
    }
    if uses(Var::Vanishing) {
        let v = name(Var::Vanishing);
        if post == Post::QbT {
            lets.extend(quote! { let #v = (q2 - #b2) * q * t; });
        } else {
            lets.extend(quote! { let #v = (q2 - #b2) / (q + #bl); });
        }
        flops += 3;
    }
    let (hw, fw) = horner(&name(w_var), &w_poly);
    let (hg, fg) = horner(&name(g_var), &g_poly);
    let g = match post {
        Post::None => hg,
        Post::DivQ => {
            flops += 1;
            quote!((#hg) / q)
        }
        Post::QbT => {
            flops += 2;
            quote!((#hg) * qb * t)
        }
    };
    (quote! { #lets (#hw, #g) }, flops + fw + fg)
}

/// W's and W''s pieces end at the same joints.
fn same_joints(w: &Radial, dw: &Radial) -> bool {
    w.pieces.len() == dw.pieces.len() && w.pieces.iter().zip(&dw.pieces).all(|(a, b)| a.to == b.to)
}

/// The fused (W, (dW/dq)/q) and its largest flop count over branches. When
/// W's and W''s pieces do not share their joints, W and (dW/dq)/q each with
/// its own branches, in turn.
pub(super) fn fused(w: &Radial, dw: &Radial) -> (TokenStream, u32) {
    if !same_joints(w, dw) {
        let (wb, fw) = piecewise(w, Which::W);
        let (gb, fg) = piecewise(dw, Which::DwOverQ);
        return (quote! { let w = #wb; let g = #gb; (w, g) }, fw + fg);
    }
    let n = w.pieces.len();
    let mut branches = Vec::new();
    let mut max_flops = 0;
    for (i, (pw, pd)) in w.pieces.iter().zip(&dw.pieces).enumerate() {
        let (body, f) = fused_piece(pw, pd);
        max_flops = max_flops.max(f);
        let bound = if i + 1 == n {
            quote!(Self::SUPPORT2_CLOSED)
        } else {
            let b2 = lit(Rational::from(&pw.to * &pw.to).to_f64());
            quote!(#b2)
        };
        branches.push(quote! { if q2 <= #bound { #body } });
    }
    (
        quote! { #(#branches else)* { (0.0, 0.0) } },
        max_flops + n as u32,
    )
}

/// `((c_n * v + c_{n-1}) * v + ...) + c_0` over variables named `c0..cn`:
/// the coefficients are chosen per pair, so none is known to be zero.
fn horner_vars(var: &TokenStream, prefix: &str, n: usize) -> TokenStream {
    let c = |k: usize| {
        let id = format_ident!("{prefix}{k}");
        quote!(#id)
    };
    let mut acc = c(n - 1);
    for k in (0..n - 1).rev() {
        let ck = c(k);
        acc = if k + 2 == n {
            quote!(#acc * #var + #ck)
        } else {
            quote!((#acc) * #var + #ck)
        };
    }
    acc
}

/// (W, (dW/dq)/q) without branches, for loops that evaluate many pairs in
/// vector lanes: every piece in one form, its constants selected by q^2 (a
/// select, not a branch), one Horner each. The form: s = q - b as (q^2 - b^2)
/// q t with t = 1/(q (q + b)), which keeps the vanishing forms' accuracy and
/// gives 1/q = (q + b) t for the pieces that divide by q: one square root and
/// one division per pair whatever the piece. When every piece is even in q,
/// u = q^2 - b^2 instead, with neither. Beyond the support every constant is
/// 0. None when W's and W''s pieces do not share their joints, or when there
/// is one piece (the fused function has no branch to remove then, and its
/// forms are cheaper).
pub(super) fn lanes(w: &Radial, dw: &Radial) -> Option<(TokenStream, u32)> {
    if !same_joints(w, dw) || w.pieces.len() < 2 {
        return None;
    }
    let (pieces, all_even) = lane_pieces(w, dw);
    let nw = pieces.iter().map(|p| p.w.len()).max().unwrap_or(1);
    let ng = pieces.iter().map(|p| p.g.len()).max().unwrap_or(1);
    let divides = pieces.iter().any(|p| p.div);
    let select = lane_select(&pieces, nw, ng, divides);
    let n = pieces.len();
    let mut flops = n as u32 + 2 * (nw as u32 - 1) + 2 * (ng as u32 - 1);
    let body = if all_even {
        let hw = horner_vars(&quote!(u), "w", nw);
        let hg = horner_vars(&quote!(u), "g", ng);
        flops += 1;
        quote! {
            #select
            let _ = b;
            let u = q2 - b2;
            (#hw, #hg)
        }
    } else {
        let hw = horner_vars(&quote!(s), "w", nw);
        let hg = horner_vars(&quote!(s), "g", ng);
        // sqrt, max, q + b, q (q + b), 1/.., (q2 - b2) q t
        flops += 8;
        let g = if divides {
            flops += 2;
            quote! { (#hg) * if div { qb * t } else { 1.0 } }
        } else {
            hg
        };
        quote! {
            #select
            // q > 0, so that a pair at q = 0 (W finite there) takes s = -b
            let q = q2.sqrt().max(f64::MIN_POSITIVE);
            let qb = q + b;
            let t = 1.0 / (q * qb);
            let s = (q2 - b2) * q * t;
            (#hw, #g)
        }
    };
    Some((body, flops))
}

/// One piece of the lanes form: its right end b, the coefficients of W and
/// of G = (dW/dq)/q (or of dW/dq when `div`: divided by q at run time) in
/// the shifted variable, as f64.
struct LanePiece {
    b: Rational,
    w: Vec<f64>,
    g: Vec<f64>,
    div: bool,
}

/// The pieces of the lanes form, and whether every one is even in q (then
/// the variable is u = q^2 - b^2, else s = q - b).
fn lane_pieces(w: &Radial, dw: &Radial) -> (Vec<LanePiece>, bool) {
    let exact_div = |p: &Piece| p.poly.coef.first().is_none_or(|c| c.is_zero());
    let g_poly = |p: &Piece| {
        if exact_div(p) {
            div_q(&p.poly)
        } else {
            p.poly.clone()
        }
    };
    let all_even = w.pieces.iter().all(|p| p.poly.is_even())
        && dw
            .pieces
            .iter()
            .all(|p| exact_div(p) && g_poly(p).is_even());
    // Coefficients of each piece in its shifted variable, as f64.
    let coefs = |poly: &Poly, b: &Rational| -> Vec<f64> {
        let shifted = if all_even {
            shift_q2(poly, b)
        } else {
            shift_q(poly, b)
        };
        let mut c: Vec<f64> = shifted.coef.iter().map(|c| c.to_f64()).collect();
        if all_even {
            // u-polynomial: the even coefficients only
            c = c.into_iter().step_by(2).collect();
        }
        if c.is_empty() {
            c.push(0.0);
        }
        c
    };
    let pieces = w
        .pieces
        .iter()
        .zip(&dw.pieces)
        .map(|(pw, pd)| LanePiece {
            b: pw.to.clone(),
            w: coefs(&pw.poly, &pw.to),
            g: coefs(&g_poly(pd), &pw.to),
            div: !exact_div(pd),
        })
        .collect();
    (pieces, all_even)
}

/// `let (b, b2, [div,] w0.., g0..) = if q2 <= b1^2 { .. } else if ..`: each
/// piece's constants (`nw` of W, `ng` of G, zero-padded) selected by q^2,
/// the last piece up to the closed support, all 0 beyond it.
fn lane_select(pieces: &[LanePiece], nw: usize, ng: usize, divides: bool) -> TokenStream {
    let names = |prefix: &str, n: usize| -> Vec<proc_macro2::Ident> {
        (0..n).map(|k| format_ident!("{prefix}{k}")).collect()
    };
    let (wn, gn) = (names("w", nw), names("g", ng));
    let tuple = |b: f64, b2: f64, cw: &[f64], cg: &[f64], div: bool| {
        let (b, b2) = (lit(b), lit(b2));
        let cw = (0..nw).map(|k| lit(cw.get(k).copied().unwrap_or(0.0)));
        let cg = (0..ng).map(|k| lit(cg.get(k).copied().unwrap_or(0.0)));
        if divides {
            quote!((#b, #b2, #div, #(#cw,)* #(#cg),*))
        } else {
            quote!((#b, #b2, #(#cw,)* #(#cg),*))
        }
    };
    let n = pieces.len();
    let mut branches = Vec::new();
    for (i, p) in pieces.iter().enumerate() {
        let b2 = Rational::from(&p.b * &p.b).to_f64();
        let t = tuple(Exact::rational(p.b.clone()).to_f64(), b2, &p.w, &p.g, p.div);
        let bound = if i + 1 == n {
            quote!(Self::SUPPORT2_CLOSED)
        } else {
            let b2 = lit(b2);
            quote!(#b2)
        };
        branches.push(quote! { if q2 <= #bound { #t } });
    }
    // beyond the support: W = 0 and W' = 0 (b any finite value)
    let last_b = pieces.last().map(|p| p.b.clone()).unwrap_or_default();
    let outside = tuple(
        Exact::rational(last_b.clone()).to_f64(),
        Rational::from(&last_b * &last_b).to_f64(),
        &[],
        &[],
        false,
    );
    let pattern = if divides {
        quote!((b, b2, div, #(#wn,)* #(#gn),*))
    } else {
        quote!((b, b2, #(#wn,)* #(#gn),*))
    };
    quote! { let #pattern = #(#branches else)* { #outside }; }
}

#[derive(Clone, Copy)]
pub(super) enum Which {
    W,
    DwOverQ,
}

/// `if q2 <= b1^2 { .. } else if .. else { 0.0 }`; the last piece ends at the
/// closed support. Returns the body and the largest flop count of a branch.
pub(super) fn piecewise(r: &Radial, what: Which) -> (TokenStream, u32) {
    let n = r.pieces.len();
    let mut branches = Vec::new();
    let mut max_flops = 0;
    for (i, p) in r.pieces.iter().enumerate() {
        let (body, f) = piece_body(p, what);
        max_flops = max_flops.max(f);
        let bound = if i + 1 == n {
            quote!(Self::SUPPORT2_CLOSED)
        } else {
            let b2 = lit(Rational::from(&p.to * &p.to).to_f64());
            quote!(#b2)
        };
        branches.push(quote! { if q2 <= #bound { #body } });
    }
    (
        quote! { #(#branches else)* { 0.0 } },
        max_flops + n as u32, // comparisons
    )
}
