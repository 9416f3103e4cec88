//! The ordered lattice's growth map: per kernel and discretisation, the
//! leading growth rate of perturbations of the perfect sheared lattice
//! (`shearsph stability`) over c0 / U (columns) at each Re (row groups),
//! each cell shaded by it: red where perturbations grow (the order is lost,
//! and the paper's analysis holds only until then), blue where every one
//! decays.

use std::fmt::Write as _;

use super::{esc, num};
use crate::report::stability::GrowthCell;
use crate::report::ReportData;

/// A cell's background: red growing, blue decaying, deeper with |e-folds
/// per period| up to 10; grey without a rate.
fn shade(c: &GrowthCell) -> String {
    match c.growth_rate_per_period {
        None => "#ddd".into(),
        Some(r) => {
            let depth = (r.abs() / 10.0).min(1.0);
            let light = (235.0 - 120.0 * depth) as u8;
            if r > 0.0 {
                format!("rgb(250,{light},{light})")
            } else {
                format!("rgb({light},{light},250)")
            }
        }
    }
}

pub(super) fn growth(h: &mut String, d: &ReportData) {
    let g = &d.config.growth;
    if d.growth.is_empty() {
        return;
    }
    let _ = write!(
        h,
        "<h2 id=\"growth\">The ordered lattice's growth map</h2>\n<p>Per kernel and discretisation at N = {}, alpha = {}: the leading growth rate per unit time (U = d = 1) of perturbations of the perfect sheared lattice in its steady profile, over every Bloch sector of a strip 2B wide (<code>shearsph stability</code>, docs/stability.md; each perturbation followed over t = {}), and below it the e-folds per lattice period T = d N² / U. Red: a perturbation grows, so any run's lattice disorders (the time a 1e-4 d jitter takes is in the cell's title); blue: every one decays, the ordered state the paper analyses holds. The data: <a href=\"growth_map.json\">growth_map.json</a>.</p>\n",
        d.config.maps.n,
        num(d.config.maps.alpha),
        num(g.horizon)
    );
    let mut groups: Vec<(&str, &str)> = Vec::new();
    for c in &d.growth {
        if !groups.contains(&(c.kernel.as_str(), c.discretisation.as_str())) {
            groups.push((c.kernel.as_str(), c.discretisation.as_str()));
        }
    }
    h.push_str(
        "<table><tr><th class=\"l\">kernel</th><th class=\"l\">discretisation</th><th>Re</th>",
    );
    for c in &g.c0_over_u {
        let _ = write!(h, "<th>{} U</th>", num(*c));
    }
    h.push_str("</tr>\n");
    for (kernel, disc) in groups {
        for &re in &g.re {
            let _ = write!(
                h,
                "<tr><td class=\"l\">{}</td><td class=\"l\">{}</td><td>{}</td>",
                esc(kernel),
                esc(disc),
                num(re)
            );
            for &c0 in &g.c0_over_u {
                let cell = d.growth.iter().find(|c| {
                    c.kernel == kernel
                        && c.discretisation == disc
                        && c.re == re
                        && c.c0_over_u == c0
                });
                match cell {
                    None => h.push_str("<td></td>"),
                    Some(c) => {
                        let title = match (c.t_disorder, &c.note) {
                            (_, Some(n)) => n.clone(),
                            (Some(t), None) => {
                                format!("a 1e-4 d jitter disorders it by t = {}", num(t))
                            }
                            (None, None) => "no perturbation grows".into(),
                        };
                        let text = match (c.growth_rate, c.growth_rate_per_period) {
                            (Some(r), Some(p)) => {
                                format!("{}<br><small>{} / T</small>", num(r), num(p))
                            }
                            _ => "failed".into(),
                        };
                        let _ = write!(
                            h,
                            "<td style=\"background:{}\" title=\"{}\">{}</td>",
                            shade(c),
                            esc(&title),
                            text
                        );
                    }
                }
            }
            h.push_str("</tr>\n");
        }
    }
    h.push_str("</table>\n");
}
