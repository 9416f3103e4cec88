//! One run's charts: the velocity profile against the analytic one, and the
//! time series of the error and the compaction.

use anyhow::Result;
use plotters::coord::ranged1d::AsRangedCoord;
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;

use super::{chart_err, LogAxis};
use crate::output::StagedSet;
use crate::solver::{Outcome, RunResult, Sample};

const SIZE: (u32, u32) = (900, 650);

/// u / U against y / B: the SPH layer means at a few output times (points)
/// and the analytic reference at the same times (lines).
pub fn profile_svg(r: &RunResult) -> Result<String> {
    let flow = r.problem.flow;
    let from_rest = r.problem.initial == crate::config::Initial::Rest;
    // Up to five samples, spread over the run, always the last.
    let n = r.samples.len();
    let mut picks: Vec<usize> = (1..=5).map(|k| k * (n - 1) / 5).collect();
    picks.dedup();
    let u_max = r
        .samples
        .iter()
        .flat_map(|s| s.profile.iter().map(|l| l.u.abs()))
        .filter(|u| u.is_finite())
        .fold(flow.u, f64::max);
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, SIZE).into_drawing_area();
        root.fill(&WHITE).map_err(chart_err)?;
        let mut title = format!(
            "{} N = {} Re = {:.4} c0 = {:.4} U ({}) alpha = {}",
            r.kernel,
            r.problem.lattice.n_layers,
            r.problem.re,
            r.problem.c0 / flow.u,
            r.problem.c0_rule,
            r.problem.alpha
        );
        match &r.outcome {
            Outcome::Ok => {}
            Outcome::Failed { t, .. } => title.push_str(&format!(": FAILED at t = {t:.4}")),
            Outcome::Interrupted { t, .. } => {
                title.push_str(&format!(": INTERRUPTED at t = {t:.4}"))
            }
        }
        let mut chart = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 20))
            .margin(15)
            .x_label_area_size(45)
            .y_label_area_size(55)
            .build_cartesian_2d(0.0..1.05 * u_max / flow.u, -1.0..1.0)
            .map_err(chart_err)?;
        chart
            .configure_mesh()
            .x_desc("u / U")
            .y_desc("y / B")
            .draw()
            .map_err(chart_err)?;
        for (k, &i) in picks.iter().enumerate() {
            let s = &r.samples[i];
            let color = Palette99::pick(k).to_rgba();
            let curve = (0..=200).map(|m| {
                let y = -flow.b + 2.0 * flow.b * m as f64 / 200.0;
                let u = if from_rest {
                    flow.startup(y, s.t)
                } else {
                    flow.steady(y)
                };
                (u / flow.u, y / flow.b)
            });
            chart
                .draw_series(LineSeries::new(curve, color.stroke_width(2)))
                .map_err(chart_err)?
                .label(format!("t = {:.4}", s.t))
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2))
                });
            let points = s
                .profile
                .iter()
                .filter(|l| l.u.is_finite() && l.y.is_finite())
                .map(|l| Circle::new((l.u / flow.u, l.y / flow.b), 3, color.filled()));
            chart.draw_series(points).map_err(chart_err)?;
        }
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperLeft)
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .draw()
            .map_err(chart_err)?;
        root.present().map_err(chart_err)?;
    }
    Ok(svg)
}

/// Errors (log scale), compaction and transverse pulsation over time.
pub fn timeseries_svg(r: &RunResult) -> Result<String> {
    let s = &r.samples;
    let t_max = s.last().map_or(1.0, |l| l.t).max(1e-12);
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (SIZE.0, 900)).into_drawing_area();
        root.fill(&WHITE).map_err(chart_err)?;
        let panels = root.split_evenly((3, 1));
        error_panel(&panels[0], s, t_max)?;
        eps_panel(&panels[1], s, t_max)?;
        pulsation_panel(&panels[2], s, t_max, r.problem.flow.u)?;
        root.present().map_err(chart_err)?;
    }
    Ok(svg)
}

/// Stage the run's charts, `profile.svg` and `timeseries.svg`, in `set`.
pub fn stage_charts(set: &StagedSet, r: &RunResult) -> Result<()> {
    set.put("profile.svg", profile_svg(r)?.as_bytes())?;
    set.put("timeseries.svg", timeseries_svg(r)?.as_bytes())
}

type Panel<'a> = DrawingArea<SVGBackend<'a>, Shift>;

/// `Some(v)` when `v` is finite.
fn finite(v: f64) -> Option<f64> {
    if v.is_finite() {
        Some(v)
    } else {
        None
    }
}

/// A panel's chart: time across, `y` up.
fn panel_chart<'a, 'b, Y: AsRangedCoord<Value = f64>>(
    area: &'a Panel<'b>,
    caption: &str,
    t_max: f64,
    y: Y,
) -> Result<ChartContext<'a, SVGBackend<'b>, Cartesian2d<RangedCoordf64, Y::CoordDescType>>> {
    ChartBuilder::on(area)
        .caption(caption, ("sans-serif", 18))
        .margin(10)
        .x_label_area_size(35)
        .y_label_area_size(60)
        .build_cartesian_2d(0.0..t_max, y)
        .map_err(chart_err)
}

/// A line's points, its legend entry and its colour.
type Line<'n> = (Vec<(f64, f64)>, &'n str, RGBColor);

/// Lines with a legend entry each, and the legend.
fn labelled_lines<'a, 'b: 'a, CT: CoordTranslate<From = (f64, f64)>>(
    chart: &mut ChartContext<'a, SVGBackend<'b>, CT>,
    lines: [Line; 2],
) -> Result<()> {
    for (pts, name, color) in lines {
        chart
            .draw_series(LineSeries::new(pts, color.stroke_width(2)))
            .map_err(chart_err)?
            .label(name)
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2))
            });
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()
        .map_err(chart_err)
}

/// The errors, on a log scale (the error at t = 0 is zero: skipped).
fn error_panel(area: &Panel, s: &[Sample], t_max: f64) -> Result<()> {
    let err_points = |f: fn(&Sample) -> f64| -> Vec<(f64, f64)> {
        s.iter()
            .map(|x| (x.t, f(x)))
            .filter(|p| p.1 > 0.0 && p.1.is_finite())
            .collect()
    };
    let linf = err_points(|x| x.linf_rel_err);
    let l2 = err_points(|x| x.l2_rel_err);
    let (lo, hi) = linf
        .iter()
        .chain(&l2)
        .fold((f64::INFINITY, 0.0f64), |(lo, hi), p| {
            (lo.min(p.1), hi.max(p.1))
        });
    let (lo, hi) = if lo < hi {
        (lo / 2.0, hi * 2.0)
    } else {
        (1e-6, 1.0)
    };
    let (y_coord, y_axis) = LogAxis::new(lo, hi, 8);
    let mut chart = panel_chart(area, "velocity error / U (layer means)", t_max, y_coord)?;
    chart
        .configure_mesh()
        .x_desc("t")
        .y_label_formatter(&|v| y_axis.label(v))
        .draw()
        .map_err(chart_err)?;
    labelled_lines(&mut chart, [(linf, "L_inf", RED), (l2, "L2", BLUE)])
}

/// The compaction, largest and mean.
fn eps_panel(area: &Panel, s: &[Sample], t_max: f64) -> Result<()> {
    let eps: Vec<(f64, f64, f64)> = s
        .iter()
        .filter_map(|x| Some((x.t, finite(x.max_eps)?, finite(x.mean_eps)?)))
        .collect();
    let (lo, hi) = eps
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), e| {
            (lo.min(e.2).min(e.1), hi.max(e.1))
        });
    let pad = ((hi - lo) * 0.1).max(1e-6);
    let (lo, hi) = if lo <= hi {
        (lo - pad, hi + pad)
    } else {
        (-1.0, 1.0)
    };
    let mut chart = panel_chart(area, "compaction eps = rho/rho0 - 1 (fluid)", t_max, lo..hi)?;
    chart
        .configure_mesh()
        .x_desc("t")
        .draw()
        .map_err(chart_err)?;
    let max: Vec<(f64, f64)> = eps.iter().map(|e| (e.0, e.1)).collect();
    let mean: Vec<(f64, f64)> = eps.iter().map(|e| (e.0, e.2)).collect();
    labelled_lines(&mut chart, [(max, "max", RED), (mean, "mean", BLUE)])
}

/// The transverse pulsation, RMS v / U.
fn pulsation_panel(area: &Panel, s: &[Sample], t_max: f64, u: f64) -> Result<()> {
    let v: Vec<(f64, f64)> = s
        .iter()
        .filter_map(|x| Some((x.t, finite(x.rms_v / u)?)))
        .collect();
    let hi = v.iter().map(|p| p.1).fold(0.0f64, f64::max).max(1e-12) * 1.1;
    let mut chart = panel_chart(area, "RMS transverse velocity / U", t_max, 0.0..hi)?;
    chart
        .configure_mesh()
        .x_desc("t")
        .draw()
        .map_err(chart_err)?;
    chart
        .draw_series(LineSeries::new(v, GREEN.stroke_width(2)))
        .map_err(chart_err)?;
    Ok(())
}
