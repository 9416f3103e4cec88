//! The sound speed c0 as a scene gives it: a number, or a factor times a
//! typed rule.

use std::fmt;
use std::str::FromStr;

use serde::{Deserialize, Deserializer, Serialize, Serializer};

use crate::format::fmt_value;

/// A base rule for c0. U is the steady centre-line speed, B the half-width,
/// F = p the body force per unit mass, nu = p B^2 / (2 U), L = 2 B the
/// distance between the plates.
#[derive(Debug, Clone, PartialEq)]
pub enum C0Rule {
    /// A model derived for the kernel (`derived` is its default model,
    /// `derived:NAME` a named one): Reshetnikova (2024).
    Derived(Option<String>),
    /// The paper's construction with a technical eps0 (`derived-eps`, 0.01 by
    /// default; `derived-eps:0.02`) in place of the kernel's kinematic one,
    /// with the kernel's default model (the paper's closing suggestion).
    DerivedEps(Option<f64>),
    /// c0 = 10 U (Monaghan 1994, JCP 110:399; PySPH examples/poiseuille.py,
    /// SPHinXsys test_2d_poiseuille_flow).
    Rule10,
    /// c^2 = max(U^2/delta, nu U/(L delta), F L/delta), delta = 0.01, L = 2 B
    /// (Morris, Fox and Zhu 1997, JCP 136:214, section 2.2; their Poiseuille
    /// case has the plates at y = 0 and y = L).
    Morris1997,
    /// c0 = 20 max(sqrt(2 F L), U), L = 2 B (GPUSPH
    /// src/problems/Poiseuille.cu: hydrostatic_vel = sqrt(2 driving_force
    /// lz), c0 = 20 fmax(hydrostatic_vel, max_vel), lz the channel height).
    Gpusph,
    /// c0 = coefsound x speedsystem with coefsound = 20 and speedsystem =
    /// sqrt(|g| hswl), the body force as gravity and the fluid depth hswl =
    /// 2 B: c0 = 20 sqrt(2 F B) (DualSPHysics JCaseCtes / GenCase defaults).
    DualSphysics,
    /// c0 = 100 U (TrixiParticles.jl examples/fluid/poiseuille_flow_2d.jl).
    Trixi,
    /// The solver's answer for the scene (`shearsph c0 --empirical`): the
    /// smallest c0 ok on the perfect lattice and on every perturbed seed,
    /// times the margin. Found by running the bisection first, so only the
    /// commands that run the solver resolve it (`run` and `c0 --empirical`);
    /// the problem layer refuses it.
    Empirical,
    /// The paper's printed row of Table 2 for the kernel.
    Table2,
}

/// The technical eps0 of `derived-eps` when none is given: 1 %, the usual
/// weakly compressible tolerance the paper's conclusion names.
pub const DEFAULT_TECHNICAL_EPS0: f64 = 0.01;

impl fmt::Display for C0Rule {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            C0Rule::Derived(None) => write!(f, "derived"),
            C0Rule::Derived(Some(m)) => write!(f, "derived:{m}"),
            C0Rule::DerivedEps(None) => write!(f, "derived-eps"),
            C0Rule::DerivedEps(Some(e)) => write!(f, "derived-eps:{e}"),
            C0Rule::Rule10 => write!(f, "rule10"),
            C0Rule::Morris1997 => write!(f, "morris1997"),
            C0Rule::Gpusph => write!(f, "gpusph"),
            C0Rule::DualSphysics => write!(f, "dualsphysics"),
            C0Rule::Trixi => write!(f, "trixi"),
            C0Rule::Empirical => write!(f, "empirical"),
            C0Rule::Table2 => write!(f, "table2"),
        }
    }
}

/// c0 as a number, or a factor times a rule: `3.5`, `derived`,
/// `derived:MODEL`, `rule10`, `table2`, `0.5*derived`, `0.01*rule10`.
#[derive(Debug, Clone, PartialEq)]
pub enum C0Spec {
    Value(f64),
    Rule { factor: f64, rule: C0Rule },
}

impl Default for C0Spec {
    fn default() -> Self {
        C0Spec::Rule {
            factor: 1.0,
            rule: C0Rule::Derived(None),
        }
    }
}

const C0_SYNTAX: &str = "a number, or [FACTOR*]RULE with RULE one of derived, derived:MODEL, \
     derived-eps, derived-eps:EPS0, rule10, morris1997, gpusph, dualsphysics, trixi, table2, empirical";

impl FromStr for C0Spec {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        let s = s.trim();
        if let Ok(v) = s.parse::<f64>() {
            return Ok(C0Spec::Value(v));
        }
        let (factor, rule) = match s.split_once('*') {
            Some((f, r)) => {
                let factor = f.trim().parse::<f64>().map_err(|_| {
                    format!(
                        "bad factor {:?} in c0 = {s:?}: expected {C0_SYNTAX}",
                        f.trim()
                    )
                })?;
                (factor, r.trim())
            }
            None => (1.0, s),
        };
        let rule = match rule {
            "derived" => C0Rule::Derived(None),
            "derived-eps" => C0Rule::DerivedEps(None),
            "rule10" => C0Rule::Rule10,
            "morris1997" => C0Rule::Morris1997,
            "gpusph" => C0Rule::Gpusph,
            "dualsphysics" => C0Rule::DualSphysics,
            "trixi" => C0Rule::Trixi,
            "empirical" => C0Rule::Empirical,
            "table2" => C0Rule::Table2,
            r => {
                if let Some(e) = r.strip_prefix("derived-eps:") {
                    match e.parse::<f64>() {
                        Ok(eps) if eps > 0.0 && eps.is_finite() => C0Rule::DerivedEps(Some(eps)),
                        _ => {
                            return Err(format!(
                                "bad technical eps0 {e:?} in c0 = {s:?}: give a positive number, \
                                 e.g. derived-eps:0.01"
                            ))
                        }
                    }
                } else {
                    match r.strip_prefix("derived:") {
                        Some(m) if !m.is_empty() => C0Rule::Derived(Some(m.to_string())),
                        _ => return Err(format!("unknown c0 rule {r:?}: expected {C0_SYNTAX}")),
                    }
                }
            }
        };
        Ok(C0Spec::Rule { factor, rule })
    }
}

impl fmt::Display for C0Spec {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            C0Spec::Value(v) => write!(f, "{}", fmt_value(*v)),
            C0Spec::Rule { factor, rule } if *factor == 1.0 => write!(f, "{rule}"),
            C0Spec::Rule { factor, rule } => write!(f, "{}*{rule}", fmt_value(*factor)),
        }
    }
}

impl Serialize for C0Spec {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self {
            C0Spec::Value(v) => s.serialize_f64(*v),
            rule => s.collect_str(rule),
        }
    }
}

impl<'de> Deserialize<'de> for C0Spec {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        // A visitor, not an untagged enum: anything but a number or a
        // string (`c0 = true`, a table) gets our message, not serde's
        // "did not match any variant".
        struct V;
        impl serde::de::Visitor<'_> for V {
            type Value = C0Spec;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                write!(f, "c0 as a number or a rule name ({C0_SYNTAX})")
            }
            fn visit_bool<E: serde::de::Error>(self, v: bool) -> Result<C0Spec, E> {
                Err(E::custom(format!(
                    "c0 must be a number or a rule name: {C0_SYNTAX}; not {v}"
                )))
            }
            fn visit_f64<E: serde::de::Error>(self, v: f64) -> Result<C0Spec, E> {
                Ok(C0Spec::Value(v))
            }
            fn visit_i64<E: serde::de::Error>(self, v: i64) -> Result<C0Spec, E> {
                Ok(C0Spec::Value(v as f64))
            }
            fn visit_u64<E: serde::de::Error>(self, v: u64) -> Result<C0Spec, E> {
                Ok(C0Spec::Value(v as f64))
            }
            fn visit_str<E: serde::de::Error>(self, v: &str) -> Result<C0Spec, E> {
                v.parse().map_err(E::custom)
            }
        }
        d.deserialize_any(V)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn c0_spec_round_trips() {
        for s in [
            "3.5",
            "derived",
            "derived:full",
            "rule10",
            "table2",
            "derived-eps",
            "derived-eps:0.02",
            "morris1997",
            "gpusph",
            "dualsphysics",
            "trixi",
            "empirical",
            "1.2*empirical",
            "0.5*derived",
            "0.01*rule10",
        ] {
            let spec: C0Spec = s.parse().unwrap();
            assert_eq!(spec.to_string(), s);
        }
        assert!("2*nonsense".parse::<C0Spec>().is_err());
        assert!("x*rule10".parse::<C0Spec>().is_err());
        assert!("derived:".parse::<C0Spec>().is_err());
        assert!("derived-eps:0".parse::<C0Spec>().is_err());
        assert!("derived-eps:x".parse::<C0Spec>().is_err());
    }
}
