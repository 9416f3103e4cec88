//! The analytic solutions the solver is checked against: the steady profile
//! (7) of plane Poiseuille flow and its start-up from rest (Morris, Fox & Zhu
//! 1997), for walls at y = ±B and a body force p along +x.

use std::f64::consts::PI;

use serde::Serialize;

/// Relative accuracy of the start-up series: terms are summed until the
/// bound on the rest is below this times U.
const SERIES_TOL: f64 = 1e-15;

/// Below this tau = pi^2 nu t / L^2 the start-up is summed as its image
/// series in erfc instead of the sine series: the sine series needs about
/// sqrt(36 / tau) terms (1,000 here, 1e7 at tau = 1e-13), the image series
/// at most a few (each image is L / (2 sqrt(nu t)) >= 260 diffusion lengths
/// farther, so erfc of it is 0).
const SMALL_TAU: f64 = 4e-5;

/// Plane Poiseuille flow: half-width `b`, centre-line speed `u` (U), kinematic
/// viscosity `nu` and body force per unit mass `p`, tied by (9):
/// 2 nu U / B^2 = p.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Poiseuille {
    pub b: f64,
    pub u: f64,
    pub nu: f64,
    pub p: f64,
}

impl Poiseuille {
    /// From the Reynolds number Re = U B / nu: p = 2 U^2 / (Re B).
    pub fn from_re(u: f64, b: f64, re: f64) -> Self {
        Poiseuille {
            b,
            u,
            nu: u * b / re,
            p: 2.0 * u * u / (re * b),
        }
    }

    /// From the body force: nu = p B^2 / (2 U), the balance (9)-(10).
    pub fn from_p(u: f64, b: f64, p: f64) -> Self {
        Poiseuille {
            b,
            u,
            nu: p * b * b / (2.0 * u),
            p,
        }
    }

    /// Re = U B / nu.
    pub fn re(&self) -> f64 {
        self.u * self.b / self.nu
    }

    /// The steady profile (7): u(y) = U (B^2 - y^2) / B^2, zero outside the channel.
    pub fn steady(&self, y: f64) -> f64 {
        if y.abs() >= self.b {
            return 0.0;
        }
        self.u * (self.b * self.b - y * y) / (self.b * self.b)
    }

    /// Start-up from rest at time t, with y' = y + B in [0, L], L = 2B:
    /// u = p/(2 nu) y'(L - y') - sum_n 4 p L^2 / (nu pi^3 k^3) sin(k pi y'/L)
    /// exp(-k^2 pi^2 nu t / L^2), k = 2n + 1.
    pub fn startup(&self, y: f64, t: f64) -> f64 {
        if y.abs() >= self.b || t <= 0.0 {
            return 0.0;
        }
        let l = 2.0 * self.b;
        let yp = y + self.b;
        let amplitude = 4.0 * self.p * l * l / (self.nu * PI.powi(3));
        let tau = PI * PI * self.nu * t / (l * l);
        if tau < SMALL_TAU {
            return self.startup_small_t(yp, t);
        }
        let tol = SERIES_TOL * self.u;
        let mut sum = 0.0;
        let mut k = 1.0_f64;
        loop {
            let decay = (-k * k * tau).exp();
            let term = amplitude / (k * k * k) * decay;
            sum += term * (k * PI * yp / l).sin();
            // Bound on the rest of the series: the terms fall at least
            // geometrically with ratio exp(-4 k tau), and at least as 1/k^3
            // (tail below amplitude exp(-k^2 tau) / (4 k^2)).
            let ratio = (-4.0 * k * tau).exp();
            let geometric = term * ratio / (1.0 - ratio);
            let cubic = amplitude * decay / (4.0 * k * k);
            if geometric.min(cubic) < tol {
                break;
            }
            k += 2.0;
        }
        self.p / (2.0 * self.nu) * yp * (l - yp) - sum
    }

    /// The start-up at small t by images: u = p t - w, where w solves the
    /// diffusion equation with w = p t on both walls, the alternating sum
    /// over images of the half-space solution p t 4 i^2erfc(z), z = distance
    /// / (2 sqrt(nu t)), 4 i^2erfc(z) = (1 + 2 z^2) erfc(z) - 2 z exp(-z^2) /
    /// sqrt(pi). Exact; it is summed until the images' erfc vanish.
    fn startup_small_t(&self, yp: f64, t: f64) -> f64 {
        let l = 2.0 * self.b;
        let scale = 2.0 * (self.nu * t).sqrt();
        let half_space = |dist: f64| {
            let z = dist / scale;
            (1.0 + 2.0 * z * z) * libm::erfc(z) - 2.0 * z * (-z * z).exp() / PI.sqrt()
        };
        let mut w = 0.0;
        let mut sign = 1.0;
        for n in 0..64 {
            let n = f64::from(n);
            let pair = half_space(yp + n * l) + half_space((n + 1.0) * l - yp);
            w += sign * pair;
            sign = -sign;
            if pair == 0.0 {
                break;
            }
        }
        self.p * t * (1.0 - w)
    }

    /// Time for the slowest mode of the start-up series to fall below `tol`
    /// times U: its amplitude is 32 U / pi^3 and it decays as
    /// exp(-pi^2 nu t / L^2).
    pub fn decay_time(&self, tol: f64) -> f64 {
        let l = 2.0 * self.b;
        let amplitude = 32.0 / PI.powi(3);
        l * l / (PI * PI * self.nu) * (amplitude / tol).ln().max(0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn flow() -> Poiseuille {
        Poiseuille::from_re(1.0, 3.0, 10.0)
    }

    #[test]
    fn balance_ties_re_and_p() {
        let f = flow();
        let g = Poiseuille::from_p(f.u, f.b, f.p);
        assert!((g.nu - f.nu).abs() < 1e-15 * f.nu);
        assert!((f.re() - 10.0).abs() < 1e-12);
    }

    #[test]
    fn startup_starts_at_rest_and_tends_to_steady() {
        let f = flow();
        for &y in &[-2.9, -1.0, 0.0, 0.5, 2.0] {
            // Tiny time: the series is the sine series of the parabola.
            assert!(f.startup(y, 1e-9).abs() < 1e-3, "y = {y}");
            let late = f.startup(y, f.decay_time(1e-12));
            assert!((late - f.steady(y)).abs() < 1e-11, "y = {y}");
        }
    }

    #[test]
    fn startup_solves_the_diffusion_equation() {
        // du/dt = nu u'' + p, checked by central differences inside the channel.
        let f = flow();
        let (t, hy, ht) = (2.0, 1e-3, 1e-3);
        for &y in &[-2.0, -0.3, 0.0, 1.7] {
            let dudt = (f.startup(y, t + ht) - f.startup(y, t - ht)) / (2.0 * ht);
            let d2u =
                (f.startup(y + hy, t) - 2.0 * f.startup(y, t) + f.startup(y - hy, t)) / (hy * hy);
            assert!((dudt - (f.nu * d2u + f.p)).abs() < 1e-5, "y = {y}");
        }
    }

    #[test]
    fn small_t_images_match_the_sine_series() {
        // Where both are valid (tau just above and well above SMALL_TAU the
        // sine series is used; the image series is exact at every t), they
        // agree to rounding; below SMALL_TAU the image form is used.
        let f = flow();
        let l = 2.0 * f.b;
        for tau in [5e-5, 1e-4, 1e-3, 1e-2] {
            let t = tau * l * l / (PI * PI * f.nu);
            for &y in &[-2.99, -2.9, -1.0, 0.0, 0.5, 2.95] {
                let series = f.startup(y, t);
                let images = f.startup_small_t(y + f.b, t);
                assert!(
                    (series - images).abs() < 1e-13 * f.u,
                    "tau {tau} y {y}: {series} vs {images}"
                );
            }
        }
        // Tiny t: the centre moves as p t, the wall layer less.
        let t = 1e-12;
        assert!((f.startup(0.0, t) - f.p * t).abs() < 1e-15 * f.p * t);
        assert!(f.startup(-f.b + 1e-9, t) < f.p * t);
    }

    #[test]
    fn decay_time_matches_first_mode() {
        let f = flow();
        let t = f.decay_time(1e-3);
        // At that time the deficit at the centre is the first mode's, 1e-3 U
        // (higher modes are far smaller, and they alternate in sign).
        let deficit = f.steady(0.0) - f.startup(0.0, t);
        assert!((deficit - 1e-3).abs() < 1e-9, "deficit {deficit}");
    }
}
