//! The sound speed c0 as a scene gives it: a number, or a factor times a
//! typed rule.

use std::fmt;
use std::str::FromStr;

use serde::{Deserialize, Deserializer, Serialize, Serializer};

use crate::format::fmt_value;

/// A base rule for c0: how a program names one. What each is (its name,
/// its c0 in words, its source, a code's formula) is its entry in
/// [`RULES`].
#[derive(Debug, Clone, PartialEq)]
pub enum C0Rule {
    /// A model derived for the kernel: `derived` is its default model,
    /// `derived:NAME` a named one.
    Derived(Option<String>),
    /// The derivation with a technical eps0 (`derived-eps`, 0.01 by default;
    /// `derived-eps:0.02`) in place of the kernel's kinematic one, with the
    /// kernel's default model.
    DerivedEps(Option<f64>),
    /// A code's rule: a formula of the flow alone ([`RuleKind::Code`]), one
    /// of [`RULES`]' entries ([`RULE10`] and the others).
    Code(&'static RuleEntry),
    /// The solver's answer for the scene: found by running the search
    /// first, so only the commands that run the solver resolve it (`run`
    /// and `c0 --empirical`); the problem layer refuses it.
    Empirical,
    Table2,
}

/// The technical eps0 of `derived-eps` when none is given: 1 %, the usual
/// weakly compressible tolerance the paper's conclusion names.
pub const DEFAULT_TECHNICAL_EPS0: f64 = 0.01;

/// The flow a code's rule reads: U the centre-line speed, F = p the body
/// force per unit mass, nu the viscosity and B the half-width (L = 2 B).
#[derive(Debug, Clone, Copy)]
pub struct RuleFlow {
    pub u: f64,
    pub p: f64,
    pub nu: f64,
    pub b: f64,
}

/// Morris, Fox and Zhu's (1997) relative density variation, delta = 0.01.
pub const MORRIS_DELTA: f64 = 0.01;

/// What a rule is: the kernel's derivation, its printed row, the solver's
/// answer, or a code's formula of the flow alone.
#[derive(Debug, Clone, Copy)]
pub enum RuleKind {
    Derived,
    DerivedEps,
    Table2,
    Empirical,
    /// A code's rule: its c0 from the flow.
    Code {
        c0: fn(&RuleFlow) -> f64,
    },
}

/// One c0 rule: how a scene names it, its c0 in words (with U, B, F, nu and
/// L = 2 B as [`RuleFlow`] has them) and where it comes from, and for a
/// code's rule its formula. The parser, the `--c0` help, every answer's
/// list of rules and the tests read [`RULES`]; docs/c0-rules.md's table is
/// held to it by a test.
#[derive(Debug, Clone, Copy)]
pub struct RuleEntry {
    /// The name, or the names' pattern for a rule with a parameter.
    pub syntax: &'static str,
    pub formula: &'static str,
    pub source: &'static str,
    pub kind: RuleKind,
}

/// Entries are one rule each, named by their syntax (their formulas are
/// functions, which do not compare).
impl PartialEq for RuleEntry {
    fn eq(&self, other: &Self) -> bool {
        self.syntax == other.syntax
    }
}

impl RuleEntry {
    /// The rule's fixed name: its syntax when it takes no parameter.
    pub fn fixed(&'static self) -> Option<C0Rule> {
        match self.kind {
            RuleKind::Code { .. } => Some(C0Rule::Code(self)),
            RuleKind::Table2 => Some(C0Rule::Table2),
            RuleKind::Empirical => Some(C0Rule::Empirical),
            RuleKind::Derived | RuleKind::DerivedEps => None,
        }
    }
}

/// The kernel's derived models.
pub static DERIVED: RuleEntry = RuleEntry {
    syntax: "derived, derived:MODEL",
    formula: "the kernel's derived models",
    source: "Reshetnikova (2024), `codegen`",
    kind: RuleKind::Derived,
};

/// The derivation with a technical eps0.
pub static DERIVED_EPS: RuleEntry = RuleEntry {
    syntax: "derived-eps[:E]",
    formula: "the same balance with a technical eps0 E (default 0.01)",
    source: "the paper's conclusion",
    kind: RuleKind::DerivedEps,
};

/// The paper's printed Table 2.
pub static TABLE2: RuleEntry = RuleEntry {
    syntax: "table2",
    formula: "the paper's printed row",
    source: "Table 2",
    kind: RuleKind::Table2,
};

/// c0 = 10 U.
pub static RULE10: RuleEntry = RuleEntry {
    syntax: "rule10",
    formula: "10 U",
    source: "Monaghan 1994; PySPH, SPHinXsys Poiseuille examples",
    kind: RuleKind::Code { c0: |f| 10.0 * f.u },
};

/// Morris, Fox and Zhu (1997), 2.2.
pub static MORRIS1997: RuleEntry = RuleEntry {
    syntax: "morris1997",
    formula: "c² = max(U²/δ, ν U/(L δ), F L/δ), δ = 0.01",
    source: "Morris, Fox & Zhu 1997, 2.2 (plates at 0 and L)",
    kind: RuleKind::Code {
        c0: |f| {
            let (delta, l) = (MORRIS_DELTA, 2.0 * f.b);
            let c2 = (f.u * f.u / delta)
                .max(f.nu * f.u / (l * delta))
                .max(f.p * l / delta);
            c2.sqrt()
        },
    },
};

/// GPUSPH.
pub static GPUSPH: RuleEntry = RuleEntry {
    syntax: "gpusph",
    formula: "20 max(sqrt(2 F L), U)",
    source: "GPUSPH `src/problems/Poiseuille.cu`",
    kind: RuleKind::Code {
        c0: |f| 20.0 * (2.0 * f.p * (2.0 * f.b)).sqrt().max(f.u),
    },
};

/// DualSPHysics.
pub static DUALSPHYSICS: RuleEntry = RuleEntry {
    syntax: "dualsphysics",
    formula: "20 sqrt(2 F B): coefsound 20 × speedsystem sqrt(\\|g\\| hswl), F as g, hswl = 2B",
    source: "DualSPHysics JCaseCtes / GenCase defaults",
    kind: RuleKind::Code {
        c0: |f| 20.0 * (f.p * (2.0 * f.b)).sqrt(),
    },
};

/// TrixiParticles.jl.
pub static TRIXI: RuleEntry = RuleEntry {
    syntax: "trixi",
    formula: "100 U",
    source: "TrixiParticles.jl `examples/fluid/poiseuille_flow_2d.jl`",
    kind: RuleKind::Code {
        c0: |f| 100.0 * f.u,
    },
};

/// The solver's answer.
pub static EMPIRICAL: RuleEntry = RuleEntry {
    syntax: "empirical",
    formula: "the solver's answer for the scene",
    source: "this project's `c0 --empirical`, docs/answer.md",
    kind: RuleKind::Empirical,
};

/// Every c0 rule, in the order tables list them.
pub static RULES: &[&RuleEntry] = &[
    &DERIVED,
    &DERIVED_EPS,
    &TABLE2,
    &RULE10,
    &MORRIS1997,
    &GPUSPH,
    &DUALSPHYSICS,
    &TRIXI,
    &EMPIRICAL,
];

/// The entry of a rule.
pub fn entry_of(rule: &C0Rule) -> &'static RuleEntry {
    match rule {
        C0Rule::Derived(_) => &DERIVED,
        C0Rule::DerivedEps(_) => &DERIVED_EPS,
        C0Rule::Code(e) => e,
        C0Rule::Empirical => &EMPIRICAL,
        C0Rule::Table2 => &TABLE2,
    }
}

/// What a c0 may be, for messages: the rules' names from [`RULES`].
pub fn c0_syntax() -> String {
    let names: Vec<&str> = RULES.iter().map(|e| e.syntax).collect();
    format!(
        "a number, or [FACTOR*]RULE with RULE one of {}",
        names.join(", ")
    )
}

/// The `--c0` flag's help, from [`RULES`]: every rule with its c0 and
/// source.
pub fn c0_help() -> String {
    let rules: Vec<String> = RULES
        .iter()
        .map(|e| {
            format!(
                "{}: {} ({})",
                e.syntax,
                e.formula.replace("\\|", "|"),
                e.source.replace('`', "")
            )
        })
        .collect();
    format!(
        "Sound speed: a number, or [F*]RULE. With U the centre-line speed, B the half-width, F = p \
         the body force, nu = p B^2/(2U), L = 2B the plates' distance, RULE is one of: {}. \
         `empirical` is found by running the search first: `run` does, then runs",
        rules.join("; ")
    )
}

impl fmt::Display for C0Rule {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            C0Rule::Derived(None) => write!(f, "derived"),
            C0Rule::Derived(Some(m)) => write!(f, "derived:{m}"),
            C0Rule::DerivedEps(None) => write!(f, "derived-eps"),
            C0Rule::DerivedEps(Some(e)) => write!(f, "derived-eps:{e}"),
            fixed => write!(f, "{}", entry_of(fixed).syntax),
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
                        "bad factor {:?} in c0 = {s:?}: expected {}",
                        f.trim(),
                        c0_syntax()
                    )
                })?;
                (factor, r.trim())
            }
            None => (1.0, s),
        };
        let fixed = RULES
            .iter()
            .find(|e| e.fixed().is_some() && e.syntax == rule)
            .and_then(|e| e.fixed());
        let rule = match rule {
            "derived" => C0Rule::Derived(None),
            "derived-eps" => C0Rule::DerivedEps(None),
            _ if fixed.is_some() => fixed.expect("just found"),
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
                        _ => {
                            return Err(format!("unknown c0 rule {r:?}: expected {}", c0_syntax()))
                        }
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
                write!(f, "c0 as a number or a rule name ({})", c0_syntax())
            }
            fn visit_bool<E: serde::de::Error>(self, v: bool) -> Result<C0Spec, E> {
                Err(E::custom(format!(
                    "c0 must be a number or a rule name: {}; not {v}",
                    c0_syntax()
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
            "1.2*empirical",
            "0.5*derived",
            "0.01*rule10",
        ] {
            let spec: C0Spec = s.parse().unwrap();
            assert_eq!(spec.to_string(), s);
        }
        // Every fixed rule of the registry by its name, and once with a
        // factor; the derived ones' patterns are above.
        for e in RULES {
            if let Some(rule) = e.fixed() {
                assert_eq!(
                    e.syntax.parse::<C0Spec>().unwrap(),
                    C0Spec::Rule {
                        factor: 1.0,
                        rule: rule.clone()
                    }
                );
                assert_eq!(rule.to_string(), e.syntax);
                assert_eq!(
                    format!("2*{}", e.syntax)
                        .parse::<C0Spec>()
                        .unwrap()
                        .to_string(),
                    format!("2*{}", e.syntax)
                );
            }
            assert!(
                c0_syntax().contains(e.syntax) && c0_help().contains(e.syntax),
                "{}",
                e.syntax
            );
        }
        assert!("2*nonsense".parse::<C0Spec>().is_err());
        assert!("x*rule10".parse::<C0Spec>().is_err());
        assert!("derived:".parse::<C0Spec>().is_err());
        assert!("derived-eps:0".parse::<C0Spec>().is_err());
        assert!("derived-eps:x".parse::<C0Spec>().is_err());
    }
}
