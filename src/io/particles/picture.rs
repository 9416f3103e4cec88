//! A picture of the particle field (SVG, plotters): fluid particles as dots
//! coloured by the compaction eps or by the transverse velocity v_y (a
//! colour bar beside), wall particles as grey squares, and optionally one
//! particle ringed and labelled (the one that triggered a failure).

use anyhow::Result;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::colors::colormaps::ViridisRGB;

use super::vtk::ParticleFrame;

/// What the dots' colour shows.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ColourBy {
    /// eps = rho / rho0 - 1.
    Eps,
    /// v_y, across the flow (zero in the steady solution).
    TransverseVelocity,
}

impl ColourBy {
    fn label(self) -> &'static str {
        match self {
            ColourBy::Eps => "eps",
            ColourBy::TransverseVelocity => "v_y",
        }
    }
}

/// A particle to point at, and what to say about it.
#[derive(Debug, Clone, PartialEq)]
pub struct Mark {
    pub index: usize,
    pub label: String,
}

/// The SVG element of the ring drawn around a marked particle (test hook:
/// no other circle in the picture is unfilled).
pub const RING_RADIUS_PX: i32 = 11;

fn draw_err<E: std::error::Error + Send + Sync + 'static>(
    e: DrawingAreaErrorKind<E>,
) -> anyhow::Error {
    anyhow::anyhow!("drawing the particle picture: {e}")
}

/// Draws the frame. Particles with a non-finite position are left out (a
/// failed run may have some); a non-finite colour value is drawn black.
pub fn particle_svg(
    frame: &ParticleFrame,
    by: ColourBy,
    mark: Option<&Mark>,
    title: &str,
) -> Result<String> {
    let n = frame.len()?;
    if let Some(m) = mark {
        anyhow::ensure!(
            m.index < n,
            "marked particle {} is not among the {n} particles",
            m.index
        );
    }
    let finite: Vec<usize> = (0..n)
        .filter(|&i| frame.x[i].is_finite() && frame.y[i].is_finite())
        .collect();
    let view = View::of(frame, &finite);
    let values: &[f64] = match by {
        ColourBy::Eps => frame.eps,
        ColourBy::TransverseVelocity => frame.vy,
    };
    let colours = colour_range(frame, &finite, values, by);

    let plot_w = 860u32;
    let aspect = ((view.y1 - view.y0) / (view.x1 - view.x0)).clamp(0.2, 3.0);
    let plot_h = (plot_w as f64 * aspect) as u32 + 90;
    let width = plot_w + 150;
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (width, plot_h)).into_drawing_area();
        root.fill(&WHITE).map_err(draw_err)?;
        let (main, bar) = root.split_horizontally(plot_w + 20);
        let dots = Dots {
            frame,
            finite: &finite,
            values,
            colours,
        };
        draw_field(&main, &dots, &view, plot_w, mark, title)?;
        draw_colour_bar(&bar, by, colours)?;
        root.present().map_err(draw_err)?;
    }
    Ok(svg)
}

type Area<'a> = DrawingArea<SVGBackend<'a>, Shift>;

/// The plotted window: the finite particles' extent, padded.
#[derive(Clone, Copy)]
struct View {
    x0: f64,
    x1: f64,
    y0: f64,
    y1: f64,
}

impl View {
    fn of(frame: &ParticleFrame, finite: &[usize]) -> View {
        let range = |v: &[f64]| {
            let (lo, hi) = finite
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &i| {
                    (a.min(v[i]), b.max(v[i]))
                });
            if lo.is_finite() && hi > lo {
                (lo, hi)
            } else if lo.is_finite() {
                (lo - 1.0, lo + 1.0)
            } else {
                (-1.0, 1.0)
            }
        };
        let (x0, x1) = range(frame.x);
        let (y0, y1) = range(frame.y);
        let pad = 0.03 * (x1 - x0).max(y1 - y0);
        View {
            x0: x0 - pad,
            x1: x1 + pad,
            y0: y0 - pad,
            y1: y1 + pad,
        }
    }
}

/// The colour scale's ends: the fluid's finite values (symmetric about 0
/// for v_y), widened when they are all one value.
fn colour_range(
    frame: &ParticleFrame,
    finite: &[usize],
    values: &[f64],
    by: ColourBy,
) -> (f64, f64) {
    let (mut c0, mut c1) = finite
        .iter()
        .filter(|&&i| !frame.wall[i])
        .map(|&i| values[i])
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        });
    if by == ColourBy::TransverseVelocity {
        // symmetric about 0, so the colour of v_y = 0 is the middle one
        let m = c0.abs().max(c1.abs());
        (c0, c1) = (-m, m);
    }
    if !(c0.is_finite() && c1 > c0) {
        let mid = if c0.is_finite() { c0 } else { 0.0 };
        (c0, c1) = (mid - 1e-12, mid + 1e-12);
    }
    (c0, c1)
}

/// What the dots show: the frame's finite particles, coloured by `values`
/// over the scale `colours`.
struct Dots<'a> {
    frame: &'a ParticleFrame<'a>,
    finite: &'a [usize],
    values: &'a [f64],
    colours: (f64, f64),
}

/// The particles (walls grey squares, fluid coloured dots) and the mark.
fn draw_field(
    area: &Area,
    dots: &Dots,
    view: &View,
    plot_w: u32,
    mark: Option<&Mark>,
    title: &str,
) -> Result<()> {
    let (frame, finite, values, (c0, c1)) = (dots.frame, dots.finite, dots.values, dots.colours);
    let View { x0, x1, y0, y1 } = *view;
    let mut chart = ChartBuilder::on(area)
        .caption(title, ("sans-serif", 18))
        .margin(10)
        .x_label_area_size(35)
        .y_label_area_size(55)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(draw_err)?;
    chart
        .configure_mesh()
        .disable_mesh()
        .x_desc("x / d")
        .y_desc("y / d")
        .label_style(("sans-serif", 13))
        .axis_desc_style(("sans-serif", 14))
        .draw()
        .map_err(draw_err)?;
    // a dot a little smaller than the particle spacing
    let spacing = ((x1 - x0) * (y1 - y0) / finite.len().max(1) as f64).sqrt();
    let px = spacing / (x1 - x0) * plot_w as f64;
    let r = (0.4 * px).clamp(1.0, 6.0) as i32;
    let grey = RGBColor(150, 150, 150);
    chart
        .draw_series(finite.iter().filter(|&&i| frame.wall[i]).map(|&i| {
            EmptyElement::at((frame.x[i], frame.y[i]))
                + Rectangle::new([(-r, -r), (r, r)], grey.filled())
        }))
        .map_err(draw_err)?;
    chart
        .draw_series(finite.iter().filter(|&&i| !frame.wall[i]).map(|&i| {
            let v = values[i];
            let colour = if v.is_finite() {
                ViridisRGB.get_color_normalized(v, c0, c1)
            } else {
                BLACK
            };
            Circle::new((frame.x[i], frame.y[i]), r, colour.filled())
        }))
        .map_err(draw_err)?;
    if let Some(m) = mark {
        let (x, y) = (frame.x[m.index], frame.y[m.index]);
        let (x, y) = if x.is_finite() && y.is_finite() {
            (x, y)
        } else {
            ((x0 + x1) / 2.0, (y0 + y1) / 2.0)
        };
        chart
            .draw_series([EmptyElement::at((x, y))
                + Circle::new((0, 0), RING_RADIUS_PX, RED.stroke_width(3))
                + Text::new(
                    m.label.clone(),
                    (RING_RADIUS_PX + 4, -RING_RADIUS_PX - 4),
                    ("sans-serif", 15).into_font().color(&RED),
                )])
            .map_err(draw_err)?;
    }
    Ok(())
}

/// The colour bar of the scale (c0, c1).
fn draw_colour_bar(area: &Area, by: ColourBy, (c0, c1): (f64, f64)) -> Result<()> {
    let mut cb = ChartBuilder::on(area)
        .margin_top(40)
        .margin_bottom(45)
        .margin_right(30)
        .y_label_area_size(60)
        .caption(by.label(), ("sans-serif", 15))
        .build_cartesian_2d(0.0..1.0, c0..c1)
        .map_err(draw_err)?;
    cb.configure_mesh()
        .disable_mesh()
        .disable_x_axis()
        .y_labels(6)
        .y_label_style(("sans-serif", 13))
        .y_label_formatter(&|v| {
            // a tick at round-off from zero reads 0, not -5.55e-17
            let v = if v.abs() <= 1e-9 * (c1 - c0) { 0.0 } else { *v };
            crate::format::fmt_num(v)
        })
        .draw()
        .map_err(draw_err)?;
    let steps = 64;
    cb.draw_series((0..steps).map(|k| {
        let a = c0 + (c1 - c0) * k as f64 / steps as f64;
        let b = c0 + (c1 - c0) * (k + 1) as f64 / steps as f64;
        Rectangle::new(
            [(0.0, a), (1.0, b)],
            ViridisRGB
                .get_color_normalized((a + b) / 2.0, c0, c1)
                .filled(),
        )
    }))
    .map_err(draw_err)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    struct Field {
        x: Vec<f64>,
        y: Vec<f64>,
        v: Vec<f64>,
        eps: Vec<f64>,
        wall: Vec<bool>,
        layer: Vec<i32>,
    }

    fn field() -> Field {
        let (mut f, n) = (
            Field {
                x: vec![],
                y: vec![],
                v: vec![],
                eps: vec![],
                wall: vec![],
                layer: vec![],
            },
            8,
        );
        for j in -2..n + 2 {
            for i in 0..12 {
                f.x.push(i as f64 + 0.5 * (j % 2) as f64);
                f.y.push(j as f64 * 0.866);
                f.v.push(0.01 * (i as f64 - 6.0));
                f.eps.push(1e-3 * j as f64);
                f.wall.push(!(0..n).contains(&j));
                f.layer.push(j);
            }
        }
        f
    }

    fn frame(f: &Field) -> ParticleFrame<'_> {
        ParticleFrame {
            time: 1.5,
            x: &f.x,
            y: &f.y,
            vx: &f.v,
            vy: &f.v,
            density: &f.eps,
            pressure: &f.eps,
            eps: &f.eps,
            wall: &f.wall,
            layer: &f.layer,
        }
    }

    /// Unfilled circles: only the ring is drawn so.
    fn rings(svg: &str) -> usize {
        svg.split("<circle")
            .skip(1)
            .filter(|c| c.split("/>").next().unwrap().contains("fill=\"none\""))
            .count()
    }

    #[test]
    fn a_marked_particle_is_ringed_and_labelled() {
        let f = field();
        let mark = Mark {
            index: 40,
            label: "particle 40: eps > eps0 + margin at t = 1.5".into(),
        };
        let svg = particle_svg(&frame(&f), ColourBy::Eps, Some(&mark), "failure").unwrap();
        assert_eq!(rings(&svg), 1, "one ring");
        assert!(svg.contains(&format!("r=\"{RING_RADIUS_PX}\"")));
        assert!(
            svg.contains("particle 40: eps &gt; eps0 + margin at t = 1.5"),
            "the label, XML-escaped"
        );
        let plain =
            particle_svg(&frame(&f), ColourBy::TransverseVelocity, None, "t = 1.5").unwrap();
        assert_eq!(rings(&plain), 0, "no ring without a mark");
        assert!(!plain.contains("particle 40"));
        // fluid dots and wall squares are both there, and the colour bar
        let fluid = f.wall.iter().filter(|w| !**w).count();
        assert_eq!(plain.matches("<circle").count(), fluid);
        assert!(plain.matches("<rect").count() >= f.wall.len() - fluid + 64);
        // the colour bar's caption says what the colour shows
        assert!(plain.contains("v_y") && !svg.contains("v_y"));
    }

    #[test]
    fn a_mark_outside_the_field_is_an_error() {
        let f = field();
        let mark = Mark {
            index: 10_000,
            label: "x".into(),
        };
        let e = particle_svg(&frame(&f), ColourBy::Eps, Some(&mark), "t").unwrap_err();
        assert!(e.to_string().contains("not among the"), "{e}");
    }
}
