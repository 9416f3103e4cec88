//! The particle lattice of a kind (`shearsph-lattice`: its dy and the odd
//! layers' offset; the triangular one of section 2 is the paper's), fluid
//! layers n = -(N-1) ..= N-1, wall layers beyond, in a periodic strip of
//! whole columns just wider than the support.

use serde::Serialize;

use crate::kernel::{Kernel, Lattice};

/// Relative tolerance for "a lattice distance equals the support", the same
/// as `Kernel::SUPPORT2_CLOSED`'s: neighbours at exactly q = R count.
pub const CLOSED_TOL: f64 = 1e-9;

/// The equation of state a lattice's sound waves are taken under
/// ([`LatticeGeometry::acoustic_stable_factor`]): P = (c0^2 rho0 / gamma)
/// ((rho / rho0)^gamma - 1), clamped at 0 unless negative pressures are
/// allowed, and the pressure term's form.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Eos {
    pub gamma: f64,
    pub allow_negative: bool,
    /// The symmetric form, -m sum (P_i / rho_i^2 + P_j / rho_j^2) grad W;
    /// else the paper's (12).
    pub symmetric: bool,
}

impl Eos {
    /// The equation of state of a scene's or problem's fields.
    pub fn new(gamma: f64, allow_negative: bool, form: crate::config::PressureForm) -> Eos {
        Eos {
            gamma,
            allow_negative,
            symmetric: form == crate::config::PressureForm::Symmetric,
        }
    }

    /// The equation of state a scene's fields give.
    pub fn of_scene(scene: &crate::config::Scene) -> Eos {
        Eos::new(
            scene.gamma,
            scene.allow_negative_pressure,
            scene.pressure_form,
        )
    }

    /// The pressure at rho = sigma rho0 (clamped at 0 unless negative
    /// pressures are allowed) and the slope dP / drho of a compression
    /// there, in units of rho0 = 1 and c0 = 1. Under the clamp, a lattice
    /// below rho0 has no pressure at rest; the waves that set the step are
    /// those of its compressed parts, at the slope taken here.
    fn at(self, sigma: f64) -> (f64, f64) {
        let p = (sigma.powf(self.gamma) - 1.0) / self.gamma;
        let p = if self.allow_negative { p } else { p.max(0.0) };
        (p, sigma.powf(self.gamma - 1.0))
    }
}

/// Where the particles sit and how many there are.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct LatticeGeometry {
    /// The lattice kind.
    pub kind: Lattice,
    /// Fluid half-width in layers: fluid layers |n| <= N - 1, B = N dy.
    pub n_layers: u32,
    pub d: f64,
    pub h: f64,
    /// Layer spacing: `kind.dy(d)` ((sqrt 3 / 2) d on the triangular lattice).
    pub dy: f64,
    /// Periodic strip: `columns` particles per layer, width = columns d
    /// (a whole number of the lattice's x period d, on either lattice).
    pub columns: u32,
    pub width: f64,
    /// Wall layers on each side, at |n| = N .. N + wall_layers - 1.
    pub wall_layers: u32,
}

impl LatticeGeometry {
    /// The lattice of kind `kind` for N layers, spacing d, smoothing length
    /// h and kernel support R (in h).
    ///
    /// Width: the fewest whole columns wider than 2 R h, so no particle sees
    /// two images of one neighbour. Walls: every layer within R h of the last
    /// fluid layer n = N - 1 (closed support), and no more.
    pub fn new(kind: Lattice, n_layers: u32, d: f64, h: f64, support: f64) -> Self {
        let reach = support * h * (1.0 + CLOSED_TOL);
        let dy = kind.dy(d);
        let columns = (2.0 * reach / d).floor() as u32 + 1;
        let wall_layers = (reach / dy).floor() as u32;
        LatticeGeometry {
            kind,
            n_layers,
            d,
            h,
            dy,
            columns,
            width: f64::from(columns) * d,
            wall_layers,
        }
    }

    /// Half-width of the channel, B = N dy: the first wall layer.
    pub fn b(&self) -> f64 {
        f64::from(self.n_layers) * self.dy
    }

    /// The area per particle, dy d: m = dy d rho0 (the paper's (11) on the
    /// triangular lattice, d^2 rho0 on the square one).
    pub fn area(&self) -> f64 {
        self.dy * self.d
    }

    /// Every site of the perfect, unbounded lattice within kernel K's
    /// closed support of a particle at the origin, itself included: (x, y,
    /// q^2), row by row from the lowest, each by x.
    fn support_sites<K: Kernel>(&self) -> Vec<(f64, f64, f64)> {
        let (d, h, dy) = (self.d, self.h, self.dy);
        let reach = K::SUPPORT2_CLOSED.sqrt() * h;
        let rows = (reach / dy).ceil() as i64;
        let cols = (reach / d).ceil() as i64 + 1;
        let inv_h2 = 1.0 / (h * h);
        let mut sites = Vec::new();
        for j in -rows..=rows {
            let shift = self.kind.offset(j) * d;
            let y = j as f64 * dy;
            for i in -cols..=cols {
                let x = i as f64 * d + shift;
                let q2 = (x * x + y * y) * inv_h2;
                if q2 <= K::SUPPORT2_CLOSED {
                    sites.push((x, y, q2));
                }
            }
        }
        sites
    }

    /// The viscous operator's lattice sum lambda = L_yy / sigma^2 for kernel
    /// K: what the solver's Laplacian, 2 (nu / sigma) sum_j (A / sigma)
    /// (u_i - u_j) F(r_ij) with F = W'(r) / r, gives for u = y^2 / 2 at a
    /// particle of the perfect, unbounded lattice, where the continuum gives
    /// one. sigma = A sum_j W(r_j) (self included) is the summation density
    /// over rho0, 1 + eps(0), so m / rho = A / sigma; L_yy = -A sum_j
    /// y_j^2 F(r_j) over the other sites, A = d dy; every site within the
    /// closed support counts, as in the solver's neighbour lists. A
    /// quadratic velocity is the steady profile (7), so the interior of a
    /// steady run has the viscosity lambda nu (`ViscousNormalisation`).
    pub fn viscous_lattice_sum<K: Kernel>(&self) -> f64 {
        let inv_h2 = 1.0 / (self.h * self.h);
        let (mut w_sum, mut lyy) = (0.0, 0.0);
        for (_, y, q2) in self.support_sites::<K>() {
            w_sum += K::w(q2) * inv_h2;
            if y != 0.0 {
                // The own row has y = 0 (and W' / r of the self site
                // may be infinite: (22b) is not 0 at q = 0).
                lyy -= y * y * K::w_dw_over_q_lanes(q2).1 * inv_h2 * inv_h2;
            }
        }
        let area = self.area();
        let sigma = area * w_sum;
        area * lyy / (sigma * sigma)
    }

    /// The largest factor F of the viscous limit dt <= F h^2 / nu at which
    /// the solver's viscous term is stable on the perfect, unbounded
    /// lattice, for kernel K: F = 1 / (h^2 Lambda / nu), with Lambda the
    /// largest rate at which the term, 2 (nu / sigma) sum_j (A / sigma)
    /// (u_i - u_j) F(r_ij), damps a velocity mode u_j = cos(k . r_j) over
    /// the wave vectors k: Lambda(k) = 2 (nu / sigma^2) A sum_j (-F(r_j))
    /// (1 - cos(k . r_j)) over the other sites within the closed support
    /// (sigma and A as in [`Self::viscous_lattice_sum`]). The solver's
    /// step is stable while dt Lambda <= 1: runs from rest at Re = 1 went
    /// unstable at no factor below this one and by 1.16 times it on every
    /// kernel and discretisation measured (docs/timestep.md). The maximum over k
    /// is taken on a grid over the reciprocal cell and refined from the
    /// best point by a pattern search, to a relative 1e-12 of the rate.
    pub fn viscous_stable_factor<K: Kernel>(&self) -> f64 {
        let inv_h2 = 1.0 / (self.h * self.h);
        let mut w_sum = 0.0;
        // (x, y, -F h^4) of every other site in the support.
        let mut sites = Vec::new();
        for (x, y, q2) in self.support_sites::<K>() {
            w_sum += K::w(q2) * inv_h2;
            if x != 0.0 || y != 0.0 {
                sites.push((x, y, -K::w_dw_over_q_lanes(q2).1));
            }
        }
        let best = self.max_over_wave_vectors(|kx, ky| {
            sites
                .iter()
                .map(|&(x, y, f)| f * (1.0 - (kx * x + ky * y).cos()))
                .sum::<f64>()
        });
        let area = self.area();
        let sigma = area * w_sum;
        // h^2 Lambda / nu, with F = (-F h^4) / h^4.
        let rate_h2_over_nu = 2.0 * area * best * inv_h2 / (sigma * sigma);
        if rate_h2_over_nu > 0.0 {
            1.0 / rate_h2_over_nu
        } else {
            // A term that damps no mode (a kernel whose gradient vanishes
            // at every neighbour) sets no limit.
            f64::INFINITY
        }
    }

    /// The largest value of `rate(kx, ky)` over the wave vectors k of the
    /// lattice's reciprocal cell: a 48 x 48 grid over the cell, refined from
    /// its best point by a pattern search to a relative 1e-12 of the value.
    fn max_over_wave_vectors(&self, rate: impl Fn(f64, f64) -> f64) -> f64 {
        let (d, dy) = (self.d, self.dy);
        // The reciprocal basis of the lattice's a1 = (d, 0), a2 = (shift
        // of layer 1, dy): k = s b1 + t b2, (s, t) over [0, 1)^2.
        let c = self.kind.offset(1) * d;
        let tau = std::f64::consts::TAU;
        let (b1, b2) = ((tau / d, -tau * c / (d * dy)), (0.0, tau / dy));
        let rate = |s: f64, t: f64| rate(s * b1.0 + t * b2.0, s * b1.1 + t * b2.1);
        const GRID: u32 = 48;
        let mut best = (0.0, 0.0, f64::NEG_INFINITY);
        for a in 0..GRID {
            for b in 0..GRID {
                let (s, t) = (
                    f64::from(a) / f64::from(GRID),
                    f64::from(b) / f64::from(GRID),
                );
                let r = rate(s, t);
                if r > best.2 {
                    best = (s, t, r);
                }
            }
        }
        let mut step = 1.0 / f64::from(GRID);
        while step > 1e-9 {
            let (s, t, r) = best;
            let around = [(step, 0.0), (-step, 0.0), (0.0, step), (0.0, -step)]
                .map(|(ds, dt)| (s + ds, t + dt, rate(s + ds, t + dt)));
            match around.into_iter().find(|p| p.2 > r * (1.0 + 1e-12)) {
                Some(p) => best = p,
                None => step /= 2.0,
            }
        }
        best.2
    }

    /// The largest factor of the CFL limit dt <= CFL h / c0 at which the
    /// solver's pressure term is stable on the perfect, unbounded lattice
    /// for kernel K, its fluid at rest under the equation of state `eos`:
    /// CFL = 2 / (h omega_max / c0).
    ///
    /// A displacement wave xi_j = xi e^(i k . r_j) of the lattice changes
    /// the summation density by delta rho = i m G(k) . xi, with G(k) =
    /// sum_j grad W(r_j) sin(k . r_j) over the other sites within the
    /// closed support. The pressure term, linearised about the lattice's
    /// density rho = rho0 sigma and pressure P, accelerates it by -D(k) xi:
    ///
    /// - paper form, -(m / rho_i^2) sum_j (P_i + P_j) grad_i W_ij:
    ///   D = (m / rho^2) (m P' G G^T + 2 P M(k));
    /// - symmetric form, -m sum_j (P_i / rho_i^2 + P_j / rho_j^2) grad_i W_ij:
    ///   D = (m / rho^2) (m (P' - 2 P / rho) G G^T + 2 P M(k));
    ///
    /// P' the equation of state's slope there (that of a compression, also
    /// where the clamp holds a lattice below rho0 at P = 0), M(k) = sum_j H(r_j) (1 -
    /// cos(k . r_j)) and H the Hessian of W (the second term: the lattice's
    /// own pressure acting on the kernel's curvature, which the compaction
    /// eps0 = sigma - 1 of a kernel far from its lattice makes large). The
    /// sound waves' omega^2 are D's eigenvalues; the kick-drift-kick
    /// leapfrog keeps a wave bounded while dt omega <= 2, so the factor is
    /// 2 / (h sqrt(max_k lambda_max(D)) / c0), the maximum over k as in
    /// [`Self::viscous_stable_factor`]. H takes the derivative of W' / r
    /// by central differences in q^2, from inside the support for a
    /// neighbour at its edge. Infinite where no wave oscillates (a kernel
    /// whose gradient vanishes at every neighbour). The viscous terms,
    /// which damp, and the speeds |v| in the limit's denominator, which
    /// shorten the step, are not in it. Checked against runs: the onset
    /// within 3 % of it for Monaghan's and Morris's kernels, 3-10 % below
    /// it for Wendland C2; the composite kernel's square lattice at h = d
    /// keeps no order at any factor, so no factor applies there
    /// (docs/timestep.md).
    pub fn acoustic_stable_factor<K: Kernel>(&self, eos: Eos) -> f64 {
        let (h, area) = (self.h, self.area());
        let inv_h2 = 1.0 / (h * h);
        let mut w_sum = 0.0;
        // (x, y, f, f') of every other site in the support, f = (dW/dq)/q
        // in units h^-4 and f' its derivative in q^2: grad W = f r / h^4,
        // H = (f I + 2 f' r r^T / h^2) / h^4.
        let mut sites = Vec::new();
        let f = |q2: f64| K::w_dw_over_q_lanes(q2).1;
        let step = 1e-6 * K::SUPPORT2_CLOSED;
        for (x, y, q2) in self.support_sites::<K>() {
            w_sum += K::w(q2) * inv_h2;
            if x != 0.0 || y != 0.0 {
                // Inside the support: at its edge (a neighbour at q = R
                // exactly, which the closed support lists) from below, a
                // kernel whose gradient does not vanish there jumping to 0
                // beyond it.
                let slope = if q2 + step <= K::SUPPORT2_CLOSED {
                    (f(q2 + step) - f(q2 - step)) / (2.0 * step)
                } else {
                    (3.0 * f(q2) - 4.0 * f(q2 - step) + f(q2 - 2.0 * step)) / (2.0 * step)
                };
                sites.push((x, y, f(q2), slope));
            }
        }
        let sigma = area * w_sum;
        // In units of rho0 = 1 and c0 = 1: m = A, the pressure and slope at
        // rho = sigma, and the factors of G G^T and M in D.
        let (p, slope) = eos.at(sigma);
        let scale = area / (sigma * sigma);
        let g_coef = scale
            * area
            * if eos.symmetric {
                slope - 2.0 * p / sigma
            } else {
                slope
            };
        let m_coef = scale * 2.0 * p;
        let inv_h4 = inv_h2 * inv_h2;
        let omega2_max = self.max_over_wave_vectors(|kx, ky| {
            let (mut g, mut m) = ([0.0; 2], [0.0; 3]);
            for &(x, y, f, fd) in &sites {
                let phase = kx * x + ky * y;
                let (sin, one_minus_cos) = (phase.sin(), 1.0 - phase.cos());
                g[0] += f * x * sin;
                g[1] += f * y * sin;
                let c = 2.0 * fd * inv_h2 * one_minus_cos;
                m[0] += f * one_minus_cos + c * x * x;
                m[1] += c * x * y;
                m[2] += f * one_minus_cos + c * y * y;
            }
            // G = g / h^4 and M = m / h^4.
            let gg = g_coef * inv_h4 * inv_h4;
            let mm = m_coef * inv_h4;
            let d = [
                gg * g[0] * g[0] + mm * m[0],
                gg * g[0] * g[1] + mm * m[1],
                gg * g[1] * g[1] + mm * m[2],
            ];
            let (mean, half) = (0.5 * (d[0] + d[2]), 0.5 * (d[0] - d[2]));
            mean + (half * half + d[1] * d[1]).sqrt()
        });
        // omega^2 in units of c0^2 (rho0 = c0 = 1): h omega_max / c0.
        let omega_h = h * omega2_max.max(0.0).sqrt();
        if omega_h > 0.0 {
            2.0 / omega_h
        } else {
            f64::INFINITY
        }
    }

    pub fn fluid_layers(&self) -> u32 {
        2 * self.n_layers - 1
    }

    pub fn n_fluid(&self) -> usize {
        (self.fluid_layers() * self.columns) as usize
    }

    pub fn n_wall(&self) -> usize {
        (2 * self.wall_layers * self.columns) as usize
    }

    pub fn n_particles(&self) -> usize {
        self.n_fluid() + self.n_wall()
    }

    /// Layer indices in storage order: fluid layers bottom to top, then the
    /// walls bottom then top. Particles of one layer are stored together.
    pub fn layers(&self) -> impl Iterator<Item = i32> {
        let n = self.n_layers as i32;
        let m = self.wall_layers as i32;
        (-(n - 1)..n).chain(-(n + m - 1)..=-n).chain(n..n + m)
    }

    /// Positions and layer index of every particle, in storage order.
    pub fn positions(&self) -> (Vec<f64>, Vec<f64>, Vec<i32>) {
        let cap = self.n_particles();
        let (mut x, mut y, mut layer) = (
            Vec::with_capacity(cap),
            Vec::with_capacity(cap),
            Vec::with_capacity(cap),
        );
        for n in self.layers() {
            let offset = self.kind.offset(n) * self.d;
            for c in 0..self.columns {
                x.push(f64::from(c) * self.d + offset);
                y.push(f64::from(n) * self.dy);
                layer.push(n);
            }
        }
        (x, y, layer)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strip_and_walls_fit_the_support() {
        // R = 1, 2, 3 with h = d: widths 3, 5, 7; walls floor(R / dy) = 1, 2, 3.
        for (r, cols, walls) in [(1.0, 3, 1), (2.0, 5, 2), (3.0, 7, 3)] {
            let l = LatticeGeometry::new(Lattice::Triangular, 10, 1.0, 1.0, r);
            assert_eq!((l.columns, l.wall_layers), (cols, walls), "R = {r}");
        }
        // A support of exactly 2 dy reaches the second wall layer (closed).
        let l = LatticeGeometry::new(Lattice::Triangular, 10, 1.0, 3f64.sqrt() / 2.0, 2.0);
        assert_eq!(l.wall_layers, 2);
        // Square, R h = 2.6 d (Wendland C2 at h = 1.3 d): 6 columns, 2 walls;
        // R h = 2 d exactly reaches the second wall layer.
        let l = LatticeGeometry::new(Lattice::Square, 10, 1.0, 1.3, 2.0);
        assert_eq!((l.columns, l.wall_layers, l.dy), (6, 2, 1.0));
        let l = LatticeGeometry::new(Lattice::Square, 10, 1.0, 1.0, 2.0);
        assert_eq!((l.columns, l.wall_layers), (5, 2));
    }

    #[test]
    fn square_lattice_has_no_offset() {
        let l = LatticeGeometry::new(Lattice::Square, 4, 1.0, 1.0, 2.0);
        let (x, y, layer) = l.positions();
        for i in 0..x.len() {
            assert_eq!(x[i], f64::from(i as u32 % l.columns));
            assert_eq!(y[i], f64::from(layer[i]));
        }
        assert_eq!(l.area(), 1.0);
    }

    #[test]
    fn positions_cover_fluid_then_walls() {
        let l = LatticeGeometry::new(Lattice::Triangular, 4, 1.0, 1.0, 2.0);
        let (x, y, layer) = l.positions();
        assert_eq!(x.len(), l.n_particles());
        assert_eq!(l.n_fluid(), 7 * 5);
        assert!(layer[..l.n_fluid()].iter().all(|n| n.abs() < 4));
        assert!(layer[l.n_fluid()..].iter().all(|n| n.abs() >= 4));
        let b = l.b();
        assert!(y[..l.n_fluid()].iter().all(|y| y.abs() < b));
        // Odd layers are offset by d / 2.
        let first_odd = layer.iter().position(|&n| n == 1).unwrap();
        assert_eq!(x[first_odd], 0.5);
    }
}
