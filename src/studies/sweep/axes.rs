//! The typed values of a sweep's axes beyond kernel, N, Re, alpha and c0:
//! the discretisation (lattice and an exact h/d) and the start (perfect or
//! jittered by an amplitude with a seed), and [`GridPosition`], a point's integer
//! position on every axis: the key rows are joined by.

use serde::{Deserialize, Serialize};

pub use crate::config::HOverD;
use crate::kernel::Lattice;

/// A point's discretisation: the starting lattice and h/d.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Discretisation {
    pub lattice: Lattice,
    pub h_over_d: HOverD,
}

impl Discretisation {
    /// The paper's: triangular, h = d.
    pub const PAPER: Discretisation = Discretisation {
        lattice: Lattice::Triangular,
        h_over_d: HOverD::ONE,
    };

    /// The id's suffix: none for the paper's, `/lattice=square` for another
    /// lattice, `/h=13/10` for another h/d.
    pub fn id_suffix(&self) -> String {
        let mut s = String::new();
        if self.lattice != Lattice::Triangular {
            s.push_str(&format!("/lattice={}", self.lattice.name()));
        }
        if self.h_over_d != HOverD::ONE {
            s.push_str(&format!("/h={}", self.h_over_d));
        }
        s
    }
}

impl Default for Discretisation {
    fn default() -> Self {
        Discretisation::PAPER
    }
}

/// A point's start: the perfect lattice, or each fluid particle displaced
/// by up to `amplitude` d per component with the jitter's `seed` (the
/// scene's `jitter` and `jitter_seed`).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum Start {
    #[default]
    Perfect,
    Jittered {
        amplitude: f64,
        seed: u32,
    },
}

impl Start {
    /// The id's suffix: none for the perfect start, `/jitter=0.05/seed=2`.
    pub fn id_suffix(&self) -> String {
        match self {
            Start::Perfect => String::new(),
            Start::Jittered { amplitude, seed } => format!("/jitter={amplitude}/seed={seed}"),
        }
    }

    /// The scene's `jitter` (0 for the perfect start) and `jitter_seed`.
    pub fn jitter(&self) -> (f64, u32) {
        match *self {
            Start::Perfect => (0.0, 0),
            Start::Jittered { amplitude, seed } => (amplitude, seed),
        }
    }
}

/// A point's position on every axis of its grid: indices into the spec's
/// lists (kernels, lattice, h_over_d, n, re, alpha, jitter, and the c0 list
/// with `c0` first, then `c0_over_u`), and the seed (1..=seeds, 0 for a
/// perfect start). Two rows of one grid are the same point, or differ only
/// by seed, exactly when these integers say so: the key to join rows by,
/// never their strings or floats.
#[derive(
    Debug, Clone, Copy, Default, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize,
)]
pub struct GridPosition {
    pub kernel: u32,
    pub lattice: u32,
    pub h_over_d: u32,
    pub n: u32,
    pub re: u32,
    pub alpha: u32,
    pub jitter: u32,
    pub seed: u32,
    pub c0: u32,
}

impl GridPosition {
    /// The same position with the seed dropped: what the seeds of one
    /// perturbed point share.
    pub fn without_seed(self) -> GridPosition {
        GridPosition { seed: 0, ..self }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_point_s_id_names_its_discretisation_and_start() {
        let h: HOverD = "26/20".parse().unwrap();
        let d = Discretisation {
            lattice: Lattice::Square,
            h_over_d: h,
        };
        assert_eq!(d.id_suffix(), "/lattice=square/h=13/10");
        assert_eq!(Discretisation::PAPER.id_suffix(), "");
        let s = Start::Jittered {
            amplitude: 0.05,
            seed: 2,
        };
        assert_eq!(s.id_suffix(), "/jitter=0.05/seed=2");
        assert_eq!(Start::Perfect.id_suffix(), "");
    }
}
