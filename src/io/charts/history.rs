//! A run's history in the two regimes: the compaction (the per-frame 99th
//! percentile of eps) and how far the particles have left their lattice
//! (dy_rms), against t, for the perfect lattice and a jittered start at
//! one c0: the relaxation of the jitter, the growth of disorder and the
//! stationary state, the judged window shaded.

use anyhow::Result;
use plotters::prelude::*;

use super::{chart_err, LogAxis};

/// One run's frames: (t, eps_p99, max_eps, dy_rms).
pub struct History<'a> {
    pub label: String,
    pub frames: &'a [[f64; 4]],
    /// The window it was judged on.
    pub window: (f64, f64),
}

const COLOURS: [RGBColor; 4] = [
    RGBColor(50, 90, 200),
    RGBColor(210, 60, 40),
    RGBColor(40, 150, 70),
    RGBColor(150, 60, 170),
];

/// Two panels (eps_p99 above, dy_rms below), log y, one line per run.
pub fn history_svg(title: &str, runs: &[History]) -> Result<String> {
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (900, 650)).into_drawing_area();
        root.fill(&WHITE).map_err(chart_err)?;
        let root = root.titled(title, ("sans-serif", 18)).map_err(chart_err)?;
        let panels = root.split_evenly((2, 1));
        let t_max = runs
            .iter()
            .flat_map(|r| r.frames.iter().map(|f| f[0]))
            .fold(1e-9, f64::max);
        for (k, (area, (col, name, floor))) in panels
            .iter()
            .zip([
                (1usize, "compaction: p99 of eps over the fluid", 1e-6),
                (3, "dy_rms / d: distance from the lattice rows", 1e-8),
            ])
            .enumerate()
        {
            let vals: Vec<f64> = runs
                .iter()
                .flat_map(|r| r.frames.iter().map(move |f| f[col]))
                .filter(|v| v.is_finite() && *v > floor)
                .collect();
            let lo = vals
                .iter()
                .copied()
                .fold(f64::INFINITY, f64::min)
                .max(floor);
            let hi = vals.iter().copied().fold(floor * 10.0, f64::max);
            let (lo, hi) = if lo < hi {
                (lo / 1.5, hi * 1.5)
            } else {
                (floor, 1.0)
            };
            let (y, axis) = LogAxis::new(lo, hi, 6);
            let mut chart = ChartBuilder::on(area)
                .caption(name, ("sans-serif", 15))
                .margin(10)
                .x_label_area_size(35)
                .y_label_area_size(60)
                .build_cartesian_2d(0.0..t_max, y)
                .map_err(chart_err)?;
            chart
                .configure_mesh()
                .x_desc("t")
                .y_label_formatter(&|v| axis.label(v))
                .draw()
                .map_err(chart_err)?;
            for (i, r) in runs.iter().enumerate() {
                let c = COLOURS[i % COLOURS.len()];
                let (a, b) = r.window;
                chart
                    .draw_series(std::iter::once(Rectangle::new(
                        [(a, lo), (b, hi)],
                        c.mix(0.08).filled(),
                    )))
                    .map_err(chart_err)?;
                let pts: Vec<(f64, f64)> = r
                    .frames
                    .iter()
                    .filter(|f| f[col].is_finite())
                    .map(|f| (f[0], f[col].max(lo)))
                    .collect();
                let s = chart
                    .draw_series(LineSeries::new(pts, c.stroke_width(2)))
                    .map_err(chart_err)?;
                if k == 0 {
                    s.label(r.label.clone())
                        .legend(move |(x, y)| PathElement::new([(x, y), (x + 18, y)], c));
                }
            }
            if col == 3 {
                chart
                    .draw_series(LineSeries::new(
                        [(0.0, 0.1), (t_max, 0.1)],
                        BLACK.mix(0.4).stroke_width(1),
                    ))
                    .map_err(chart_err)?;
            }
            if k == 0 {
                chart
                    .configure_series_labels()
                    .background_style(WHITE.mix(0.9))
                    .border_style(BLACK)
                    .position(SeriesLabelPosition::LowerRight)
                    .draw()
                    .map_err(chart_err)?;
            }
        }
        root.present().map_err(chart_err)?;
    }
    Ok(svg)
}
