//! The triangular lattice of section 2, with h = d (lengths in d): layer j at
//! y = j sqrt(3)/2, odd layers offset by 1/2 along x. Fluid layers are
//! |j| < N, walls |j| >= N (fixed, u = 0).
//!
//! Under the steady shear (7), u(j) = U (1 - j^2/N^2), so over a time t = tau
//! T (T = d N^2 / U, (19)) layer j moves by (u(j) - u(n)) t = (n^2 - j^2) tau
//! relative to a particle of layer n (in d); a wall layer moves by
//! (n^2 - N^2) tau. These multipliers are integers, so every neighbourhood is
//! periodic with T, and at tau = 1/2 odd relative layers sit straight above
//! the particle (shift by a half) while even ones return to place.

use rug::Rational;

/// A neighbour at an exact position: x offset (in d), layer offset k, and
/// r^2 = x^2 + 3 k^2 / 4.
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

/// The two exact configurations of the analysis.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Config {
    /// t = 0: the undisturbed lattice.
    T0,
    /// t = 0.5 T: every layer has a particle straight above/below.
    Half,
}

impl Config {
    pub fn label(self) -> &'static str {
        match self {
            Config::T0 => "t = 0",
            Config::Half => "t = 0.5 T",
        }
    }
}

/// Largest layer offset whose layer can hold a neighbour within `support`:
/// (sqrt(3)/2) k <= R, i.e. 3 k^2 <= 4 R^2.
pub fn max_layer_offset(support: &Rational) -> i64 {
    let r2x4 = Rational::from(support * support) * 4;
    let mut k = 0i64;
    while 3 * (k + 1) * (k + 1) <= r2x4 {
        k += 1;
    }
    k
}

/// The x offset of layer k at t = 0 relative to the particle, modulo 1.
pub fn phase0(k: i64) -> Rational {
    if k.rem_euclid(2) == 1 {
        Rational::from((1, 2))
    } else {
        Rational::new()
    }
}

/// Neighbours (self included) within the closed support of an interior
/// particle, in a fixed order: by layer offset k, then x.
pub fn stencil(support: &Rational, config: Config) -> Vec<Neighbour> {
    let kmax = max_layer_offset(support);
    let r2max = Rational::from(support * support);
    let mut out = Vec::new();
    for k in -kmax..=kmax {
        let phase = match config {
            Config::T0 => phase0(k),
            Config::Half => Rational::new(),
        };
        let y2 = Rational::from((3 * k * k, 4));
        // x = a + phase for integers a with x^2 + y2 <= R^2
        let reach = support.clone().ceil().numer().to_i64().unwrap() + 1;
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

    #[test]
    fn r1_stencils_match_figure_5() {
        let one = Rational::from(1);
        let t0 = stencil(&one, Config::T0);
        // self + 6 neighbours at distance d
        assert_eq!(t0.len(), 7);
        assert!(t0.iter().filter(|n| !n.is_self()).all(|n| n.r2 == 1));
        let half = stencil(&one, Config::Half);
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
    fn layer_reach() {
        assert_eq!(max_layer_offset(&Rational::from(1)), 1);
        assert_eq!(max_layer_offset(&Rational::from(2)), 2);
        assert_eq!(max_layer_offset(&Rational::from(3)), 3);
        assert_eq!(max_layer_offset(&Rational::from((1, 2))), 0);
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
