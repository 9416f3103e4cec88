//! The lattices of the analysis, as data: a [`Discretisation`] is a lattice
//! kind and h/d. Lengths here are in d (the particle spacing along x).
//!
//! The kinds are described once, in the crate `shearsph-lattice`
//! (`lattice/`), which the solver reads too: each is a name, dy^2 (exact,
//! rational) and the offset of its odd layers (0 or 1/2); [`ExactLattice`]
//! turns those integers into rationals here. The paper's (section 2) is
//! `triangular`: dy = (sqrt(3)/2) d, odd layers offset by d/2; `square`
//! (PySPH, DualSPHysics, SPHinXsys) has dy = d and no offset.
//!
//! Fluid layers are |j| < N, walls |j| >= N (fixed, u = 0), B = N dy.
//!
//! Kinematics, derived from dy and the initial offset: under the steady shear
//! (7) layer j (at y = j dy) moves at u(j) = U (1 - (j dy)^2 / B^2) = U (1 -
//! j^2/N^2) whatever dy is, because B = N dy. Over t = tau T (T = d N^2 / U,
//! (19)) layer j moves by (n^2 - j^2) tau (in d) relative to a particle of
//! layer n, a wall layer by (n^2 - N^2) tau. These multipliers are integers
//! and every layer is periodic in x with period d, so every neighbourhood is
//! periodic with T on every lattice. The phase of layer k = j - n at tau is
//! phase0(k) + (n^2 - j^2) tau (mod 1), phase0 being the initial offset. The
//! symmetric configurations are tau = 0 and tau = 1/2: n^2 - j^2 = -k (2n + k)
//! is odd exactly when k is, so at 1/2 odd relative layers gain an offset of
//! 1/2 and even ones return to place; with the odd layers' initial offset 0
//! or 1/2 every phase is 0 or 1/2 and the neighbourhood is mirror-symmetric,
//! with r^2 = x^2 + k^2 dy^2 rational (dy^2 is: 3/4 or 1). On the triangular
//! lattice tau = 1/2 puts every layer straight above the particle; on the
//! square lattice it staggers the odd layers (a triangular-like arrangement).

use rug::Rational;
pub use shearsph_lattice::Lattice;
use shearsph_lattice::Ratio;

/// A lattice kind's exact numbers as rationals, from the integers of its
/// entry in `shearsph-lattice`.
pub trait ExactLattice {
    /// dy^2 / d^2: 3/4 or 1.
    fn dy2(self) -> Rational;
    /// The x offset of layer k at t = 0 relative to the particle, modulo 1.
    fn phase0(self, k: i64) -> Rational;
}

fn rational(r: Ratio) -> Rational {
    Rational::from((r.num, r.den))
}

impl ExactLattice for Lattice {
    fn dy2(self) -> Rational {
        rational(self.kind().dy2)
    }

    fn phase0(self, k: i64) -> Rational {
        rational(self.phase(k))
    }
}

/// A lattice kind and h/d: what the analysis is derived for.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Discretisation {
    pub lattice: Lattice,
    /// h/d, exact and positive.
    pub h: Rational,
}

impl Discretisation {
    /// The paper's: triangular lattice, h = d.
    pub fn paper() -> Self {
        Discretisation {
            lattice: Lattice::Triangular,
            h: Rational::from(1),
        }
    }

    pub fn is_paper(&self) -> bool {
        *self == Self::paper()
    }

    /// `triangular, h/d = 1`.
    pub fn label(&self) -> String {
        format!("{}, h/d = {}", self.lattice.name(), self.h)
    }

    /// A short identifier: `triangular_1`, `square_13_10`.
    pub fn ident(&self) -> String {
        format!(
            "{}_{}",
            self.lattice.name(),
            self.h.to_string().replace('/', "_")
        )
    }

    /// (h/d)^2.
    pub fn h2(&self) -> Rational {
        Rational::from(&self.h * &self.h)
    }

    /// The support radius in d: R h/d.
    pub fn support_d(&self, support: &Rational) -> Rational {
        Rational::from(support * &self.h)
    }
}

/// A neighbour at an exact position: x offset (in d), layer offset k, and
/// r^2 = x^2 + k^2 dy^2 (in d^2).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Neighbour {
    pub x: Rational,
    pub k: i64,
    pub r2: Rational,
}

impl Neighbour {
    pub fn is_self(&self) -> bool {
        self.k == 0 && self.x == 0
    }
}

/// The two exact (symmetric) configurations of the analysis.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Config {
    /// t = 0: the undisturbed lattice.
    T0,
    /// t = 0.5 T: odd relative layers shifted by d/2.
    Half,
}

impl Config {
    pub fn label(self) -> &'static str {
        match self {
            Config::T0 => "t = 0",
            Config::Half => "t = 0.5 T",
        }
    }

    /// t / T.
    pub fn tau(self) -> Rational {
        match self {
            Config::T0 => Rational::new(),
            Config::Half => Rational::from((1, 2)),
        }
    }

    /// The phase of layer k in this configuration, for the centre particle.
    pub fn phase(self, lattice: Lattice, k: i64) -> Rational {
        let p = lattice.phase0(k);
        match self {
            Config::T0 => p,
            Config::Half if k.rem_euclid(2) == 1 => {
                let s = p + Rational::from((1, 2));
                if s >= 1 {
                    s - 1u32
                } else {
                    s
                }
            }
            Config::Half => p,
        }
    }
}

/// Largest layer offset whose layer can hold a neighbour within the support
/// R h: k^2 dy^2 <= R^2 h^2.
pub fn max_layer_offset(disc: &Discretisation, support: &Rational) -> i64 {
    let rd = disc.support_d(support);
    let r2 = Rational::from(&rd * &rd);
    let dy2 = disc.lattice.dy2();
    let mut k = 0i64;
    while Rational::from(&dy2 * ((k + 1) * (k + 1))) <= r2 {
        k += 1;
    }
    k
}

/// How far along x (in d, whole spacings) a row can hold neighbours: ceil(R h/d) + 1.
pub fn row_reach(disc: &Discretisation, support: &Rational) -> i64 {
    disc.support_d(support)
        .ceil()
        .numer()
        .to_i64()
        .expect("support fits i64")
        + 1
}

/// Neighbours (self included) within the closed support of an interior
/// particle, in a fixed order: by layer offset k, then x.
pub fn stencil(disc: &Discretisation, support: &Rational, config: Config) -> Vec<Neighbour> {
    let kmax = max_layer_offset(disc, support);
    let rd = disc.support_d(support);
    let r2max = Rational::from(&rd * &rd);
    let dy2 = disc.lattice.dy2();
    let reach = row_reach(disc, support);
    let mut out = Vec::new();
    for k in -kmax..=kmax {
        let phase = config.phase(disc.lattice, k);
        let y2 = Rational::from(&dy2 * (k * k));
        // x = a + phase for integers a with x^2 + y2 <= (R h)^2
        for a in -reach..=reach {
            let x = Rational::from(a) + &phase;
            let r2 = Rational::from(&x * &x) + &y2;
            if r2 <= r2max {
                out.push(Neighbour { x, k, r2 });
            }
        }
    }
    out
}

/// How layer j = n + k moves relative to a particle of layer n, as the
/// integer multiplier of tau (in d): n^2 - j^2 for fluid, n^2 - N^2 for walls.
/// `n_layers = None` means no walls in reach (an interior particle).
pub fn layer_speed(n: i64, k: i64, n_layers: Option<i64>) -> i64 {
    let j = n + k;
    match n_layers {
        Some(nl) if j.abs() >= nl => n * n - nl * nl,
        _ => n * n - j * j,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn disc(lattice: Lattice, h: (i64, i64)) -> Discretisation {
        Discretisation {
            lattice,
            h: Rational::from(h),
        }
    }

    #[test]
    fn r1_stencils_match_figure_5() {
        let one = Rational::from(1);
        let p = Discretisation::paper();
        let t0 = stencil(&p, &one, Config::T0);
        // self + 6 neighbours at distance d
        assert_eq!(t0.len(), 7);
        assert!(t0.iter().filter(|n| !n.is_self()).all(|n| n.r2 == 1));
        let half = stencil(&p, &one, Config::Half);
        // self, 2 in the own layer at x = -1, 1, and 2 straight above/below
        assert_eq!(half.len(), 5);
        assert_eq!(
            half.iter()
                .filter(|n| n.r2 == Rational::from((3, 4)))
                .count(),
            2
        );
    }

    #[test]
    fn square_r1_stencils() {
        let one = Rational::from(1);
        let sq = disc(Lattice::Square, (1, 1));
        // t = 0: self + 4 at distance d
        let t0 = stencil(&sq, &one, Config::T0);
        assert_eq!(t0.len(), 5);
        // t = 0.5 T: odd layers staggered, sqrt(5)/2 > 1: only the own layer's pair
        let half = stencil(&sq, &one, Config::Half);
        assert_eq!(half.len(), 3);
        assert!(half.iter().all(|n| n.k == 0));
    }

    #[test]
    fn layer_reach() {
        let p = Discretisation::paper();
        assert_eq!(max_layer_offset(&p, &Rational::from(1)), 1);
        assert_eq!(max_layer_offset(&p, &Rational::from(2)), 2);
        assert_eq!(max_layer_offset(&p, &Rational::from(3)), 3);
        assert_eq!(max_layer_offset(&p, &Rational::from((1, 2))), 0);
        let sq = disc(Lattice::Square, (13, 10));
        // 2 * 1.3 = 2.6 d
        assert_eq!(max_layer_offset(&sq, &Rational::from(2)), 2);
        let tri = disc(Lattice::Triangular, (3, 2));
        // 2 * 1.5 = 3 d, k sqrt(3)/2 <= 3: k <= 3
        assert_eq!(max_layer_offset(&tri, &Rational::from(2)), 3);
    }

    #[test]
    fn half_period_shift_is_a_half_for_odd_layers_only() {
        // (n^2 - j^2) / 2 is a half-integer exactly when k is odd.
        for n in 0..6 {
            for k in -4i64..=4 {
                let s = layer_speed(n, k, None);
                assert_eq!(s.rem_euclid(2) == 1, k.rem_euclid(2) == 1);
            }
        }
    }
}
