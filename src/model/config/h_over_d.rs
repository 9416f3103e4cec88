//! h/d, the smoothing length in units of the spacing d, as one type: an
//! exact rational P/Q in lowest terms, as the generator derives each
//! discretisation for. A flag, a scene file and a sweep give it as a number
//! (`1.3`) or a rational (`"13/10"`); both read into [`HOverD`], which is
//! written as its exact text. A scene keeps its f64 ([`HOverD::value`]):
//! that is the number the run uses and `scene.toml` records.

use std::fmt;
use std::str::FromStr;

use serde::{Deserialize, Deserializer, Serialize, Serializer};

use crate::format::fmt_value;

/// h/d as an exact rational P/Q in lowest terms (`1`, `13/10`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct HOverD {
    p: u32,
    q: u32,
}

/// The largest denominator a number is matched to (`1.3` is 13/10).
const MAX_Q: u32 = 1000;

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

    /// The rational P/Q (Q up to 1000) within a relative 1e-12 of `v`, as
    /// the discretisation lookup matches a number; `None` when there is
    /// none (or `v` is not positive).
    pub fn near(v: f64) -> Option<HOverD> {
        if !(v > 0.0 && v < f64::from(u32::MAX) / f64::from(MAX_Q)) {
            return None;
        }
        (1..=MAX_Q).find_map(|q| {
            let p = (v * f64::from(q)).round();
            if p < 1.0 || (p / f64::from(q) - v).abs() > 1e-12 * v {
                return None;
            }
            HOverD::new(p as u32, q)
        })
    }

    /// The rational whose f64 `v` is, exactly.
    fn of_number(v: f64) -> Result<HOverD, String> {
        HOverD::near(v).filter(|h| h.value() == v).ok_or_else(|| {
            format!(
                "h_over_d {} is not a positive rational P/Q with Q up to {MAX_Q}; give a \
                 generated one (1, 13/10, ...: `shearsph kernels` lists them)",
                fmt_value(v)
            )
        })
    }

    /// P / Q rounded once: bit for bit the f64 of a number that names it
    /// (`1.3`) and the generated h/d.
    pub fn value(self) -> f64 {
        f64::from(self.p) / f64::from(self.q)
    }

    /// `v` as a TOML value for a message: `1`, `"13/10"`, or the number
    /// itself when no rational is near it ([`HOverD::near`]).
    pub fn toml_text(v: f64) -> String {
        match HOverD::near(v) {
            Some(h) if h.q == 1 => h.to_string(),
            Some(h) => format!("\"{h}\""),
            None => fmt_value(v),
        }
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

/// `P/Q` (whole P and Q), or a number whose f64 is exactly some P/Q's
/// (`1.3`, `2`); an error naming `h_over_d` and the syntax otherwise.
impl FromStr for HOverD {
    type Err = String;
    fn from_str(s: &str) -> Result<HOverD, String> {
        let s = s.trim();
        let bad = || format!("h_over_d {s:?} is neither a number nor a rational P/Q (e.g. 13/10)");
        match s.split_once('/') {
            Some((p, q)) => {
                let p: u32 = p.trim().parse().map_err(|_| bad())?;
                let q: u32 = q.trim().parse().map_err(|_| bad())?;
                HOverD::new(p, q).ok_or_else(bad)
            }
            None => {
                let v: f64 = s.parse().map_err(|_| bad())?;
                HOverD::of_number(v)
            }
        }
    }
}

/// In JSON and TOML as its exact text (`"13/10"`, `"1"`).
impl Serialize for HOverD {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_str(self)
    }
}

/// h/d as TOML or JSON gives it: a number, or a string holding a number or
/// a rational.
#[derive(Deserialize)]
#[serde(untagged)]
enum Given {
    Number(f64),
    Text(String),
}

/// Read from its text or from a number that is one exactly (`1`, `1.3`).
impl<'de> Deserialize<'de> for HOverD {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        match Given::deserialize(d)? {
            Given::Number(v) => HOverD::of_number(v),
            Given::Text(t) => t.parse(),
        }
        .map_err(serde::de::Error::custom)
    }
}

/// A scene's h/d from TOML: a number as it is (the scene's guards and the
/// discretisation lookup judge it), or the value of the rational a string
/// names.
pub(super) fn de_scene_h_over_d<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    match Given::deserialize(d)? {
        Given::Number(v) => Ok(v),
        Given::Text(t) => t
            .parse::<HOverD>()
            .map(HOverD::value)
            .map_err(serde::de::Error::custom),
    }
}

#[cfg(test)]
mod tests {
    use super::HOverD;

    #[test]
    fn a_number_and_its_rational_are_one_value() {
        let h: HOverD = "1.3".parse().unwrap();
        assert_eq!(h.to_string(), "13/10");
        assert_eq!(h, "26/20".parse().unwrap());
        assert_eq!(h.value().to_bits(), 1.3f64.to_bits());
        assert_eq!("2".parse::<HOverD>().unwrap().to_string(), "2");
        for bad in ["13/x", "13/0", "0", "-1", "nan", "1.2345678901"] {
            assert!(bad.parse::<HOverD>().is_err(), "{bad}");
        }
        assert_eq!(HOverD::toml_text(1.5), "\"3/2\"");
        assert_eq!(HOverD::toml_text(1.0), "1");
        let json: HOverD = serde_json::from_str("1.3").unwrap();
        assert_eq!(serde_json::to_string(&json).unwrap(), "\"13/10\"");
    }
}
