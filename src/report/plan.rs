//! The report's config (the embedded `report.toml`, `quick.toml`, or a file)
//! and its plan: every scene it runs, each once, with the places in the
//! report it serves as typed keys (grid indices as integers, the rule as a
//! [`C0Rule`]). The report joins rows to its tables and figures by these
//! keys and the rows' grid index, never by comparing strings or floats.

use std::collections::BTreeMap;

use anyhow::{bail, Context, Result};
use serde::{Deserialize, Serialize};

use crate::config::{C0Rule, C0Spec};
use crate::kernel::KernelInfo;
use crate::kernels;
use crate::problem::c0::all_rules;
use crate::sweep::{ClassRules, Point, PointC0, Row};

/// The default report's config.
pub const DEFAULT_CONFIG: &str = include_str!("report.toml");
/// The `--quick` report's config.
pub const QUICK_CONFIG: &str = include_str!("quick.toml");

#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Config {
    /// Kernel names; empty means every kernel.
    #[serde(default)]
    pub kernels: Vec<String>,
    #[serde(default)]
    pub classes: ClassRules,
    /// Scene fields over the built-in scene, for every run.
    #[serde(default)]
    pub scene: toml::Table,
    pub speed: SpeedConfig,
    pub maps: MapsConfig,
    pub empirical: EmpiricalConfig,
    pub figure4: Figure4Config,
}

#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SpeedConfig {
    pub n: Vec<u32>,
    pub re: Vec<f64>,
    pub alpha: f64,
    pub c0: Vec<String>,
}

#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MapsConfig {
    pub n: u32,
    pub alpha: f64,
    pub re: Vec<f64>,
    pub c0_over_u: Vec<f64>,
}

#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EmpiricalConfig {
    pub re: Vec<f64>,
    pub rel_tol: f64,
    pub max_extend: u32,
}

#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Figure4Config {
    pub n: u32,
    pub samples: usize,
}

impl Config {
    pub fn parse(text: &str, origin: &str) -> Result<Config> {
        let c: Config = toml::from_str(text)
            .map_err(|e| anyhow::anyhow!("{origin}: {}", e.message().trim()))?;
        c.check().with_context(|| origin.to_string())?;
        Ok(c)
    }

    pub fn default_full() -> Config {
        Config::parse(DEFAULT_CONFIG, "src/report/report.toml")
            .expect("the embedded report config is valid")
    }

    pub fn quick() -> Config {
        Config::parse(QUICK_CONFIG, "src/report/quick.toml")
            .expect("the embedded quick config is valid")
    }

    fn check(&self) -> Result<()> {
        for k in &self.kernels {
            crate::config::kernel_info(k)?;
        }
        for re in &self.empirical.re {
            if !self.maps.re.contains(re) {
                bail!("empirical.re = {re} is not one of maps.re: the bisection starts from the map's row at that Re");
            }
        }
        if self.maps.c0_over_u.is_empty() || self.maps.re.is_empty() {
            bail!("maps.re and maps.c0_over_u need at least one value each");
        }
        if self.empirical.rel_tol.is_nan() || self.empirical.rel_tol <= 0.0 {
            bail!("empirical.rel_tol must be positive");
        }
        if self.figure4.samples < 2 {
            bail!("figure4.samples must be at least 2");
        }
        Ok(())
    }

    pub fn kernel_infos(&self) -> Vec<&'static KernelInfo> {
        if self.kernels.is_empty() {
            kernels::KERNELS.to_vec()
        } else {
            self.kernels
                .iter()
                .filter_map(|k| kernels::kernel_info(k))
                .collect()
        }
    }

    /// The index into `maps.re` of `empirical.re[re]` (checked to be one of
    /// them when the config was read).
    pub fn map_re_of_verdict(&self, re: usize) -> usize {
        self.maps
            .re
            .iter()
            .position(|m| *m == self.empirical.re[re])
            .expect("checked by Config::check")
    }

    /// Every scene of the report but the bisection's, each once, with its
    /// keys: the speed grid, the rules at the verdicts' Re (every derived
    /// model, 10 U, Table 2) and the maps.
    pub fn plan(&self) -> Plan {
        let infos = self.kernel_infos();
        let mut plan = Plan::default();
        let mut seen: BTreeMap<String, usize> = BTreeMap::new();
        let mut push = |kernel: usize, n: u32, re: f64, alpha: f64, c0: PointC0, role: Role| {
            let p = Point {
                index: plan.points.len(),
                kernel: infos[kernel].name.to_string(),
                n,
                re,
                alpha,
                c0,
            };
            let key = Key { kernel, role };
            match seen.get(&p.id()) {
                Some(&i) => plan.keys[i].push(key),
                None => {
                    seen.insert(p.id(), plan.points.len());
                    plan.points.push(p);
                    plan.keys.push(vec![key]);
                }
            }
        };
        for (k, &info) in infos.iter().enumerate() {
            for (ni, &n) in self.speed.n.iter().enumerate() {
                for (ri, &re) in self.speed.re.iter().enumerate() {
                    for (ci, c) in self.speed.c0.iter().enumerate() {
                        if let Ok(spec) = c.parse::<C0Spec>() {
                            let role = Role::Speed {
                                n: ni,
                                re: ri,
                                c0: ci,
                            };
                            push(k, n, re, self.speed.alpha, PointC0::Spec(spec), role);
                        }
                    }
                }
            }
            for (ri, &re) in self.empirical.re.iter().enumerate() {
                for rule in all_rules(info).into_iter().filter(is_verdict_rule) {
                    let spec = PointC0::Spec(scene_spec(info, &rule));
                    let role = Role::Rule { re: ri, rule };
                    push(k, self.maps.n, re, self.maps.alpha, spec, role);
                }
            }
            for (ri, &re) in self.maps.re.iter().enumerate() {
                for (ci, &x) in self.maps.c0_over_u.iter().enumerate() {
                    let role = Role::Map { re: ri, c0: ci };
                    push(k, self.maps.n, re, self.maps.alpha, PointC0::OverU(x), role);
                }
            }
        }
        plan
    }

    /// The points of [`Config::plan`].
    pub fn points(&self) -> Vec<Point> {
        self.plan().points
    }
}

/// The rules the verdicts compare: every derived model, `rule10`, and
/// `table2` when printed. The other codes' rules are in the c0 tables and
/// drawn on the maps, but not run here: 100 U (trixi) alone would cost ten
/// times the runs of 10 U, past the report's few minutes.
fn is_verdict_rule(rule: &C0Rule) -> bool {
    matches!(rule, C0Rule::Derived(_) | C0Rule::Rule10 | C0Rule::Table2)
}

/// A verdict rule in scene syntax: the default model as `derived`.
fn scene_spec(info: &KernelInfo, rule: &C0Rule) -> C0Spec {
    let rule = match rule {
        C0Rule::Derived(Some(m)) if m == info.c0_default => C0Rule::Derived(None),
        r => r.clone(),
    };
    C0Spec::Rule { factor: 1.0, rule }
}

/// Which part of the report a scene serves, by indices into the config's
/// lists.
#[derive(Debug, Clone, PartialEq)]
pub enum Role {
    /// The speed grid: `speed.n[n]`, `speed.re[re]`, `speed.c0[c0]`.
    Speed { n: usize, re: usize, c0: usize },
    /// A verdict rule at `empirical.re[re]` (N = maps.n, alpha = maps.alpha),
    /// its derived model named (the default one too).
    Rule { re: usize, rule: C0Rule },
    /// The stability map: `maps.re[re]`, `maps.c0_over_u[c0]`.
    Map { re: usize, c0: usize },
}

/// A scene's place in the report: the kernel (an index into
/// [`Config::kernel_infos`]) and its role.
#[derive(Debug, Clone, PartialEq)]
pub struct Key {
    pub kernel: usize,
    pub role: Role,
}

/// The report's scenes and, for each (by its grid index), every place it
/// serves.
#[derive(Debug, Default)]
pub struct Plan {
    pub points: Vec<Point>,
    pub keys: Vec<Vec<Key>>,
}

impl Plan {
    /// The rows (in their order) with a key `want` takes.
    pub fn rows<'a>(&self, rows: &'a [Row], want: impl Fn(&Key) -> bool) -> Vec<&'a Row> {
        rows.iter()
            .filter(|r| {
                self.keys
                    .get(r.index)
                    .is_some_and(|ks| ks.iter().any(&want))
            })
            .collect()
    }

    /// The row with a key `want` takes, if any.
    pub fn row<'a>(&self, rows: &'a [Row], want: impl Fn(&Key) -> bool) -> Option<&'a Row> {
        self.rows(rows, want).into_iter().next()
    }

    /// Kernel `kernel`'s stability-map rows at `maps.re[re]`, or at every Re.
    pub fn map_rows<'a>(&self, rows: &'a [Row], kernel: usize, re: Option<usize>) -> Vec<&'a Row> {
        self.rows(rows, |k| {
            k.kernel == kernel
                && matches!(k.role, Role::Map { re: r, .. } if re.is_none_or(|x| x == r))
        })
    }
}

#[cfg(test)]
mod tests {
    use std::collections::BTreeSet;

    use super::*;

    #[test]
    fn embedded_configs_parse_and_cover_the_verdicts() {
        for c in [Config::default_full(), Config::quick()] {
            let plan = c.plan();
            let ids: BTreeSet<String> = plan.points.iter().map(Point::id).collect();
            assert_eq!(ids.len(), plan.points.len());
            assert_eq!(plan.keys.len(), plan.points.len());
            for (k, info) in c.kernel_infos().iter().enumerate() {
                for (ri, &re) in c.empirical.re.iter().enumerate() {
                    let id = format!(
                        "{}/n={}/re={re}/alpha={}/c0=rule10",
                        info.name, c.maps.n, c.maps.alpha
                    );
                    let i = plan.points.iter().position(|p| p.id() == id).expect(&id);
                    let want = Key {
                        kernel: k,
                        role: Role::Rule {
                            re: ri,
                            rule: C0Rule::Rule10,
                        },
                    };
                    assert!(plan.keys[i].contains(&want), "{id}");
                }
            }
        }
    }
}
