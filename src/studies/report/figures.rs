//! The report's figure data from the generated constants and the rows: the
//! stability map's cells, each rule's c0 line over Re, and Figure 4 (the
//! generated eps_at beside the solver's density under ideal shear).

use anyhow::{Context, Result};

use crate::charts::{EpsCurve, EpsPanel, MapCell, MapLine};
use crate::config::C0Rule;
use crate::kernel::{DiscretisationInfo, Kernel, KernelInfo, KernelVisitor};
use crate::kernels;
use crate::problem::c0::{all_rules_on, by_rule};
use crate::problem::channel::Channel;
use crate::solver::ideal_shear;
use crate::sweep::{Discretisation, Point, PointC0, Row};

/// Map cells from rows with a numeric c0.
pub fn map_cells(rows: &[&Row]) -> Vec<MapCell> {
    rows.iter()
        .filter(|r| r.c0_over_u.is_finite() && r.c0_over_u > 0.0)
        .map(|r| MapCell {
            re: r.re,
            c0_over_u: r.c0_over_u,
            class: r.class,
            failure_kind: r.failure_kind,
            linf_max: r.linf_max,
            max_eps: r.max_eps,
            id: r.id.clone(),
        })
        .collect()
}

/// Each rule's c0 / U against Re over (and a little beyond) the range of
/// `res`, for kernel `kernel` at N = `n` and `alpha` on the paper's
/// discretisation: every rule. A rule is cut where it has no positive value.
pub fn rule_lines(
    kernel: &str,
    base: &toml::Table,
    n: u32,
    alpha: f64,
    res: &[f64],
) -> Result<Vec<MapLine>> {
    rule_lines_on(kernel, Discretisation::PAPER, base, n, alpha, res)
}

/// [`rule_lines`] on discretisation `disc` (its derived models).
pub fn rule_lines_on(
    kernel: &str,
    disc: Discretisation,
    base: &toml::Table,
    n: u32,
    alpha: f64,
    res: &[f64],
) -> Result<Vec<MapLine>> {
    let info = crate::config::kernel_info(kernel)?;
    let (lo, hi) = res
        .iter()
        .filter(|r| **r > 0.0)
        .fold((f64::INFINITY, 0.0f64), |(a, b), &r| (a.min(r), b.max(r)));
    if lo > hi {
        return Ok(Vec::new());
    }
    let (lo, hi) = (lo / 1.5, hi * 1.5);
    const SAMPLES: usize = 60;
    let mut lines = Vec::new();
    let on = crate::config::discretisation(info, disc.lattice, disc.h_over_d.value())?;
    for rule in all_rules_on(info, on) {
        let mut pieces: Vec<Vec<(f64, f64)>> = Vec::new();
        let mut cur: Vec<(f64, f64)> = Vec::new();
        for k in 0..=SAMPLES {
            let re = lo * (hi / lo).powf(k as f64 / SAMPLES as f64);
            let point = Point {
                disc,
                ..Point::paper(0, kernel, n, re, alpha, PointC0::OverU(1.0))
            };
            let scene = point.scene(base)?;
            let channel = Channel::resolve(&scene, info)?;
            let c0 = by_rule(&rule, info, &channel, scene.alpha)
                .map(|(c, _)| c / scene.u)
                .unwrap_or(f64::NAN);
            if c0 > 0.0 && c0.is_finite() {
                cur.push((re, c0));
            } else if !cur.is_empty() {
                pieces.push(std::mem::take(&mut cur));
            }
        }
        if !cur.is_empty() {
            pieces.push(cur);
        }
        let label = match &rule {
            C0Rule::Derived(Some(m)) if m == info.c0_default => format!("derived:{m} (default)"),
            r if *r == C0Rule::Code(&crate::config::RULE10) => "10 U".to_string(),
            r => r.to_string(),
        };
        lines.push(MapLine { label, pieces });
    }
    Ok(lines)
}

/// Figure 4's data: for each kernel, eps over one period for layers 0,
/// N - R and N - 1 (walls at N), from the generated `eps_at` and from the
/// solver's density summation under ideal shear, on the discretisation
/// `pick` chooses for it (the paper's: [`papers`]; a kernel it gives none
/// for is left out).
pub fn figure4(
    infos: &[&'static KernelInfo],
    pick: impl Fn(&'static KernelInfo) -> Option<&'static DiscretisationInfo>,
    n_layers: u32,
    samples: usize,
) -> Result<Vec<EpsPanel>> {
    struct Measure<'a> {
        disc: &'static DiscretisationInfo,
        n_layers: u32,
        layers: &'a [u32],
        t: &'a [f64],
    }
    impl KernelVisitor for Measure<'_> {
        type Output = Result<Vec<Vec<f64>>, crate::config::SceneError>;
        fn visit<K: Kernel>(self) -> Self::Output {
            ideal_shear::eps_series::<K>(self.disc, self.n_layers, self.layers, self.t)
        }
    }
    let t: Vec<f64> = (0..=samples).map(|k| k as f64 / samples as f64).collect();
    let mut panels = Vec::new();
    for &info in infos {
        let Some(disc) = pick(info) else {
            continue;
        };
        let r = info.support.ceil() as u32;
        let mut layers: Vec<(u32, String)> = vec![(0, "n = 0".to_string())];
        if n_layers > r {
            layers.push((n_layers - r, format!("n = N - R = {}", n_layers - r)));
        }
        if n_layers >= 1 && !layers.iter().any(|l| l.0 == n_layers - 1) {
            layers.push((n_layers - 1, format!("n = N - 1 = {}", n_layers - 1)));
        }
        let ids: Vec<u32> = layers.iter().map(|l| l.0).collect();
        let measured = kernels::with_kernel(
            info.name,
            Measure {
                disc,
                n_layers,
                layers: &ids,
                t: &t,
            },
        )
        .expect("the registry lists this kernel")
        .with_context(|| format!("Figure 4 for kernel {} on {}", info.name, disc.label()))?;
        let curves = layers
            .iter()
            .zip(measured)
            .map(|((n, label), measured)| EpsCurve {
                kernel: info.name.to_string(),
                n: *n,
                label: label.clone(),
                t: t.clone(),
                model: t
                    .iter()
                    .map(|&tf| (disc.eps_at)(tf, *n, Some(n_layers)))
                    .collect(),
                measured,
            })
            .collect();
        panels.push(EpsPanel {
            kernel: info.name.to_string(),
            title: format!(
                "{}: eps over one period T = d N^2 / U, N = {n_layers}, {}",
                info.title,
                disc.label()
            ),
            mean: disc.eps.mean.value,
            curves,
        });
    }
    Ok(panels)
}

/// The paper's discretisation of a kernel (triangular, h = d).
pub fn papers(info: &'static KernelInfo) -> Option<&'static DiscretisationInfo> {
    info.discretisations.first()
}
