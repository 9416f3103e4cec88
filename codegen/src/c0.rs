//! The c0 derivation of section 5, for any support, as explicit lattice sums.
//!
//! Lengths in d, h = d. For a configuration C (neighbours j of i with x
//! offset x_j and layer offset k_j) the sums are, with W' the kernel's
//! gradient function (given or dW/dq):
//!
//! - G(C)  = sum_j x_j^2 W'(r_j)/r_j                      (pressure, (25)-(28))
//! - V(C)  = sum_{k_j>0} k_j^2 W'(r_j)/r_j                 (viscous, (29)-(30))
//! - Av(C) = sum_{k_j>0, x_j>0} 2 k_j^2 x_j^2 W'(r_j)/r_j^3 (artificial viscosity, (31)-(32))
//!
//! In the paper's own sign conventions (kept here so the result compares with
//! (34)): a linear pressure field P_j = P_i - rho0 p x_j gives dP/dx = -m p G,
//! the viscous term (14) on the profile (7) gives M u'' = -(3/2) p m V
//! (rho_i = rho0), and the Monaghan term (31) gives Pi = alpha c0 (U/N^2) m Av
//! for every n. At maximum compaction rho_i = rho0 (1 + eps0) divides the
//! pressure and viscous sums (Pi carries no 1/rho_i in (31)), and the
//! compaction adds a pressure difference c0^2 eps0 carried as the model says.
//! The balance dP/dx(0) - M u''(0) = dP/dx(max) - M u''(max), times
//! (1 + eps0) d^3/m, is
//!
//!   a c0^2 + b alpha (U/N^2) c0 + c p d = 0,
//!   a = eps0 K,  b = (1 + eps0) Av(0) - chi (1 + eps0) Av(max),
//!   c = G(max) - (3/2) V(max) + (1 + eps0) ((3/2) V(0) - G(0)),
//!
//! with K the compaction carrier's sum and chi = 1 when Pi acts at maximum
//! compaction. Its root is c0 = (U/N^2)(sqrt(P alpha^2 + Q A) - S alpha) with
//! S = b/(2a), P = S^2, Q = -c/a, A = p d N^4/U^2.

use crate::exact::{Exact, Ratio};
use crate::kernel::Radial;
use crate::lattice::{stencil, Config, Neighbour};
use rug::Rational;

/// Which neighbours carry the compaction term c0^2 eps0 at maximum
/// compaction (for R = 1 all choices coincide with (27)-(28)).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Carrier {
    /// As a linear pressure field of slope c0^2 eps0 / d, like the body
    /// force's: every neighbour with an x offset carries it. K = G(max).
    Field,
    /// Only the two nearest neighbours of the own layer (x = -d, +d), the
    /// literal reading of (27). K = 2 W'(1).
    Pair,
}

/// One named way of closing the derivation for R > 1.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Model {
    pub name: &'static str,
    pub carrier: Carrier,
    /// Whether Pi (31) acts at maximum compaction (chi = 1) or is set to 0 as
    /// (34) does for R = 1 (where it vanishes by geometry).
    pub av_at_max: bool,
    pub description: &'static str,
}

/// The models offered side by side; the first is the default.
pub const MODELS: [Model; 4] = [
    Model {
        name: "field-av",
        carrier: Carrier::Field,
        av_at_max: true,
        description: "default: compaction as a pressure field over every neighbour (slope c0^2 eps0/d, like the body force's), and the artificial viscosity (31) evaluated at maximum compaction from its lattice sum; it keeps every term of the equation of motion in both configurations, as the paper asks, and treats compaction and thrust alike",
    },
    Model {
        name: "field",
        carrier: Carrier::Field,
        av_at_max: false,
        description: "compaction as a pressure field over every neighbour; artificial viscosity set to 0 at maximum compaction, as (34) has it for R = 1",
    },
    Model {
        name: "pair-av",
        carrier: Carrier::Pair,
        av_at_max: true,
        description: "compaction carried only by the two nearest neighbours of the own layer (27); artificial viscosity evaluated at maximum compaction",
    },
    Model {
        name: "pair",
        carrier: Carrier::Pair,
        av_at_max: false,
        description: "the literal transcription of the R = 1 text: compaction carried only by the two nearest neighbours of the own layer (27), artificial viscosity 0 at maximum compaction",
    },
];

pub const DEFAULT_MODEL: &str = "field-av";

/// The lattice sums of one configuration, exactly.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Sums {
    pub g: Exact,
    pub v: Exact,
    pub av: Exact,
    /// 2 W'(1): the own layer's nearest pair, sum over x = -1, 1 of x^2 W'/r.
    pub pair: Exact,
}

/// Each neighbour's contribution to the sums, for the tables `show` prints.
#[derive(Clone, Debug)]
pub struct Term {
    pub nb: Neighbour,
    pub w: Exact,
    pub dw: Exact,
    /// x^2 W'/r, k^2 W'/r (k > 0), 2 k^2 x^2 W'/r^3 (k > 0, x > 0)
    pub g: Exact,
    pub v: Exact,
    pub av: Exact,
}

/// W'(r)/r at r = sqrt(r2): W' * sqrt(r2) / r2.
fn dw_over_r(dw: &Radial, r2: &Rational) -> Exact {
    let d = dw.eval_q2(r2);
    let inv_r = Exact::sqrt_rational(r2)
        .div_monomial(&Exact::rational(r2.clone()))
        .expect("r2 > 0");
    &d * &inv_r
}

pub fn terms(w: &Radial, dw: &Radial, support: &Rational, config: Config) -> Vec<Term> {
    stencil(support, config)
        .into_iter()
        .map(|nb| {
            let wv = w.eval_q2(&nb.r2);
            if nb.is_self() {
                return Term {
                    nb,
                    w: wv,
                    dw: Exact::zero(),
                    g: Exact::zero(),
                    v: Exact::zero(),
                    av: Exact::zero(),
                };
            }
            let dwv = dw.eval_q2(&nb.r2);
            let f = dw_over_r(dw, &nb.r2);
            let x2 = Exact::rational(Rational::from(&nb.x * &nb.x));
            let k2 = Exact::int(nb.k * nb.k);
            let g = &x2 * &f;
            let v = if nb.k > 0 { &k2 * &f } else { Exact::zero() };
            let av = if nb.k > 0 && nb.x > 0 {
                // 2 k^2 x^2 W'/r^3 = 2 k^2 x^2 (W'/r) / r^2
                (&Exact::int(2) * &(&k2 * &g))
                    .div_monomial(&Exact::rational(nb.r2.clone()))
                    .unwrap()
            } else {
                Exact::zero()
            };
            Term {
                nb,
                w: wv,
                dw: dwv,
                g,
                v,
                av,
            }
        })
        .collect()
}

pub fn sums(terms: &[Term]) -> Sums {
    let mut s = Sums {
        g: Exact::zero(),
        v: Exact::zero(),
        av: Exact::zero(),
        pair: Exact::zero(),
    };
    for t in terms {
        s.g = &s.g + &t.g;
        s.v = &s.v + &t.v;
        s.av = &s.av + &t.av;
        if t.nb.k == 0 && (t.nb.x == 1 || t.nb.x == -1) {
            s.pair = &s.pair + &t.g;
        }
    }
    s
}

/// The polynomial and its root's coefficients for one model.
#[derive(Clone, Debug)]
pub struct Derivation {
    pub model: Model,
    pub a: Exact,
    pub b: Exact,
    pub c: Exact,
    pub s: Ratio,
    pub p: Ratio,
    pub q: Ratio,
}

pub fn derive(model: Model, eps0: &Exact, s0: &Sums, s1: &Sums) -> Derivation {
    let one_eps = &Exact::one() + eps0;
    let k = match model.carrier {
        Carrier::Field => &s1.g,
        Carrier::Pair => &s1.pair,
    };
    let a = eps0 * k;
    let av_max = if model.av_at_max {
        s1.av.clone()
    } else {
        Exact::zero()
    };
    let b = &one_eps * &(&s0.av - &av_max);
    let three_halves = Exact::rational(Rational::from((3, 2)));
    let c = &(&s1.g - &(&three_halves * &s1.v)) + &(&one_eps * &(&(&three_halves * &s0.v) - &s0.g));
    let s = Ratio::new(b.clone(), &Exact::int(2) * &a);
    let p = s.square();
    let q = Ratio::new(-&c, a.clone());
    Derivation {
        model,
        a,
        b,
        c,
        s,
        p,
        q,
    }
}
