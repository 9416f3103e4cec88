//! Emission of `generated/`: one module per kernel and a registry, built as
//! token trees with `quote!`, printed with `prettyplease`, and written only
//! when the bytes change. `check` mode compares instead of writing.
//!
//! Each piece of W and W' is emitted as a Horner polynomial in a variable
//! shifted to the piece's right end — `u = q^2 - b^2` when the piece is even
//! in q (no square root), `s = q - b` otherwise — so values near the end of
//! the support, where W has a high-order zero, keep full relative accuracy.

use crate::analysis::Analysis;
use crate::c0::DEFAULT_MODEL;
use crate::compaction::Known;
use crate::exact::Exact;
use crate::kernel::{Piece, Radial};
use crate::lattice::{max_layer_offset, phase0, Neighbour};
use crate::poly::{parse_decimal, Poly};
use proc_macro2::{Literal, TokenStream};
use quote::{format_ident, quote};
use rug::Rational;
use std::path::{Path, PathBuf};

/// The command that writes `generated/`; named in every file's header.
pub const COMMAND: &str = "cargo run -p shearsph-codegen -- generate";

fn header(source: &str) -> String {
    format!("{}\n// Source: {source}\n\n", own_header_line())
}

fn lit(x: f64) -> Literal {
    assert!(x.is_finite(), "emitted constants are finite");
    Literal::f64_unsuffixed(x)
}

/// The Rust type name of a kernel: `monaghan` -> `Monaghan`, `my_k2` -> `MyK2`.
pub fn type_name(name: &str) -> String {
    name.split('_')
        .map(|w| {
            let mut c = w.chars();
            match c.next() {
                Some(f) => f.to_ascii_uppercase().to_string() + c.as_str(),
                None => String::new(),
            }
        })
        .collect()
}

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
/// W: Horner in u if even, else in s. dW/dq: when W'(0) = 0, q times
/// W'(q)/q (divided exactly on the polynomial), else as W. (dW/dq)/q: when W'(0) = 0 the division by q is done
/// exactly on the polynomial (no cancellation near q = 0), then as W; only a
/// gradient with W'(0) != 0 divides at run time.
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
        Which::Dw => {
            if p.poly.coef.first().is_none_or(|c| c.is_zero()) {
                // W'(q) = q (W'(q)/q): no cancellation near q = 0
                let (body, f) = plain(&div_q(&p.poly));
                (quote! { q2.sqrt() * { #body } }, f + 2)
            } else {
                plain(&p.poly)
            }
        }
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

/// The fused (W, (dW/dq)/q) and its largest flop count over branches. When
/// W's and W''s pieces do not share their joints, the two functions in turn.
fn fused(w: &Radial, dw: &Radial) -> (TokenStream, u32) {
    let same_joints = w.pieces.len() == dw.pieces.len()
        && w.pieces.iter().zip(&dw.pieces).all(|(a, b)| a.to == b.to);
    if !same_joints {
        let (_, fw) = piecewise(w, Which::W);
        let (_, fg) = piecewise(dw, Which::DwOverQ);
        return (quote! { (Self::w(q2), Self::dw_over_q(q2)) }, fw + fg);
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
fn lanes(w: &Radial, dw: &Radial) -> Option<(TokenStream, u32)> {
    let same_joints = w.pieces.len() == dw.pieces.len()
        && w.pieces.iter().zip(&dw.pieces).all(|(a, b)| a.to == b.to);
    if !same_joints || w.pieces.len() < 2 {
        return None;
    }
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
    let pieces: Vec<(Rational, Vec<f64>, Vec<f64>, bool)> = w
        .pieces
        .iter()
        .zip(&dw.pieces)
        .map(|(pw, pd)| {
            let b = pw.to.clone();
            (
                b.clone(),
                coefs(&pw.poly, &b),
                coefs(&g_poly(pd), &b),
                !exact_div(pd),
            )
        })
        .collect();
    let nw = pieces.iter().map(|p| p.1.len()).max().unwrap_or(1);
    let ng = pieces.iter().map(|p| p.2.len()).max().unwrap_or(1);
    let divides = pieces.iter().any(|p| p.3);
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
    for (i, (b, cw, cg, div)) in pieces.iter().enumerate() {
        let b2 = Rational::from(b * b).to_f64();
        let t = tuple(Exact::rational(b.clone()).to_f64(), b2, cw, cg, *div);
        let bound = if i + 1 == n {
            quote!(Self::SUPPORT2_CLOSED)
        } else {
            let b2 = lit(b2);
            quote!(#b2)
        };
        branches.push(quote! { if q2 <= #bound { #t } });
    }
    // beyond the support: W = 0 and W' = 0 (b any finite value)
    let last_b = pieces.last().map(|p| p.0.clone()).unwrap_or_default();
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
    let select = quote! { let #pattern = #(#branches else)* { #outside }; };
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

#[derive(Clone, Copy)]
enum Which {
    W,
    Dw,
    DwOverQ,
}

/// `if q2 <= b1^2 { .. } else if .. else { 0.0 }`; the last piece ends at the
/// closed support. Returns the body and the largest flop count of a branch.
fn piecewise(r: &Radial, what: Which) -> (TokenStream, u32) {
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

fn derived(k: &Known) -> TokenStream {
    let v = lit(k.value.to_f64());
    let (s, exact) = match &k.exact {
        Some(e) => (e.to_string(), true),
        None => (
            crate::exact::decimal(&k.value, k.digits.unwrap_or(30) as usize),
            false,
        ),
    };
    quote!(Derived { value: #v, exact: #s, is_exact: #exact })
}

fn derived_exact(value: f64, form: String) -> TokenStream {
    let v = lit(value);
    quote!(Derived { value: #v, exact: #form, is_exact: true })
}

fn stencil_tokens(nbs: &[Neighbour]) -> TokenStream {
    let pts = nbs.iter().map(|n| {
        let x = lit(n.x.to_f64());
        let k = n.k as i32;
        let r2 = lit(n.r2.to_f64());
        quote!(StencilPoint { x: #x, k: #k, r2: #r2 })
    });
    quote!(&[#(#pts),*])
}

/// One `#[doc]` attribute per line, so prettyplease prints `///` comments.
fn doc(s: &str) -> TokenStream {
    let lines = s.lines().map(|l| quote!(#[doc = #l]));
    quote!(#(#lines)*)
}

/// The module for one kernel.
pub fn kernel_module(a: &Analysis) -> String {
    let d = &a.def;
    let ty = format_ident!("{}", type_name(&d.name));
    let name = &d.name;
    let title = &d.title;
    let reference = &d.reference;
    let support = lit(d.support.to_f64());
    let support_exact = d.support.to_string();
    let support2_closed = lit(Rational::from(&d.support * &d.support).to_f64() * (1.0 + 1e-9));
    let (w_body, _) = piecewise(&d.w, Which::W);
    let (dw_body, _) = piecewise(&d.dw, Which::Dw);
    let (dwq_body, _) = piecewise(&d.dw, Which::DwOverQ);
    // the solver evaluates W and (dW/dq)/q of a pair together, in lanes
    let (fused_body, fused_flops) = fused(&d.w, &d.dw);
    let (lanes_body, flops) =
        lanes(&d.w, &d.dw).unwrap_or((quote!(Self::w_dw_over_q(q2)), fused_flops));

    let e = &a.eps;
    let (t0, half, max, t_max, min, t_min, mean) = (
        derived(&e.t0),
        derived(&e.half_period),
        derived(&e.max),
        derived(&e.t_max),
        derived(&e.min),
        derived(&e.t_min),
        derived(&e.mean),
    );
    let models = a.models.iter().map(|m| {
        let mname = m.model.name;
        let desc = m.model.description;
        let (av, bv, cv) = (
            derived_exact(m.a.to_f64(), m.a.to_string()),
            derived_exact(m.b.to_f64(), m.b.to_string()),
            derived_exact(m.c.to_f64(), m.c.to_string()),
        );
        let (sv, pv, qv) = (
            derived_exact(m.s.to_f64(), m.s.to_string()),
            derived_exact(m.p.to_f64(), m.p.to_string()),
            derived_exact(m.q.to_f64(), m.q.to_string()),
        );
        quote!(C0Model { name: #mname, description: #desc, a: #av, b: #bv, c: #cv, s: #sv, p: #pv, q: #qv })
    });
    let printed = match d.paper.as_ref().and_then(|p| p.table2.as_ref()) {
        Some(t) => {
            let f = |s: &str| lit(parse_decimal(s).map(|q| q.to_f64()).unwrap_or(f64::NAN));
            let (e0, fa, s, p, q) = (f(&t.eps0), f(&t.factor), f(&t.s), f(&t.p), f(&t.q));
            quote!(Some(PrintedC0 { eps0: #e0, factor: #fa, s: #s, p: #p, q: #q }))
        }
        None => quote!(None),
    };
    let printed_eps = match d.paper.as_ref() {
        Some(p) => {
            let (t0, h, m) = (&p.table1.t0, &p.table1.half_period, &p.table1.mean);
            quote!(Some(PrintedEps { t0: #t0, half_period: #h, mean: #m }))
        }
        None => quote!(None),
    };
    let st0 = stencil_tokens(&a.terms_t0.iter().map(|t| t.nb.clone()).collect::<Vec<_>>());
    let sth = stencil_tokens(
        &a.terms_half
            .iter()
            .map(|t| t.nb.clone())
            .collect::<Vec<_>>(),
    );

    // eps(t, n): one row sum per layer offset k, with its phase and speed
    let kmax = max_layer_offset(&d.support);
    let rows = (-kmax..=kmax).map(|k| {
        if k == 0 {
            // the own layer never moves relative to the particle
            return quote! { sum += row(0.0, 0.0); };
        }
        let ph = lit(phase0(k).to_f64());
        let y2 = lit(0.75 * (k * k) as f64);
        let kk = lit(k as f64);
        // layer j = n + k moves by (n^2 - j^2) tau relative to the particle, a
        // wall layer (|j| >= N) by (n^2 - N^2) tau
        quote! {
            let j = n + #kk;
            let speed = match walls {
                Some(nl) if j.abs() >= nl => n * n - nl * nl,
                _ => n * n - j * j,
            };
            sum += row(#ph + speed * t, #y2);
        }
    });
    let reach = d.support.to_f64().ceil() as i32 + 1;

    let doc_struct = doc(&format!(" {title}.\n\n Reference: {reference}.\n\n Support R = {support_exact} h. Generated from `kernels/{name}.toml`."));
    let doc_w = doc(&format!(
        " W(q), q^2 = `q2`, units h^-2. Pieces (exact):\n{}",
        d.w.pieces
            .iter()
            .map(|p| format!(" - ({}, {}]: {}\n", p.from, p.to, p.poly))
            .collect::<String>()
    ));
    let doc_dw = doc(&format!(
        " dW/dq ({}), units h^-3. Pieces (exact):\n{}",
        if d.dw_given {
            "given separately"
        } else {
            "derivative of W"
        },
        d.dw.pieces
            .iter()
            .map(|p| format!(" - ({}, {}]: {}\n", p.from, p.to, p.poly))
            .collect::<String>()
    ));
    let default_model = DEFAULT_MODEL;
    let tokens = quote! {
        use crate::kernel::{C0Model, Derived, EpsInfo, Kernel, KernelInfo, PrintedC0, PrintedEps, StencilPoint};

        #doc_struct
        #[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
        pub struct #ty;

        impl Kernel for #ty {
            const NAME: &'static str = #name;
            const SUPPORT: f64 = #support;
            const SUPPORT2_CLOSED: f64 = #support2_closed;
            const INFO: &'static KernelInfo = &INFO;

            #doc_w
            #[inline(always)]
            fn w(q2: f64) -> f64 { #w_body }

            #doc_dw
            #[inline(always)]
            fn dw(q2: f64) -> f64 { #dw_body }

            #[doc = " (dW/dq)/q, units h^-4."]
            #[inline(always)]
            fn dw_over_q(q2: f64) -> f64 { #dwq_body }

            #[doc = " (W, (dW/dq)/q) together: one branch, square root and shifted variable for both."]
            #[inline(always)]
            fn w_dw_over_q(q2: f64) -> (f64, f64) { #fused_body }

            #[doc = " (W, (dW/dq)/q) without branches, for pair loops in vector lanes."]
            #[inline(always)]
            fn w_dw_over_q_lanes(q2: f64) -> (f64, f64) { #lanes_body }
        }

        /// Sum of W over one lattice row at height y (y2 = y^2 in d^2), the
        /// row's particles at x = a + phase, a integer.
        fn row(phase: f64, y2: f64) -> f64 {
            let phase = phase - phase.floor();
            let mut sum = 0.0;
            for a in -#reach..=#reach {
                let x = a as f64 + phase;
                sum += <#ty as Kernel>::w(x * x + y2);
            }
            sum
        }

        /// eps(t, n) = rho/rho0 - 1 for a particle of layer n under the ideal
        /// shear (7), t as a fraction of T = d N^2 / U (h = d); `walls = Some(N)`
        /// for fixed walls at |j| >= N, `None` for an interior particle.
        pub fn eps_at(t: f64, n: u32, walls: Option<u32>) -> f64 {
            let n = n as f64;
            let walls = walls.map(|nl| nl as f64);
            let mut sum = 0.0;
            #(#rows)*
            0.8660254037844386 * sum - 1.0
        }

        /// Everything the derivation found; see `shearsph-codegen show`.
        pub const INFO: KernelInfo = KernelInfo {
            name: #name,
            title: #title,
            reference: #reference,
            support: #support,
            support_exact: #support_exact,
            eps: EpsInfo { t0: #t0, half_period: #half, max: #max, t_max: #t_max, min: #min, t_min: #t_min, mean: #mean },
            c0_default: #default_model,
            c0_models: &[#(#models),*],
            printed_c0: #printed,
            stencil_t0: #st0,
            stencil_half: #sth,
            eps_at,
            printed_eps: #printed_eps,
            flops_per_pair: #flops,
        };
    };
    format_file(tokens, &format!("kernels/{}.toml", name))
}

fn format_file(tokens: TokenStream, source: &str) -> String {
    let file: syn::File = syn::parse2(tokens).expect("emitted tokens parse as a file");
    header(source) + &prettyplease::unparse(&file)
}

/// The registry of every kernel.
pub fn registry(analyses: &[Analysis]) -> String {
    let mods = analyses.iter().map(|a| {
        let m = format_ident!("{}", a.def.name);
        let file = format!("{}.rs", a.def.name);
        let ty = format_ident!("{}", type_name(&a.def.name));
        let d = doc(&format!(" {}", a.def.title));
        quote! {
            #d
            pub mod #m { include!(#file); }
            pub use #m::#ty;
        }
    });
    let infos = analyses.iter().map(|a| {
        let m = format_ident!("{}", a.def.name);
        quote!(&#m::INFO)
    });
    let arms = analyses.iter().map(|a| {
        let name = &a.def.name;
        let ty = format_ident!("{}", type_name(&a.def.name));
        quote!(#name => Some(visitor.visit::<#ty>()))
    });
    let names = analyses.iter().map(|a| a.def.name.as_str());
    let tokens = quote! {
        use crate::kernel::{KernelInfo, KernelVisitor};

        #(#mods)*

        /// Every kernel, in file-name order.
        pub const KERNELS: &[&KernelInfo] = &[#(#infos),*];

        /// Every kernel's name, in file-name order.
        pub const NAMES: &[&str] = &[#(#names),*];

        /// The kernel called `name`.
        pub fn kernel_info(name: &str) -> Option<&'static KernelInfo> {
            KERNELS.iter().copied().find(|k| k.name == name)
        }

        /// Runs `visitor` with the kernel called `name` as its type parameter.
        pub fn with_kernel<V: KernelVisitor>(name: &str, visitor: V) -> Option<V::Output> {
            match name {
                #(#arms,)*
                _ => None,
            }
        }
    };
    format_file(tokens, "kernels/*.toml")
}

/// Every file of `generated/`, path relative to the output folder.
pub fn render(analyses: &[Analysis]) -> Vec<(PathBuf, String)> {
    let mut out: Vec<(PathBuf, String)> = analyses
        .iter()
        .map(|a| {
            (
                PathBuf::from(format!("{}.rs", a.def.name)),
                kernel_module(a),
            )
        })
        .collect();
    out.push((PathBuf::from("registry.rs"), registry(analyses)));
    out
}

/// The first line of every file the generator writes; a file in the output
/// folder is the generator's own (and may be replaced or removed) only if it
/// starts with it.
pub fn own_header_line() -> String {
    format!("// Generated by `{COMMAND}`, do not edit by hand.")
}

/// Whether the file at `path` carries the generator's header.
fn is_generated(path: &Path) -> bool {
    use std::io::Read;
    let want = own_header_line();
    let mut buf = vec![0u8; want.len()];
    std::fs::File::open(path)
        .and_then(|mut f| f.read_exact(&mut buf))
        .is_ok()
        && buf == want.as_bytes()
}

/// What `ensure` did (or, in check mode, would do).
#[derive(Debug, Default, PartialEq, Eq)]
pub struct Changes {
    /// Files written because they were missing or differed.
    pub written: Vec<PathBuf>,
    /// Files of the generator's own (they carry its header) that it no longer
    /// writes, removed as stale.
    pub removed: Vec<PathBuf>,
    /// `.rs` files in the folder that the generator did not write (no header):
    /// left alone, never removed.
    pub foreign: Vec<PathBuf>,
}

impl Changes {
    /// Whether anything was (or would be) written or removed.
    pub fn is_empty(&self) -> bool {
        self.written.is_empty() && self.removed.is_empty()
    }

    /// The written and removed paths, for a "stale" message.
    pub fn stale(&self) -> Vec<&Path> {
        self.written
            .iter()
            .chain(&self.removed)
            .map(PathBuf::as_path)
            .collect()
    }
}

/// Writes (or, in check mode, compares) the rendered files. A `.rs` file in
/// `dir` that the generator would not write is removed only if it carries the
/// generator's header (it was generated from a kernel since deleted); any
/// other file is the user's and is left alone, listed in `foreign`. A file
/// that would be overwritten must be missing or the generator's own, so
/// `generate --out src` never replaces a hand-written file either.
pub fn ensure(dir: &Path, files: &[(PathBuf, String)], check: bool) -> std::io::Result<Changes> {
    let mut changes = Changes::default();
    if !check {
        std::fs::create_dir_all(dir)?;
    }
    for (rel, _) in files {
        let path = dir.join(rel);
        if path.exists() && !is_generated(&path) {
            return Err(std::io::Error::new(
                std::io::ErrorKind::AlreadyExists,
                format!(
                    "{} exists and was not written by the generator (its first line is not \
                     `{}`); refusing to overwrite it: choose an empty folder with --out, or move \
                     the file",
                    path.display(),
                    own_header_line()
                ),
            ));
        }
    }
    for (rel, contents) in files {
        let path = dir.join(rel);
        let current = std::fs::read_to_string(&path).ok();
        if current.as_deref() == Some(contents.as_str()) {
            continue;
        }
        changes.written.push(path.clone());
        if !check {
            write_atomically(&path, contents)?;
        }
    }
    if let Ok(entries) = std::fs::read_dir(dir) {
        let mut extra: Vec<PathBuf> = entries
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.extension().is_some_and(|x| x == "rs"))
            .filter(|p| !files.iter().any(|(rel, _)| dir.join(rel) == *p))
            .collect();
        extra.sort();
        for p in extra {
            if is_generated(&p) {
                if !check {
                    std::fs::remove_file(&p)?;
                }
                changes.removed.push(p);
            } else {
                changes.foreign.push(p);
            }
        }
    }
    Ok(changes)
}

/// Writes `contents` to a temporary file beside `path` and renames it over
/// `path`; on any failure (a full disk) the temporary file is removed, so
/// nothing but the old file remains.
fn write_atomically(path: &Path, contents: &str) -> std::io::Result<()> {
    let tmp = path.with_extension("rs.tmp");
    let result = std::fs::write(&tmp, contents).and_then(|()| std::fs::rename(&tmp, path));
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}
