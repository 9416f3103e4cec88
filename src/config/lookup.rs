//! What a scene names, found: the kernel by name, its discretisation by
//! lattice and h/d, and h/d's own syntax (a number or an exact rational).

use serde::{Deserialize, Deserializer, Serialize, Serializer};

use super::{invalid, SceneError};
use crate::format::fmt_value;
use crate::kernel::{DiscretisationInfo, KernelInfo, Lattice};
use crate::kernels;

/// h/d from TOML: a number, or a string holding a number or an exact
/// rational "P/Q".
pub(super) fn de_h_over_d<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    #[derive(Deserialize)]
    #[serde(untagged)]
    enum Raw {
        Number(f64),
        Text(String),
    }
    match Raw::deserialize(d)? {
        Raw::Number(v) => Ok(v),
        Raw::Text(t) => parse_h_over_d(&t).map_err(serde::de::Error::custom),
    }
}

/// h/d as a flag or TOML string gives it: a number (`1.3`) or an exact
/// rational `P/Q` (`13/10`, whole P and Q). The rational's f64 is P / Q
/// rounded once (P and Q are exact in f64), so it equals the generated,
/// correctly rounded h/d of the same rational bit for bit; two rationals
/// with denominators below 10^5 differ by far more than the lookup's 1e-12,
/// so matching the f64 matches the exact rational.
pub fn parse_h_over_d(s: &str) -> Result<f64, String> {
    let s = s.trim();
    let bad = || format!("h_over_d {s:?} is neither a number nor a rational P/Q (e.g. 13/10)");
    match s.split_once('/') {
        Some((p, q)) => {
            let p: u64 = p.trim().parse().map_err(|_| bad())?;
            let q: u64 = q.trim().parse().map_err(|_| bad())?;
            if q == 0 || p >= 1 << 53 || q >= 1 << 53 {
                return Err(bad());
            }
            Ok(p as f64 / q as f64)
        }
        None => s.parse().map_err(|_| bad()),
    }
}

/// h/d as a short exact rational for a message ("13/10"), or the number
/// itself when no fraction with a denominator up to 1000 gives it to 1e-12.
pub fn rational_text(v: f64) -> String {
    (1..=1000u32)
        .find_map(|q| {
            let p = (v * f64::from(q)).round();
            ((p / f64::from(q) - v).abs() <= 1e-12 * v.abs()).then_some((p, q))
        })
        .map_or_else(
            || fmt_value(v),
            |(p, q)| {
                if q == 1 {
                    format!("{p}")
                } else {
                    format!("\"{p}/{q}\"")
                }
            },
        )
}

/// The generated discretisation of `info` a scene names (its `lattice` and
/// `h_over_d`), or an error naming the line to add to
/// kernels/discretisations.toml and the command to run.
pub fn discretisation(
    info: &'static KernelInfo,
    lattice: Lattice,
    h_over_d: f64,
) -> Result<&'static DiscretisationInfo, SceneError> {
    // the generator derives 0 < h/d <= 4 (codegen's MAX_H_OVER_D): outside
    // it there is no line to add, only a value to change
    if !(h_over_d > 0.0 && h_over_d <= 4.0) {
        return Err(invalid(
            "h_over_d",
            format!(
                "{} is outside (0, 4], the h/d the generator derives; use a generated one (1, 13/10, ...)",
                fmt_value(h_over_d)
            ),
        ));
    }
    info.discretisation(lattice, h_over_d).ok_or_else(|| {
        let known: Vec<String> = info.discretisations.iter().map(|d| d.label()).collect();
        invalid(
            "h_over_d",
            format!(
                "kernel {} has no generated discretisation with lattice = {:?} and h = {} d \
                 (generated: {}); add to kernels/discretisations.toml\n\n[[discretisation]]\n\
                 lattice = \"{}\"\nh_over_d = {}\n\nthen run `cargo run -p shearsph-codegen -- generate` \
                 and rebuild",
                info.name,
                lattice.name(),
                fmt_value(h_over_d),
                known.join("; "),
                lattice.name(),
                rational_text(h_over_d),
            ),
        )
    })
}

/// A kernel's data by name, or an error listing the known kernels and
/// suggesting the nearest name.
pub fn kernel_info(name: &str) -> Result<&'static KernelInfo, SceneError> {
    kernels::kernel_info(name).ok_or_else(|| {
        let nearest = kernels::NAMES
            .iter()
            .map(|k| (strsim::levenshtein(name, k), *k))
            .min()
            .filter(|(dist, k)| *dist <= k.len().max(2) / 2)
            .map(|(_, k)| format!("; did you mean {k:?}?"))
            .unwrap_or_default();
        SceneError::UnknownKernel {
            name: name.to_string(),
            known: format!("{}{nearest}", kernels::NAMES.join(", ")),
        }
    })
}

/// A lattice kind in TOML and JSON: `"triangular"` or `"square"`.
impl Serialize for Lattice {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.name())
    }
}

impl<'de> Deserialize<'de> for Lattice {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let s = String::deserialize(d)?;
        s.parse().map_err(serde::de::Error::custom)
    }
}
