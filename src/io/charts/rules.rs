//! The report's first picture, per kernel: c0 / U by every rule, each
//! marked by the class of its runs on the perfect and on the perturbed
//! lattice, against the empirical band (the c0 / U over which runs were
//! ok) of each, one panel per Re.

use std::fmt::Write as _;

use anyhow::Result;
use plotters::prelude::*;

use super::sweep::{class_color, draw_legend, log_range, Mark};
use super::{chart_err, LogAxis};
use crate::sweep::store::csv_field;
use crate::sweep::Class;

/// One rule in a panel: its c0 / U (None: the rule gives none here) and
/// the class of its run on each start (None: not run).
#[derive(Debug, Clone)]
pub struct RuleMark {
    pub label: String,
    pub c0_over_u: Option<f64>,
    pub perfect: Option<Class>,
    pub perturbed: Option<Class>,
}

/// The c0 / U range over which the runs were ok (the smallest ok c0 to the
/// top of the ok block it starts).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Band {
    pub lo: f64,
    pub hi: f64,
}

/// One panel: the rules at one scene (one Re) and the two bands.
#[derive(Debug, Clone)]
pub struct RulesPanel {
    pub re: f64,
    pub rules: Vec<RuleMark>,
    pub perfect: Option<Band>,
    pub perturbed: Option<Band>,
}

const BAND_PERFECT: RGBAColor = RGBAColor(46, 160, 67, 0.13);
const BAND_PERTURBED: RGBAColor = RGBAColor(46, 160, 67, 0.33);
const NOT_RUN: RGBColor = RGBColor(170, 170, 170);

/// The panels as a table: one line per panel and rule, the bands on each.
pub fn rules_csv(kernel: &str, panels: &[RulesPanel]) -> String {
    let mut out = String::from(
        "kernel,re,rule,c0_over_u,class_perfect,class_perturbed,band_perfect_lo,band_perfect_hi,band_perturbed_lo,band_perturbed_hi\n",
    );
    let f = |v: Option<f64>| v.map_or(String::new(), |v| v.to_string());
    let c = |v: Option<Class>| v.map_or(String::new(), |v| v.to_string());
    for p in panels {
        for r in &p.rules {
            let _ = writeln!(
                out,
                "{},{},{},{},{},{},{},{},{},{}",
                csv_field(kernel),
                p.re,
                csv_field(&r.label),
                f(r.c0_over_u),
                c(r.perfect),
                c(r.perturbed),
                f(p.perfect.map(|b| b.lo)),
                f(p.perfect.map(|b| b.hi)),
                f(p.perturbed.map(|b| b.lo)),
                f(p.perturbed.map(|b| b.hi)),
            );
        }
    }
    out
}

/// The picture: the rules' names in a column on the left, one panel per
/// Re (c0 / U on a log axis; a dot for the perfect start's class, a
/// triangle below it for the perturbed one's; the bands shaded), the
/// legend on the right. `perturbed` names the perturbation for the legend.
pub fn rules_svg(title: &str, panels: &[RulesPanel], perturbed: &str) -> Result<String> {
    let n = panels
        .iter()
        .map(|p| p.rules.len())
        .max()
        .unwrap_or(0)
        .max(1);
    let (xlo, xhi) = log_range(
        panels.iter().flat_map(|p| {
            p.rules.iter().filter_map(|r| r.c0_over_u).chain(
                [p.perfect, p.perturbed]
                    .into_iter()
                    .flatten()
                    .flat_map(|b| [b.lo, b.hi]),
            )
        }),
        1.6,
    );
    let (width, height) = (1150u32, 90 + 30 * n as u32);
    let (names_w, legend_w) = (190u32, 300u32);
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (width, height)).into_drawing_area();
        root.fill(&WHITE).map_err(chart_err)?;
        let root = root.titled(title, ("sans-serif", 16)).map_err(chart_err)?;
        let (left, legend) = root.split_horizontally(width - legend_w);
        let (names, plots) = left.split_horizontally(names_w);
        let areas = plots.split_evenly((1, panels.len().max(1)));
        let y_of = |i: usize| (n - 1 - i) as f64;
        let mut row_px: Vec<i32> = Vec::new();
        for (area, p) in areas.iter().zip(panels) {
            let (x_coord, x_axis) = LogAxis::new(xlo, xhi, 6);
            let mut chart = ChartBuilder::on(area)
                .caption(
                    format!("Re = {}", crate::format::fmt_num(p.re)),
                    ("sans-serif", 14),
                )
                .margin(8)
                .x_label_area_size(36)
                .y_label_area_size(0)
                .build_cartesian_2d(x_coord, -0.5f64..(n as f64 - 0.5))
                .map_err(chart_err)?;
            chart
                .configure_mesh()
                .x_desc("c0 / U")
                .disable_y_mesh()
                .light_line_style(RGBColor(245, 245, 245))
                .x_label_formatter(&|v| x_axis.label(v))
                .draw()
                .map_err(chart_err)?;
            for (band, color) in [(p.perfect, BAND_PERFECT), (p.perturbed, BAND_PERTURBED)] {
                if let Some(b) = band {
                    chart
                        .draw_series(std::iter::once(Rectangle::new(
                            [(b.lo.max(xlo), -0.5), (b.hi.min(xhi), n as f64 - 0.5)],
                            color.filled(),
                        )))
                        .map_err(chart_err)?;
                }
            }
            for (i, r) in p.rules.iter().enumerate() {
                let Some(c) = r.c0_over_u.filter(|c| *c > 0.0 && c.is_finite()) else {
                    continue;
                };
                let y = y_of(i);
                let color = |k: Option<Class>| k.map_or(NOT_RUN, class_color);
                chart
                    .draw_series([EmptyElement::at((c, y))
                        + Circle::new((0, -5), 5, color(r.perfect).filled())
                        + TriangleMarker::new((0, 6), 5, color(r.perturbed).filled())])
                    .map_err(chart_err)?;
            }
            if row_px.is_empty() {
                row_px = (0..n)
                    .map(|i| chart.backend_coord(&(xlo, y_of(i))).1)
                    .collect();
            }
        }
        // The rules' names, level with their rows (the first panel's).
        let font = ("sans-serif", 12).into_font();
        let labels = panels.first().map(|p| &p.rules[..]).unwrap_or_default();
        let top = names.get_base_pixel().1;
        for (r, y) in labels.iter().zip(&row_px) {
            let text = match r.c0_over_u {
                Some(c) if c > 0.0 && c.is_finite() => r.label.clone(),
                _ => format!("{} (no c0)", r.label),
            };
            names
                .draw(&Text::new(text, (6, y - top - 6), font.clone()))
                .map_err(chart_err)?;
        }
        let mut entries: Vec<(Mark, String)> = vec![(Mark::Heading, "run's class".into())];
        entries.extend(
            Class::ALL
                .iter()
                .map(|&c| (Mark::Square(class_color(c)), c.name().to_string())),
        );
        entries.push((Mark::Square(NOT_RUN), "not run".into()));
        entries.push((Mark::Heading, String::new()));
        entries.push((
            Mark::Dot(RGBColor(60, 60, 60)),
            "ordered: perfect lattice".into(),
        ));
        entries.push((
            Mark::Triangle(RGBColor(60, 60, 60)),
            format!("disordered: {perturbed}"),
        ));
        entries.push((Mark::Heading, String::new()));
        entries.push((Mark::Heading, "ok band (empirical)".into()));
        entries.push((Mark::Square(RGBColor(222, 240, 225)), "ordered".into()));
        entries.push((
            Mark::Square(RGBColor(175, 218, 183)),
            "disordered (the answer)".into(),
        ));
        draw_legend(&legend, &entries)?;
        root.present().map_err(chart_err)?;
    }
    Ok(svg)
}
