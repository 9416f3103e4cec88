//! `index.html`: one self-contained page (SVG figures inline, no scripts, no
//! network), readable in any browser from the file system.

use std::fmt::Write as _;

use super::tables::{C0Compare, EpsCompare};
use super::ReportData;
use crate::charts::class_hex;
use crate::config::C0Rule;
use crate::format::fmt_num;
use crate::kernel::{DiscretisationInfo, KernelInfo, Lattice};
use crate::problem::cost::DtLimit;
use crate::sweep::Class;

/// A figure as written: its SVG file, the CSV behind it, and its text.
pub struct Figure {
    /// The section it belongs to.
    pub id: &'static str,
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
    let c = &d.config;
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
        d.empirical.iter().map(|e| e.runs.len()).sum::<usize>()
    );
    h.push_str("<p>Contents: <a href=\"#verdicts\">verdicts</a> · <a href=\"#table1\">Table 1</a> · <a href=\"#table2\">Table 2</a> · <a href=\"#c0\">c0 by every rule</a> · <a href=\"#square\">square lattice</a> · <a href=\"#figure4\">Figure 4</a> · <a href=\"#speed\">speed against accuracy</a> · <a href=\"#maps\">stability maps</a> · <a href=\"#empirical\">empirical c0</a> · <a href=\"#method\">method</a> · <a href=\"#files\">files</a></p>\n");

    // Verdicts.
    h.push_str("<h2 id=\"verdicts\">Verdicts</h2>\n<p>Computed from the runs below; each scene starts from rest (the start-up problem) and is compared with the series solution.</p>\n");
    for v in &d.verdicts {
        let _ = writeln!(
            h,
            "<div class=\"verdict\"><h3>{}</h3><p><b>{}</b></p>",
            esc(&v.kernel),
            esc(&v.summary)
        );
        for a in &v.at_re {
            let _ = writeln!(
                h,
                "<p><b>Re = {}</b> (N = {}, alpha = {}):</p><ul>",
                num(a.re),
                a.n,
                a.alpha
            );
            let last = a.sentences.len().saturating_sub(1);
            for (k, sentence) in a.sentences.iter().enumerate() {
                if k == last {
                    let _ = writeln!(h, "<li><b>{}</b></li>", esc(sentence));
                } else {
                    let _ = writeln!(h, "<li>{}</li>", esc(sentence));
                }
            }
            h.push_str("</ul>\n");
        }
        h.push_str("</div>\n");
    }

    // Table 1.
    h.push_str("<h2 id=\"table1\">Table 1: compaction eps at 0 and 0.5 T, and its mean (the paper's discretisation: triangular, h = d)</h2>\n");
    h.push_str("<p>Ours from the exact derivation (exact closed form where one exists, else high-precision quadrature), beside the paper's printed values. \"≠ print\" means ours, rounded to the printed places, is not the printed number.</p>\n");
    h.push_str("<table><tr><th class=\"l\">kernel</th><th class=\"l\">quantity</th><th>ours</th><th>printed</th><th class=\"l\">compared</th><th class=\"l\">exact form of ours</th></tr>\n");
    let mut differs: Vec<String> = Vec::new();
    for (k, cells) in &d.table1 {
        for cell in cells {
            let EpsCompare {
                quantity,
                ours,
                exact,
                is_exact,
                printed,
                agrees,
            } = cell;
            if *agrees == Some(false) {
                differs.push(format!(
                    "{k} {quantity}: printed {}, ours {ours:.7}",
                    printed.clone().unwrap_or_default()
                ));
            }
            let _ = writeln!(
                h,
                "<tr><td class=\"l\">{}</td><td class=\"l\">{}</td><td>{}</td><td>{}</td><td class=\"l\">{}</td><td class=\"l wrap\"><code>{}</code>{}</td></tr>",
                esc(k),
                quantity,
                sci(*ours),
                esc(printed.as_deref().unwrap_or("–")),
                mark(*agrees),
                esc(exact),
                if *is_exact { "" } else { " (high precision)" }
            );
        }
    }
    h.push_str("</table>\n");
    if differs.is_empty() {
        h.push_str(
            "<p>Every printed value of Table 1 agrees with ours at its printed precision.</p>\n",
        );
    } else {
        let _ = writeln!(
            h,
            "<p>Where ours and the print differ: {}.</p>",
            esc(&differs.join("; "))
        );
    }

    // Table 2.
    h.push_str("<h2 id=\"table2\">Table 2: the c0 formula (the paper's discretisation: triangular, h = d)</h2>\n");
    h.push_str("<p>Every row as c0 = (U/N²)(√(P α² + Q A) − S α), A = p d N⁴ / U², with the printed factor F folded in (S = F S′, P = F² P′, Q = F² Q′). A root of one quadratic needs P = S²; Q ≤ 0 leaves no positive root. \"≠ print\" compares at the printed precision.</p>\n");
    h.push_str("<table><tr><th class=\"l\">kernel</th><th class=\"l\">row</th><th>eps0</th><th>S</th><th>P</th><th>Q</th><th>P − S²</th><th class=\"l\">positive root</th></tr>\n");
    let mut t2_differs: Vec<String> = Vec::new();
    for r in &d.table2 {
        if let Some(p) = &r.printed {
            let _ = writeln!(
                h,
                "<tr><td class=\"l\">{}</td><td class=\"l\">printed (F = {})</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td class=\"l\">{}</td></tr>",
                esc(&r.kernel),
                p.factor,
                p.eps0,
                num(p.s),
                num(p.p),
                num(p.q),
                num(p.p_minus_s2),
                if p.q > 0.0 { "yes" } else { "no" }
            );
        }
        for m in &r.models {
            let _ = writeln!(
                h,
                "<tr><td class=\"l\">{}</td><td class=\"l\">ours: {}{}</td><td>{} {}</td><td>{} {}</td><td>{} {}</td><td>{} {}</td><td>{}</td><td class=\"l\">{}</td></tr>",
                esc(&r.kernel),
                esc(&m.model),
                if m.default { " (default)" } else { "" },
                sci(r.eps0_ours),
                mark(r.eps0_agrees),
                num(m.s),
                mark(m.s_agrees),
                num(m.p),
                mark(m.p_agrees),
                num(m.q),
                mark(m.q_agrees),
                num(m.p_minus_s2),
                if m.no_positive_root { "<span class=\"diff\">no positive root</span>" } else { "yes" }
            );
            if m.default && r.printed.is_some() {
                let bad: Vec<&str> = [("S", m.s_agrees), ("P", m.p_agrees), ("Q", m.q_agrees)]
                    .iter()
                    .filter(|x| x.1 == Some(false))
                    .map(|x| x.0)
                    .collect();
                if !bad.is_empty() {
                    t2_differs.push(format!(
                        "{} (default model {}): {} differ",
                        r.kernel,
                        m.model,
                        bad.join(", ")
                    ));
                }
            }
        }
    }
    h.push_str("</table>\n");
    if !t2_differs.is_empty() {
        let _ = writeln!(
            h,
            "<p>Where our default model and the print differ at the printed precision: {}. See README, \"The derivation, and where it differs from the print\".</p>",
            esc(&t2_differs.join("; "))
        );
    }

    // c0 by every rule.
    h.push_str("<h2 id=\"c0\">c0 by every rule, the time step it implies, and its run</h2>\n");
    let _ = writeln!(
        h,
        "<p>At N = {}, alpha = {}; dt is the smallest of the CFL (0.25 h/(c0 + U)), viscous (0.125 h²/ν) and force limits; the estimates take |v| = U and |a| = p. The run columns are the solver's.</p>",
        c.maps.n, c.maps.alpha
    );
    h.push_str("<table><tr><th class=\"l\">kernel</th><th>Re</th><th class=\"l\">rule</th><th>c0 / U</th><th>dt</th><th class=\"l\">limit</th><th>steps (est.)</th><th>particle-steps (est.)</th><th>class</th><th>L_inf / U</th><th>max eps</th><th>wall s</th></tr>\n");
    for r in &d.c0_compare {
        let _ = writeln!(
            h,
            "<tr><td class=\"l\">{}</td><td>{}</td><td class=\"l\">{}{}</td><td>{}</td><td>{}</td><td class=\"l\">{}</td><td>{}</td><td>{}</td>{}<td>{}</td><td>{}</td><td>{}</td></tr>",
            esc(&r.kernel),
            num(r.re),
            esc(&r.rule.to_string()),
            if r.default_model { " (default)" } else { "" },
            if r.c0_over_u > 0.0 { num(r.c0_over_u) } else { format!("{} (no positive root)", num(r.c0_over_u)) },
            num(r.dt),
            r.dt_limit.map_or("", DtLimit::name),
            num(r.steps_est),
            num(r.particle_steps_est),
            class_cell(r.class),
            num(r.linf_max),
            num(r.max_eps),
            num(r.wall_s)
        );
    }
    h.push_str("</table>\n<p>Data: <a href=\"c0_compare.csv\">c0_compare.csv</a>, <a href=\"table1.csv\">table1.csv</a>, <a href=\"table2.csv\">table2.csv</a>.</p>\n");

    square_section(&mut h, &d.infos);

    // Figure 4.
    h.push_str("<h2 id=\"figure4\">Figure 4: eps over one period (the paper's discretisation: triangular, h = d; below it the same on one square discretisation per kernel, each panel named)</h2>\n");
    h.push_str("<p>Lines: the generated eps_at(t, n) (walls at |n| ≥ N, at rest). Dots: the solver's own density summation on particles moved exactly by the steady profile (7), no dynamics. Grey: the time mean at n = 0.</p>\n");
    let max_dev = d
        .figure4
        .iter()
        .flat_map(|p| &p.curves)
        .flat_map(|c| c.model.iter().zip(&c.measured).map(|(a, b)| (a - b).abs()))
        .fold(0.0f64, f64::max);
    let _ = writeln!(
        h,
        "<p>Largest difference between the two over every curve: {}.</p>",
        sci(max_dev)
    );
    h.push_str(&figures_html(figures, "figure4"));

    // Speed.
    h.push_str("<h2 id=\"speed\">Speed against accuracy</h2>\n");
    let _ = writeln!(
        h,
        "<p>Worst L_inf error of the layer-mean velocity over the run, against wall time and against particle-steps (machine-free), log-log; one colour per kernel and c0 rule, points labelled by N ∈ {{{}}}, one panel per Re ∈ {{{}}}. Marker shape: which time-step limit bound most steps. Ringed and joined in black: the Pareto front (no other run both cheaper and more accurate). Failed runs have no error and are left out.</p>",
        c.speed.n.iter().map(|n| n.to_string()).collect::<Vec<_>>().join(", "),
        c.speed.re.iter().map(|r| num(*r)).collect::<Vec<_>>().join(", ")
    );
    h.push_str(&figures_html(figures, "speed_accuracy"));
    h.push_str(&figures_html(figures, "speed_accuracy_work"));

    // Maps.
    h.push_str("<h2 id=\"maps\">Stability maps</h2>\n");
    let _ = writeln!(
        h,
        "<p>Outcome class of each run over c0 / U and Re, N = {}, alpha = {}: <span class=\"cls\" style=\"background:{}\">ok</span> <span class=\"cls\" style=\"background:{}\">inaccurate</span> <span class=\"cls\" style=\"background:{}\">over-compressed</span> <span class=\"cls\" style=\"background:{}\">failed</span>. Lines: each derived model's c0 (a model with no positive root is listed as such), 10 U and the printed Table 2. Ringed: the empirical c0.</p>",
        c.maps.n,
        c.maps.alpha,
        class_hex(Class::Ok),
        class_hex(Class::Inaccurate),
        class_hex(Class::OverCompressed),
        class_hex(Class::Failed)
    );
    h.push_str(&figures_html(figures, "stability"));
    if figures.iter().any(|f| f.id == "failure") {
        h.push_str("<h3 id=\"failures\">Where the method fails</h3>\n<p>Per kernel, the first run of its stability map that the solver stopped (first in grid order), run again with the same scene and drawn at the failure: fluid particles coloured by the compaction eps, walls grey, the particle that triggered the failure ringed in red.</p>\n");
        h.push_str(&figures_html(figures, "failure"));
    }

    // Empirical.
    h.push_str("<h2 id=\"empirical\">Empirical c0</h2>\n");
    let _ = writeln!(
        h,
        "<p>The smallest c0 at which the run is ok: bisection on log c0 (solver in the loop) between the map's smallest ok value and the value below it, to {} % relative. If no c0 on the map ran ok, the criterion is \"stable\" (neither failed nor over-compressed), and says so.</p>",
        num(100.0 * c.empirical.rel_tol)
    );
    h.push_str("<table><tr><th class=\"l\">kernel</th><th>Re</th><th class=\"l\">criterion</th><th>empirical c0 / U</th><th>below it</th><th class=\"l\">run below</th><th>derived c0 / U (default)</th><th>Table 2 c0 / U</th><th>rule c0 / U</th><th>bisection runs</th><th class=\"l\">isolated ok values below (not counted)</th></tr>\n");
    for e in &d.empirical {
        let rule_c0 = |want: &dyn Fn(&C0Compare) -> bool| {
            d.c0_compare
                .iter()
                .find(|x| x.kernel_index == e.kernel_index && x.re_index == e.re_index && want(x))
                .map(|x| x.c0_over_u)
        };
        let derived = rule_c0(&|x| x.default_model);
        let _ = writeln!(
            h,
            "<tr><td class=\"l\">{}</td><td>{}</td><td class=\"l\">{}</td><td><b>{}</b></td><td>{}</td><td class=\"l wrap\">{}</td><td>{}</td><td>{}</td><td>10</td><td>{}</td><td class=\"l\">{}</td></tr>",
            esc(&e.kernel),
            num(e.re),
            e.criterion,
            e.c0_over_u.map_or("none".into(), num),
            e.below.map_or("–".into(), num),
            esc(e.below_reason.as_deref().unwrap_or("–")),
            match derived {
                Some(v) if v > 0.0 => num(v),
                Some(_) => "no positive root".into(),
                None => "–".into(),
            },
            rule_c0(&|x| x.rule == C0Rule::Table2).map_or("–".into(), num),
            e.runs.len(),
            if e.isolated_below.is_empty() {
                "–".to_string()
            } else {
                e.isolated_below.iter().map(|v| format!("{} U", num(*v))).collect::<Vec<_>>().join(", ")
            }
        );
    }
    h.push_str("</table>\n<p>Data: <a href=\"empirical_c0.csv\">empirical_c0.csv</a>, the bisection's runs <a href=\"empirical_c0_runs.csv\">empirical_c0_runs.csv</a>.</p>\n");

    // Method.
    h.push_str("<h2 id=\"method\">Method</h2>\n<ul>\n");
    let _ = writeln!(
        h,
        "<li><b>ok</b>: the run ended without failing, its compaction stayed within the kernel's own lattice pulsation eps0 (the true maximum of eps(t) under ideal shear) plus {}, and the worst L_inf error of the layer-mean velocity over the run stayed within {} of U.</li>",
        pct(c.classes.eps_margin),
        pct(c.classes.linf_bound)
    );
    let _ = writeln!(
        h,
        "<li><b>over-compressed</b>: max eps above eps0 + {} (the usual weakly compressible tolerance, Mach 0.1; eps0 itself is there at any c0). <b>inaccurate</b>: L_inf above {} of U (the best runs at N = 10 stay within 0.2–2 %). <b>failed</b>: the solver stopped the run (not finite, a speed above 10 U + c0, a particle through a wall, compaction above the scene's limit), or the rule gave no positive c0.</li>",
        pct(c.classes.eps_margin),
        pct(c.classes.linf_bound)
    );
    let scene_fields: Vec<String> = c.scene.iter().map(|(k, v)| format!("{k} = {v}")).collect();
    let _ = writeln!(
        h,
        "<li>Scenes: the built-in scene with {}; start-up from rest, compared with the series solution.</li>",
        esc(&scene_fields.join(", "))
    );
    let _ = writeln!(h, "<li>The config of this run: <a href=\"report.toml\">report.toml</a>; every run: <a href=\"runs.csv\">runs.csv</a> (also <a href=\"runs.jsonl\">runs.jsonl</a>); the verdicts as data: <a href=\"verdicts.json\">verdicts.json</a>.</li>");
    h.push_str("</ul>\n");

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
    h
}

fn pct(v: f64) -> String {
    format!("{} %", fmt_num(100.0 * v))
}

/// The square discretisation a kernel's square-lattice analysis shows:
/// h = 13/10 d when generated (SPHinXsys's), else the first square one.
pub fn square_discretisation(info: &KernelInfo) -> Option<&'static DiscretisationInfo> {
    let square = || {
        info.discretisations
            .iter()
            .filter(|d| d.lattice == Lattice::Square)
    };
    square()
        .find(|d| d.h_over_d_exact == "13/10")
        .or_else(|| square().next())
}

/// The same analysis as Tables 1 and 2 for one square discretisation per
/// kernel, from the generated constants: eps at 0 and 0.5 T, its true
/// extremes and where, its mean, and the derived c0 coefficients at the
/// configuration the search found the maximum in (or the "no c0" fact).
fn square_section(h: &mut String, infos: &[&'static KernelInfo]) {
    h.push_str("<h2 id=\"square\">The square lattice: eps and the derived c0</h2>\n");
    h.push_str("<p>The analysis of Tables 1 and 2 for the discretisation the peers run: per kernel the square lattice with h = 13/10 d (SPHinXsys) where generated, else its first square one; every row names it. From the exact derivation (<code>generated/</code>); the c0 models are derived where the search found the maximum compaction, at the time given.</p>\n");
    h.push_str("<table><tr><th class=\"l\">kernel</th><th class=\"l\">discretisation</th><th>eps(0)</th><th>eps(0.5T)</th><th>max eps</th><th>at t/T</th><th>min eps</th><th>at t/T</th><th>mean eps</th></tr>\n");
    for info in infos {
        let Some(disc) = square_discretisation(info) else {
            let _ = writeln!(h, "<tr><td class=\"l\">{}</td><td class=\"l\" colspan=\"8\">no square discretisation generated</td></tr>", esc(info.name));
            continue;
        };
        let e = &disc.eps;
        let _ = writeln!(
            h,
            "<tr><td class=\"l\">{}</td><td class=\"l\">{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>",
            esc(info.name),
            esc(&disc.label()),
            num(e.t0.value),
            num(e.half_period.value),
            num(e.max.value),
            num(e.t_max.value),
            num(e.min.value),
            num(e.t_min.value),
            num(e.mean.value)
        );
    }
    h.push_str("</table>\n");
    h.push_str("<table><tr><th class=\"l\">kernel</th><th class=\"l\">discretisation</th><th class=\"l\">model</th><th>derived at t/T</th><th>eps0</th><th>S</th><th>P</th><th>Q</th></tr>\n");
    for info in infos {
        let Some(disc) = square_discretisation(info) else {
            continue;
        };
        let c = &disc.c0_configuration;
        for m in disc.c0_models {
            let _ = writeln!(
                h,
                "<tr><td class=\"l\">{}</td><td class=\"l\">{}</td><td class=\"l\">{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>",
                esc(info.name),
                esc(&disc.label()),
                esc(m.name),
                num(c.t.value),
                num(c.eps0.value),
                num(m.s.value),
                num(m.p.value),
                num(m.q.value)
            );
        }
        for m in disc.no_c0 {
            let _ = writeln!(
                h,
                "<tr><td class=\"l\">{}</td><td class=\"l\">{}</td><td class=\"l\">{}</td><td class=\"l\" colspan=\"5\">{}</td></tr>",
                esc(info.name),
                esc(&disc.label()),
                esc(m.model),
                esc(m.fact)
            );
        }
    }
    h.push_str("</table>\n");
}
