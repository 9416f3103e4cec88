//! `shearsph report`: the paper's tables and Figure 4 reproduced, the derived
//! c0 against the rules, and the solver's verdict, in one folder with an
//! `index.html` a person opens first.
//!
//! The run is data-driven: a config (the embedded `report.toml`, or
//! `quick.toml` for `--quick`) names the grids ([`plan`]: every scene once,
//! with typed keys for the places it serves); every scene goes through the
//! sweep engine ([`crate::sweep`]) in parallel; the empirical c0 is found by
//! the engine of `c0 --empirical` ([`crate::empirical`]) with the solver in
//! the loop; the verdicts are sentences built
//! from those rows, never typed in.

mod cases;
mod config;
mod empirical;
mod figures;
mod first_screen;
mod html;
pub mod law;
mod plan;
pub mod stability;
pub(crate) mod tables;
mod verdict;
mod write;

use std::path::Path;
use std::sync::atomic::AtomicBool;
use std::time::Instant;

use anyhow::Result;
use indicatif::ProgressBar;

use crate::charts::EpsPanel;
use crate::kernel::KernelInfo;
use crate::output::prepare_dir;
use crate::particles::series::{picture_svg, ParticleOutput};
use crate::solver::FailureKind;
use crate::sweep::{self, Class, Parallel, Row};

pub use cases::CaseConfig;
pub use config::{
    EmpiricalConfig, Figure4Config, MapsConfig, ReportConfig, SpeedConfig, DEFAULT_CONFIG,
    QUICK_CONFIG,
};
pub use empirical::Empirical;
pub use figures::{figure4, map_cells, papers, rule_lines};
pub use plan::{Case, CaseDiscretisation, Key, Plan, Role};
pub use tables::{C0Compare, EpsCompare, Table2Row};
pub use verdict::Verdict;

/// How to run the report.
#[derive(Debug, Clone)]
pub struct Options {
    pub par: Parallel,
    pub force: bool,
    /// A `shearsph law` output folder whose section the report shows.
    pub law: Option<std::path::PathBuf>,
}

/// Everything the report computed: what the HTML and the files show.
#[derive(Debug)]
pub struct ReportData {
    pub config: ReportConfig,
    /// The scenes and their keys; `rows[i]` is the run of `plan.points[i]`.
    pub plan: Plan,
    pub quick: bool,
    pub infos: Vec<&'static KernelInfo>,
    pub rows: Vec<Row>,
    pub empirical: Vec<Empirical>,
    pub figure4: Vec<EpsPanel>,
    /// The same on every other case's discretisation: the case's id and
    /// its panels.
    pub figure4_cases: Vec<(String, Vec<EpsPanel>)>,
    pub table1: Vec<(String, Vec<EpsCompare>)>,
    pub table2: Vec<Table2Row>,
    pub c0_compare: Vec<C0Compare>,
    pub verdicts: Vec<Verdict>,
    pub wall_s: f64,
    pub jobs: usize,
    /// The law of the minimal c0, when a `shearsph law` folder was given.
    pub law: Option<law::LawSection>,
    /// The ordered lattice's growth at the derived and rule10 c0.
    pub ordered: Vec<stability::Ordered>,
    /// Its growth map over c0 / U x Re (`[growth]`; empty without one).
    pub growth: Vec<stability::GrowthCell>,
}

/// Run the report into `out`. `stop` (Ctrl-C) ends it early with an error
/// and nothing but the files already complete; `log` gets one line per
/// stage; `bar` counts scenes.
pub fn run(
    config: &ReportConfig,
    quick: bool,
    out: &Path,
    opts: Options,
    stop: &AtomicBool,
    bar: &ProgressBar,
    log: &dyn Fn(&str),
) -> Result<ReportData> {
    let start = Instant::now();
    // A law folder that cannot be read fails before any run.
    let law = opts.law.as_deref().map(law::law_section).transpose()?;
    prepare_dir(out, opts.force)?;
    let infos = config.kernel_infos();
    let interrupted = || {
        anyhow::anyhow!(
            "interrupted: the report in {} is incomplete; run it again",
            out.display()
        )
    };

    // 1. Every scene of the grids, in parallel, longest first.
    let plan = config.plan();
    let points = &plan.points;
    log(&format!(
        "report: {} scenes ({} kernels) on {} workers, then the empirical c0 by the search of c0 --empirical",
        points.len(),
        infos.len(),
        opts.par.jobs
    ));
    bar.set_length(points.len() as u64);
    let on_row = |r: &Row| {
        bar.inc(1);
        bar.set_message(r.id.clone());
    };
    // The speed grid on its fixed horizon, the rest on the stationary one.
    let mut rows = Vec::new();
    for speed in [true, false] {
        let group: Vec<sweep::Point> = points
            .iter()
            .zip(&plan.speed)
            .filter(|(_, s)| **s == speed)
            .map(|(p, _)| p.clone())
            .collect();
        let (r, stopped) = sweep::run_points(
            &group,
            &config.base(speed),
            &config.classes,
            opts.par,
            stop,
            &on_row,
            None,
        )?;
        if stopped {
            return Err(interrupted());
        }
        rows.extend(r);
    }
    rows.sort_by_key(|r| r.index);
    log(&format!(
        "report: grid done in {:.1} s",
        start.elapsed().as_secs_f64()
    ));

    // 2. The empirical c0.
    bar.set_length(bar.position());
    let empirical = empirical::find_all(config, &infos, opts.par, stop, bar)?;
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
    let mut figure4_cases = Vec::new();
    for case in config
        .cases()
        .into_iter()
        .filter(|c| c.disc.index > 0 && !c.perturbed)
    {
        let pick = |info| case.disc.of(info).map(|(_, on)| on);
        let panels = figure4(&infos, pick, config.figure4.n, config.figure4.samples)?;
        figure4_cases.push((config.case[case.disc.index].id.clone(), panels));
    }
    let figure4 = figure4(&infos, papers, config.figure4.n, config.figure4.samples)?;
    let table1 = infos
        .iter()
        .map(|i| (i.name.to_string(), tables::table1(i)))
        .collect();
    let table2 = infos.iter().map(|i| tables::table2(i)).collect();
    let c0_compare = tables::c0_compare(config, &plan, &infos, &rows)?;
    let verdicts = verdict::verdicts(config, &infos, &empirical, &c0_compare);

    // 4. The ordered lattice's stability at the derived and rule10 c0.
    let Some(ordered) = stability::ordered_all(config, &infos, quick, stop)? else {
        return Err(interrupted());
    };
    log(&format!(
        "report: the ordered lattice's stability done at {:.1} s",
        start.elapsed().as_secs_f64()
    ));
    // 5. The ordered lattice's growth map over c0 / U x Re.
    let Some(growth) = stability::growth_map(config, &infos, stop)? else {
        return Err(interrupted());
    };
    log(&format!(
        "report: the ordered lattice's growth map ({} cells) done at {:.1} s",
        growth.len(),
        start.elapsed().as_secs_f64()
    ));
    let data = ReportData {
        config: config.clone(),
        plan,
        quick,
        infos,
        rows,
        empirical,
        figure4,
        figure4_cases,
        table1,
        table2,
        c0_compare,
        verdicts,
        wall_s: start.elapsed().as_secs_f64(),
        jobs: opts.par.jobs,
        law,
        ordered,
        growth,
    };
    write::write(&data, out)?;
    log(&format!(
        "report: written to {} in {:.1} s",
        out.join("index.html").display(),
        start.elapsed().as_secs_f64()
    ));
    Ok(data)
}

/// Where the method fails: the first run of a kernel's stability map (grid
/// order; the perturbed map's when none of the perfect one's failed, its
/// seed that was the worst) that the solver stopped, run again (the solver's results are the
/// same bits on any thread count, so it fails at the same step) keeping
/// only its last particle field, drawn with the failing particle ringed.
/// `None` when no run of the map failed in the solver.
fn failure_picture(d: &ReportData, map: &[&Row], perturbed: &[&Row]) -> Result<Option<String>> {
    let Some(row) = map.iter().chain(perturbed).find(|r| {
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
    let Some(point) = d.plan.points.get(row.index) else {
        return Ok(None);
    };
    let scene = point.scene(&d.config.base(d.plan.speed[row.index]))?;
    let mut quiet = crate::solver::Quiet;
    let mut observer = ParticleOutput::new(&mut quiet, Path::new("."), None);
    let result = crate::run::run_scene(&scene, &mut observer)?;
    let Some(last) = observer.finish()? else {
        return Ok(None);
    };
    Ok(Some(picture_svg(&last, &result)?))
}
