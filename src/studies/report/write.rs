//! The report's files: the figures and the CSV behind each, the tables, the
//! rows, and `index.html` last, staged and swapped in as one set (a full
//! disk keeps the earlier report whole).

use std::path::Path;

use anyhow::Result;

use super::figures::{map_cells, rule_lines_on};
use super::html::{self, Figure};
use super::plan::{Case, Role};
use super::{empirical, failure_picture, tables, ReportData};
use crate::charts;
use crate::output::StagedSet;
use crate::sweep::{store, Row};

/// Writes one file of the report folder and keeps its figures for the page.
struct Folder {
    set: StagedSet,
    figures: Vec<Figure>,
}

impl Folder {
    fn put(&self, name: &str, text: &str) -> Result<()> {
        self.set.put(name, text.as_bytes())
    }

    /// An SVG file, shown in section `id` with the CSV files behind it.
    fn figure(&mut self, id: &str, file: &str, svg: String, csv: &[&str]) -> Result<()> {
        self.put(file, &svg)?;
        self.figures.push(Figure {
            id: id.into(),
            svg_file: file.into(),
            csv_files: csv.iter().map(|c| c.to_string()).collect(),
            svg,
        });
        Ok(())
    }
}

/// The figures and their CSV, the tables, the rows, and `index.html` last.
pub(super) fn write(d: &ReportData, out: &Path) -> Result<()> {
    let mut f = Folder {
        set: StagedSet::begin(out)?,
        figures: Vec::new(),
    };
    runs(d, &f)?;
    answer(d, &mut f)?;
    histories(d, &mut f)?;
    figure4(d, &mut f)?;
    speed(d, &mut f)?;
    maps(d, &mut f)?;
    tables(d, &f)?;
    if let Some(law) = &d.law {
        for (name, svg) in &law.figures {
            f.put(name, svg)?;
        }
    }
    f.put("index.html", &html::page(d, &f.figures))?;
    f.set.commit()?;
    Ok(())
}

/// The config and every run of the grids.
fn runs(d: &ReportData, f: &Folder) -> Result<()> {
    f.put(
        "report.toml",
        &toml::to_string(&d.config).expect("a config serialises"),
    )?;
    f.put("runs.csv", &store::rows_csv(&d.rows))?;
    f.put(
        "ordered_lattice.json",
        &serde_json::to_string_pretty(&d.ordered)?,
    )?;
    f.put("growth_map.json", &serde_json::to_string_pretty(&d.growth)?)?;
    let mut jsonl = String::new();
    for r in &d.rows {
        jsonl.push_str(&serde_json::to_string(r)?);
        jsonl.push('\n');
    }
    f.put("runs.jsonl", &jsonl)
}

/// Figure 4 on the paper's discretisation and on every other case's.
fn figure4(d: &ReportData, f: &mut Folder) -> Result<()> {
    let n = d.config.figure4.n;
    let cases = d
        .figure4_cases
        .iter()
        .map(|(id, panels)| (panels, format!("figure4_{id}")));
    for (panels, name) in std::iter::once((&d.figure4, "figure4".to_string())).chain(cases) {
        let csv = format!("{name}.csv");
        f.put(&csv, &charts::figure4_csv(panels, n))?;
        f.figure(
            "figure4",
            &format!("{name}.svg"),
            charts::figure4_svg(panels)?,
            &[&csv],
        )?;
    }
    Ok(())
}

/// Speed against accuracy: the speed grid's rows.
fn speed(d: &ReportData, f: &mut Folder) -> Result<()> {
    let speed_rows: Vec<Row> = d
        .plan
        .rows(&d.rows, |k| matches!(k.role, Role::Speed { .. }))
        .into_iter()
        .cloned()
        .collect();
    let pts = charts::speed_points(&speed_rows);
    f.put("speed_accuracy.csv", &charts::speed_csv(&pts))?;
    for (id, cost) in [
        ("speed_accuracy", charts::Cost::WallTime),
        ("speed_accuracy_work", charts::Cost::ParticleSteps),
    ] {
        let svg = charts::speed_svg(&pts, cost)?;
        f.figure(id, &format!("{id}.svg"), svg, &["speed_accuracy.csv"])?;
    }
    Ok(())
}

/// A stability map per kernel and case, and where the method fails.
fn maps(d: &ReportData, f: &mut Folder) -> Result<()> {
    let m = &d.config.maps;
    for case in d.config.cases() {
        for (ki, &info) in d.infos.iter().enumerate() {
            let Some((disc, on)) = case.disc.of(info) else {
                continue;
            };
            let k = info.name;
            let here_rows = d.plan.map_rows(&d.rows, ki, case, None);
            let here: Vec<&Row> = here_rows.iter().collect();
            let cells = map_cells(&here);
            let res: Vec<f64> = cells.iter().map(|c| c.re).collect();
            let lines = rule_lines_on(k, disc, &d.config.scene, m.n, m.alpha, &res)?;
            let marks: Vec<charts::MapMark> = d
                .empirical
                .iter()
                .filter(|e| e.kernel_index == ki && e.case == case)
                .filter_map(|e| e.c0_over_u.map(|c| ("empirical".to_string(), e.re, c)))
                .collect();
            let start = match case.perturbed {
                false => "perfect lattice".to_string(),
                true => d.config.perturbed_label(),
            };
            let title = format!(
                "{k}: outcome over c0 / U and Re (N = {}, alpha = {}; {}, {start})",
                m.n,
                m.alpha,
                on.label()
            );
            let svg = charts::map_svg(&title, &cells, &lines, &marks)?;
            let name = format!("stability_{k}{}", d.config.file_suffix(case));
            let (csv, lines_csv) = (format!("{name}.csv"), format!("{name}_lines.csv"));
            f.put(&csv, &charts::map_csv(k, &cells))?;
            f.put(&lines_csv, &charts::map_lines_csv(k, &lines))?;
            f.figure(
                &d.config.figure_id(case),
                &format!("{name}.svg"),
                svg,
                &[&csv, &lines_csv],
            )?;
            if case == Case::PAPER {
                let perturbed_rows = d.plan.map_rows(&d.rows, ki, Case::PAPER_PERTURBED, None);
                let perturbed: Vec<&Row> = perturbed_rows.iter().collect();
                if let Some(svg) = failure_picture(d, &here, &perturbed)? {
                    f.figure("failure", &format!("failure_{k}.svg"), svg, &[])?;
                }
            }
        }
    }
    Ok(())
}

/// Per kernel, on the paper's discretisation at the first verdict Re, the
/// history of the perfect lattice and of the first jittered seed at the
/// search's first probe (10 U): the two regimes in time.
fn histories(d: &ReportData, f: &mut Folder) -> Result<()> {
    for e in d
        .empirical
        .iter()
        .filter(|e| e.case == Case::PAPER_PERTURBED && e.re_index == 0)
    {
        let a = &e.answer;
        let first = a.search.first_over_u * a.u;
        let Some(t) = a.trials.iter().find(|t| t.c0 == first) else {
            continue;
        };
        let mut runs = Vec::new();
        if let Some(p) = &t.perfect {
            runs.push(charts::history::History {
                label: "perfect lattice".into(),
                frames: &p.series,
                window: p.window,
            });
        }
        if let Some(s) = t.seeds.first() {
            runs.push(charts::history::History {
                label: format!("jittered by {} d, seed {}", s.jitter, s.seed),
                frames: &s.series,
                window: s.window,
            });
        }
        let title = format!(
            "{}: c0 = {} U, N = {}, Re = {}, alpha = {} ({}); shaded: each run's window",
            e.kernel,
            crate::format::fmt_num(t.c0_over_u),
            e.n,
            crate::format::fmt_num(e.re),
            e.alpha,
            e.discretisation
        );
        let svg = charts::history::history_svg(&title, &runs)?;
        f.figure("history", &format!("history_{}.svg", e.kernel), svg, &[])?;
    }
    Ok(())
}

/// The first screen: per kernel, c0 by every rule against the empirical
/// bands, perfect and perturbed.
fn answer(d: &ReportData, f: &mut Folder) -> Result<()> {
    let words: Vec<serde_json::Value> = (0..d.infos.len())
        .map(|ki| {
            serde_json::json!({
                "kernel": d.infos[ki].name,
                "answer": super::first_screen::answers(d, ki),
            })
        })
        .collect();
    f.put("answer.json", &serde_json::to_string_pretty(&words)?)?;
    for (ki, info) in d.infos.iter().enumerate() {
        let panels = super::first_screen::panels(d, ki);
        let k = info.name;
        let csv = format!("answer_{k}.csv");
        f.put(&csv, &charts::rules_csv(k, &panels))?;
        let title = format!(
            "{}: c0 by every rule against the empirical ok band (N = {}, alpha = {}, {})",
            info.title,
            d.config.maps.n,
            d.config.maps.alpha,
            super::papers(info).map_or(String::new(), |p| p.label())
        );
        let p = &d.config.perturbed;
        let legend = format!("jitter {} d, {} seeds pooled", p.jitter, p.seeds);
        let svg = charts::rules_svg(&title, &panels, &legend)?;
        f.figure("answer", &format!("answer_{k}.svg"), svg, &[&csv])?;
    }
    Ok(())
}

/// The tables, the empirical c0 and the verdicts as data.
fn tables(d: &ReportData, f: &Folder) -> Result<()> {
    f.put("table1.csv", &tables::table1_csv(&d.table1))?;
    f.put("table2.csv", &tables::table2_csv(&d.table2))?;
    f.put("c0_compare.csv", &tables::c0_compare_csv(&d.c0_compare))?;
    f.put("empirical_c0.csv", &empirical::csv(&d.empirical))?;
    f.put(
        "empirical_c0_trials.csv",
        &empirical::trials_csv(&d.empirical),
    )?;
    f.put("verdicts.json", &serde_json::to_string_pretty(&d.verdicts)?)
}
