//! The page's first screen: per kernel, the picture of c0 by every rule
//! against the empirical bands and the words that read it; then the
//! verdicts of the other cases (perturbed, square lattice).

use std::fmt::Write as _;

use super::{esc, num, Figure};
use crate::report::verdict::VerdictAtRe;
use crate::report::{first_screen, ReportData};

/// The answer first: per kernel its picture and, per Re, which rules were
/// sufficient, which necessary and what each cost.
pub(super) fn first_screen(h: &mut String, d: &ReportData, figures: &[Figure]) {
    let c = &d.config;
    h.push_str("<h2 id=\"answer\">The answer: c0 by every rule against the solver</h2>\n");
    let _ = writeln!(
        h,
        "<p>Per kernel, on the paper's discretisation at N = {}, alpha = {}, both regimes: each rule's c0 (rows) at each verdict Re (panels), a dot coloured by the class of its run on the perfect lattice (the ordered regime the paper analyses, while it lasts) and a triangle by the class of the perturbed starts in their stationary, disordered state ({}); shaded, the empirical ok band (the smallest ok c0, bisected, up to the largest ok trial of the block above it) of the ordered regime (light) and of the disordered one (dark). Every run goes past the start-up until its statistics are stationary and is judged on that window (docs/stationary.md). Every mark is one of this report's runs.</p>",
        c.maps.n,
        c.maps.alpha,
        esc(&c.perturbed_label())
    );
    for (ki, info) in d.infos.iter().enumerate() {
        let _ = writeln!(h, "<h3>{}</h3>", esc(info.title));
        let file = format!("answer_{}.svg", info.name);
        let one: Vec<&Figure> = figures.iter().filter(|f| f.svg_file == file).collect();
        for f in one {
            let _ = writeln!(
                h,
                "<figure id=\"fig-answer_{0}\"><div class=\"svg\">{1}</div><figcaption>File: <a href=\"{2}\">{2}</a>; data: <a href=\"answer_{0}.csv\">answer_{0}.csv</a></figcaption></figure>",
                esc(info.name),
                f.svg,
                esc(&f.svg_file)
            );
        }
        for a in first_screen::answers(d, ki) {
            let _ = writeln!(h, "<p><b>Re = {}</b>:</p><ul>", num(a.re));
            for s in &a.sentences {
                let _ = writeln!(h, "<li>{}</li>", esc(s));
            }
            h.push_str("</ul>\n");
        }
    }
    if figures.iter().any(|f| f.id == "history") {
        h.push_str("<h3 id=\"history\">The two regimes in time</h3>\n<p>Per kernel, at the search's first probe (10 U) and the first verdict Re: the perfect lattice and a jittered start, each run to its stationary horizon. Above, the compaction (the 99th percentile of eps over the fluid, per frame); below, dy_rms, how far the particles have left their lattice rows (the grey line, 0.1 d, is where a run counts as disordered). A jitter first relaxes or grows; once it has grown the flow is disordered and settles into a stationary state, which the shaded window judges. The perfect lattice's own perturbation is round-off: it stays ordered far longer.</p>\n");
        h.push_str(&super::figures_html(figures, "history"));
    }
}

/// One case's paragraphs per Re (the last sentence, the conclusion, bold).
pub(super) fn at_re_html(h: &mut String, at_re: &[VerdictAtRe]) {
    for a in at_re {
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
}

/// The verdicts of the other cases, each folded under its summary.
pub(super) fn cases(h: &mut String, d: &ReportData, kernel: &str) {
    let Some(v) = d.verdicts.iter().find(|v| v.kernel == kernel) else {
        return;
    };
    for c in &v.cases {
        let _ = writeln!(
            h,
            "<details><summary><b>{}, {} start{}:</b> {}</summary>",
            esc(&c.discretisation),
            c.start,
            if c.start == "perturbed" {
                format!(" ({})", esc(&d.config.perturbed_label()))
            } else {
                String::new()
            },
            esc(&c.summary)
        );
        at_re_html(h, &c.at_re);
        h.push_str("</details>\n");
    }
}
