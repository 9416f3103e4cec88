//! `shearsph report`: the paper's tables and Figure 4 reproduced, the derived
//! c0 against the rules, and the solver's verdict, in one folder with an
//! `index.html` a person opens first.
//!
//! The run is data-driven: a config (the embedded `report.toml`, or
//! `quick.toml` for `--quick`) names the grids; every scene goes through the
//! sweep engine ([`crate::sweep`]) in parallel; the empirical c0 is found by
//! bisection with the solver in the loop; the verdicts are sentences built
//! from those rows, never typed in.

mod empirical;
mod html;
pub use html::square_discretisation;
mod tables;
mod verdict;

use std::collections::BTreeSet;
use std::path::Path;
use std::sync::atomic::AtomicBool;
use std::time::Instant;

use anyhow::{bail, Context, Result};
use indicatif::ProgressBar;
use serde::{Deserialize, Serialize};

use crate::charts::{self, EpsCurve, EpsPanel, MapCell, MapLine};
use crate::config::{C0Rule, C0Spec};
use crate::kernel::{DiscretisationInfo, Kernel, KernelInfo, KernelVisitor};
use crate::kernels;
use crate::output::{prepare_dir, StagedSet};
use crate::particles::series::{picture_svg, ParticleOutput};
use crate::problem::c0::{all_rules, by_rule};
use crate::problem::channel::Channel;
use crate::solver::ideal_shear;
use crate::solver::FailureKind;
use crate::sweep::{self, store, Class, ClassRules, Parallel, Point, PointC0, Row};

pub use empirical::Empirical;
pub use tables::{C0Compare, EpsCompare, Table2Row};
pub use verdict::Verdict;

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

    /// Every scene of the report but the bisection's, each once: the speed
    /// grid, the rules at the verdicts' Re (every derived model, 10 U, Table
    /// 2) and the maps.
    pub fn points(&self) -> Vec<Point> {
        let mut out: Vec<Point> = Vec::new();
        let mut seen = BTreeSet::new();
        let mut push = |kernel: &str, n: u32, re: f64, alpha: f64, c0: PointC0| {
            let p = Point {
                at: Default::default(),
                disc: Default::default(),
                start: Default::default(),
                index: out.len(),
                kernel: kernel.to_string(),
                n,
                re,
                alpha,
                c0,
            };
            if seen.insert(p.id()) {
                out.push(p);
            }
        };
        for info in self.kernel_infos() {
            for &n in &self.speed.n {
                for &re in &self.speed.re {
                    for c in &self.speed.c0 {
                        if let Ok(spec) = c.parse::<C0Spec>() {
                            push(info.name, n, re, self.speed.alpha, PointC0::Spec(spec));
                        }
                    }
                }
            }
            for &re in &self.empirical.re {
                for rule in verdict_rules(info) {
                    push(
                        info.name,
                        self.maps.n,
                        re,
                        self.maps.alpha,
                        PointC0::Spec(rule),
                    );
                }
            }
            for &re in &self.maps.re {
                for &x in &self.maps.c0_over_u {
                    push(
                        info.name,
                        self.maps.n,
                        re,
                        self.maps.alpha,
                        PointC0::OverU(x),
                    );
                }
            }
        }
        out
    }
}

/// The rules the verdicts compare, in scene syntax: `derived` (the default
/// model), every other model, `rule10`, and `table2` when printed. The
/// other codes' rules are in the c0 tables and drawn on the maps, but not
/// run here: 100 U (trixi) alone would cost ten times the runs of 10 U,
/// past the report's few minutes.
fn verdict_rules(info: &KernelInfo) -> Vec<C0Spec> {
    all_rules(info)
        .into_iter()
        .filter(|rule| matches!(rule, C0Rule::Derived(_) | C0Rule::Rule10 | C0Rule::Table2))
        .map(|rule| {
            let rule = match rule {
                C0Rule::Derived(Some(m)) if m == info.c0_default => C0Rule::Derived(None),
                r => r,
            };
            C0Spec::Rule { factor: 1.0, rule }
        })
        .collect()
}

/// Map cells from rows with a numeric c0.
pub fn map_cells(rows: &[&Row]) -> Vec<MapCell> {
    rows.iter()
        .filter(|r| r.c0_over_u.is_finite() && r.c0_over_u > 0.0)
        .map(|r| MapCell {
            re: r.re,
            c0_over_u: r.c0_over_u,
            class: r.class,
            failure_kind: r.failure_kind,
            linf_max: r.linf_max,
            max_eps: r.max_eps,
            id: r.id.clone(),
        })
        .collect()
}

/// Each rule's c0 / U against Re over (and a little beyond) the range of
/// `res`, for kernel `kernel` at N = `n` and `alpha`: every derived model, 10
/// U, Table 2. A rule is cut where it has no positive value.
pub fn rule_lines(
    kernel: &str,
    base: &toml::Table,
    n: u32,
    alpha: f64,
    res: &[f64],
) -> Result<Vec<MapLine>> {
    let info = crate::config::kernel_info(kernel)?;
    let (lo, hi) = res
        .iter()
        .filter(|r| **r > 0.0)
        .fold((f64::INFINITY, 0.0f64), |(a, b), &r| (a.min(r), b.max(r)));
    if lo > hi {
        return Ok(Vec::new());
    }
    let (lo, hi) = (lo / 1.5, hi * 1.5);
    const SAMPLES: usize = 60;
    let mut lines = Vec::new();
    for rule in all_rules(info) {
        let mut pieces: Vec<Vec<(f64, f64)>> = Vec::new();
        let mut cur: Vec<(f64, f64)> = Vec::new();
        for k in 0..=SAMPLES {
            let re = lo * (hi / lo).powf(k as f64 / SAMPLES as f64);
            let point = Point {
                at: Default::default(),
                disc: Default::default(),
                start: Default::default(),
                index: 0,
                kernel: kernel.to_string(),
                n,
                re,
                alpha,
                c0: PointC0::OverU(1.0),
            };
            let scene = point.scene(base)?;
            let channel = Channel::resolve(&scene, info)?;
            let c0 = by_rule(&rule, info, &channel, scene.alpha)
                .map(|(c, _)| c / scene.u)
                .unwrap_or(f64::NAN);
            if c0 > 0.0 && c0.is_finite() {
                cur.push((re, c0));
            } else if !cur.is_empty() {
                pieces.push(std::mem::take(&mut cur));
            }
        }
        if !cur.is_empty() {
            pieces.push(cur);
        }
        let label = match &rule {
            C0Rule::Derived(Some(m)) if m == info.c0_default => format!("derived:{m} (default)"),
            C0Rule::Rule10 => "10 U".to_string(),
            r => r.to_string(),
        };
        lines.push(MapLine { label, pieces });
    }
    Ok(lines)
}

/// Figure 4's data: for each kernel, eps over one period for layers 0,
/// N - R and N - 1 (walls at N), from the generated `eps_at` and from the
/// solver's density summation under ideal shear, on the discretisation
/// `pick` chooses for it (the paper's: [`papers`]; a kernel it gives none
/// for is left out).
pub fn figure4(
    infos: &[&'static KernelInfo],
    pick: fn(&'static KernelInfo) -> Option<&'static DiscretisationInfo>,
    n_layers: u32,
    samples: usize,
) -> Result<Vec<EpsPanel>> {
    struct Measure<'a> {
        disc: &'static DiscretisationInfo,
        n_layers: u32,
        layers: &'a [u32],
        t: &'a [f64],
    }
    impl KernelVisitor for Measure<'_> {
        type Output = Result<Vec<Vec<f64>>, crate::config::SceneError>;
        fn visit<K: Kernel>(self) -> Self::Output {
            ideal_shear::eps_series::<K>(self.disc, self.n_layers, self.layers, self.t)
        }
    }
    let t: Vec<f64> = (0..=samples).map(|k| k as f64 / samples as f64).collect();
    let mut panels = Vec::new();
    for &info in infos {
        let Some(disc) = pick(info) else {
            continue;
        };
        let r = info.support.ceil() as u32;
        let mut layers: Vec<(u32, String)> = vec![(0, "n = 0".to_string())];
        if n_layers > r {
            layers.push((n_layers - r, format!("n = N - R = {}", n_layers - r)));
        }
        if n_layers >= 1 && !layers.iter().any(|l| l.0 == n_layers - 1) {
            layers.push((n_layers - 1, format!("n = N - 1 = {}", n_layers - 1)));
        }
        let ids: Vec<u32> = layers.iter().map(|l| l.0).collect();
        let measured = kernels::with_kernel(
            info.name,
            Measure {
                disc,
                n_layers,
                layers: &ids,
                t: &t,
            },
        )
        .expect("the registry lists this kernel")
        .with_context(|| format!("Figure 4 for kernel {} on {}", info.name, disc.label()))?;
        let curves = layers
            .iter()
            .zip(measured)
            .map(|((n, label), measured)| EpsCurve {
                kernel: info.name.to_string(),
                n: *n,
                label: label.clone(),
                t: t.clone(),
                model: t
                    .iter()
                    .map(|&tf| (disc.eps_at)(tf, *n, Some(n_layers)))
                    .collect(),
                measured,
            })
            .collect();
        panels.push(EpsPanel {
            kernel: info.name.to_string(),
            title: format!(
                "{}: eps over one period T = d N^2 / U, N = {n_layers}, {}",
                info.title,
                disc.label()
            ),
            mean: disc.eps.mean.value,
            curves,
        });
    }
    Ok(panels)
}

/// The paper's discretisation of a kernel (triangular, h = d).
pub fn papers(info: &'static KernelInfo) -> Option<&'static DiscretisationInfo> {
    info.discretisations.first()
}

/// How to run the report.
#[derive(Debug, Clone, Copy)]
pub struct Options {
    pub par: Parallel,
    pub force: bool,
}

/// Everything the report computed: what the HTML and the files show.
#[derive(Debug)]
pub struct ReportData {
    pub config: Config,
    pub quick: bool,
    pub infos: Vec<&'static KernelInfo>,
    pub rows: Vec<Row>,
    pub empirical: Vec<Empirical>,
    pub figure4: Vec<EpsPanel>,
    /// The same on one square discretisation per kernel
    /// ([`square_discretisation`]).
    pub figure4_square: Vec<EpsPanel>,
    pub table1: Vec<(String, Vec<EpsCompare>)>,
    pub table2: Vec<Table2Row>,
    pub c0_compare: Vec<C0Compare>,
    pub verdicts: Vec<Verdict>,
    pub wall_s: f64,
    pub jobs: usize,
}

/// Run the report into `out`. `stop` (Ctrl-C) ends it early with an error
/// and nothing but the files already complete; `log` gets one line per
/// stage; `bar` counts scenes.
pub fn run(
    config: &Config,
    quick: bool,
    out: &Path,
    opts: Options,
    stop: &AtomicBool,
    bar: &ProgressBar,
    log: &dyn Fn(&str),
) -> Result<ReportData> {
    let start = Instant::now();
    prepare_dir(out, opts.force)?;
    let infos = config.kernel_infos();
    let interrupted = || {
        anyhow::anyhow!(
            "interrupted: the report in {} is incomplete; run it again",
            out.display()
        )
    };

    // 1. Every scene of the grids, in parallel, longest first.
    let points = config.points();
    log(&format!(
        "report: {} scenes ({} kernels) on {} workers, then the empirical c0 by bisection",
        points.len(),
        infos.len(),
        opts.par.jobs
    ));
    bar.set_length(points.len() as u64);
    let on_row = |r: &Row| {
        bar.inc(1);
        bar.set_message(r.id.clone());
    };
    let (rows, stopped) = sweep::run_points(
        &points,
        &config.scene,
        &config.classes,
        opts.par,
        stop,
        &on_row,
    )?;
    if stopped {
        return Err(interrupted());
    }
    log(&format!(
        "report: grid done in {:.1} s",
        start.elapsed().as_secs_f64()
    ));

    // 2. The empirical c0.
    let empirical = empirical::find_all(config, &infos, &rows, opts.par, stop, bar)?;
    if empirical.is_none() {
        return Err(interrupted());
    }
    let empirical = empirical.unwrap_or_default();
    bar.finish_and_clear();
    log(&format!(
        "report: empirical c0 done at {:.1} s",
        start.elapsed().as_secs_f64()
    ));

    // 3. Figure 4, tables, verdicts.
    let figure4_square = figure4(
        &infos,
        square_discretisation,
        config.figure4.n,
        config.figure4.samples,
    )?;
    let figure4 = figure4(&infos, papers, config.figure4.n, config.figure4.samples)?;
    let table1 = infos
        .iter()
        .map(|i| (i.name.to_string(), tables::table1(i)))
        .collect();
    let table2 = infos.iter().map(|i| tables::table2(i)).collect();
    let c0_compare = tables::c0_compare(config, &infos, &rows)?;
    let verdicts = verdict::verdicts(config, &infos, &rows, &empirical, &c0_compare);
    let data = ReportData {
        config: config.clone(),
        quick,
        infos,
        rows,
        empirical,
        figure4,
        figure4_square,
        table1,
        table2,
        c0_compare,
        verdicts,
        wall_s: start.elapsed().as_secs_f64(),
        jobs: opts.par.jobs,
    };
    write(&data, out)?;
    log(&format!(
        "report: written to {} in {:.1} s",
        out.join("index.html").display(),
        start.elapsed().as_secs_f64()
    ));
    Ok(data)
}

/// The figures and their CSV, the tables, the rows, and `index.html` last.
/// Staged and swapped in as one set: a full disk keeps the earlier report.
fn write(d: &ReportData, out: &Path) -> Result<()> {
    let set = StagedSet::begin(out)?;
    let put = |name: &str, text: &str| set.put(name, text.as_bytes());
    let mut figures: Vec<html::Figure> = Vec::new();

    put(
        "report.toml",
        &toml::to_string(&d.config).expect("a config serialises"),
    )?;
    put("runs.csv", &store::rows_csv(&d.rows))?;
    let mut jsonl = String::new();
    for r in &d.rows {
        jsonl.push_str(&serde_json::to_string(r)?);
        jsonl.push('\n');
    }
    put("runs.jsonl", &jsonl)?;

    // Figure 4.
    let svg = charts::figure4_svg(&d.figure4)?;
    put("figure4.svg", &svg)?;
    put(
        "figure4.csv",
        &charts::figure4_csv(&d.figure4, d.config.figure4.n),
    )?;
    figures.push(html::Figure {
        id: "figure4",
        svg_file: "figure4.svg".into(),
        csv_files: vec!["figure4.csv".into()],
        svg,
    });
    let svg = charts::figure4_svg(&d.figure4_square)?;
    put("figure4_square.svg", &svg)?;
    put(
        "figure4_square.csv",
        &charts::figure4_csv(&d.figure4_square, d.config.figure4.n),
    )?;
    figures.push(html::Figure {
        id: "figure4",
        svg_file: "figure4_square.svg".into(),
        csv_files: vec!["figure4_square.csv".into()],
        svg,
    });

    // Speed against accuracy: the speed grid's rows.
    let speed_rows: Vec<Row> = d
        .rows
        .iter()
        .filter(|r| {
            d.config.speed.n.contains(&r.n)
                && d.config.speed.re.contains(&r.re)
                && r.alpha == d.config.speed.alpha
                && d.config.speed.c0.contains(&r.c0_spec)
        })
        .cloned()
        .collect();
    let pts = charts::speed_points(&speed_rows);
    put("speed_accuracy.csv", &charts::speed_csv(&pts))?;
    for (file, cost) in [
        ("speed_accuracy.svg", charts::Cost::WallTime),
        ("speed_accuracy_work.svg", charts::Cost::ParticleSteps),
    ] {
        let svg = charts::speed_svg(&pts, cost)?;
        put(file, &svg)?;
        figures.push(html::Figure {
            id: if cost == charts::Cost::WallTime {
                "speed_accuracy"
            } else {
                "speed_accuracy_work"
            },
            svg_file: file.into(),
            csv_files: vec!["speed_accuracy.csv".into()],
            svg,
        });
    }

    // A stability map per kernel.
    for info in &d.infos {
        let k = info.name;
        let here: Vec<&Row> = d
            .rows
            .iter()
            .filter(|r| {
                r.kernel == k
                    && r.n == d.config.maps.n
                    && r.alpha == d.config.maps.alpha
                    && d.config.maps.re.contains(&r.re)
                    && r.c0_spec.ends_with('U')
            })
            .collect();
        let cells = map_cells(&here);
        let lines = rule_lines(
            k,
            &d.config.scene,
            d.config.maps.n,
            d.config.maps.alpha,
            &d.config.maps.re,
        )?;
        let marks: Vec<charts::MapMark> = d
            .empirical
            .iter()
            .filter(|e| e.kernel == k)
            .filter_map(|e| {
                e.c0_over_u
                    .map(|c| (format!("empirical ({})", e.criterion), e.re, c))
            })
            .collect();
        let title = format!(
            "{k}: outcome over c0 / U and Re (N = {}, alpha = {})",
            d.config.maps.n, d.config.maps.alpha
        );
        let svg = charts::map_svg(&title, &cells, &lines, &marks)?;
        let (svg_file, csv, lines_csv) = (
            format!("stability_{k}.svg"),
            format!("stability_{k}.csv"),
            format!("stability_{k}_lines.csv"),
        );
        put(&svg_file, &svg)?;
        put(&csv, &charts::map_csv(k, &cells))?;
        put(&lines_csv, &charts::map_lines_csv(k, &lines))?;
        figures.push(html::Figure {
            id: "stability",
            svg_file,
            csv_files: vec![csv, lines_csv],
            svg,
        });
        if let Some(svg) = failure_picture(d, &here)? {
            let svg_file = format!("failure_{k}.svg");
            put(&svg_file, &svg)?;
            figures.push(html::Figure {
                id: "failure",
                svg_file,
                csv_files: Vec::new(),
                svg,
            });
        }
    }

    put("table1.csv", &tables::table1_csv(&d.table1))?;
    put("table2.csv", &tables::table2_csv(&d.table2))?;
    put("c0_compare.csv", &tables::c0_compare_csv(&d.c0_compare))?;
    put("empirical_c0.csv", &empirical::csv(&d.empirical))?;
    let bisection: Vec<Row> = d
        .empirical
        .iter()
        .flat_map(|e| e.runs.iter().cloned())
        .collect();
    put("empirical_c0_runs.csv", &store::rows_csv(&bisection))?;
    put("verdicts.json", &serde_json::to_string_pretty(&d.verdicts)?)?;
    put("index.html", &html::page(d, &figures))?;
    set.commit()?;
    Ok(())
}

/// Where the method fails: the first run of a kernel's stability map (grid
/// order) that the solver stopped, run again (the solver's results are the
/// same bits on any thread count, so it fails at the same step) keeping
/// only its last particle field, drawn with the failing particle ringed.
/// `None` when no run of the map failed in the solver.
fn failure_picture(d: &ReportData, map: &[&Row]) -> Result<Option<String>> {
    let Some(row) = map.iter().find(|r| {
        r.class == Class::Failed
            && r.failure_kind.is_some_and(|k| {
                !matches!(
                    k,
                    FailureKind::NoC0 | FailureKind::Scene | FailureKind::Panic
                )
            })
    }) else {
        return Ok(None);
    };
    let Some(point) = d.config.points().into_iter().find(|p| p.id() == row.id) else {
        return Ok(None);
    };
    let scene = point.scene(&d.config.scene)?;
    let mut quiet = crate::solver::Quiet;
    let mut observer = ParticleOutput::new(&mut quiet, Path::new("."), None);
    let result = crate::run::run_scene(&scene, &mut observer)?;
    let Some(last) = observer.finish()? else {
        return Ok(None);
    };
    Ok(Some(picture_svg(&last, &result)?))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn embedded_configs_parse_and_cover_the_verdicts() {
        for c in [Config::default_full(), Config::quick()] {
            let ids: BTreeSet<String> = c.points().iter().map(Point::id).collect();
            assert_eq!(ids.len(), c.points().len());
            for info in c.kernel_infos() {
                for &re in &c.empirical.re {
                    let id = format!(
                        "{}/n={}/re={re}/alpha={}/c0=rule10",
                        info.name, c.maps.n, c.maps.alpha
                    );
                    assert!(ids.contains(&id), "{id}");
                }
            }
        }
    }
}
