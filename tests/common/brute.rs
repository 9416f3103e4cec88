//! The perfect lattice counted by brute force, apart from the solver's
//! code: for the stable time-step factors' tests (`viscous_time_step.rs`,
//! `cfl_time_step.rs`).

use shearsph::kernel::{Kernel, Lattice};

/// The perfect lattice of `lattice`'s kind at d = 1 with smoothing length
/// `h`, from its basis a1 = (1, 0), a2 = (a2x, a2y).
pub struct Sites {
    pub a2: (f64, f64),
    /// The area per particle, d dy.
    pub area: f64,
    /// sigma = A sum W over every site in the support, self included.
    pub sigma: f64,
    /// (x, y, q^2) of every other site within kernel K's closed support.
    pub others: Vec<(f64, f64, f64)>,
}

impl Sites {
    pub fn new<K: Kernel>(lattice: Lattice, h: f64) -> Sites {
        let (a2x, a2y) = match lattice {
            Lattice::Triangular => (0.5, 3f64.sqrt() / 2.0),
            _ => (0.0, 1.0),
        };
        let area = a2y;
        let mut w = K::w(0.0) / (h * h);
        let mut others = Vec::new();
        for m in -12i32..=12 {
            for n in -12i32..=12 {
                let (x, y) = (f64::from(m) + f64::from(n) * a2x, f64::from(n) * a2y);
                let q2 = (x * x + y * y) / (h * h);
                if (m, n) != (0, 0) && q2 <= K::SUPPORT2_CLOSED {
                    w += K::w(q2) / (h * h);
                    others.push((x, y, q2));
                }
            }
        }
        Sites {
            a2: (a2x, a2y),
            area,
            sigma: area * w,
            others,
        }
    }

    /// The wave vectors of an n x n grid over the reciprocal cell:
    /// k . a1 = tau s, k . a2 = tau t, (s, t) over [0, 1)^2.
    pub fn wave_vectors(&self, n: u32) -> impl Iterator<Item = (f64, f64)> + '_ {
        let tau = std::f64::consts::TAU;
        let (a2x, a2y) = self.a2;
        (0..n).flat_map(move |i| {
            (0..n).map(move |j| {
                let (s, t) = (f64::from(i) / f64::from(n), f64::from(j) / f64::from(n));
                let kx = tau * s;
                (kx, (tau * t - kx * a2x) / a2y)
            })
        })
    }
}
