//! The sweep's and the report's charts, each drawn from plain data that is
//! also written as the CSV behind it: speed against accuracy with its Pareto
//! front, stability maps (the paper's Figure 4 is in `figure4.rs`).

use std::collections::BTreeMap;
use std::fmt::Write as _;

use anyhow::Result;
use plotters::coord::Shift;
use plotters::prelude::*;

use super::{chart_err, LogAxis};
use crate::format::fmt_num;
use crate::problem::cost::DtLimit;
use crate::solver::FailureKind;
use crate::sweep::store::csv_field;
use crate::sweep::{Class, Row};

/// Colour of an outcome class.
pub fn class_color(c: Class) -> RGBColor {
    match c {
        Class::Ok => RGBColor(46, 160, 67),
        Class::Inaccurate => RGBColor(230, 159, 0),
        Class::OverCompressed => RGBColor(148, 103, 189),
        Class::Failed => RGBColor(214, 39, 40),
        Class::Interrupted => RGBColor(127, 127, 127),
    }
}

/// Hex form of a class colour, for HTML.
pub fn class_hex(c: Class) -> String {
    let RGBColor(r, g, b) = class_color(c);
    format!("#{r:02x}{g:02x}{b:02x}")
}

pub(super) fn series_color(k: usize) -> RGBColor {
    const C: [RGBColor; 10] = [
        RGBColor(31, 119, 180),
        RGBColor(255, 127, 14),
        RGBColor(44, 160, 44),
        RGBColor(214, 39, 40),
        RGBColor(148, 103, 189),
        RGBColor(140, 86, 75),
        RGBColor(227, 119, 194),
        RGBColor(127, 127, 127),
        RGBColor(188, 189, 34),
        RGBColor(23, 190, 207),
    ];
    C[k % C.len()]
}

/// Range of positive finite values, widened by `pad` (a factor) on a log axis.
pub(super) fn log_range(values: impl Iterator<Item = f64>, pad: f64) -> (f64, f64) {
    let (lo, hi) = values
        .filter(|v| *v > 0.0 && v.is_finite())
        .fold((f64::INFINITY, 0.0f64), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    if lo > hi {
        (0.1, 10.0)
    } else if lo == hi {
        (lo / pad / 2.0, hi * pad * 2.0)
    } else {
        (lo / pad, hi * pad)
    }
}

/// A legend entry's mark.
#[derive(Debug, Clone, Copy)]
pub(super) enum Mark {
    Square(RGBColor),
    Line(RGBColor, u32),
    Dot(RGBColor),
    Ring(RGBColor),
    Triangle(RGBColor),
    Cross(RGBColor),
    /// A heading: no mark.
    Heading,
}

/// A legend in its own column beside the plot, so it never covers data.
pub(super) fn draw_legend(
    area: &DrawingArea<SVGBackend, Shift>,
    entries: &[(Mark, String)],
) -> Result<()> {
    let font = ("sans-serif", 12).into_font();
    let bold = ("sans-serif", 12).into_font().style(FontStyle::Bold);
    let x = 8;
    for (k, (mark, text)) in entries.iter().enumerate() {
        let y = 40 + 19 * k as i32;
        let (cx, cy) = (x + 8, y);
        match *mark {
            Mark::Square(c) => area.draw(&Rectangle::new(
                [(x + 2, cy - 6), (x + 14, cy + 6)],
                c.filled(),
            )),
            Mark::Line(c, w) => area.draw(&PathElement::new(
                vec![(x, cy), (x + 18, cy)],
                c.stroke_width(w),
            )),
            Mark::Dot(c) => area.draw(&Circle::new((cx, cy), 4, c.filled())),
            Mark::Ring(c) => area.draw(&Circle::new((cx, cy), 6, c.stroke_width(1))),
            Mark::Triangle(c) => area.draw(&TriangleMarker::new((cx, cy), 5, c.filled())),
            Mark::Cross(c) => area.draw(&Cross::new((cx, cy), 4, c.stroke_width(2))),
            Mark::Heading => Ok(()),
        }
        .map_err(chart_err)?;
        let (tx, f) = match mark {
            Mark::Heading => (x, bold.clone()),
            _ => (x + 26, font.clone()),
        };
        area.draw(&Text::new(text.clone(), (tx, cy - 7), f))
            .map_err(chart_err)?;
    }
    Ok(())
}

// ---------------------------------------------------------------- Pareto

/// For points (cost, error), both to be small: `true` for the points no other
/// point beats, i.e. none has cost <= and error <= with one of them strictly
/// smaller. Points with a NaN coordinate are never on the front.
pub fn pareto_flags(points: &[(f64, f64)]) -> Vec<bool> {
    points
        .iter()
        .map(|&(c, e)| {
            !c.is_nan()
                && !e.is_nan()
                && !points
                    .iter()
                    .any(|&(c2, e2)| c2 <= c && e2 <= e && (c2 < c || e2 < e))
        })
        .collect()
}

// ---------------------------------------------------------------- speed

/// The machine-free or the wall-clock cost of a run.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Cost {
    WallTime,
    ParticleSteps,
}

impl Cost {
    pub fn label(self) -> &'static str {
        match self {
            Cost::WallTime => "wall time (s)",
            Cost::ParticleSteps => "particle-steps",
        }
    }
}

/// One run on the speed-accuracy chart.
#[derive(Debug, Clone)]
pub struct SpeedPoint {
    pub kernel: String,
    /// The c0 as gridded (`derived`, `rule10`, `table2`, ...).
    pub rule: String,
    pub n: u32,
    pub re: f64,
    pub c0_over_u: f64,
    /// Worst L_inf error / U over the run.
    pub linf: f64,
    pub wall_s: f64,
    pub particle_steps: f64,
    /// The time-step limit that bound most steps.
    pub dt_limit_dominant: Option<DtLimit>,
    pub class: Class,
    /// On the Pareto front of its Re, by wall time and by particle-steps.
    pub pareto_wall: bool,
    pub pareto_work: bool,
}

impl SpeedPoint {
    /// The dominant limit's name, empty when unknown.
    fn limit_name(&self) -> &'static str {
        self.dt_limit_dominant.map_or("", DtLimit::name)
    }

    pub fn series(&self) -> String {
        format!("{} {}", self.kernel, self.rule)
    }
    fn cost(&self, cost: Cost) -> f64 {
        match cost {
            Cost::WallTime => self.wall_s.max(1e-4),
            Cost::ParticleSteps => self.particle_steps,
        }
    }
}

/// The runs that have an error to show (every class but `failed`), with
/// their Pareto flags computed per Re.
pub fn speed_points(rows: &[Row]) -> Vec<SpeedPoint> {
    let mut pts: Vec<SpeedPoint> = rows
        .iter()
        .filter(|r| r.class != Class::Failed && r.linf_max.is_finite() && r.steps > 0)
        .map(|r| SpeedPoint {
            kernel: r.kernel.clone(),
            rule: r.c0_spec.clone(),
            n: r.n,
            re: r.re,
            c0_over_u: r.c0_over_u,
            linf: r.linf_max.max(1e-12),
            wall_s: r.wall_s,
            particle_steps: r.particle_steps,
            dt_limit_dominant: r.dt_limit_dominant,
            class: r.class,
            pareto_wall: false,
            pareto_work: false,
        })
        .collect();
    let res: Vec<f64> = distinct(pts.iter().map(|p| p.re));
    for re in res {
        let idx: Vec<usize> = (0..pts.len()).filter(|&i| pts[i].re == re).collect();
        for cost in [Cost::WallTime, Cost::ParticleSteps] {
            let xy: Vec<(f64, f64)> = idx
                .iter()
                .map(|&i| (pts[i].cost(cost), pts[i].linf))
                .collect();
            for (&i, f) in idx.iter().zip(pareto_flags(&xy)) {
                match cost {
                    Cost::WallTime => pts[i].pareto_wall = f,
                    Cost::ParticleSteps => pts[i].pareto_work = f,
                }
            }
        }
    }
    pts
}

/// Sorted distinct values.
fn distinct(v: impl Iterator<Item = f64>) -> Vec<f64> {
    let mut v: Vec<f64> = v.collect();
    v.sort_by(f64::total_cmp);
    v.dedup();
    v
}

pub fn speed_csv(points: &[SpeedPoint]) -> String {
    let mut out = String::from(
        "kernel,c0_rule,n,re,c0_over_u,linf_max,wall_s,particle_steps,dt_limit,class,pareto_wall,pareto_particle_steps\n",
    );
    for p in points {
        let _ = writeln!(
            out,
            "{},{},{},{},{},{},{},{},{},{},{},{}",
            csv_field(&p.kernel),
            csv_field(&p.rule),
            p.n,
            p.re,
            p.c0_over_u,
            p.linf,
            p.wall_s,
            p.particle_steps,
            p.limit_name(),
            p.class,
            p.pareto_wall,
            p.pareto_work
        );
    }
    out
}

/// Error against cost, log-log, one panel per Re: a colour per kernel and c0
/// rule (points joined in order of N and labelled by N), the marker's shape
/// the time-step limit that bound (circle viscous, triangle CFL, cross
/// force), the Pareto front ringed and joined in black.
pub fn speed_svg(points: &[SpeedPoint], cost: Cost) -> Result<String> {
    let res = distinct(points.iter().map(|p| p.re));
    let panels = res.len().max(1);
    let series: Vec<String> = {
        let mut s: Vec<String> = points.iter().map(SpeedPoint::series).collect();
        s.sort();
        s.dedup();
        s
    };
    let (xlo, xhi) = log_range(points.iter().map(|p| p.cost(cost)), 1.6);
    let (ylo, yhi) = log_range(points.iter().map(|p| p.linf), 1.6);
    let mut svg = String::new();
    {
        let plots = 600 * panels as u32;
        let root = SVGBackend::with_string(&mut svg, (plots + 250, 600)).into_drawing_area();
        root.fill(&WHITE).map_err(chart_err)?;
        let (left, legend) = root.split_horizontally(plots);
        let areas = left.split_evenly((1, panels));
        for (k, area) in areas.iter().enumerate() {
            let re = res.get(k).copied().unwrap_or(f64::NAN);
            let here: Vec<&SpeedPoint> = points.iter().filter(|p| p.re == re).collect();
            speed_panel(area, &here, &series, cost, re, (xlo, xhi), (ylo, yhi))?;
        }
        let grey = RGBColor(90, 90, 90);
        let mut entries: Vec<(Mark, String)> = vec![(Mark::Heading, "kernel, c0 rule".into())];
        entries.extend(
            series
                .iter()
                .enumerate()
                .map(|(k, name)| (Mark::Line(series_color(k), 3), name.clone())),
        );
        entries.extend([
            (Mark::Heading, String::new()),
            (Mark::Heading, "time-step limit that bound".into()),
            (Mark::Dot(grey), "viscous".into()),
            (Mark::Triangle(grey), "CFL".into()),
            (Mark::Cross(grey), "force".into()),
            (Mark::Heading, String::new()),
            (Mark::Ring(BLACK), "Pareto front (per Re)".into()),
            (Mark::Heading, "labels: N (layers)".into()),
        ]);
        draw_legend(&legend, &entries)?;
        root.present().map_err(chart_err)?;
    }
    Ok(svg)
}

fn speed_panel(
    area: &DrawingArea<SVGBackend, Shift>,
    points: &[&SpeedPoint],
    series: &[String],
    cost: Cost,
    re: f64,
    (xlo, xhi): (f64, f64),
    (ylo, yhi): (f64, f64),
) -> Result<()> {
    let limits: Vec<&str> = {
        let mut l: Vec<&str> = points.iter().map(|p| p.limit_name()).collect();
        l.sort();
        l.dedup();
        l
    };
    let caption = format!(
        "Re = {}: L_inf error vs {} (dt bound by: {})",
        fmt_num(re),
        cost.label(),
        if limits.is_empty() {
            "-".to_string()
        } else {
            limits.join(", ")
        }
    );
    let (x_coord, x_axis) = LogAxis::new(xlo, xhi, 8);
    let (y_coord, y_axis) = LogAxis::new(ylo, yhi, 8);
    let mut chart = ChartBuilder::on(area)
        .caption(caption, ("sans-serif", 16))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(60)
        .build_cartesian_2d(x_coord, y_coord)
        .map_err(chart_err)?;
    chart
        .configure_mesh()
        .x_desc(cost.label())
        .y_desc("worst L_inf error / U")
        .x_label_formatter(&|v| x_axis.label(v))
        .y_label_formatter(&|v| y_axis.label(v))
        .draw()
        .map_err(chart_err)?;

    // The Pareto front first, under the points.
    let mut front: Vec<(f64, f64)> = points
        .iter()
        .filter(|p| match cost {
            Cost::WallTime => p.pareto_wall,
            Cost::ParticleSteps => p.pareto_work,
        })
        .map(|p| (p.cost(cost), p.linf))
        .collect();
    front.sort_by(|a, b| a.0.total_cmp(&b.0));
    chart
        .draw_series(LineSeries::new(front.clone(), BLACK.stroke_width(1)))
        .map_err(chart_err)?;
    chart
        .draw_series(
            front
                .iter()
                .map(|&at| Circle::new(at, 10, BLACK.stroke_width(1))),
        )
        .map_err(chart_err)?;

    for (si, name) in series.iter().enumerate() {
        let color = series_color(si);
        let mut mine: Vec<&&SpeedPoint> = points.iter().filter(|p| &p.series() == name).collect();
        if mine.is_empty() {
            continue;
        }
        mine.sort_by_key(|p| p.n);
        let line: Vec<(f64, f64)> = mine.iter().map(|p| (p.cost(cost), p.linf)).collect();
        chart
            .draw_series(LineSeries::new(line, color.stroke_width(1)))
            .map_err(chart_err)?;
        for p in &mine {
            let at = (p.cost(cost), p.linf);
            let label = Text::new(format!("{}", p.n), (7, -14), ("sans-serif", 11).into_font());
            match p.dt_limit_dominant {
                Some(DtLimit::Viscous) => chart
                    .draw_series(std::iter::once(
                        EmptyElement::at(at) + Circle::new((0, 0), 5, color.filled()) + label,
                    ))
                    .map_err(chart_err)?,
                Some(DtLimit::Cfl) => chart
                    .draw_series(std::iter::once(
                        EmptyElement::at(at)
                            + TriangleMarker::new((0, 0), 6, color.filled())
                            + label,
                    ))
                    .map_err(chart_err)?,
                _ => chart
                    .draw_series(std::iter::once(
                        EmptyElement::at(at) + Cross::new((0, 0), 5, color.stroke_width(2)) + label,
                    ))
                    .map_err(chart_err)?,
            };
        }
    }
    Ok(())
}

// ---------------------------------------------------------------- maps

/// One grid point of a stability map.
#[derive(Debug, Clone)]
pub struct MapCell {
    pub re: f64,
    pub c0_over_u: f64,
    pub class: Class,
    pub failure_kind: Option<FailureKind>,
    pub linf_max: f64,
    pub max_eps: f64,
    pub id: String,
}

/// A line on a map: c0/U against Re for one rule, in pieces where it is
/// positive; a rule with no piece is listed as having no positive root.
#[derive(Debug, Clone)]
pub struct MapLine {
    pub label: String,
    pub pieces: Vec<Vec<(f64, f64)>>,
}

/// A marked value on a map (the empirical c0): (label, Re, c0/U).
pub type MapMark = (String, f64, f64);

pub fn map_csv(kernel: &str, cells: &[MapCell]) -> String {
    let mut out = String::from("kernel,re,c0_over_u,class,failure_kind,linf_max,max_eps,id\n");
    for c in cells {
        let _ = writeln!(
            out,
            "{},{},{},{},{},{},{},{}",
            csv_field(kernel),
            c.re,
            c.c0_over_u,
            c.class,
            c.failure_kind.map_or("", FailureKind::name),
            c.linf_max,
            c.max_eps,
            csv_field(&c.id)
        );
    }
    out
}

pub fn map_lines_csv(kernel: &str, lines: &[MapLine]) -> String {
    let mut out = String::from("kernel,line,piece,re,c0_over_u\n");
    for l in lines {
        if l.pieces.is_empty() {
            let _ = writeln!(out, "{},{},,,", csv_field(kernel), csv_field(&l.label));
        }
        for (k, piece) in l.pieces.iter().enumerate() {
            for (re, c) in piece {
                let _ = writeln!(
                    out,
                    "{},{},{k},{re},{c}",
                    csv_field(kernel),
                    csv_field(&l.label)
                );
            }
        }
    }
    out
}

/// Outcome class (colour) over c0/U (log) and Re (log), with the rules'
/// lines and the marks.
pub fn map_svg(
    title: &str,
    cells: &[MapCell],
    lines: &[MapLine],
    marks: &[MapMark],
) -> Result<String> {
    let (xlo, xhi) = log_range(
        cells
            .iter()
            .map(|c| c.c0_over_u)
            .chain(marks.iter().map(|m| m.2)),
        1.8,
    );
    let (ylo, yhi) = log_range(cells.iter().map(|c| c.re), 1.5);
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (1020, 560)).into_drawing_area();
        root.fill(&WHITE).map_err(chart_err)?;
        let (plot, legend) = root.split_horizontally(760);
        let (x_coord, x_axis) = LogAxis::new(xlo, xhi, 8);
        let (y_coord, y_axis) = LogAxis::new(ylo, yhi, 8);
        let mut chart = ChartBuilder::on(&plot)
            .caption(title, ("sans-serif", 16))
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(55)
            .build_cartesian_2d(x_coord, y_coord)
            .map_err(chart_err)?;
        chart
            .configure_mesh()
            .x_desc("c0 / U")
            .y_desc("Re")
            .light_line_style(RGBColor(245, 245, 245))
            .x_label_formatter(&|v| x_axis.label(v))
            .y_label_formatter(&|v| y_axis.label(v))
            .draw()
            .map_err(chart_err)?;
        for class in Class::ALL {
            let color = class_color(class);
            chart
                .draw_series(cells.iter().filter(|c| c.class == class).map(|c| {
                    EmptyElement::at((c.c0_over_u, c.re))
                        + Rectangle::new([(-9, -9), (9, 9)], color.filled())
                }))
                .map_err(chart_err)?;
        }
        let mut entries: Vec<(Mark, String)> = vec![(Mark::Heading, "outcome".into())];
        entries.extend(
            Class::ALL
                .iter()
                .map(|&c| (Mark::Square(class_color(c)), c.name().to_string())),
        );
        entries.push((Mark::Heading, String::new()));
        entries.push((Mark::Heading, "c0 by rule".into()));
        let inside = |p: &(f64, f64)| p.0 >= xlo && p.0 <= xhi;
        for (k, line) in lines.iter().enumerate() {
            let color = series_color(k);
            if line.pieces.is_empty() {
                entries.push((
                    Mark::Cross(color),
                    format!("{}: no positive root", line.label),
                ));
                continue;
            }
            entries.push((Mark::Line(color, 3), line.label.clone()));
            for piece in &line.pieces {
                let pts: Vec<(f64, f64)> = piece
                    .iter()
                    .map(|&(re, c)| (c, re))
                    .filter(inside)
                    .collect();
                chart
                    .draw_series(LineSeries::new(pts, color.stroke_width(3)))
                    .map_err(chart_err)?;
            }
        }
        if !marks.is_empty() {
            entries.push((Mark::Heading, String::new()));
            entries.push((Mark::Ring(BLACK), "empirical c0 (smallest ok)".into()));
        }
        for (label, re, c) in marks {
            chart
                .draw_series(std::iter::once(
                    EmptyElement::at((*c, *re))
                        + Circle::new((0, 0), 7, BLACK.stroke_width(2))
                        + Text::new(label.clone(), (9, 4), ("sans-serif", 12).into_font()),
                ))
                .map_err(chart_err)?;
        }
        draw_legend(&legend, &entries)?;
        root.present().map_err(chart_err)?;
    }
    Ok(svg)
}

/// Group rows by kernel, in kernel order of first appearance.
pub fn by_kernel(rows: &[Row]) -> BTreeMap<String, Vec<&Row>> {
    let mut m: BTreeMap<String, Vec<&Row>> = BTreeMap::new();
    for r in rows {
        m.entry(r.kernel.clone()).or_default().push(r);
    }
    m
}
