//! The law of the minimal c0 (`shearsph law`): the empirical c0_min (the
//! engine's, [`crate::empirical::answer`]: the smallest c0 ok in the
//! stationary, disordered state) per kernel over N x Re x alpha, the
//! disordered law eps_stat = k (U / c0)^m at each point, every rule's
//! c0 at each point, and least-squares fits of log c0_min ([`fit`]): free
//! exponents of N and Re (and alpha), the paper's scaling c0 ~ U / sqrt(N
//! Re) (from its root at alpha = 0: c0 = (U/N^2) sqrt(Q A), A = p d N^4 /
//! U^2, p = 2 U^2 / (Re B), B = N dy), and the hypothesis that c0_min tracks
//! the largest relative speed of adjacent layers, (2N - 1) U / N^2.

pub mod fit;

use std::fmt::Write as _;
use std::sync::atomic::AtomicBool;

use anyhow::{bail, Context, Result};
use indicatif::ProgressBar;
use serde::{Deserialize, Serialize};

use crate::config::Scene;
use crate::empirical::{answer, Extras, Search};
use crate::problem::c0::{all_rules_on, by_rule};
use crate::problem::channel::Channel;
use crate::problem::cost::Estimate;
use fit::{least_squares, Fit};

/// The law's sweep (src/studies/law/law.toml).
pub const DEFAULT_CONFIG: &str = include_str!("law.toml");
/// `--quick`'s (src/studies/law/quick.toml).
pub const QUICK_CONFIG: &str = include_str!("quick.toml");

#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LawConfig {
    pub kernels: Vec<String>,
    pub n: Vec<u32>,
    pub re: Vec<f64>,
    pub alpha: Vec<f64>,
    pub amplitude: f64,
    pub seeds: u32,
    pub rel_tol: f64,
    pub first_over_u: f64,
    pub lo_over_u: f64,
    pub hi_over_u: f64,
    /// Scene fields over the built-in scene.
    #[serde(default)]
    pub scene: toml::Table,
}

impl LawConfig {
    pub fn parse(text: &str, origin: &str) -> Result<LawConfig> {
        let c: LawConfig =
            toml::from_str(text).with_context(|| format!("reading law config {origin}"))?;
        for (field, empty) in [
            ("kernels", c.kernels.is_empty()),
            ("n", c.n.is_empty()),
            ("re", c.re.is_empty()),
            ("alpha", c.alpha.is_empty()),
        ] {
            if empty {
                bail!("law config {origin}: `{field}` is empty; give at least one value");
            }
        }
        // A value twice would run (and fit) one point twice; every count
        // bounded (the search's own by Search::check below).
        let field = |f: &str| format!("law config {origin}: `{f}`");
        use crate::config::bounds::{distinct, POINTS};
        distinct(&field("kernels"), &c.kernels)?;
        distinct(&field("n"), &c.n)?;
        distinct(&field("re"), &c.re)?;
        distinct(&field("alpha"), &c.alpha)?;
        if c.n.contains(&0) {
            bail!("{}: 0 is not a number of layers; give N >= 1", field("n"));
        }
        let points = [c.kernels.len(), c.n.len(), c.re.len(), c.alpha.len()]
            .into_iter()
            .fold(1u64, |a, b| a.saturating_mul(b as u64));
        POINTS.check(
            &format!("law config {origin}: points (kernels x n x re x alpha)"),
            points,
        )?;
        for key in [
            "kernel",
            "n_layers",
            "re",
            "p",
            "alpha",
            "c0",
            "jitter",
            "jitter_seed",
            "horizon",
            "t_end",
        ] {
            if c.scene.contains_key(key) {
                bail!(
                    "law config {origin}: [scene] sets `{key}`, which the law sets per point; \
                     remove it (the grid's `kernels`, `n`, `re`, `alpha` and the search's \
                     `amplitude`, `seeds` set these)"
                );
            }
        }
        c.search()
            .check(|field| format!("law config {origin}: `{field}`"))?;
        Ok(c)
    }

    pub fn default_full() -> LawConfig {
        LawConfig::parse(DEFAULT_CONFIG, "src/studies/law/law.toml")
            .expect("the embedded law config is valid")
    }

    pub fn quick() -> LawConfig {
        LawConfig::parse(QUICK_CONFIG, "src/studies/law/quick.toml")
            .expect("the embedded quick config is valid")
    }

    pub fn search(&self) -> Search {
        Search {
            amplitude: self.amplitude,
            seeds: self.seeds,
            rel_tol: self.rel_tol,
            first_over_u: self.first_over_u,
            lo_over_u: self.lo_over_u,
            hi_over_u: self.hi_over_u,
            ..Search::default()
        }
    }

    /// The scene of one point (checked before anything runs).
    pub fn scene(&self, kernel: &str, n: u32, re: f64, alpha: f64) -> Result<Scene> {
        let mut over = self.scene.clone();
        over.insert("kernel".into(), toml::Value::String(kernel.into()));
        over.insert("n_layers".into(), toml::Value::Integer(n.into()));
        over.insert("re".into(), toml::Value::Float(re));
        over.insert("alpha".into(), toml::Value::Float(alpha));
        Ok(Scene::load(None, over)?)
    }

    /// Every point's key, kernel-major.
    pub fn points(&self) -> Vec<(String, u32, f64, f64)> {
        let mut v = Vec::new();
        for k in &self.kernels {
            for &n in &self.n {
                for &re in &self.re {
                    for &a in &self.alpha {
                        v.push((k.clone(), n, re, a));
                    }
                }
            }
        }
        v
    }
}

/// One point of the law.
#[derive(Debug, Clone, Serialize)]
pub struct Point {
    pub kernel: String,
    pub n: u32,
    pub re: f64,
    pub alpha: f64,
    /// The smallest c0 / U ok on every start (None: no c0 probed was).
    pub c0_min_over_u: Option<f64>,
    /// The largest c0 / U found over-compressed (or failed) below it.
    pub below_over_u: Option<f64>,
    /// The disordered law at this point: k, m and their errors (None: too
    /// few settled trials).
    pub law: Option<crate::empirical::DisorderedLaw>,
    /// Why no c0 is ok, when none is.
    pub binds: Option<String>,
    /// Runs, those stationary, and the times they reached.
    pub runs: usize,
    pub stationary: usize,
    pub t_min: f64,
    pub t_max: f64,
    /// The time step's limit at c0_min (at U and p as scales).
    pub dt_limit: Option<&'static str>,
    /// Every rule's c0 / U at this point (NaN: none).
    pub rules: Vec<(String, f64)>,
    pub trials: usize,
    /// Wall-clock seconds of the point's runs, summed (runs overlap, and
    /// under load each waits: not CPU time; law.json's `wall_s` is the
    /// sweep's own).
    pub run_s: f64,
}

/// Run every point of `config` (in parallel; each run on one thread),
/// ticking `bar` per point.
pub fn run(config: &LawConfig, bar: &ProgressBar) -> Result<Vec<Point>> {
    run_until(config, bar, &AtomicBool::new(false))
}

/// [`run`], starting no point once `stop` is set (a signal): the points
/// finished by then, in order. The points run one after another, each
/// engine's runs across the cores, so a stop keeps every point finished.
pub fn run_until(config: &LawConfig, bar: &ProgressBar, stop: &AtomicBool) -> Result<Vec<Point>> {
    let search = config.search();
    let keys = config.points();
    // every scene valid before the first run
    let scenes = keys
        .iter()
        .map(|(k, n, re, a)| {
            let s = config.scene(k, *n, *re, *a)?;
            crate::problem::c0::table(&s).with_context(|| {
                format!("law point kernel {k}, N = {n}, Re = {re}, alpha = {a}")
            })?;
            Ok(s)
        })
        .collect::<Result<Vec<Scene>>>()?;
    bar.set_length(keys.len() as u64);
    let points: Vec<Result<Option<Point>>> = keys
        .iter()
        .zip(scenes.iter())
        .map(|((kernel, n, re, alpha), scene)| {
            if stop.load(std::sync::atomic::Ordering::Relaxed) {
                return Ok(None);
            }
            let extras = Extras {
                law_ladder: true,
                ..Extras::default()
            };
            let a = match answer(scene, &search, extras, stop, &ProgressBar::hidden()) {
                // Stopped while it ran: its runs were cut short, so the
                // point is not kept.
                Err(_) if stop.load(std::sync::atomic::Ordering::Relaxed) => return Ok(None),
                r => r?,
            };
            let info = scene.kernel_info()?;
            let channel = Channel::resolve(scene, info)?;
            let u = channel.flow.u;
            let t_end = channel.t_end(scene)?;
            let mut rules = Vec::new();
            for rule in all_rules_on(info, channel.discretisation) {
                let (c0, name) = by_rule(&rule, info, &channel, *alpha)?;
                rules.push((name, c0 / u));
            }
            bar.inc(1);
            Ok(Some(Point {
                kernel: kernel.clone(),
                n: *n,
                re: *re,
                alpha: *alpha,
                c0_min_over_u: a.c0_min_ok.map(|c| c / u),
                below_over_u: a.c0_min_ok.and(a.disordered.compressed).map(|c| c.0 / u),
                law: a.law.clone(),
                binds: a.diagnosis.as_ref().map(|d| d.binds.clone()),
                runs: a.horizon.runs,
                stationary: a.horizon.stationary,
                t_min: a.horizon.t_min,
                t_max: a.horizon.t_max,
                dt_limit: a
                    .c0_min_ok
                    .map(|c| Estimate::new(&channel, c, t_end).time_step.limit.name()),
                rules,
                trials: a.trials.len(),
                run_s: a.trials.iter().map(|t| t.wall_s()).sum(),
            }))
        })
        .collect();
    Ok(points
        .into_iter()
        .collect::<Result<Vec<_>>>()?
        .into_iter()
        .flatten()
        .collect())
}

/// Every point as CSV: its c0_min, bracket, regime and every rule's c0 / U.
pub fn csv(points: &[Point]) -> String {
    let names: Vec<&str> = points
        .first()
        .map(|p| p.rules.iter().map(|r| r.0.as_str()).collect())
        .unwrap_or_default();
    let mut s = String::from(
        "kernel,n,re,alpha,c0_min_over_u,below_over_u,law_k,law_m,law_m_se,dt_limit,trials,runs,stationary,t_min,t_max,run_s",
    );
    for n in &names {
        write!(s, ",{n}").unwrap();
    }
    s.push('\n');
    let opt = |v: Option<f64>| v.map_or(String::new(), |v| format!("{v:.6e}"));
    for p in points {
        write!(
            s,
            "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{:.3}",
            p.kernel,
            p.n,
            p.re,
            p.alpha,
            opt(p.c0_min_over_u),
            opt(p.below_over_u),
            opt(p.law.as_ref().map(|l| l.k)),
            opt(p.law.as_ref().map(|l| l.m)),
            opt(p.law.as_ref().map(|l| l.m_se)),
            p.dt_limit.unwrap_or(""),
            p.trials,
            p.runs,
            p.stationary,
            p.t_min,
            p.t_max,
            p.run_s
        )
        .unwrap();
        for n in &names {
            let v = p.rules.iter().find(|r| r.0 == *n).map(|r| r.1);
            write!(s, ",{}", opt(v.filter(|v| v.is_finite()))).unwrap();
        }
        s.push('\n');
    }
    s
}

/// One kernel's law.
#[derive(Debug, Clone, Serialize)]
pub struct KernelLaw {
    pub kernel: String,
    /// Points with a bracketed c0_min (a not-ok c0 below it), fitted.
    pub fitted: usize,
    /// Points no c0 probed was ok at, or ok down to the lowest probe (no
    /// bracket): stated, not fitted.
    pub unfitted: Vec<String>,
    /// ln c0_min/U = b0 + bN ln N + bRe ln Re (+ balpha alpha when both
    /// alphas have points).
    pub free: Option<Fit>,
    /// The same on the alpha = 0 points alone, beside the paper's -1/2, -1/2.
    pub free_alpha0: Option<Fit>,
    /// The paper's scaling at alpha = 0: ln c0_min/U = ln k - (ln N + ln Re)/2.
    pub paper: Option<Fit>,
    /// The layers' hypothesis: ln c0_min/U = ln k + ln((2N - 1)/N^2), every point.
    pub layers: Option<Fit>,
}

impl KernelLaw {
    /// c0/U by the free fit at (N, Re, alpha).
    pub fn free_at(&self, n: f64, re: f64, alpha: f64) -> Option<f64> {
        let f = self.free.as_ref()?;
        let mut v = f.coef[0] + f.coef[1] * n.ln() + f.coef[2] * re.ln();
        if let Some(j) = f.names.iter().position(|s| s == "alpha") {
            v += f.coef[j] * alpha;
        }
        Some(v.exp())
    }
}

/// The fits of one kernel's points.
pub fn fit_kernel(kernel: &str, points: &[Point]) -> KernelLaw {
    let mine: Vec<&Point> = points.iter().filter(|p| p.kernel == kernel).collect();
    let unfitted = mine
        .iter()
        .filter_map(|p| match (p.c0_min_over_u, p.below_over_u) {
            (None, _) => Some(format!(
                "N = {}, Re = {}, alpha = {}: no c0 probed was ok on every start",
                p.n, p.re, p.alpha
            )),
            (Some(c), None) => Some(format!(
                "N = {}, Re = {}, alpha = {}: ok down to the lowest probe, {c} U (c0_min is at most that)",
                p.n, p.re, p.alpha
            )),
            _ => None,
        })
        .collect();
    // a c0_min with a not-ok c0 below it: bracketed, not censored
    let ok: Vec<(&Point, f64)> = mine
        .iter()
        .filter(|p| p.below_over_u.is_some())
        .filter_map(|p| p.c0_min_over_u.map(|c| (*p, c.ln())))
        .collect();
    let cols = |pts: &[(&Point, f64)], alpha: bool| {
        let mut x = vec![
            vec![1.0; pts.len()],
            pts.iter().map(|p| f64::from(p.0.n).ln()).collect(),
            pts.iter().map(|p| p.0.re.ln()).collect(),
        ];
        if alpha {
            x.push(pts.iter().map(|p| p.0.alpha).collect());
        }
        x
    };
    let y = |pts: &[(&Point, f64)]| pts.iter().map(|p| p.1).collect::<Vec<_>>();
    let alphas = {
        let mut a: Vec<f64> = ok.iter().map(|p| p.0.alpha).collect();
        a.sort_by(f64::total_cmp);
        a.dedup();
        a.len()
    };
    let free = if alphas > 1 {
        least_squares(&["1", "ln N", "ln Re", "alpha"], &cols(&ok, true), &y(&ok)).ok()
    } else {
        least_squares(&["1", "ln N", "ln Re"], &cols(&ok, false), &y(&ok)).ok()
    };
    let zero: Vec<(&Point, f64)> = ok.iter().filter(|p| p.0.alpha == 0.0).copied().collect();
    let free_alpha0 = least_squares(&["1", "ln N", "ln Re"], &cols(&zero, false), &y(&zero)).ok();
    let offset_fit = |pts: &[(&Point, f64)], shape: &dyn Fn(&Point) -> f64| {
        let ys: Vec<f64> = pts.iter().map(|p| p.1 - shape(p.0).ln()).collect();
        least_squares(&["ln k"], &[vec![1.0; pts.len()]], &ys).ok()
    };
    let paper = offset_fit(&zero, &|p| 1.0 / (f64::from(p.n) * p.re).sqrt());
    let layers = offset_fit(&ok, &|p| {
        let n = f64::from(p.n);
        (2.0 * n - 1.0) / (n * n)
    });
    KernelLaw {
        kernel: kernel.to_string(),
        fitted: ok.len(),
        unfitted,
        free,
        free_alpha0,
        paper,
        layers,
    }
}

/// law.json: the config, every point and each kernel's fits.
#[derive(Debug, Clone, Serialize)]
pub struct Law {
    pub config: LawConfig,
    pub points: Vec<Point>,
    pub laws: Vec<KernelLaw>,
    /// Wall-clock seconds of the whole sweep.
    pub wall_s: f64,
}

impl Law {
    pub fn new(config: &LawConfig, points: Vec<Point>, wall_s: f64) -> Law {
        let laws = config
            .kernels
            .iter()
            .map(|k| fit_kernel(k, &points))
            .collect();
        Law {
            config: config.clone(),
            points,
            laws,
            wall_s,
        }
    }
}

/// "b = -0.48 +- 0.05" lines of a fit.
pub fn describe(f: &Fit) -> String {
    f.names
        .iter()
        .zip(f.coef.iter().zip(&f.se))
        .map(|(n, (c, se))| format!("{n}: {c:.3} +- {se:.3}"))
        .collect::<Vec<_>>()
        .join(", ")
        + &format!(" (rms residual in ln c0 {:.3}, {} dof)", f.rms, f.dof)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every law config the project ships (the embedded ones and those in
    /// docs/law/) parses with the engine as it is: a field added to the
    /// config fails here, not when a user reruns a documented command.
    #[test]
    fn every_shipped_law_config_parses() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
        let mut files = vec![
            root.join("src/studies/law/law.toml"),
            root.join("src/studies/law/quick.toml"),
        ];
        for e in std::fs::read_dir(root.join("docs/law")).unwrap() {
            let path = e.unwrap().path();
            if path.extension().is_some_and(|x| x == "toml") {
                files.push(path);
            }
        }
        assert!(files.len() >= 3, "{files:?}");
        for f in files {
            let text = std::fs::read_to_string(&f).unwrap();
            if let Err(e) = LawConfig::parse(&text, &f.display().to_string()) {
                panic!("{}: {e:#}", f.display());
            }
        }
    }

    fn point(n: u32, re: f64, alpha: f64, c: Option<f64>) -> Point {
        Point {
            kernel: "k".into(),
            n,
            re,
            alpha,
            c0_min_over_u: c,
            below_over_u: None,
            law: None,
            binds: None,
            runs: 0,
            stationary: 0,
            t_min: 0.0,
            t_max: 0.0,
            dt_limit: None,
            rules: vec![],
            trials: 0,
            run_s: 0.0,
        }
    }

    #[test]
    fn the_papers_scaling_fits_exactly_where_the_data_follow_it() {
        // c0_min = 2 / sqrt(N Re) at alpha = 0: the paper's fit has k = 2
        // and no residual, the free fit -1/2, -1/2; a point with no c0 is
        // stated, not fitted.
        let mut pts = vec![];
        for n in [6, 8, 10, 14] {
            for re in [1.0, 3.0, 10.0, 30.0] {
                let c = 2.0 / (f64::from(n) * re).sqrt();
                let mut p = point(n, re, 0.0, Some(c));
                p.below_over_u = Some(0.9 * c);
                pts.push(p);
            }
        }
        pts.push(point(20, 30.0, 0.0, None));
        pts.push(point(20, 1.0, 0.0, Some(0.01)));
        let law = fit_kernel("k", &pts);
        assert_eq!((law.fitted, law.unfitted.len()), (16, 2));
        let paper = law.paper.unwrap();
        assert!((paper.coef[0].exp() - 2.0).abs() < 1e-12 && paper.rms < 1e-12);
        let free = law.free.unwrap();
        assert!((free.coef[1] + 0.5).abs() < 1e-12 && (free.coef[2] + 0.5).abs() < 1e-12);
        assert!(
            law.layers.unwrap().rms > 0.1,
            "(2N-1)/N^2 does not follow 1/sqrt(N Re)"
        );
    }

    #[test]
    fn a_search_field_out_of_range_names_the_file_and_the_field() {
        for (field, bad) in [
            ("amplitude", "-1.0"),
            ("amplitude", "nan"),
            ("seeds", "0"),
            ("rel_tol", "0.0"),
            ("rel_tol", "inf"),
            ("lo_over_u", "-0.01"),
            ("hi_over_u", "inf"),
            ("hi_over_u", "0.001"),
        ] {
            let text: String = DEFAULT_CONFIG
                .lines()
                .map(|l| {
                    if l.starts_with(&format!("{field} =")) {
                        format!("{field} = {bad}\n")
                    } else {
                        format!("{l}\n")
                    }
                })
                .collect();
            let err = LawConfig::parse(&text, "my-law.toml")
                .unwrap_err()
                .to_string();
            assert!(
                err.contains("my-law.toml") && err.contains(&format!("`{field}`")),
                "{field} = {bad}: {err}"
            );
        }
    }

    #[test]
    fn the_embedded_configs_parse_and_their_points_resolve() {
        for c in [LawConfig::default_full(), LawConfig::quick()] {
            assert!(!c.n.is_empty() && c.re.len() >= 2);
            for (k, n, re, a) in c.points() {
                let s = c.scene(&k, n, re, a).unwrap();
                crate::problem::c0::table(&s).unwrap();
            }
        }
        let full = LawConfig::default_full();
        assert!(full.n.len() >= 4 && full.re.len() >= 4 && full.alpha == [0.0, 0.1]);
    }
}
