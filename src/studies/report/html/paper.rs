//! The page's sections from the exact derivation: Tables 1 and 2 beside
//! the print, and the same analysis on every other case's discretisation.

use std::fmt::Write as _;

use super::{esc, mark, num, sci};
use crate::kernel::KernelInfo;
use crate::report::plan::CaseDiscretisation;
use crate::report::tables::EpsCompare;
use crate::report::ReportData;

/// Table 1: eps beside the print.
pub(super) fn table1(h: &mut String, d: &ReportData) {
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
}

/// Table 2: the c0 formula's coefficients beside the print.
pub(super) fn table2(h: &mut String, d: &ReportData) {
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
            "<p>Where our default model and the print differ at the printed precision: {}. See docs/derivation.md, \"Where the print differs\".</p>",
            esc(&t2_differs.join("; "))
        );
    }
}

/// The same analysis as Tables 1 and 2 for a case's discretisation, from
/// the generated constants: eps at 0 and 0.5 T, its true extremes and
/// where, its mean, and the derived c0 coefficients at the configuration
/// the search found the maximum in (or the "no c0" fact).
pub(super) fn case_section(h: &mut String, d: &ReportData, case: CaseDiscretisation) {
    let c = &d.config.case[case.index];
    let infos: &[&'static KernelInfo] = &d.infos;
    let _ = writeln!(
        h,
        "<h2 id=\"{}\">The {}: eps and the derived c0</h2>",
        c.id,
        esc(c.label.as_deref().unwrap_or(&c.id))
    );
    let _ = writeln!(h, "<p>The analysis of Tables 1 and 2 for {}; every row names it. From the exact derivation (<code>generated/</code>); the c0 models are derived where the search found the maximum compaction, at the time given.</p>", esc(c.about.as_deref().unwrap_or_default()));
    let not_generated = format!(
        "not generated at lattice = {}, h = {} d",
        c.lattice.name(),
        c.h_over_d
    );
    let generated_on = |info: &'static KernelInfo| case.of(info).map(|(_, on)| on);
    h.push_str("<table><tr><th class=\"l\">kernel</th><th class=\"l\">discretisation</th><th>eps(0)</th><th>eps(0.5T)</th><th>max eps</th><th>at t/T</th><th>min eps</th><th>at t/T</th><th>mean eps</th></tr>\n");
    for info in infos {
        let Some(disc) = generated_on(info) else {
            let _ = writeln!(h, "<tr><td class=\"l\">{}</td><td class=\"l\" colspan=\"8\">{not_generated}</td></tr>", esc(info.name));
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
        let Some(disc) = generated_on(info) else {
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
