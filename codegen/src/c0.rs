//! The c0 derivation of section 5, for any support, as explicit lattice sums.
//!
//! Lengths in d; the paper has h = d, and for h = k d (the paper's
//! W(r, kd, R)) the kernel's gradient is grad W = F(r) r_vec with
//! F(r) = W'(r/h)/(h^3 r). For a configuration C (neighbours j of i with x
//! offset x_j and layer offset k_j) the sums are, with W' the kernel's
//! gradient function (given or dW/dq):
//!
//! - G(C)  = sum_j x_j^2 F(r_j)                        (pressure, (25)-(28))
//! - V(C)  = sum_{k_j>0} k_j^2 F(r_j)                  (viscous, (29)-(30))
//! - Av(C) = sum_{k_j>0, x_j>0} 2 k_j^2 x_j^2 h F(r_j)/r_j^2 (artificial viscosity, (31)-(32):
//!   mu_ij carries one h)
//!
//! For h = d these are the paper's x^2 W'/r, k^2 W'/r and 2 k^2 x^2 W'/r^3.
//! The viscous sum meets the profile through y_j^2/B^2 = k_j^2/N^2 (B = N dy),
//! so the lattice enters the balance through 2 dy^2/d^2, the factor of V: 3/2
//! on the triangular lattice (the paper's), 2 on the square one.
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
//!   c = G(max) - (3/2) V(max) + (1 + eps0) ((3/2) V(0) - G(0))   (3/2 = 2 dy^2),
//!
//! with K the compaction carrier's sum and chi = 1 when Pi acts at maximum
//! compaction. Its root is c0 = (U/N^2)(sqrt(P alpha^2 + Q A) - S alpha) with
//! S = b/(2a), P = S^2, Q = -c/a, A = p d N^4/U^2.

use crate::compaction::{FloatRadial, Known};
use crate::exact::{decimal, Exact, Ratio};
use crate::kernel::Radial;
use crate::lattice::{stencil, Config, Discretisation, ExactLattice, Neighbour};
use rug::{Float, Rational};

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

/// F(r) = W'(r/h)/(h^3 r) at r = sqrt(r2) (in d): W' * sqrt(r2) / (r2 h^3).
fn dw_over_r(dw: &Radial, r2: &Rational, disc: &Discretisation) -> Exact {
    let h2 = disc.h2();
    let d = dw.eval_q2(&Rational::from(r2 / &h2));
    let inv_r = Exact::sqrt_rational(r2)
        .div_monomial(&Exact::rational(r2.clone()))
        .expect("r2 > 0");
    let inv_h3 = Exact::rational(Rational::from(1) / Rational::from(&h2 * &disc.h));
    &(&d * &inv_r) * &inv_h3
}

/// 2 dy^2 / d^2, the factor of V in the balance (3/2 for the paper's lattice).
pub fn viscous_factor(disc: &Discretisation) -> Exact {
    Exact::rational(disc.lattice.dy2() * 2u32)
}

pub fn terms(
    w: &Radial,
    dw: &Radial,
    support: &Rational,
    disc: &Discretisation,
    config: Config,
) -> Vec<Term> {
    let h2 = disc.h2();
    let h = Exact::rational(disc.h.clone());
    stencil(disc, support, config)
        .into_iter()
        .map(|nb| {
            let wv = w.eval_q2(&Rational::from(&nb.r2 / &h2));
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
            let dwv = dw.eval_q2(&Rational::from(&nb.r2 / &h2));
            let f = dw_over_r(dw, &nb.r2, disc);
            let x2 = Exact::rational(Rational::from(&nb.x * &nb.x));
            let k2 = Exact::int(nb.k * nb.k);
            let g = &x2 * &f;
            let v = if nb.k > 0 { &k2 * &f } else { Exact::zero() };
            let av = if nb.k > 0 && nb.x > 0 {
                // 2 k^2 x^2 h F / r^2
                (&(&Exact::int(2) * &h) * &(&k2 * &g))
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

/// The polynomial and its root's coefficients for one model, exactly.
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

/// The same coefficients at high precision: from the exact ones, or computed
/// at a configuration that is not exactly representable.
#[derive(Clone, Debug)]
pub struct Coefs {
    pub a: Float,
    pub b: Float,
    pub c: Float,
    pub s: Float,
    pub p: Float,
    pub q: Float,
}

/// One model's outcome: its coefficients (exact when the maximum is at a
/// symmetric configuration), or the fact that makes the derivation degenerate.
#[derive(Clone, Debug)]
pub struct ModelC0 {
    pub model: Model,
    pub exact: Option<Derivation>,
    /// `Err(fact)` when the derivation gives no c0 at any Re and alpha: the
    /// lattice never compacts (max eps < 0), a = eps0 K = 0, or c = 0
    /// exactly with no positive root (see [`derive_all`]).
    pub coefs: Result<Coefs, String>,
    /// t / T of the configuration the coefficients come from: the maximum's,
    /// or for an `-av` model at a maximum off the symmetric configurations
    /// whichever of t and T - t gives it the larger c0 ([`stricter_mirror`]).
    pub tau: Known,
}

/// Why the lattice gives no c0 when its maximum compaction is negative.
fn never_compacts(eps0: &Float, tau: &Known) -> String {
    format!(
        "no c0: the lattice never compacts: the maximum of eps over the period is {} < 0 (at t = {} T), \
         so there is no compaction for a sound speed to balance",
        decimal(eps0, 6),
        match &tau.exact {
            Some(t) => t.to_f64().to_string(),
            None => decimal(&tau.value, 6),
        }
    )
}

/// Why an exact balance with c = 0 has no positive root: its roots are 0
/// and -b alpha (U/N^2)/a = -2 S alpha U/N^2, and S >= 0.
fn constant_term_zero(d: &Derivation, config: Option<Config>) -> String {
    let why = if config == Some(Config::T0) {
        "the maximum compaction is at t = 0, the undisturbed lattice, so the balance compares it with \
         itself: its constant term c = eps0 (2 dy^2 V(0) - G(0)) is exactly 0, the lattice's second \
         moments being isotropic (G(0) = 2 dy^2 V(0))"
    } else {
        "the constant term c of the balance is exactly 0"
    };
    let roots = if d.b.is_zero() {
        "with b = 0 too (the artificial viscosity acts alike in both configurations) the balance is \
         a c0^2 = 0: c0 = 0"
    } else {
        "its roots are then 0 and -2 S alpha U/N^2 with S = b/(2a) > 0: none is positive"
    };
    format!("no c0: {why}; {roots}, at every Re and alpha")
}

/// Why a = eps0 K vanishes, as a fact for the reader.
fn degenerate(model: Model, eps0_zero: bool, n_neighbours: usize) -> String {
    let carrier = match model.carrier {
        Carrier::Field => "G(max)",
        Carrier::Pair => "2 W'(1) (the own layer's nearest pair)",
    };
    if eps0_zero {
        "no c0: eps0 = 0, the lattice does not compact at its maximum".into()
    } else if n_neighbours == 0 {
        "no c0: the support reaches no neighbour at maximum compaction (only the particle itself), so nothing carries the compaction pressure".into()
    } else {
        // K sums x^2 W'/r over the carriers: it vanishes when W' does at
        // every one of them (no cancellation: W' keeps its sign there)
        format!("no c0: the gradient W' vanishes at every neighbour that carries the compaction at maximum compaction (for R = 1 on the paper's lattice: W'(1) = 0, the six neighbours exert no force), so {carrier} = 0 and a = eps0 K = 0")
    }
}

/// The lattice sums at high precision.
#[derive(Clone, Debug)]
pub struct FloatSums {
    pub g: Float,
    pub v: Float,
    pub av: Float,
    pub pair: Float,
}

impl FloatSums {
    pub fn from_exact(s: &Sums, prec: u32) -> Self {
        FloatSums {
            g: s.g.to_float(prec),
            v: s.v.to_float(prec),
            av: s.av.to_float(prec),
            pair: s.pair.to_float(prec),
        }
    }

    /// The sums over neighbours (x, k, r^2) in d, at `prec` bits.
    pub fn at(
        dw: &FloatRadial,
        nbs: &[(Float, i64, Float)],
        disc: &Discretisation,
        prec: u32,
    ) -> Self {
        let h = Float::with_val(prec, &disc.h);
        let h2 = Float::with_val(prec, h.square_ref());
        let h3 = Float::with_val(prec, &h2 * &h);
        let zero = || Float::with_val(prec, 0);
        let mut s = FloatSums {
            g: zero(),
            v: zero(),
            av: zero(),
            pair: zero(),
        };
        for (x, k, r2) in nbs {
            if r2.is_zero() {
                continue;
            }
            let q2 = Float::with_val(prec, r2 / &h2);
            let r = Float::with_val(prec, r2.sqrt_ref());
            let f = dw.eval(&q2) / Float::with_val(prec, &h3 * &r);
            let x2 = Float::with_val(prec, x.square_ref());
            let g = Float::with_val(prec, &x2 * &f);
            if *k > 0 {
                s.v += Float::with_val(prec, &f * (k * k));
                if *x > 0 {
                    s.av += Float::with_val(prec, &g * (2 * k * k)) * &h / r2;
                }
            }
            let one = Float::with_val(prec, 1);
            let near = Float::with_val(prec, x.abs_ref()) - &one;
            if *k == 0 && near.abs() < Float::with_val(prec, Float::i_exp(1, -(prec as i32) / 2)) {
                s.pair += &g;
            }
            s.g += g;
        }
        s
    }
}

impl Coefs {
    fn from_exact(d: &Derivation, prec: u32) -> Self {
        Coefs {
            a: d.a.to_float(prec),
            b: d.b.to_float(prec),
            c: d.c.to_float(prec),
            s: d.s.to_float(prec),
            p: d.p.to_float(prec),
            q: d.q.to_float(prec),
        }
    }
}

/// The balance at high precision (the same formulas as [`derive`]); `None`
/// when a = 0.
pub fn derive_float(
    model: Model,
    eps0: &Float,
    s0: &FloatSums,
    s1: &FloatSums,
    vf: &Float,
) -> Option<Coefs> {
    let prec = eps0.prec();
    let one_eps = Float::with_val(prec, eps0 + 1u32);
    let k = match model.carrier {
        Carrier::Field => &s1.g,
        Carrier::Pair => &s1.pair,
    };
    let a = Float::with_val(prec, eps0 * k);
    if a.is_zero() {
        return None;
    }
    let av_max = if model.av_at_max {
        s1.av.clone()
    } else {
        Float::with_val(prec, 0)
    };
    let b = Float::with_val(prec, &s0.av - &av_max) * &one_eps;
    let c = Float::with_val(prec, &s1.g - Float::with_val(prec, vf * &s1.v))
        + Float::with_val(prec, Float::with_val(prec, vf * &s0.v) - &s0.g) * &one_eps;
    let s = Float::with_val(prec, &b / Float::with_val(prec, &a * 2u32));
    let p = Float::with_val(prec, s.square_ref());
    let q = Float::with_val(prec, -Float::with_val(prec, &c / &a));
    Some(Coefs { a, b, c, s, p, q })
}

/// The configuration of maximum compaction a balance is taken at: exact
/// (`Ok`) at a symmetric configuration, high precision (`Err`) at a searched
/// one.
#[derive(Clone, Copy, Debug)]
pub struct AtMax<'a> {
    /// eps0, the maximum of eps.
    pub eps0: Result<&'a Exact, &'a Float>,
    /// The lattice sums there.
    pub sums: Result<&'a Sums, &'a FloatSums>,
    /// Neighbours (self excluded) in reach there.
    pub neighbours: usize,
    /// The symmetric configuration, when it is one.
    pub config: Option<Config>,
    /// t / T.
    pub tau: &'a Known,
}

/// Every model at a symmetric configuration (`at.config`, exact), or at a
/// searched one (`None`, high precision), at `at.tau`. No c0, as a
/// fact, where the data decide it at every Re and alpha:
///
/// - max eps < 0: the lattice never compacts (also for derived-eps);
/// - a = eps0 K = 0 (see `degenerate`);
/// - exactly c = 0 (always so when the maximum is at t = 0) with S >= 0:
///   the roots 0 and -2 S alpha U/N^2 are not positive. (With S < 0 the
///   root -2 S alpha U/N^2 is positive and the model keeps it.)
pub fn derive_all(at: &AtMax, s0: &Sums, disc: &Discretisation, prec: u32) -> Vec<ModelC0> {
    let AtMax {
        eps0,
        sums: s1,
        neighbours: n_neighbours,
        config,
        tau,
    } = *at;
    let vf = viscous_factor(disc);
    MODELS
        .iter()
        .map(|&model| {
            let fs1 = match s1 {
                Ok(s) => FloatSums::from_exact(s, prec),
                Err(f) => f.clone(),
            };
            let eps0_f = match eps0 {
                Ok(e) => e.to_float(prec),
                Err(f) => f.clone(),
            };
            let exact = match (eps0, s1) {
                (Ok(e), Ok(s)) => derive(model, e, s0, s, &vf),
                _ => None,
            };
            let coefs = if eps0_f < 0 {
                Err(never_compacts(&eps0_f, tau))
            } else {
                match &exact {
                    Some(d) => {
                        let c = Coefs::from_exact(d, prec);
                        if d.c.is_zero() && c.s >= 0 {
                            Err(constant_term_zero(d, config))
                        } else {
                            Ok(c)
                        }
                    }
                    None => derive_float(
                        model,
                        &eps0_f,
                        &FloatSums::from_exact(s0, prec),
                        &fs1,
                        &vf.to_float(prec),
                    )
                    .ok_or_else(|| degenerate(model, eps0_f.is_zero(), n_neighbours)),
                }
            };
            ModelC0 {
                model,
                exact: exact.filter(|_| coefs.is_ok()),
                coefs,
                tau: tau.clone(),
            }
        })
        .collect()
}

/// Of one model derived at a maximum t off the symmetric configurations
/// (`at_t`) and at its mirror T - t (`at_mirror`), the one to use. The
/// configuration at T - t is the one at t mirrored in x, so eps0, G, V and
/// the pair's sum agree there, and a model without artificial viscosity at
/// the maximum is the same at both: it keeps `at_t`. The artificial
/// viscosity's Av sums only the approaching pairs (x > 0), which the mirror
/// exchanges with receding ones, so b and S differ: an `-av` model takes the
/// one with the smaller S, whose c0 = (U/N^2)(sqrt(S^2 alpha^2 + Q A) - S
/// alpha) (Q the same at both) is the larger at every Re and alpha where
/// either has a positive root: the stricter of the two instants, whichever
/// one the search happened to return.
pub fn stricter_mirror(at_t: ModelC0, at_mirror: ModelC0) -> ModelC0 {
    if !at_t.model.av_at_max {
        return at_t;
    }
    match (&at_t.coefs, &at_mirror.coefs) {
        (Ok(x), Ok(y)) if y.s < x.s => at_mirror,
        (Err(_), Ok(_)) => at_mirror,
        _ => at_t,
    }
}

/// The balance exactly; `None` when a = eps0 K = 0 (no c0).
pub fn derive(model: Model, eps0: &Exact, s0: &Sums, s1: &Sums, vf: &Exact) -> Option<Derivation> {
    let one_eps = &Exact::one() + eps0;
    let k = match model.carrier {
        Carrier::Field => &s1.g,
        Carrier::Pair => &s1.pair,
    };
    let a = eps0 * k;
    if a.is_zero() {
        return None;
    }
    let av_max = if model.av_at_max {
        s1.av.clone()
    } else {
        Exact::zero()
    };
    let b = &one_eps * &(&s0.av - &av_max);
    let c = &(&s1.g - &(vf * &s1.v)) + &(&one_eps * &(&(vf * &s0.v) - &s0.g));
    let s = Ratio::new(b.clone(), &Exact::int(2) * &a);
    let p = s.square();
    let q = Ratio::new(-&c, a.clone());
    Some(Derivation {
        model,
        a,
        b,
        c,
        s,
        p,
        q,
    })
}
