//! The report's config: the embedded `report.toml`, `quick.toml`, or a
//! file, its defaults for older configs, and its validation (every count
//! bounded, every value in range) before anything runs.

use anyhow::{bail, Context, Result};
use serde::{Deserialize, Serialize};

use super::cases::CaseConfig;
use crate::kernel::KernelInfo;
use crate::kernels;
use crate::sweep::{ClassRules, Start};

/// The default report's config.
pub const DEFAULT_CONFIG: &str = include_str!("report.toml");
/// The `--quick` report's config.
pub const QUICK_CONFIG: &str = include_str!("quick.toml");

#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ReportConfig {
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
    pub perturbed: PerturbedConfig,
    /// The discretisations the report runs, the paper's first.
    pub case: Vec<CaseConfig>,
    pub figure4: Figure4Config,
    /// A config without `[growth]` has no growth map.
    #[serde(default)]
    pub growth: GrowthConfig,
}

/// A config written before the report ran perturbed lattices has no
/// `[perturbed]`: it gets the default report's, every map Re perturbed
/// (0.05 d, 3 seeds); one written before the cases were listed gets them
/// ([`super::cases::fill_missing_cases`]). Left alone when `[maps]` or
/// `[empirical]` is missing (the error then names those).
fn fill_missing_lattices(table: &mut toml::Table) {
    let re_of = |section: &str| table.get(section).and_then(|t| t.get("re")).cloned();
    let (Some(maps_re), Some(empirical_re)) = (re_of("maps"), re_of("empirical")) else {
        return;
    };
    table.entry("perturbed").or_insert_with(|| {
        let mut t = toml::Table::new();
        t.insert("jitter".into(), toml::Value::Float(0.05));
        t.insert("seeds".into(), toml::Value::Integer(3));
        t.insert("re".into(), maps_re);
        toml::Value::Table(t)
    });
    super::cases::fill_missing_cases(table, empirical_re);
}

/// Perturbed starts: every map point (at `re`), every rule at the verdicts'
/// Re and the empirical c0 also run from `seeds` starts jittered by
/// `jitter` d; a point's perturbed outcome pools the seeds
/// (docs/stationary.md).
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PerturbedConfig {
    pub jitter: f64,
    pub seeds: u32,
    /// The maps' Re run perturbed too (each one of maps.re, every
    /// empirical.re among them).
    pub re: Vec<f64>,
}

/// Speed against accuracy: the start-up problem from rest to the time its
/// slowest mode falls below `decay_tol` U (a fixed horizon: the cost of a
/// laminar run to a given accuracy, not the disordered answer).
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SpeedConfig {
    pub n: Vec<u32>,
    pub re: Vec<f64>,
    pub alpha: f64,
    pub c0: Vec<String>,
    #[serde(default = "speed_decay_tol")]
    pub decay_tol: f64,
}

fn speed_decay_tol() -> f64 {
    0.01
}

#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MapsConfig {
    pub n: u32,
    pub alpha: f64,
    pub re: Vec<f64>,
    pub c0_over_u: Vec<f64>,
}

/// The empirical c0: the engine's answer (`c0 --empirical`'s) at each Re,
/// the bisection to `rel_tol`.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EmpiricalConfig {
    pub re: Vec<f64>,
    pub rel_tol: f64,
    /// Read and ignored: configs written when the bisection started from
    /// the map's rows had it (the engine brackets its own search now).
    #[serde(default, skip_serializing)]
    pub max_extend: Option<u32>,
}

/// The growth map: the ordered lattice's leading growth rate (`shearsph
/// stability`'s analysis) over `c0_over_u` x `re`, per kernel on each
/// case's discretisation at maps.n and maps.alpha, each perturbation
/// followed over `horizon` (in t, U = d = 1); none when a list is empty.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GrowthConfig {
    pub re: Vec<f64>,
    pub c0_over_u: Vec<f64>,
    #[serde(default = "growth_horizon")]
    pub horizon: f64,
}

/// `shearsph stability`'s default horizon.
fn growth_horizon() -> f64 {
    300.0
}

/// The growth map's horizon's bounds: below 20 t the rate is the start's
/// transient (the analysis warms up over 20 t); above 3000 t one map cell
/// costs minutes.
pub const GROWTH_HORIZON: (f64, f64) = (20.0, 3000.0);
/// The most values in each of the growth map's lists.
pub const GROWTH_MAX_VALUES: usize = 16;

#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Figure4Config {
    pub n: u32,
    pub samples: usize,
}

impl ReportConfig {
    pub fn parse(text: &str, origin: &str) -> Result<ReportConfig> {
        let mut table: toml::Table = toml::from_str(text)
            .map_err(|e| anyhow::anyhow!("{origin}: {}", e.message().trim()))?;
        fill_missing_lattices(&mut table);
        let c: ReportConfig = table
            .try_into()
            .map_err(|e: toml::de::Error| anyhow::anyhow!("{origin}: {}", e.message().trim()))?;
        c.check().with_context(|| origin.to_string())?;
        Ok(c)
    }

    pub fn default_full() -> ReportConfig {
        ReportConfig::parse(DEFAULT_CONFIG, "src/studies/report/report.toml")
            .expect("the embedded report config is valid")
    }

    pub fn quick() -> ReportConfig {
        ReportConfig::parse(QUICK_CONFIG, "src/studies/report/quick.toml")
            .expect("the embedded quick config is valid")
    }

    pub(super) fn check(&self) -> Result<()> {
        for k in &self.kernels {
            crate::config::kernel_info(k)?;
        }
        for re in &self.empirical.re {
            if !self.maps.re.contains(re) {
                bail!("empirical.re = {re} is not one of maps.re: the empirical search is reported beside the map's row at that Re");
            }
        }
        self.check_re_list("perturbed.re", &self.perturbed.re)?;
        self.check_cases()?;
        let j = self.perturbed.jitter;
        if !(j > 0.0 && j < 0.5) || self.perturbed.seeds == 0 {
            bail!("perturbed.jitter must be in (0, 0.5) d and perturbed.seeds at least 1 (got {j} and {})", self.perturbed.seeds);
        }
        if self.maps.c0_over_u.is_empty() || self.maps.re.is_empty() {
            bail!("maps.re and maps.c0_over_u need at least one value each");
        }
        self.search().check(|field| match field {
            "amplitude" => "perturbed.jitter".to_string(),
            "seeds" => "perturbed.seeds".to_string(),
            "rel_tol" => "empirical.rel_tol".to_string(),
            f => f.to_string(),
        })?;
        if self.figure4.samples < 2 {
            bail!("figure4.samples must be at least 2");
        }
        self.check_growth()?;
        self.check_counts()
    }

    /// A list of the maps' Re a part runs: each one of maps.re, every
    /// empirical.re among them.
    pub(super) fn check_re_list(&self, field: &str, list: &[f64]) -> Result<()> {
        if let Some(re) = list.iter().find(|re| !self.maps.re.contains(re)) {
            bail!("{field} = {re} is not one of maps.re: give each as one of the map's Re");
        }
        if let Some(re) = self.empirical.re.iter().find(|re| !list.contains(re)) {
            bail!("{field} lacks empirical.re = {re}: the empirical search is reported beside the map's row at that Re");
        }
        crate::config::bounds::distinct(field, list)?;
        Ok(())
    }

    /// The growth map's lists: every value a positive finite number, at
    /// most [`GROWTH_MAX_VALUES`] of each, none twice; the horizon within
    /// [`GROWTH_HORIZON`] when the map is asked.
    fn check_growth(&self) -> Result<()> {
        let g = &self.growth;
        for (field, list, what) in [
            ("growth.re", &g.re, "a Reynolds number"),
            ("growth.c0_over_u", &g.c0_over_u, "a sound speed in U"),
        ] {
            if let Some(v) = list.iter().find(|v| !(v.is_finite() && **v > 0.0)) {
                bail!("{field} = {v} is not {what}: give positive finite numbers (or none: no growth map)");
            }
            if list.len() > GROWTH_MAX_VALUES {
                bail!(
                    "{field} has {} values, more than {GROWTH_MAX_VALUES}: each cell of the map is a stability analysis of seconds",
                    list.len()
                );
            }
            crate::config::bounds::distinct(field, list)?;
        }
        let (lo, hi) = GROWTH_HORIZON;
        let asked = !(g.re.is_empty() || g.c0_over_u.is_empty());
        if asked && !(lo..=hi).contains(&g.horizon) {
            bail!(
                "growth.horizon = {} must be from {lo} to {hi} (t, U = d = 1): below, the rate is the warm-up's transient; above, a cell costs minutes",
                g.horizon
            );
        }
        Ok(())
    }

    /// Every count of the config within its bound and no list giving a
    /// value twice, as a sweep's grid, before any scene runs (a `maps.n =
    /// 0` would otherwise surface after the whole grid): each N a lattice
    /// the memory bound holds for every kernel, the seeds and the
    /// bisection's extensions bounded.
    fn check_counts(&self) -> Result<()> {
        use crate::config::bounds::{self, distinct, Count};
        distinct("kernels", &self.kernels)?;
        distinct("speed.n", &self.speed.n)?;
        distinct("speed.re", &self.speed.re)?;
        distinct("speed.c0", &self.speed.c0)?;
        distinct("maps.re", &self.maps.re)?;
        distinct("maps.c0_over_u", &self.maps.c0_over_u)?;
        distinct("empirical.re", &self.empirical.re)?;
        bounds::SEEDS.check("perturbed.seeds", self.perturbed.seeds.into())?;
        Count {
            min: 0,
            max: 100,
            why_min: "",
            why_max: "each extension divides the map's lowest c0 by 3: 100 reach 2e-48 of it, below any c0 a run can take",
        }
        .check("empirical.max_extend", self.empirical.max_extend.unwrap_or(0).into())?;
        Count {
            min: 2,
            max: 1_000_000,
            why_min: "a curve needs two points",
            why_max:
                "points of each curve of Figure 4: a million already make an SVG of tens of MB",
        }
        .check_usize("figure4.samples", self.figure4.samples)?;
        let ns = self
            .speed
            .n
            .iter()
            .map(|&n| ("speed.n", n))
            .chain([("maps.n", self.maps.n), ("figure4.n", self.figure4.n)]);
        for (field, n) in ns {
            if n == 0 {
                bail!("{field} = 0 is not a number of layers; give N >= 1");
            }
            for info in self.kernel_infos() {
                let mut over = self.scene.clone();
                over.insert("kernel".into(), toml::Value::String(info.name.into()));
                over.insert("n_layers".into(), toml::Value::Integer(n.into()));
                let Ok(scene) = crate::config::Scene::load(None, over) else {
                    continue;
                };
                // The lattice's own guards (too small for the support, or
                // more particles than the memory bound holds).
                if let Err(e) = crate::problem::channel::Channel::resolve(&scene, info) {
                    if e.field() == Some("n_layers") {
                        bail!("{field} = {n}, kernel {}: {e}", info.name);
                    }
                }
            }
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
            .expect("checked by ReportConfig::check")
    }

    /// The seeds of a case's starts: 0 (the perfect lattice) or 1..=seeds.
    pub fn seeds(&self, perturbed: bool) -> std::ops::RangeInclusive<u32> {
        if perturbed {
            1..=self.perturbed.seeds
        } else {
            0..=0
        }
    }

    /// The start of seed `seed` (0: perfect).
    pub fn start(&self, seed: u32) -> Start {
        match seed {
            0 => Start::Perfect,
            seed => Start::Jittered {
                amplitude: self.perturbed.jitter,
                seed,
            },
        }
    }

    /// The perturbation in words: "jittered by 0.05 d, 3 seeds pooled".
    pub fn perturbed_label(&self) -> String {
        format!(
            "jittered by {} d, {} seeds pooled",
            self.perturbed.jitter, self.perturbed.seeds
        )
    }

    /// The engine's search as the report asks it.
    pub fn search(&self) -> crate::empirical::Search {
        super::empirical::search(self)
    }

    /// The scene fields under every run: `[scene]`, and for the speed
    /// grid's runs (`speed`) the fixed horizon of the start-up problem.
    pub fn base(&self, speed: bool) -> toml::Table {
        let mut t = self.scene.clone();
        if speed {
            t.insert("horizon".into(), toml::Value::String("fixed".into()));
            t.insert("decay_tol".into(), toml::Value::Float(self.speed.decay_tol));
        }
        t
    }
}

#[cfg(test)]
mod tests {
    use std::collections::BTreeSet;

    use super::*;
    use crate::config::C0Rule;
    use crate::report::plan::{CaseDiscretisation, Key, Role};

    #[test]
    fn embedded_configs_parse_and_cover_the_verdicts() {
        for c in [ReportConfig::default_full(), ReportConfig::quick()] {
            let plan = c.plan();
            // One scene per id and horizon (the speed grid's own fixed one).
            let ids: BTreeSet<(bool, String)> = plan
                .points
                .iter()
                .zip(&plan.speed)
                .map(|(p, s)| (*s, p.id()))
                .collect();
            assert_eq!(ids.len(), plan.points.len());
            assert_eq!(plan.keys.len(), plan.points.len());
            for (k, info) in c.kernel_infos().iter().enumerate() {
                for (ri, &re) in c.empirical.re.iter().enumerate() {
                    let id = format!(
                        "{}/n={}/re={re}/alpha={}/c0=rule10",
                        info.name, c.maps.n, c.maps.alpha
                    );
                    let i = plan
                        .points
                        .iter()
                        .zip(&plan.speed)
                        .position(|(p, s)| p.id() == id && !s)
                        .expect(&id);
                    let want = Key {
                        kernel: k,
                        role: Role::Rule {
                            disc: CaseDiscretisation::PAPER,
                            seed: 0,
                            re: ri,
                            rule: C0Rule::Code(&crate::config::RULE10),
                        },
                    };
                    assert!(plan.keys[i].contains(&want), "{id}");
                }
            }
        }
    }

    /// Every value of the growth map's lists and its horizon is checked,
    /// naming the field; a config without `[growth]` has no map; empty
    /// lists are no map, whatever the horizon.
    #[test]
    fn the_growth_map_is_checked_field_by_field() {
        let bad = |edit: &dyn Fn(&mut GrowthConfig), field: &str| {
            let mut c = ReportConfig::quick();
            edit(&mut c.growth);
            let err = c.check().expect_err(field).to_string();
            assert!(err.contains(field), "{field}: {err}");
        };
        bad(&|g| g.re = vec![1.0, 0.0], "growth.re");
        bad(&|g| g.re = vec![f64::NAN], "growth.re");
        bad(&|g| g.re = vec![1.0, 1.0], "growth.re");
        bad(&|g| g.c0_over_u = vec![-3.0], "growth.c0_over_u");
        bad(&|g| g.c0_over_u = vec![f64::INFINITY], "growth.c0_over_u");
        bad(
            &|g| g.c0_over_u = vec![1.0; GROWTH_MAX_VALUES + 1],
            "growth.c0_over_u",
        );
        bad(&|g| g.horizon = 5.0, "growth.horizon");
        bad(&|g| g.horizon = f64::NAN, "growth.horizon");
        let mut none = ReportConfig::quick();
        none.growth.re.clear();
        none.growth.horizon = 0.0;
        none.check().expect("no growth map");
        let start = QUICK_CONFIG
            .find("[growth]")
            .expect("the quick config has a map");
        let old =
            ReportConfig::parse(&QUICK_CONFIG[..start], "old.toml").expect("an old config parses");
        assert!(old.growth.re.is_empty() && old.growth.c0_over_u.is_empty());
    }
}
