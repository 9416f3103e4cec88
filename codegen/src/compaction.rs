//! The compaction analysis of section 4: eps(t, n) = rho_i(t, n)/rho0 - 1 with
//! rho_i = m sum_j W(r_ij/h)/h^2, m = dy d rho0 (11), for a particle of layer
//! n as the layers shear past it (see `lattice`), on any [`Discretisation`].
//! Exact at t = 0 and t = 0.5 T; extremes found by search (f64 scan, then
//! golden section at high precision); the time mean from per-layer line
//! integrals (exact for pieces even in q, Gauss-Legendre at high precision
//! otherwise, with the digits stated).

use crate::exact::{decimal, Exact};
use crate::kernel::Radial;
use crate::lattice::{
    layer_speed, max_layer_offset, row_reach, stencil, Config, Discretisation, ExactLattice,
};
use crate::poly::Poly;
use rug::{Float, Rational};

/// The particle area m/rho0 in h^2: dy d / h^2 (sqrt(3)/2 for the paper's).
pub fn cell_area(disc: &Discretisation) -> Exact {
    &Exact::sqrt_rational(&disc.lattice.dy2()) * &Exact::rational(Rational::from(1) / disc.h2())
}

/// eps in a configuration, exactly: (dy d/h^2) sum_j W(r_j/h) - 1.
pub fn eps_exact(w: &Radial, support: &Rational, disc: &Discretisation, config: Config) -> Exact {
    let h2 = disc.h2();
    let mut sum = Exact::zero();
    for nb in stencil(disc, support, config) {
        sum = &sum + &w.eval_q2(&Rational::from(&nb.r2 / &h2));
    }
    &(&cell_area(disc) * &sum) - &Exact::one()
}

/// W's pieces in floating point at a given precision, for fast evaluation.
#[derive(Clone, Debug)]
pub struct FloatRadial {
    prec: u32,
    /// (to^2, coefficients low to high)
    pieces: Vec<(Float, Vec<Float>)>,
    pieces_f64: Vec<(f64, Vec<f64>)>,
    support2: Float,
    support2_f64: f64,
}

impl FloatRadial {
    pub fn new(w: &Radial, prec: u32) -> Self {
        let pieces: Vec<(Float, Vec<Float>)> = w
            .pieces
            .iter()
            .map(|p| {
                (
                    Float::with_val(prec, Rational::from(&p.to * &p.to)),
                    p.poly.coef.iter().map(|c| c.to_float(prec)).collect(),
                )
            })
            .collect();
        let pieces_f64 = pieces
            .iter()
            .map(|(t, c)| (t.to_f64(), c.iter().map(|x| x.to_f64()).collect()))
            .collect();
        let s = w.support();
        let support2 = Float::with_val(prec, Rational::from(s * s));
        let support2_f64 = support2.to_f64();
        FloatRadial {
            prec,
            pieces,
            pieces_f64,
            support2,
            support2_f64,
        }
    }

    pub fn eval(&self, q2: &Float) -> Float {
        for (to2, coef) in &self.pieces {
            if q2 <= to2 {
                let q = Float::with_val(self.prec, q2.sqrt_ref());
                let mut acc = Float::with_val(self.prec, 0);
                for c in coef.iter().rev() {
                    acc *= &q;
                    acc += c;
                }
                return acc;
            }
        }
        Float::with_val(self.prec, 0)
    }

    pub fn eval_f64(&self, q2: f64) -> f64 {
        for (to2, coef) in &self.pieces_f64 {
            if q2 <= *to2 {
                let q = q2.sqrt();
                return coef.iter().rev().fold(0.0, |acc, c| acc * q + c);
            }
        }
        0.0
    }
}

/// Where a particle sits: its layer n, and N (walls at |j| >= N), or `None`
/// for an interior particle with no wall in reach.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Site {
    pub n: i64,
    pub n_layers: Option<i64>,
}

impl Site {
    pub const CENTRE: Site = Site {
        n: 0,
        n_layers: None,
    };
}

/// eps(t, n) as a function of tau = t/T, evaluable in f64 and at high
/// precision.
pub struct EpsCurve<'a> {
    w: &'a FloatRadial,
    kmax: i64,
    reach: i64,
    site: Site,
    /// phase0 of layer k (index k + kmax), dy^2 (d^2), (d/h)^2, area (h^2)
    phase0: Vec<Rational>,
    dy2: Rational,
    inv_h2: Rational,
    area: Exact,
}

impl<'a> EpsCurve<'a> {
    pub fn new(w: &'a FloatRadial, support: &Rational, disc: &Discretisation, site: Site) -> Self {
        let kmax = max_layer_offset(disc, support);
        EpsCurve {
            w,
            kmax,
            reach: row_reach(disc, support),
            site,
            phase0: (-kmax..=kmax).map(|k| disc.lattice.phase0(k)).collect(),
            dy2: disc.lattice.dy2(),
            inv_h2: Rational::from(1) / disc.h2(),
            area: cell_area(disc),
        }
    }

    /// The largest |speed| of a layer in reach: the curve's top frequency.
    pub fn max_frequency(&self) -> i64 {
        (-self.kmax..=self.kmax)
            .map(|k| layer_speed(self.site.n, k, self.site.n_layers).abs())
            .max()
            .unwrap_or(0)
    }

    /// The neighbours at tau (positions in d, at `prec` bits): (x, k, r^2).
    pub fn neighbours(&self, tau: &Float) -> Vec<(Float, i64, Float)> {
        let prec = self.w.prec;
        let mut out = Vec::new();
        let r2max = Float::with_val(prec, &self.w.support2 / self.inv_h2.clone());
        for k in -self.kmax..=self.kmax {
            let speed = layer_speed(self.site.n, k, self.site.n_layers);
            let mut ph =
                Float::with_val(prec, tau * speed) + &self.phase0[(k + self.kmax) as usize];
            let fl = Float::with_val(prec, ph.floor_ref());
            ph -= fl;
            let y2 = Float::with_val(prec, Rational::from(&self.dy2 * (k * k)));
            for a in -self.reach..=self.reach {
                let x = Float::with_val(prec, &ph + a);
                let r2 = Float::with_val(prec, x.square_ref()) + &y2;
                if r2 <= r2max {
                    out.push((x, k, r2));
                }
            }
        }
        out
    }

    pub fn eval_f64(&self, tau: f64) -> f64 {
        let s2 = self.w.support2_f64;
        let inv_h2 = self.inv_h2.to_f64();
        let dy2 = self.dy2.to_f64();
        let mut sum = 0.0;
        for k in -self.kmax..=self.kmax {
            let speed = layer_speed(self.site.n, k, self.site.n_layers) as f64;
            let ph = self.phase0[(k + self.kmax) as usize].to_f64() + speed * tau;
            let ph = ph - ph.floor();
            let y2 = dy2 * (k * k) as f64;
            for a in -self.reach..=self.reach {
                let x = a as f64 + ph;
                let q2 = (x * x + y2) * inv_h2;
                if q2 <= s2 {
                    sum += self.w.eval_f64(q2);
                }
            }
        }
        self.area.to_f64() * sum - 1.0
    }

    pub fn eval(&self, tau: &Float) -> Float {
        let prec = self.w.prec;
        let mut sum = Float::with_val(prec, 0);
        for (_, _, r2) in self.neighbours(tau) {
            sum += self.w.eval(&Float::with_val(prec, r2 * &self.inv_h2));
        }
        sum * self.area.to_float(prec) - 1
    }
}

/// An extreme of eps over the period found by search.
#[derive(Clone, Debug)]
pub struct Extreme {
    pub tau: Float,
    pub value: Float,
}

/// Scans eps on a grid fine enough for its top frequency, then refines every
/// local extreme by golden section at the curve's precision; returns the
/// global maximum and minimum over [0, 1] (the one with the smaller tau when
/// the curve is symmetric).
pub fn extremes(curve: &EpsCurve) -> (Extreme, Extreme) {
    let samples = (256 * curve.max_frequency().max(1)) as usize;
    let vals: Vec<f64> = (0..samples)
        .map(|i| curve.eval_f64(i as f64 / samples as f64))
        .collect();
    let best = |sign: f64| -> Extreme {
        // local extremes of sign*eps on the periodic grid
        let mut cands: Vec<(f64, usize)> = (0..samples)
            .filter(|&i| {
                let l = vals[(i + samples - 1) % samples] * sign;
                let r = vals[(i + 1) % samples] * sign;
                let c = vals[i] * sign;
                c >= l && c >= r
            })
            .map(|i| (vals[i] * sign, i))
            .collect();
        cands.sort_by(|a, b| b.0.partial_cmp(&a.0).unwrap().then(a.1.cmp(&b.1)));
        cands.truncate(8);
        let mut out: Option<Extreme> = None;
        for (_, i) in cands {
            let e = golden(
                curve,
                (i as f64 - 1.0) / samples as f64,
                (i as f64 + 1.0) / samples as f64,
                sign,
            );
            let better = match &out {
                None => true,
                Some(o) => {
                    let d = Float::with_val(o.value.prec(), &e.value - &o.value) * sign;
                    let tol = Float::with_val(o.value.prec(), 1e-30);
                    d > tol || (d.abs() <= tol && e.tau < o.tau)
                }
            };
            if better {
                out = Some(e);
            }
        }
        out.expect("a periodic curve has extremes")
    };
    (best(1.0), best(-1.0))
}

/// Golden-section search for the extreme of sign*eps on [a, b] (tau wrapped
/// into [0, 1)).
fn golden(curve: &EpsCurve, a: f64, b: f64, sign: f64) -> Extreme {
    let prec = curve.w.prec;
    let mut a = Float::with_val(prec, a);
    let mut b = Float::with_val(prec, b);
    let g = (Float::with_val(prec, 5).sqrt() - 1u32) / 2u32; // 0.618...
    let f = |t: &Float| curve.eval(t) * sign;
    let mut c = Float::with_val(prec, &b - &a) * &g;
    c = Float::with_val(prec, &b - &c);
    let mut d = Float::with_val(prec, &b - &a) * &g;
    d += &a;
    let (mut fc, mut fd) = (f(&c), f(&d));
    let tol = Float::with_val(prec, Float::i_exp(1, -((prec / 2) as i32)));
    let mut iters = 0;
    while Float::with_val(prec, &b - &a) > tol && iters < 2 * prec {
        if fc > fd {
            b = d;
            d = c.clone();
            fd = fc;
            c = Float::with_val(prec, &b - &a) * &g;
            c = Float::with_val(prec, &b - &c);
            fc = f(&c);
        } else {
            a = c;
            c = d.clone();
            fc = fd;
            d = Float::with_val(prec, &b - &a) * &g;
            d += &a;
            fd = f(&d);
        }
        iters += 1;
    }
    let mut tau = Float::with_val(prec, &a + &b) / 2u32;
    let fl = Float::with_val(prec, tau.floor_ref());
    tau -= fl;
    let value = curve.eval(&tau);
    Extreme { tau, value }
}

/// A value known exactly or to stated high precision.
#[derive(Clone, Debug)]
pub struct Known {
    pub value: Float,
    pub exact: Option<Exact>,
    /// Correct decimal digits (significant) when not exact.
    pub digits: Option<u32>,
    /// How it was obtained, for the reader.
    pub how: String,
}

impl Known {
    pub fn exact(e: Exact, prec: u32, how: &str) -> Self {
        Known {
            value: e.to_float(prec),
            exact: Some(e),
            digits: None,
            how: how.to_string(),
        }
    }

    /// "exact form" or "<decimal> (D digits)".
    pub fn form(&self) -> String {
        match &self.exact {
            Some(e) => e.to_string(),
            None => format!(
                "{} ({} significant digits, {})",
                decimal(&self.value, self.digits.unwrap_or(30) as usize),
                self.digits.unwrap_or(0),
                self.how
            ),
        }
    }
}

/// The integral over the whole line of W(sqrt(x^2 + y2)) dx: exact for
/// pieces even in q, Gauss-Legendre at `prec` bits for the others. Returns
/// the value, the exact part, and an error estimate of the quadrature part
/// (zero when all exact).
pub fn line_integral(w: &Radial, y2: &Rational, prec: u32) -> (Float, Exact, Float) {
    let mut exact = Exact::zero();
    let mut quad = Float::with_val(prec, 0);
    let mut err = Float::with_val(prec, 0);
    for p in &w.pieces {
        let a2 = Rational::from(&p.from * &p.from);
        let b2 = Rational::from(&p.to * &p.to);
        if b2 <= *y2 {
            continue;
        }
        // x from sqrt(max(a^2 - y2, 0)) to sqrt(b^2 - y2); both halves of the line
        let x0sq = if a2 > *y2 {
            Rational::from(&a2 - y2)
        } else {
            Rational::new()
        };
        let x1sq = Rational::from(&b2 - y2);
        if p.poly.is_even() {
            // p(q) = sum c_2m (x^2 + y2)^m: a polynomial in x
            let xsq_plus = Poly {
                coef: vec![Exact::rational(y2.clone()), Exact::zero(), Exact::one()],
            };
            let mut in_x = Poly::default();
            for (e, c) in p.poly.coef.iter().enumerate().step_by(2) {
                in_x = in_x.add(&xsq_plus.pow((e / 2) as u32).scale(c));
            }
            // antiderivative
            let mut anti = vec![Exact::zero()];
            for (e, c) in in_x.coef.iter().enumerate() {
                anti.push(c * &Exact::rational(Rational::from((1, e as i64 + 1))));
            }
            let anti = Poly { coef: anti };
            let part = &anti.eval_sqrt(&x1sq) - &anti.eval_sqrt(&x0sq);
            exact = &exact + &(&part * &Exact::int(2));
        } else {
            let lo = Float::with_val(prec, &x0sq).sqrt();
            let hi = Float::with_val(prec, &x1sq).sqrt();
            let y = Float::with_val(prec, y2).sqrt();
            let coef: Vec<Float> = p.poly.coef.iter().map(|c| c.to_float(prec)).collect();
            let f = |x: &Float| {
                let q = Float::with_val(prec, Float::with_val(prec, x.square_ref()) + &y2.clone())
                    .sqrt();
                let mut acc = Float::with_val(prec, 0);
                for c in coef.iter().rev() {
                    acc *= &q;
                    acc += c;
                }
                acc
            };
            // sub-intervals no longer than y/2 keep the singularities at x = +-i y far away
            let span = Float::with_val(prec, &hi - &lo);
            let pieces = (span.to_f64() / (0.5 * y.to_f64().max(1e-3)))
                .ceil()
                .max(1.0) as u32;
            let (coarse, fine) = (gauss_legendre(24, prec), gauss_legendre(48, prec));
            for s in 0..pieces {
                let a = Float::with_val(prec, &lo + Float::with_val(prec, &span * s) / pieces);
                let b =
                    Float::with_val(prec, &lo + Float::with_val(prec, &span * (s + 1)) / pieces);
                let i1 = integrate(&f, &a, &b, &coarse, prec);
                let i2 = integrate(&f, &a, &b, &fine, prec);
                err += Float::with_val(prec, &i2 - &i1).abs() * 2u32;
                quad += i2 * 2u32;
            }
        }
    }
    let value = Float::with_val(prec, exact.to_float(prec) + &quad);
    (value, exact, err)
}

fn integrate(
    f: &dyn Fn(&Float) -> Float,
    a: &Float,
    b: &Float,
    rule: &[(Float, Float)],
    prec: u32,
) -> Float {
    let half = Float::with_val(prec, b - a) / 2u32;
    let mid = Float::with_val(prec, b + a) / 2u32;
    let mut acc = Float::with_val(prec, 0);
    for (x, wgt) in rule {
        let t = Float::with_val(prec, &mid + Float::with_val(prec, &half * x));
        acc += f(&t) * wgt;
    }
    acc * half
}

/// Gauss-Legendre nodes and weights on [-1, 1] at `prec` bits (Newton on the
/// Legendre recurrence).
pub fn gauss_legendre(n: usize, prec: u32) -> Vec<(Float, Float)> {
    let pi = Float::with_val(prec, rug::float::Constant::Pi);
    let mut out = Vec::with_capacity(n);
    for i in 1..=n {
        let guess = Float::with_val(prec, &pi * (i as f64 - 0.25)) / (n as f64 + 0.5);
        let mut x = guess.cos();
        let mut dp = Float::with_val(prec, 0);
        for _ in 0..100 {
            // P_n(x) and P_n'(x)
            let mut p0 = Float::with_val(prec, 1);
            let mut p1 = x.clone();
            for j in 2..=n {
                let p2 = (Float::with_val(prec, &x * &p1) * (2 * j - 1) as u32
                    - Float::with_val(prec, &p0 * (j - 1) as u32))
                    / j as u32;
                p0 = p1;
                p1 = p2;
            }
            // P_n' = n (x P_n - P_{n-1}) / (x^2 - 1)
            let x2m1 = Float::with_val(prec, x.square_ref()) - 1u32;
            dp = (Float::with_val(prec, &x * &p1) - &p0) * n as u32 / &x2m1;
            let dx = Float::with_val(prec, &p1 / &dp);
            x -= &dx;
            if dx.is_zero() || dx.get_exp().unwrap_or(0) < -(prec as i32) + 4 {
                break;
            }
        }
        let x2 = Float::with_val(prec, x.square_ref());
        let wgt = Float::with_val(prec, 2)
            / (Float::with_val(prec, 1u32 - x2) * Float::with_val(prec, dp.square_ref()));
        out.push((x, wgt));
    }
    out
}

/// The time mean of eps over T for a particle at `site`: layers that move
/// (nonzero integer speed) average to their line integral; layers at rest
/// relative to the particle (its own, and for 0 < n the mirror layer -n if
/// in reach) keep their t = 0 sum.
pub fn mean(w: &Radial, support: &Rational, disc: &Discretisation, site: Site, prec: u32) -> Known {
    let kmax = max_layer_offset(disc, support);
    let h2 = disc.h2();
    let h = Exact::rational(disc.h.clone());
    let mut exact = Exact::zero();
    let mut quad = Float::with_val(prec, 0);
    let mut err = Float::with_val(prec, 0);
    let mut quadrature_used = false;
    let t0 = stencil(disc, support, Config::T0);
    for k in -kmax..=kmax {
        if layer_speed(site.n, k, site.n_layers) == 0 {
            for nb in t0.iter().filter(|nb| nb.k == k) {
                exact = &exact + &w.eval_q2(&Rational::from(&nb.r2 / &h2));
            }
        } else {
            // a moving row averages to its line integral: in h units, times h/d
            let y2 = disc.lattice.dy2() * (k * k) / &h2;
            let (v, e, er) = line_integral(w, &y2, prec);
            let (v, e, er) = (
                Float::with_val(prec, v * &disc.h),
                &e * &h,
                Float::with_val(prec, er * &disc.h),
            );
            let q = Float::with_val(prec, &v - e.to_float(prec));
            if !q.is_zero() || !er.is_zero() {
                quadrature_used = true;
            }
            exact = &exact + &e;
            quad += q;
            err += er;
        }
    }
    let c = cell_area(disc);
    if !quadrature_used {
        let e = &(&c * &exact) - &Exact::one();
        return Known::exact(e, prec, "exact: line integrals of pieces even in q");
    }
    let value = Float::with_val(prec, (exact.to_float(prec) + &quad) * c.to_float(prec)) - 1u32;
    let err = Float::with_val(prec, err * c.to_float(prec));
    // significant digits: limited by the quadrature error estimate and the precision
    let mag = value.clone().abs().log10().to_f64();
    let err_digits = if err.is_zero() {
        f64::INFINITY
    } else {
        mag - err.log10().to_f64()
    };
    let prec_digits = prec as f64 * std::f64::consts::LOG10_2 - 10.0;
    let digits = err_digits.min(prec_digits).floor().max(1.0) as u32;
    Known {
        value,
        exact: None,
        digits: Some(digits),
        how: "Gauss-Legendre quadrature of the layers' line integrals".into(),
    }
}
