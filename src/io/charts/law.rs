//! The law of the minimal c0 (`shearsph law`): c0_min / U against N, one
//! panel per Re, with every rule's c0 and the fitted law.

use anyhow::Result;
use plotters::prelude::*;

use super::sweep::{draw_legend, log_range, series_color, Mark};
use super::{chart_err, LogAxis};
use crate::law::{KernelLaw, Point};

/// One kernel's chart: for each Re a panel of c0 / U against N, the
/// empirical c0_min (dots alpha = 0, triangles alpha > 0; a ring on the
/// axis's floor where no c0 probed was ok), every rule's c0 at the largest
/// alpha as lines, and the fitted law (solid: the largest alpha, dashed: 0).
pub fn law_svg(law: &KernelLaw, points: &[Point]) -> Result<String> {
    let mine: Vec<&Point> = points.iter().filter(|p| p.kernel == law.kernel).collect();
    let mut res: Vec<f64> = mine.iter().map(|p| p.re).collect();
    res.sort_by(f64::total_cmp);
    res.dedup();
    let mut alphas: Vec<f64> = mine.iter().map(|p| p.alpha).collect();
    alphas.sort_by(f64::total_cmp);
    alphas.dedup();
    let a_rule = alphas.last().copied().unwrap_or(0.1);
    let (xlo, xhi) = log_range(mine.iter().map(|p| f64::from(p.n)), 1.15);
    let (ylo, yhi) = log_range(
        mine.iter()
            .filter_map(|p| p.c0_min_over_u)
            .chain(mine.iter().flat_map(|p| p.rules.iter().map(|r| r.1))),
        1.6,
    );
    let rule_names: Vec<String> = mine
        .first()
        .map(|p| p.rules.iter().map(|r| r.0.clone()).collect())
        .unwrap_or_default();
    let panels = res.len().max(1);
    let w = 330 * panels as u32;
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (w + 260, 480)).into_drawing_area();
        root.fill(&WHITE).map_err(chart_err)?;
        let (left, legend) = root.split_horizontally(w);
        let areas = left.split_evenly((1, panels));
        for (area, &re) in areas.iter().zip(&res) {
            let (x_coord, x_axis) = LogAxis::new(xlo, xhi, 6);
            let (y_coord, y_axis) = LogAxis::new(ylo, yhi, 8);
            let mut chart = ChartBuilder::on(area)
                .caption(format!("{}, Re = {re}", law.kernel), ("sans-serif", 15))
                .margin(10)
                .x_label_area_size(36)
                .y_label_area_size(50)
                .build_cartesian_2d(x_coord, y_coord)
                .map_err(chart_err)?;
            chart
                .configure_mesh()
                .x_desc("N")
                .y_desc("c0 / U")
                .light_line_style(RGBColor(245, 245, 245))
                .x_label_formatter(&|v| x_axis.label(v))
                .y_label_formatter(&|v| y_axis.label(v))
                .draw()
                .map_err(chart_err)?;
            let at_re: Vec<&&Point> = mine.iter().filter(|p| p.re == re).collect();
            for (k, name) in rule_names.iter().enumerate() {
                let pts: Vec<(f64, f64)> = at_re
                    .iter()
                    .filter(|p| p.alpha == a_rule)
                    .filter_map(|p| {
                        let c = p.rules.iter().find(|r| &r.0 == name)?.1;
                        (c > 0.0 && c.is_finite()).then_some((f64::from(p.n), c))
                    })
                    .collect();
                chart
                    .draw_series(LineSeries::new(pts, series_color(k).stroke_width(2)))
                    .map_err(chart_err)?;
            }
            for (j, &a) in alphas.iter().enumerate() {
                let solid = a == a_rule;
                let line: Vec<(f64, f64)> = (0..=40)
                    .map(|i| xlo * (xhi / xlo).powf(f64::from(i) / 40.0))
                    .filter_map(|n| law.free_at(n, re, a).map(|c| (n, c)))
                    .filter(|p| p.1 >= ylo && p.1 <= yhi)
                    .collect();
                if solid {
                    chart
                        .draw_series(LineSeries::new(line, BLACK.stroke_width(2)))
                        .map_err(chart_err)?;
                } else {
                    chart
                        .draw_series(DashedLineSeries::new(line, 6, 4, BLACK.stroke_width(1)))
                        .map_err(chart_err)?;
                }
                for p in at_re.iter().filter(|p| p.alpha == a) {
                    let x = f64::from(p.n);
                    let e = match p.c0_min_over_u {
                        Some(c) if j == 0 => {
                            EmptyElement::at((x, c))
                                + Circle::new((0, 0), 5, BLACK.filled()).into_dyn()
                        }
                        Some(c) => {
                            EmptyElement::at((x, c))
                                + TriangleMarker::new((0, 0), 6, RGBColor(90, 90, 90).filled())
                                    .into_dyn()
                        }
                        None => {
                            EmptyElement::at((x, ylo * 1.05))
                                + Circle::new((0, 0), 6, RED.stroke_width(2)).into_dyn()
                        }
                    };
                    chart.draw_series(std::iter::once(e)).map_err(chart_err)?;
                }
            }
        }
        let mut entries: Vec<(Mark, String)> = vec![(Mark::Heading, "empirical c0_min".into())];
        for (j, a) in alphas.iter().enumerate() {
            let m = if j == 0 {
                Mark::Dot(BLACK)
            } else {
                Mark::Triangle(RGBColor(90, 90, 90))
            };
            entries.push((m, format!("alpha = {a}")));
        }
        entries.push((Mark::Ring(RED), "no c0 probed ok".into()));
        entries.push((
            Mark::Line(BLACK, 2),
            format!("fitted law, alpha = {a_rule}"),
        ));
        if alphas.len() > 1 {
            entries.push((
                Mark::Line(BLACK, 1),
                format!("fitted law, alpha = {} (dashed)", alphas[0]),
            ));
        }
        entries.push((Mark::Heading, String::new()));
        entries.push((Mark::Heading, format!("c0 by rule (alpha = {a_rule})")));
        for (k, name) in rule_names.iter().enumerate() {
            entries.push((Mark::Line(series_color(k), 2), name.clone()));
        }
        draw_legend(&legend, &entries)?;
        root.present().map_err(chart_err)?;
    }
    Ok(svg)
}
