//! The typed values of a sweep's axes beyond kernel, N, Re, alpha and c0:
//! the discretisation (lattice and an exact h/d) and the start (perfect or
//! jittered by an amplitude with a seed), and [`At`], a point's integer
//! position on every axis: the key rows are joined by.

use std::fmt;

use serde::{Deserialize, Deserializer, Serialize, Serializer};

use crate::kernel::Lattice;

/// h/d as an exact rational P/Q in lowest terms (`1`, `13/10`), as the
/// generator derives it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct HOverD {
    p: u32,
    q: u32,
}

impl HOverD {
    /// The paper's h = d.
    pub const ONE: HOverD = HOverD { p: 1, q: 1 };

    /// P/Q reduced; `None` for Q = 0 or P = 0.
    pub fn new(p: u32, q: u32) -> Option<HOverD> {
        if p == 0 || q == 0 {
            return None;
        }
        let (mut a, mut b) = (p, q);
        while b != 0 {
            (a, b) = (b, a % b);
        }
        Some(HOverD { p: p / a, q: q / a })
    }

    /// An exact rational as the generator writes it: `1`, `13/10`.
    pub fn parse_exact(s: &str) -> Option<HOverD> {
        let s = s.trim();
        match s.split_once('/') {
            Some((p, q)) => HOverD::new(p.trim().parse().ok()?, q.trim().parse().ok()?),
            None => HOverD::new(s.parse().ok()?, 1),
        }
    }

    /// P / Q rounded once: bit for bit the f64 a scene's `"P/Q"` gives
    /// (`config::parse_h_over_d`) and the generated h/d.
    pub fn value(self) -> f64 {
        f64::from(self.p) / f64::from(self.q)
    }
}

impl fmt::Display for HOverD {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.q == 1 {
            write!(f, "{}", self.p)
        } else {
            write!(f, "{}/{}", self.p, self.q)
        }
    }
}

/// In JSON and TOML as its exact text (`"13/10"`); read from that text or
/// from a number that is one exactly (`1`).
impl Serialize for HOverD {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_str(self)
    }
}

impl<'de> Deserialize<'de> for HOverD {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let v = HOverDValue::deserialize(d)?;
        let text = match &v {
            HOverDValue::Text(t) => t.clone(),
            HOverDValue::Number(x) => x.to_string(),
        };
        HOverD::parse_exact(&text).ok_or_else(|| {
            serde::de::Error::custom(format!("h_over_d {text:?} is not an exact rational P/Q"))
        })
    }
}

/// h/d as a sweep file or flag gives it: a number (`1.3`) or a string
/// holding a number or an exact rational (`"13/10"`). `resolved()` makes
/// each the generated exact text.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum HOverDValue {
    Number(f64),
    Text(String),
}

impl fmt::Display for HOverDValue {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            HOverDValue::Number(x) => write!(f, "{x}"),
            HOverDValue::Text(t) => f.write_str(t),
        }
    }
}

impl std::str::FromStr for HOverDValue {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        crate::config::parse_h_over_d(s)?;
        Ok(HOverDValue::Text(s.trim().to_string()))
    }
}

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
pub struct At {
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

impl At {
    /// The same position with the seed dropped: what the seeds of one
    /// perturbed point share.
    pub fn without_seed(self) -> At {
        At { seed: 0, ..self }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn h_over_d_is_exact_and_matches_the_scene() {
        let h = HOverD::parse_exact("26/20").unwrap();
        assert_eq!(h.to_string(), "13/10");
        assert_eq!(
            h.value().to_bits(),
            crate::config::parse_h_over_d("13/10").unwrap().to_bits()
        );
        assert_eq!(HOverD::parse_exact("1"), Some(HOverD::ONE));
        assert_eq!(HOverD::parse_exact("0"), None);
        assert_eq!(HOverD::parse_exact("1/0"), None);
        assert_eq!(HOverD::parse_exact("1.3"), None);
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
