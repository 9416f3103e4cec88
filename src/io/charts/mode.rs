//! The most unstable mode of `shearsph stability` as a picture (SVG,
//! plotters): each fluid particle a dot at its place on the sheared
//! lattice, and an arrow from it along its displacement in the mode,
//! scaled so the largest is 0.8 d; the arrows' colour is the displacement's
//! size, so where the mode lives (walls, centre, rows) shows at a glance.

use anyhow::Result;
use plotters::prelude::*;
use plotters::style::colors::colormaps::ViridisRGB;

use super::chart_err;

/// The picture of `mode` (per particle x, y in d and its displacement
/// dx, dy, normalised), titled `title`.
pub fn mode_svg(mode: &[[f64; 4]], title: &str) -> Result<String> {
    let pts: Vec<[f64; 4]> = mode
        .iter()
        .copied()
        .filter(|p| p.iter().all(|v| v.is_finite()))
        .collect();
    anyhow::ensure!(!pts.is_empty(), "no mode to draw");
    let (x0, x1) = pts
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
            (a.min(p[0]), b.max(p[0]))
        });
    let (y0, y1) = pts
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
            (a.min(p[1]), b.max(p[1]))
        });
    let big = pts
        .iter()
        .map(|p| p[2].hypot(p[3]))
        .fold(0.0f64, f64::max)
        .max(f64::MIN_POSITIVE);
    let scale = 0.8 / big;
    let (x0, x1, y0, y1) = (x0 - 1.0, x1 + 1.0, y0 - 1.0, y1 + 1.0);
    let plot_w = 900u32;
    let plot_h = ((f64::from(plot_w) * (y1 - y0) / (x1 - x0)).clamp(200.0, 1400.0)) as u32 + 80;
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (plot_w, plot_h)).into_drawing_area();
        root.fill(&WHITE).map_err(chart_err)?;
        let mut chart = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 15))
            .margin(10)
            .x_label_area_size(35)
            .y_label_area_size(45)
            .build_cartesian_2d(x0..x1, y0..y1)
            .map_err(chart_err)?;
        chart
            .configure_mesh()
            .disable_mesh()
            .x_desc("x / d")
            .y_desc("y / d")
            .draw()
            .map_err(chart_err)?;
        chart
            .draw_series(
                pts.iter()
                    .map(|p| Circle::new((p[0], p[1]), 2, BLACK.mix(0.6).filled())),
            )
            .map_err(chart_err)?;
        chart
            .draw_series(pts.iter().map(|p| {
                let size = p[2].hypot(p[3]) / big;
                let c = ViridisRGB::get_color(size);
                PathElement::new(
                    [(p[0], p[1]), (p[0] + scale * p[2], p[1] + scale * p[3])],
                    c.stroke_width(2),
                )
            }))
            .map_err(chart_err)?;
        root.present().map_err(chart_err)?;
    }
    Ok(svg)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_particle_has_its_dot_and_arrow() {
        let mode = [
            [0.0, 0.0, 1.0, 0.0],
            [1.0, 0.0, 0.0, -0.5],
            [0.5, 0.9, 0.1, 0.1],
        ];
        let svg = mode_svg(&mode, "a mode").unwrap();
        assert_eq!(svg.matches("<circle").count(), 3);
        assert!(svg.matches("<polyline").count() >= 3);
        assert!(mode_svg(&[[f64::NAN; 4]], "none").is_err());
    }
}
