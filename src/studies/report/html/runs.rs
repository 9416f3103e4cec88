//! The page's sections from the runs: the verdicts, c0 by every rule,
//! Figure 4, speed against accuracy, the stability maps and the empirical c0.

use std::fmt::Write as _;

use super::{class_cell, esc, figures_html, num, sci, Figure};
use crate::charts::class_hex;
use crate::config::C0Rule;
use crate::problem::cost::DtLimit;
use crate::report::plan::Case;
use crate::report::tables::C0Compare;
use crate::report::ReportData;
use crate::sweep::Class;

/// The verdicts, per kernel and Re.
pub(super) fn verdicts(h: &mut String, d: &ReportData) {
    // Verdicts.
    h.push_str("<h2 id=\"verdicts\">Verdicts</h2>\n<p>Computed from the runs below; each scene starts from rest (the start-up problem) and is compared with the series solution.</p>\n");
    for v in &d.verdicts {
        let _ = writeln!(
            h,
            "<div class=\"verdict\"><h3>{}</h3><p><b>{}</b></p>",
            esc(&v.kernel),
            esc(&v.summary)
        );
        super::first_screen::at_re_html(h, &v.at_re);
        super::first_screen::cases(h, d, &v.kernel);
        h.push_str("</div>\n");
    }
}

/// c0 by every rule, the time step it implies, and its run.
pub(super) fn c0_by_rule(h: &mut String, d: &ReportData) {
    let c = &d.config;
    // c0 by every rule.
    h.push_str("<h2 id=\"c0\">c0 by every rule, the time step it implies, and its run</h2>\n");
    let _ = writeln!(
        h,
        "<p>At N = {}, alpha = {}; dt is the smallest of the CFL (C h/(c0 + U)), viscous (F h²/ν) and force limits, C and F the kernel's defaults: half the largest factor at which its pressure term is stable on the lattice, at most 1, and 0.85 of the largest at which its viscous term is (docs/timestep.md); the estimates take |v| = U and |a| = p. The run columns are the solver's.</p>",
        c.maps.n, c.maps.alpha
    );
    h.push_str("<table><tr><th class=\"l\">kernel</th><th>Re</th><th class=\"l\">rule</th><th>c0 / U</th><th>dt</th><th class=\"l\">limit</th><th>steps (est.)</th><th>particle-steps (est.)</th><th>class</th><th>mean-flow L_inf / U</th><th>eps_stat</th><th>wall s</th></tr>\n");
    for r in &d.c0_compare {
        let _ = writeln!(
            h,
            "<tr><td class=\"l\">{}</td><td>{}</td><td class=\"l\">{}{}</td><td>{}</td><td>{}</td><td class=\"l\">{}</td><td>{}</td><td>{}</td>{}<td>{}</td><td>{}</td><td>{}</td></tr>",
            esc(&format!("{} ({}, {})", r.kernel, r.discretisation, r.case.start_name())),
            num(r.re),
            esc(&r.rule.to_string()),
            if r.default_model { " (default)" } else { "" },
            if r.c0_over_u > 0.0 { num(r.c0_over_u) } else { format!("{} (no positive root)", num(r.c0_over_u)) },
            num(r.dt),
            r.dt_limit.map_or("", DtLimit::name),
            num(r.steps_est),
            num(r.particle_steps_est),
            class_cell(r.class),
            num(r.linf_stat),
            num(r.eps_stat),
            num(r.wall_s)
        );
    }
    h.push_str("</table>\n<p>Data: <a href=\"c0_compare.csv\">c0_compare.csv</a>, <a href=\"table1.csv\">table1.csv</a>, <a href=\"table2.csv\">table2.csv</a>.</p>\n");
}

/// Figure 4: the generated eps against the solver's density.
pub(super) fn figure4(h: &mut String, d: &ReportData, figures: &[Figure]) {
    // Figure 4.
    h.push_str("<h2 id=\"figure4\">Figure 4: eps over one period (the paper's discretisation: triangular, h = d; below it the same on each further case's discretisation, each panel named)</h2>\n");
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
}

/// Speed against accuracy.
pub(super) fn speed(h: &mut String, d: &ReportData, figures: &[Figure]) {
    let c = &d.config;
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
}

/// The stability maps, and where the method fails.
pub(super) fn maps(h: &mut String, d: &ReportData, figures: &[Figure]) {
    let c = &d.config;
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
    h.push_str(&figures_html(figures, &d.config.figure_id(Case::PAPER)));
    let _ = writeln!(
        h,
        "<h3 id=\"maps-perturbed\">Perturbed starts</h3>\n<p>The same maps from starts jittered by up to {} d ({} seeds each), at Re in {{{}}}: each cell the class of its seeds pooled (failed if one failed, otherwise judged on the seeds' mean window statistics, docs/stationary.md); ringed, the empirical c0 of the disordered regime.</p>",
        c.perturbed.jitter,
        c.perturbed.seeds,
        c.perturbed.re.iter().map(|r| num(*r)).collect::<Vec<_>>().join(", ")
    );
    h.push_str(&figures_html(
        figures,
        &d.config.figure_id(Case::PAPER_PERTURBED),
    ));
    if figures.iter().any(|f| f.id == "failure") {
        h.push_str("<h3 id=\"failures\">Where the method fails</h3>\n<p>Per kernel, the first run of its stability map that the solver stopped (first in grid order; of the perturbed map, its worst seed, when none on the perfect lattice failed), run again with the same scene and drawn at the failure: fluid particles coloured by the compaction eps, walls grey, the particle that triggered the failure ringed in red.</p>\n");
        h.push_str(&figures_html(figures, "failure"));
    }
}

/// The empirical c0 table.
pub(super) fn empirical(h: &mut String, d: &ReportData) {
    let c = &d.config;
    // Empirical.
    h.push_str("<h2 id=\"empirical\">Empirical c0</h2>\n");
    let _ = writeln!(
        h,
        "<p>The smallest c0 at which the run is ok, by the engine of <code>shearsph c0 --empirical</code> (the same answer for the same scene): from 10 U by steps of sqrt 10 to a bracket, then bisection on log c0 to {} % relative, each run to its stationary horizon (docs/stationary.md). Perturbed: the stationary, disordered state of the pooled seeds; perfect: the perfect lattice, the ordered regime.</p>",
        num(100.0 * c.empirical.rel_tol)
    );
    h.push_str("<table><tr><th class=\"l\">kernel</th><th>Re</th><th>empirical c0 / U</th><th>below it</th><th class=\"l\">run below</th><th>derived c0 / U (default)</th><th>Table 2 c0 / U</th><th>rule c0 / U</th><th>trials</th><th class=\"l\">disordered law k, m</th></tr>\n");
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
            "<tr><td class=\"l\">{}</td><td>{}</td><td><b>{}</b></td><td>{}</td><td class=\"l wrap\">{}</td><td>{}</td><td>{}</td><td>10</td><td>{}</td><td class=\"l\">{}</td></tr>",
            esc(&format!("{} ({}, {})", e.kernel, e.discretisation, e.case.start_name())),
            num(e.re),
            e.c0_over_u.map_or("none".into(), num),
            e.below.map_or("–".into(), num),
            esc(e.below_reason.as_deref().unwrap_or("–")),
            match derived {
                Some(v) if v > 0.0 => num(v),
                Some(_) => "no positive root".into(),
                None => "–".into(),
            },
            rule_c0(&|x| x.rule == C0Rule::Table2).map_or("–".into(), num),
            e.answer.trials.len(),
            e.answer
                .law
                .as_ref()
                .filter(|_| e.case.perturbed)
                .map_or("–".to_string(), |l| format!("{}, {} ± {}", num(l.k), num(l.m), num(l.m_se)))
        );
    }
    h.push_str("</table>\n<p>Data: <a href=\"empirical_c0.csv\">empirical_c0.csv</a>, every trial <a href=\"empirical_c0_trials.csv\">empirical_c0_trials.csv</a>.</p>\n");
}
