//! The paper's claims about eps (section 4), checked on any discretisation:
//! the maximum at 0.5 T, an amplitude and a mean independent of the layer n,
//! and the amplitude's drop near the wall.

use crate::analysis::{EpsSummary, Fact};
use crate::compaction::{self, EpsCurve, FloatRadial, Site};
use crate::exact::{decimal, Exact};
use crate::kernel::KernelDef;
use crate::lattice::{layer_speed, max_layer_offset, Discretisation};
use rug::{Float, Rational};

/// The largest N (`show --n-layers`) the claims are checked for. The claim
/// that the amplitude of eps does not depend on n searches eps(t) at every
/// layer n = 1 .. N - R, and layer n's curve has a top frequency of about
/// 2 n R h/d (the speed of its farthest row), so the work grows as N^2: N =
/// 100 takes one to two minutes for a shipped kernel (monaghan 63 s, morris
/// 107 s on a loaded 2-core machine). (The mean's claim costs the same at
/// any N: see `mean_claim`.)
pub const MAX_CHECK_LAYERS: i64 = 100;

/// The fewest layers N the claims need on `disc`: the support reaches
/// ceil(R h/d) layers, and the claims compare layers 1 .. N - ceil(R h/d).
pub fn min_check_layers(def: &KernelDef, disc: &Discretisation) -> i64 {
    reach_layers(def, disc) + 1
}

/// Layers in reach of the support, in whole d: ceil(R h/d).
fn reach_layers(def: &KernelDef, disc: &Discretisation) -> i64 {
    disc.support_d(&def.support)
        .ceil()
        .numer()
        .to_i64()
        .unwrap_or(i64::MAX)
}

/// The curve's amplitude (max - min) and mean for a site, at `prec` bits.
fn amplitude(
    fr: &FloatRadial,
    def: &KernelDef,
    disc: &Discretisation,
    site: Site,
) -> (f64, f64, f64) {
    let curve = EpsCurve::new(fr, &def.support, disc, site);
    let (mx, mn) = compaction::extremes(&curve);
    (
        Float::with_val(mx.value.prec(), &mx.value - &mn.value).to_f64(),
        mx.value.to_f64(),
        mx.tau.to_f64(),
    )
}

/// The paper's claims about eps, checked on one discretisation.
pub fn claims(def: &KernelDef, disc: &Discretisation, eps: &EpsSummary, nl: i64) -> Vec<Fact> {
    let r = &def.support;
    let kmax = max_layer_offset(disc, r);
    // layers in reach of the support, in whole d (ceil(R) for h = d)
    let rr = reach_layers(def, disc);
    let check_prec = 128;
    let frc = FloatRadial::new(&def.w, check_prec);
    let mut claims = Vec::new();
    let half = Exact::rational(Rational::from((1, 2)));
    claims.push(Fact {
        name: "maximum of eps at exactly 0.5 T (n = 0)".into(),
        holds: eps.t_max.exact.as_ref() == Some(&half),
        detail: format!(
            "search finds the maximum at t = {} T",
            decimal(&eps.t_max.value, 20)
        ),
    });
    let site = |n| Site {
        n,
        n_layers: Some(nl),
    };
    let (amp0, _, _) = amplitude(&frc, def, disc, Site::CENTRE);
    let mut amp_bad = Vec::new();
    let mut amps = Vec::new();
    for n in 1..=(nl - rr) {
        let (a, _, _) = amplitude(&frc, def, disc, site(n));
        amps.push(format!("n={n}: {:.6e}", a));
        if ((a - amp0) / amp0).abs() > 1e-9 {
            amp_bad.push(n);
        }
    }
    claims.push(Fact {
        name: format!("amplitude of eps independent of n (0 <= n <= N - R, N = {nl})"),
        holds: amp_bad.is_empty(),
        detail: format!(
            "amplitude at n=0: {:.6e}; {}{}",
            amp0,
            amps.join(", "),
            if amp_bad.is_empty() {
                String::new()
            } else {
                format!("; differs (relative 1e-9) at n = {amp_bad:?}")
            }
        ),
    });
    claims.push(mean_claim(def, disc, nl, rr, check_prec));
    let (amp_wall, _, _) = amplitude(&frc, def, disc, site(nl - 1));
    let drops = amp_wall < amp0 * (1.0 - 1e-9);
    claims.push(Fact {
        name: format!("amplitude drops near the wall (n = N - 1 = {}) when R > 1", nl - 1),
        holds: if kmax > 1 { drops } else { !drops },
        detail: if amp0 == 0.0 {
            format!("amplitude at n = N - 1: {amp_wall:.6e}, at n = 0: 0 (eps does not vary at n = 0: no neighbour moves within reach)")
        } else {
            format!(
                "amplitude at n = N - 1: {:.6e}, at n = 0: {:.6e} (ratio {:.4})",
                amp_wall,
                amp0,
                amp_wall / amp0
            )
        },
    });
    claims
}

/// The paper's claim that the mean of eps is the same for every inner layer.
fn mean_claim(def: &KernelDef, disc: &Discretisation, nl: i64, rr: i64, prec: u32) -> Fact {
    let r = &def.support;
    let site = |n| Site {
        n,
        n_layers: Some(nl),
    };
    let mut mean_bad = Vec::new();
    let mut means = Vec::new();
    // the mean of layer n depends on n only through which layers in reach
    // are at rest relative to it (its own, and the mirror layer -n when
    // 2 n <= kmax): one derivation per such set, whatever N is
    let kmax = max_layer_offset(disc, r);
    let mut by_rest: Vec<(Vec<i64>, compaction::Known)> = Vec::new();
    let mut mean_at = |n: i64| {
        let rest: Vec<i64> = (-kmax..=kmax)
            .filter(|&k| layer_speed(n, k, Some(nl)) == 0)
            .collect();
        if let Some((_, m)) = by_rest.iter().find(|(r, _)| *r == rest) {
            return m.clone();
        }
        let m = compaction::mean(&def.w, r, disc, site(n), prec);
        by_rest.push((rest, m.clone()));
        m
    };
    let mean1 = mean_at(nl - rr);
    for n in 1..=(nl - rr) {
        let m = mean_at(n);
        means.push(format!("n={n}: {}", decimal(&m.value, 8)));
        let d = Float::with_val(prec, &m.value - &mean1.value)
            .abs()
            .to_f64();
        if d > 1e-20 {
            mean_bad.push(n);
        }
    }
    let reach = if disc.is_paper() {
        "2 n (sqrt(3)/2) <= R".to_string()
    } else {
        format!("2 n dy <= R h ({})", disc.label())
    };
    Fact {
        name: format!("mean of eps the same for 0 < n <= N - R (N = {nl})"),
        holds: mean_bad.is_empty(),
        detail: format!(
            "{}{}",
            means.join(", "),
            if mean_bad.is_empty() {
                String::new()
            } else {
                format!(
                    "; differs at n = {mean_bad:?}: there the mirror layer -n (at rest relative to the particle) is within reach of {reach}"
                )
            }
        ),
    }
}
