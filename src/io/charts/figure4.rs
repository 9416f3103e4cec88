//! The paper's Figure 4: eps over one period for a few layers, the generated
//! model beside the solver's own density summation under ideal shear.

use std::fmt::Write as _;

use anyhow::Result;
use plotters::prelude::*;

use super::chart_err;
use super::sweep::{draw_legend, series_color, Mark};
use crate::sweep::store::csv_field;

/// eps(t) of one layer over one period: the generated model and the solver's
/// density summation on particles moved by the ideal shear.
#[derive(Debug, Clone)]
pub struct EpsCurve {
    pub kernel: String,
    /// The layer n.
    pub n: u32,
    /// e.g. `n = 0`, `n = N - R = 8`.
    pub label: String,
    /// t / T.
    pub t: Vec<f64>,
    pub model: Vec<f64>,
    pub measured: Vec<f64>,
}

/// One kernel's panel: its title, its mean eps (`KernelInfo.eps.mean`), its curves.
#[derive(Debug, Clone)]
pub struct EpsPanel {
    pub kernel: String,
    pub title: String,
    pub mean: f64,
    pub curves: Vec<EpsCurve>,
}

pub fn figure4_csv(panels: &[EpsPanel], n_layers: u32) -> String {
    let mut out = String::from("kernel,n_layers,n,curve,t_over_T,eps_model,eps_solver,eps_mean\n");
    for p in panels {
        for c in &p.curves {
            for k in 0..c.t.len() {
                let _ = writeln!(
                    out,
                    "{},{n_layers},{},{},{},{},{},{}",
                    csv_field(&p.kernel),
                    c.n,
                    csv_field(&c.label),
                    c.t[k],
                    c.model[k],
                    c.measured[k],
                    p.mean
                );
            }
        }
    }
    out
}

/// Figure 4: eps over one period, a panel per kernel; lines the generated
/// eps_at, dots the solver's density summation under ideal shear, the
/// dashed-looking grey line the time mean.
pub fn figure4_svg(panels: &[EpsPanel]) -> Result<String> {
    let mut svg = String::new();
    {
        let height = 340 * panels.len().max(1) as u32;
        let root = SVGBackend::with_string(&mut svg, (1100, height)).into_drawing_area();
        root.fill(&WHITE).map_err(chart_err)?;
        let areas = root.split_evenly((panels.len().max(1), 1));
        for (panel, area) in panels.iter().zip(&areas) {
            let (plot, legend) = area.split_horizontally(800);
            let all = panel
                .curves
                .iter()
                .flat_map(|c| c.model.iter().chain(&c.measured))
                .copied()
                .chain(std::iter::once(panel.mean))
                .filter(|v| v.is_finite());
            let (lo, hi) = all.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
                (a.min(v), b.max(v))
            });
            let pad = ((hi - lo) * 0.08).max(1e-9);
            let mut chart = ChartBuilder::on(&plot)
                .caption(&panel.title, ("sans-serif", 16))
                .margin(10)
                .x_label_area_size(35)
                .y_label_area_size(80)
                .build_cartesian_2d(0.0..1.0, (lo - pad)..(hi + pad))
                .map_err(chart_err)?;
            chart
                .configure_mesh()
                .x_desc("t / T")
                .y_desc("eps = rho/rho0 - 1")
                .y_label_formatter(&|v| format!("{v:.2e}"))
                .draw()
                .map_err(chart_err)?;
            let grey = RGBColor(100, 100, 100);
            chart
                .draw_series(LineSeries::new(
                    vec![(0.0, panel.mean), (1.0, panel.mean)],
                    grey.stroke_width(1),
                ))
                .map_err(chart_err)?;
            let mut entries: Vec<(Mark, String)> = Vec::new();
            for (k, c) in panel.curves.iter().enumerate() {
                let color = series_color(k);
                chart
                    .draw_series(LineSeries::new(
                        c.t.iter().copied().zip(c.model.iter().copied()),
                        color.stroke_width(2),
                    ))
                    .map_err(chart_err)?;
                // Every few samples, so the line stays visible under the dots.
                let step = (c.t.len() / 60).max(1);
                chart
                    .draw_series(
                        c.t.iter()
                            .zip(&c.measured)
                            .step_by(step)
                            .map(|(&t, &e)| Circle::new((t, e), 3, color.stroke_width(1))),
                    )
                    .map_err(chart_err)?;
                entries.push((Mark::Heading, c.label.clone()));
                entries.push((Mark::Line(color, 2), "eps_at (generated)".into()));
                entries.push((Mark::Ring(color), "solver density, ideal shear".into()));
            }
            entries.push((
                Mark::Line(grey, 1),
                format!("mean eps {:.4e} (n = 0)", panel.mean),
            ));
            draw_legend(&legend, &entries)?;
        }
        root.present().map_err(chart_err)?;
    }
    Ok(svg)
}
