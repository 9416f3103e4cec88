//! `index.html`: one self-contained page (SVG figures inline, no scripts, no
//! network), readable in any browser from the file system.

use std::fmt::Write as _;

mod first_screen;
mod growth;
mod paper;
mod runs;

use super::ReportData;
use crate::charts::class_hex;
use crate::format::fmt_num;
use crate::sweep::Class;

/// A figure as written: its SVG file, the CSV behind it, and its text.
pub struct Figure {
    /// The section it belongs to.
    pub id: String,
    pub svg_file: String,
    pub csv_files: Vec<String>,
    pub svg: String,
}

fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

fn sci(v: f64) -> String {
    if v.is_finite() {
        format!("{v:.6e}")
    } else {
        "–".into()
    }
}

fn num(v: f64) -> String {
    if v.is_finite() {
        fmt_num(v)
    } else {
        "–".into()
    }
}

fn class_cell(c: Option<Class>) -> String {
    match c {
        Some(c) => format!(
            "<td><span class=\"cls\" style=\"background:{}\">{}</span></td>",
            class_hex(c),
            c
        ),
        None => "<td>not run</td>".into(),
    }
}

fn mark(agrees: Option<bool>) -> &'static str {
    match agrees {
        Some(true) => "<span class=\"same\">= print</span>",
        Some(false) => "<span class=\"diff\">≠ print</span>",
        None => "",
    }
}

fn figures_html(figures: &[Figure], id: &str) -> String {
    let mut out = String::new();
    for f in figures.iter().filter(|f| f.id == id) {
        let csv: Vec<String> = f
            .csv_files
            .iter()
            .map(|c| format!("<a href=\"{0}\">{0}</a>", esc(c)))
            .collect();
        let _ = writeln!(
            out,
            "<figure id=\"fig-{0}\"><div class=\"svg\">{1}</div><figcaption>File: <a href=\"{2}\">{2}</a>; data: {3}</figcaption></figure>",
            esc(f.svg_file.trim_end_matches(".svg")),
            f.svg,
            esc(&f.svg_file),
            csv.join(", ")
        );
    }
    out
}

const STYLE: &str = "body{font-family:sans-serif;max-width:1280px;margin:1em auto;padding:0 1em;color:#222;line-height:1.4}
table{border-collapse:collapse;margin:0.5em 0 1.2em}td,th{border:1px solid #ccc;padding:2px 7px;text-align:right;font-size:0.9em;white-space:nowrap}td.wrap{white-space:normal}
th{background:#f2f2f2}td.l,th.l{text-align:left}.diff{color:#b00;font-weight:bold}.same{color:#070}
.cls{color:white;padding:0 5px;border-radius:3px;white-space:nowrap}.svg svg{max-width:100%;height:auto}
figure{margin:1em 0}figcaption{font-size:0.85em;color:#555}.verdict{border-left:4px solid #888;padding:0.2em 0.8em;margin:0.6em 0;background:#fafafa}
.warn{background:#fff3cd;padding:0.5em 1em;border:1px solid #e0c060}code{background:#f4f4f4;padding:0 3px}";

pub fn page(d: &ReportData, figures: &[Figure]) -> String {
    let mut h = String::new();
    let _ = write!(
        h,
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>shearsph report: the model sound speed c0 for SPH plane shear flow</title><style>{STYLE}</style></head><body>\n"
    );
    h.push_str("<h1>The model sound speed c0 for SPH plane shear flow: the derivation against the solver</h1>\n");
    h.push_str(
        "<p>Reshetnikova (2024) derives the sound speed c0 of a weakly compressible SPH run of plane Poiseuille flow from the shape \
         of the smoothing kernel. This report reproduces the paper's Tables 1 and 2 and its Figure 4 from the exact derivation \
         (<code>generated/</code>), then runs the solver around each derived c0 to see whether it is necessary and sufficient.</p>\n",
    );
    if d.quick {
        h.push_str("<p class=\"warn\">This is a <b>--quick</b> report: tiny grids and short runs, for testing. Its numbers are not the verdicts of the full report (<code>shearsph report</code>).</p>\n");
    }
    let _ = writeln!(
        h,
        "<p>Made by <code>shearsph report{}</code> in {:.1} s with {} scenes at once; {} runs in the grids, {} in the bisections.</p>",
        if d.quick { " --quick" } else { "" },
        d.wall_s,
        d.jobs,
        d.rows.len(),
        d.empirical.iter().filter(|e| e.case.perturbed).map(|e| e.answer.horizon.runs).sum::<usize>()
    );
    let cases: String = d.config.case[1..]
        .iter()
        .map(|c| {
            let label = c.label.as_deref().unwrap_or(&c.id);
            format!("<a href=\"#{}\">{}</a> · ", c.id, esc(label))
        })
        .collect();
    h.push_str("<p>Contents: <a href=\"#answer\">the answer</a> · <a href=\"#verdicts\">verdicts</a> · <a href=\"#table1\">Table 1</a> · <a href=\"#table2\">Table 2</a> · <a href=\"#c0\">c0 by every rule</a> · ");
    h.push_str(&cases);
    h.push_str("<a href=\"#figure4\">Figure 4</a> · <a href=\"#speed\">speed against accuracy</a> · <a href=\"#maps\">stability maps</a> · <a href=\"#growth\">growth map</a> · <a href=\"#empirical\">empirical c0</a> · <a href=\"#method\">method</a> · <a href=\"#files\">files</a></p>\n");

    first_screen::first_screen(&mut h, d, figures);
    runs::verdicts(&mut h, d);
    paper::table1(&mut h, d);
    paper::table2(&mut h, d);
    runs::c0_by_rule(&mut h, d);
    for case in d.config.cases() {
        if case.disc.index == 0 {
            continue;
        }
        if !case.perturbed {
            paper::case_section(&mut h, d, case.disc);
        }
        h.push_str(&figures_html(figures, &d.config.figure_id(case)));
    }
    runs::figure4(&mut h, d, figures);
    runs::speed(&mut h, d, figures);
    runs::maps(&mut h, d, figures);
    growth::growth(&mut h, d);
    runs::empirical(&mut h, d);
    if let Some(law) = &d.law {
        h.push_str(&law.html);
    }
    method(&mut h, d);
    files(&mut h, figures);
    h
}

/// The method: the classes' bounds, the scenes, the config.
fn method(h: &mut String, d: &ReportData) {
    let c = &d.config;
    // Method.
    h.push_str("<h2 id=\"method\">Method</h2>\n<ul>\n");
    let _ = writeln!(
        h,
        "<li><b>ok</b>: the run ended without failing, and on its judged window (the stationary window of a long run, docs/stationary.md) its compaction eps_stat (the window's mean of the per-frame max eps) stayed within the kernel's own lattice pulsation eps0 (the true maximum of eps(t) under ideal shear) plus {}, and its mean-flow error linf_stat (the window's mean L_inf error of the velocity profile, binned by current position) within {} of U.</li>",
        pct(c.classes.eps_margin),
        pct(c.classes.linf_bound)
    );
    let _ = writeln!(
        h,
        "<li><b>over-compressed</b>: eps_stat above eps0 + {} (the usual weakly compressible tolerance; eps0 itself is there at any c0). <b>inaccurate</b>: linf_stat above {} of U. <b>failed</b>: the solver stopped the run (not finite, a speed above 10 U + c0, a particle through a wall, compaction above the scene's limit), or the rule gave no positive c0.</li>",
        pct(c.classes.eps_margin),
        pct(c.classes.linf_bound)
    );
    let scene_fields: Vec<String> = c.scene.iter().map(|(k, v)| format!("{k} = {v}")).collect();
    let _ = writeln!(
        h,
        "<li>Scenes: the built-in scene with {}; start-up from rest, compared with the series solution.</li>",
        esc(&scene_fields.join(", "))
    );
    let _ = writeln!(h, "<li>The config of this run: <a href=\"report.toml\">report.toml</a>; every run: <a href=\"runs.csv\">runs.csv</a> (also <a href=\"runs.jsonl\">runs.jsonl</a>); the verdicts as data: <a href=\"verdicts.json\">verdicts.json</a>, the first screen's words: <a href=\"answer.json\">answer.json</a>; the ordered lattice's growth at the derived and rule10 c0 (shearsph stability): <a href=\"ordered_lattice.json\">ordered_lattice.json</a>, and over c0 / U x Re: <a href=\"growth_map.json\">growth_map.json</a>.</li>");
    h.push_str("</ul>\n");
}

/// Every figure file and its data.
fn files(h: &mut String, figures: &[Figure]) {
    // Files.
    h.push_str("<h2 id=\"files\">Files</h2>\n<ul>\n");
    for f in figures {
        let _ = writeln!(
            h,
            "<li><a href=\"{0}\">{0}</a> ({1})</li>",
            esc(&f.svg_file),
            f.csv_files
                .iter()
                .map(|c| format!("<a href=\"{0}\">{0}</a>", esc(c)))
                .collect::<Vec<_>>()
                .join(", ")
        );
    }
    h.push_str("</ul>\n</body></html>\n");
}

fn pct(v: f64) -> String {
    format!("{} %", fmt_num(100.0 * v))
}
