//! A sweep's grid: the points (kernels x discretisation x N x Re x alpha x
//! start x c0) a spec spans, each with its stable id, its position [`GridPosition`]
//! and its scene.

use std::fmt;

use anyhow::{bail, Context, Result};
use serde::{Deserialize, Serialize};

use super::axes::{Discretisation, GridPosition, HOverD, Start};
use super::ClassRules;
use crate::config::bounds::{self, distinct};
use crate::config::{C0Spec, Scene, SceneError};
use crate::kernel::Lattice;
use crate::kernels;

/// A point's sound speed: a rule in scene syntax (`derived`, `0.5*rule10`,
/// a number) or a multiple of U.
#[derive(Debug, Clone, PartialEq)]
pub enum PointC0 {
    Spec(C0Spec),
    OverU(f64),
}

impl fmt::Display for PointC0 {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            PointC0::Spec(s) => write!(f, "{s}"),
            PointC0::OverU(x) => write!(f, "{x}U"),
        }
    }
}

/// One scene of a sweep.
#[derive(Debug, Clone, PartialEq)]
pub struct Point {
    /// Position in the whole grid (before sharding).
    pub index: usize,
    /// Position on each axis of the grid.
    pub at: GridPosition,
    pub kernel: String,
    pub n: u32,
    pub re: f64,
    pub alpha: f64,
    pub c0: PointC0,
    pub disc: Discretisation,
    pub start: Start,
}

impl Point {
    /// A point on the paper's discretisation from a perfect start, at
    /// position `at` (the default when the caller keeps no grid).
    pub fn paper(index: usize, kernel: &str, n: u32, re: f64, alpha: f64, c0: PointC0) -> Point {
        Point {
            index,
            at: GridPosition::default(),
            kernel: kernel.to_string(),
            n,
            re,
            alpha,
            c0,
            disc: Discretisation::PAPER,
            start: Start::Perfect,
        }
    }

    /// The stable key of this point: the same grid values give the same id.
    /// The paper's discretisation from a perfect start has the id it had
    /// before those axes existed (`monaghan/n=10/re=30/alpha=0.1/c0=rule10`,
    /// so every earlier results.jsonl resumes); another one adds
    /// `/lattice=square`, `/h=13/10`, `/jitter=0.05/seed=2`.
    pub fn id(&self) -> String {
        format!(
            "{}/n={}/re={}/alpha={}/c0={}{}{}",
            self.kernel,
            self.n,
            self.re,
            self.alpha,
            self.c0,
            self.disc.id_suffix(),
            self.start.id_suffix()
        )
    }

    /// [`Point::scene`] with the bounds that classify its run set from the
    /// sweep's `[classes]`: the scene's `linf_bound` and `eps_margin`, the
    /// one place a run's class is judged from, for `run` and a sweep alike.
    pub fn scene_classed(
        &self,
        base: &toml::Table,
        rules: &ClassRules,
    ) -> Result<Scene, SceneError> {
        let mut scene = self.scene(base)?;
        scene.linf_bound = rules.linf_bound;
        scene.eps_margin = rules.eps_margin;
        Ok(scene)
    }

    /// The scene: the built-in one, `base` over it, then this point's values.
    pub fn scene(&self, base: &toml::Table) -> Result<Scene, SceneError> {
        use toml::Value;
        let mut over = base.clone();
        over.remove("c0");
        over.insert("kernel".into(), Value::String(self.kernel.clone()));
        over.insert("n_layers".into(), Value::Integer(self.n.into()));
        over.remove("p");
        over.insert("re".into(), Value::Float(self.re));
        over.insert("alpha".into(), Value::Float(self.alpha));
        // The paper's discretisation is the built-in scene's: `base` may
        // name another (a report's scene; a sweep refuses it in `scene`).
        if self.disc != Discretisation::PAPER {
            over.insert(
                "lattice".into(),
                Value::String(self.disc.lattice.name().into()),
            );
            over.insert(
                "h_over_d".into(),
                Value::String(self.disc.h_over_d.to_string()),
            );
        }
        if let Start::Jittered { amplitude, seed } = self.start {
            over.insert("jitter".into(), Value::Float(amplitude));
            over.insert("jitter_seed".into(), Value::Integer(seed.into()));
        }
        let mut scene = Scene::load(None, over)?;
        scene.c0 = match &self.c0 {
            PointC0::Spec(s) => s.clone(),
            PointC0::OverU(x) => C0Spec::Value(x * scene.u),
        };
        Ok(scene)
    }
}

/// A sweep as written in a sweep file (TOML) or given by flags: the grid, the
/// base scene and the class rules. Its canonical form is stored as
/// `sweep.toml` in the output folder and identifies the sweep on resume and
/// merge.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SweepSpec {
    /// Kernel names; empty means every kernel.
    #[serde(default)]
    pub kernels: Vec<String>,
    #[serde(default = "default_n")]
    pub n: Vec<u32>,
    #[serde(default = "default_re")]
    pub re: Vec<f64>,
    #[serde(default = "default_alpha")]
    pub alpha: Vec<f64>,
    /// Sound speeds as rules in scene syntax (`derived`, `derived:MODEL`,
    /// `rule10`, `table2`, `0.5*derived`, a number).
    #[serde(default)]
    pub c0: Vec<String>,
    /// Sound speeds as multiples of U.
    #[serde(default)]
    pub c0_over_u: Vec<f64>,
    /// Starting lattices, by name (`Lattice::ALL`).
    #[serde(default = "default_lattice")]
    pub lattice: Vec<Lattice>,
    /// h/d values, numbers or exact rationals (`"13/10"`); each with each
    /// lattice must be a generated discretisation of every kernel. Written
    /// as the exact text.
    #[serde(default = "default_h_over_d")]
    pub h_over_d: Vec<HOverD>,
    /// Jitter amplitudes of the start, in d (0: the perfect lattice).
    #[serde(default = "default_jitter")]
    pub jitter: Vec<f64>,
    /// Seeds (1..=seeds) of each non-zero jitter amplitude.
    #[serde(default = "default_seeds")]
    pub seeds: u32,
    #[serde(default)]
    pub classes: ClassRules,
    /// Scene fields laid over the built-in scene for every point (e.g.
    /// `decay_tol`, `initial`, `u`); the grid's fields win.
    #[serde(default)]
    pub scene: toml::Table,
}

fn default_n() -> Vec<u32> {
    vec![10]
}
fn default_re() -> Vec<f64> {
    vec![1.0, 30.0]
}
fn default_alpha() -> Vec<f64> {
    vec![crate::config::DEFAULT_ALPHA]
}
fn default_lattice() -> Vec<Lattice> {
    vec![Lattice::Triangular]
}
fn default_h_over_d() -> Vec<HOverD> {
    vec![HOverD::ONE]
}
fn default_jitter() -> Vec<f64> {
    vec![0.0]
}
/// Three seeds per amplitude, as `c0 --empirical` takes (docs/stationary.md:
/// on a strip as wide as the channel the seeds agree to a few per cent).
fn default_seeds() -> u32 {
    3
}

/// Where a sweep's values came from, to name them in an error: a flag,
/// the sweep file, the `--scene` file, the default. The default names
/// each field as the sweep's, with its flag.
pub trait Origins {
    /// The grid's field `field` (`n`, `seeds`, `classes.linf_bound`).
    fn grid(&self, field: &str) -> String {
        format!("sweep field `{field}` (flag --{})", grid_flag(field))
    }
    /// The base scene's field `field` (`t_end`, `gamma`).
    fn scene(&self, field: &str) -> String {
        format!("sweep field `scene.{field}`")
    }
    /// The base scene as a whole.
    fn scene_table(&self) -> String {
        "sweep field `scene`".into()
    }
}

/// The flag of a grid field.
pub fn grid_flag(field: &str) -> String {
    match field {
        "kernels" => "kernel".into(),
        "classes.linf_bound" => "linf-bound".into(),
        "classes.eps_margin" => "eps-margin".into(),
        f => f.replace('_', "-"),
    }
}

/// Fields named as the sweep's own (see [`Origins`]).
pub struct Unlabelled;
impl Origins for Unlabelled {}

/// The grid field a scene field of a point comes from (`n_layers` from
/// `n`), or `None` for the base scene's own.
pub fn grid_field_of(scene_field: &str) -> Option<&'static str> {
    Some(match scene_field {
        "kernel" => "kernels",
        "n_layers" => "n",
        "re" | "p" => "re",
        "alpha" => "alpha",
        "c0" => "c0",
        "lattice" => "lattice",
        "h_over_d" => "h_over_d",
        "jitter" => "jitter",
        "jitter_seed" => "seeds",
        "linf_bound" => "classes.linf_bound",
        "eps_margin" => "classes.eps_margin",
        _ => return None,
    })
}

/// A scene's error (a point's, or the base scene's) naming its field where
/// it came from: a grid axis (`n_layers` from the grid's `n`) or the base
/// scene.
pub fn label_scene(e: SceneError, origins: &dyn Origins) -> SceneError {
    match e.field() {
        Some(f) => {
            let origin = match grid_field_of(f) {
                Some(g) => origins.grid(g),
                None => origins.scene(f),
            };
            e.from_origin(origin)
        }
        None => e,
    }
}

impl Default for SweepSpec {
    fn default() -> Self {
        toml::from_str("").expect("the empty sweep is valid")
    }
}

impl SweepSpec {
    pub fn from_toml(text: &str, origin: &str) -> Result<SweepSpec> {
        toml::from_str(text).map_err(|e| anyhow::anyhow!("{origin}: {}", e.message().trim()))
    }

    pub fn to_toml(&self) -> String {
        toml::to_string(self).expect("a sweep serialises")
    }

    /// Fill the defaults (every kernel; derived, rule10 and table2 when no
    /// c0 is given) and check every value, so that the stored form is
    /// complete and a bad grid fails before anything runs. Errors name each
    /// field as `sweep field `n` (flag --n)`; see [`SweepSpec::resolved_as`].
    pub fn resolved(self) -> Result<SweepSpec> {
        self.resolved_as(&Unlabelled)
    }

    /// [`SweepSpec::resolved`], naming each field where `origins` says it
    /// came from (a flag, the sweep file, the default).
    pub fn resolved_as(mut self, origins: &dyn Origins) -> Result<SweepSpec> {
        if self.kernels.is_empty() {
            self.kernels = kernels::NAMES.iter().map(|s| s.to_string()).collect();
        }
        if self.c0.is_empty() && self.c0_over_u.is_empty() {
            self.c0 = vec!["derived".into(), "rule10".into(), "table2".into()];
        }
        let name = |field: &str| origins.grid(field);
        for k in &self.kernels {
            crate::config::kernel_info(k).with_context(|| name("kernels"))?;
        }
        for c in &self.c0 {
            let spec = c
                .parse::<C0Spec>()
                .map_err(|e| anyhow::anyhow!("{}: {e}", name("c0")))?;
            // The solver's own search is not a rule a point can take: it is
            // many runs per point (`c0 --empirical`), and each point's row
            // would be its bisection's, not one run's.
            if let C0Spec::Rule {
                rule: crate::config::C0Rule::Empirical,
                ..
            } = spec
            {
                bail!(
                    "{}: {c:?} is the solver's own search (shearsph c0 --empirical: a bisection of \
                     many runs), not a c0 a grid point can run at; find it per scene with \
                     `shearsph c0 --empirical` (or `shearsph law` over N x Re x alpha) and grid \
                     the numbers it gives",
                    name("c0")
                );
            }
        }
        let check = |field: &str, empty: bool| -> Result<()> {
            if empty {
                bail!("{} is empty: give at least one value", name(field));
            }
            Ok(())
        };
        check("n", self.n.is_empty())?;
        check("re", self.re.is_empty())?;
        check("alpha", self.alpha.is_empty())?;
        check("lattice", self.lattice.is_empty())?;
        check("h_over_d", self.h_over_d.is_empty())?;
        check("jitter", self.jitter.is_empty())?;
        for (field, values) in [("re", &self.re), ("c0_over_u", &self.c0_over_u)] {
            if let Some(v) = values.iter().find(|v| !(**v > 0.0 && v.is_finite())) {
                bail!("{}: {v} must be a positive number", name(field));
            }
        }
        for &v in &self.alpha {
            crate::config::check_alpha(v).map_err(|e| anyhow::anyhow!("{}: {e}", name("alpha")))?;
        }
        if self.n.contains(&0) {
            bail!("{}: 0 is not a number of layers; give N >= 1", name("n"));
        }
        // A repeated value would run (and count) one point twice: an error,
        // for every list alike.
        distinct(&name("kernels"), &self.kernels)?;
        distinct(&name("n"), &self.n)?;
        distinct(&name("re"), &self.re)?;
        distinct(&name("alpha"), &self.alpha)?;
        distinct(&name("c0"), &self.c0)?;
        distinct(&name("c0_over_u"), &self.c0_over_u)?;
        distinct(&name("lattice"), &self.lattice)?;
        distinct(&name("jitter"), &self.jitter)?;
        // Checked whether or not a start is jittered: a count out of its
        // bound is an error wherever it is given, not only where it is used.
        bounds::SEEDS.check(&name("seeds"), self.seeds.into())?;
        // The grid's size before the grid is built: a count of 1e9 points
        // is an error now, not gigabytes of points later.
        bounds::POINTS.check(
            "the grid's points (kernels x lattice x h_over_d x n x re x alpha x starts x c0)",
            self.point_count(),
        )?;
        for (key, instead) in [
            ("kernel", "kernels"),
            ("n_layers", "n"),
            ("re", "re"),
            ("p", "re"),
            ("alpha", "alpha"),
            ("c0", "c0 or c0_over_u"),
            ("lattice", "lattice"),
            ("h_over_d", "h_over_d"),
            ("jitter", "jitter"),
            ("jitter_seed", "seeds"),
            ("linf_bound", "classes.linf_bound"),
            ("eps_margin", "classes.eps_margin"),
        ] {
            if self.scene.contains_key(key) {
                bail!(
                    "{}: the grid sets it; give it as the grid's own `{instead}` instead",
                    origins.scene(key)
                );
            }
        }
        // The base scene must be a valid scene by itself: its own fields
        // first, each named, before any value of the grid is laid over it.
        let base = Scene::load(None, self.scene.clone())
            .map_err(|e| anyhow::anyhow!("{}: {e}", origins.scene_table()))?;
        crate::problem::check_fields(&base).map_err(|e| label_scene(e, origins))?;
        self.check_discretisations(origins)?;
        distinct(&name("h_over_d"), &self.h_over_d)?;
        self.check_by_scene(&base, origins)?;
        Ok(self)
    }

    /// The number of points [`SweepSpec::points`] gives, without building
    /// them (saturating: a grid too large to count is too large).
    pub fn point_count(&self) -> u64 {
        let c0s = (self.c0.len() + self.c0_over_u.len()) as u64;
        let starts: u64 = self
            .jitter
            .iter()
            .map(|&a| if a == 0.0 { 1 } else { u64::from(self.seeds) })
            .fold(0u64, u64::saturating_add);
        [
            self.kernels.len() as u64,
            self.lattice.len() as u64,
            self.h_over_d.len() as u64,
            self.n.len() as u64,
            self.re.len() as u64,
            self.alpha.len() as u64,
            starts,
            c0s,
        ]
        .into_iter()
        .fold(1u64, u64::saturating_mul)
    }

    /// Check that every kernel has every lattice x h/d pair (else the
    /// scene's own error, naming the line to add and the command to run).
    fn check_discretisations(&self, origins: &dyn Origins) -> Result<()> {
        for v in &self.h_over_d {
            for k in &self.kernels {
                let info = crate::config::kernel_info(k)?;
                for &lattice in &self.lattice {
                    crate::config::discretisation(info, lattice, v.value())
                        .with_context(|| format!("{} = {v}", origins.grid("h_over_d")))?;
                }
            }
        }
        Ok(())
    }

    /// The values the scene guards, by its own guards: the class bounds
    /// (they become the scene's `linf_bound` and `eps_margin`) and every
    /// jitter amplitude; and seeds for the non-zero amplitudes. `base` is
    /// the base scene, its own fields already checked.
    fn check_by_scene(&self, base: &Scene, origins: &dyn Origins) -> Result<()> {
        // The bounds are the scene's (`scene_classed`): its guards.
        for (field, v) in [
            ("linf_bound", self.classes.linf_bound),
            ("eps_margin", self.classes.eps_margin),
        ] {
            crate::config::positive(field, v).map_err(|e| {
                anyhow::anyhow!("{}: {e}", origins.grid(&format!("classes.{field}")))
            })?;
        }
        for &a in &self.jitter {
            crate::problem::check_fields(&Scene {
                jitter: a,
                ..base.clone()
            })
            .map_err(|e| anyhow::anyhow!("{}: {e}", origins.grid("jitter")))?;
        }
        Ok(())
    }

    /// The grid's discretisations in order (lattice, then h/d), with their
    /// indices.
    fn discretisations(&self) -> Vec<(u32, u32, Discretisation)> {
        let mut out = Vec::new();
        for (li, &lattice) in (0..).zip(&self.lattice) {
            for (hi, &h_over_d) in (0..).zip(&self.h_over_d) {
                out.push((li, hi, Discretisation { lattice, h_over_d }));
            }
        }
        out
    }

    /// The grid's starts in order: per amplitude, the perfect lattice for
    /// 0, else seeds 1..=seeds; with the amplitude's index.
    fn starts(&self) -> Vec<(u32, Start)> {
        let mut out = Vec::new();
        for (ji, &amplitude) in (0..).zip(&self.jitter) {
            if amplitude == 0.0 {
                out.push((ji, Start::Perfect));
            } else {
                out.extend((1..=self.seeds).map(|seed| (ji, Start::Jittered { amplitude, seed })));
            }
        }
        out
    }

    /// Every point of the grid, in grid order (kernel, lattice, h/d, N, Re,
    /// alpha, start, c0): with one lattice, h/d and start the order, and so
    /// the index, of the grid before those axes.
    pub fn points(&self) -> Vec<Point> {
        let mut c0s: Vec<PointC0> = self
            .c0
            .iter()
            .map(|c| PointC0::Spec(c.parse().expect("checked by resolved()")))
            .collect();
        c0s.extend(self.c0_over_u.iter().map(|&x| PointC0::OverU(x)));
        let (discs, starts) = (self.discretisations(), self.starts());
        let mut out = Vec::new();
        for (ki, kernel) in (0..).zip(&self.kernels) {
            for &(li, hi, disc) in &discs {
                for (ni, &n) in (0..).zip(&self.n) {
                    for (ri, &re) in (0..).zip(&self.re) {
                        for (ai, &alpha) in (0..).zip(&self.alpha) {
                            for &(ji, start) in &starts {
                                for (ci, c0) in (0..).zip(&c0s) {
                                    let (_, seed) = start.jitter();
                                    out.push(Point {
                                        index: out.len(),
                                        at: GridPosition {
                                            kernel: ki,
                                            lattice: li,
                                            h_over_d: hi,
                                            n: ni,
                                            re: ri,
                                            alpha: ai,
                                            jitter: ji,
                                            seed,
                                            c0: ci,
                                        },
                                        kernel: kernel.clone(),
                                        n,
                                        re,
                                        alpha,
                                        c0: c0.clone(),
                                        disc,
                                        start,
                                    });
                                }
                            }
                        }
                    }
                }
            }
        }
        out
    }
}

#[cfg(test)]
mod tests;
