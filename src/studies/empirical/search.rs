//! The search for the smallest c0 that does not over-compress: in c0 the
//! classes run over-compressed (or failed) at small c0, then ok, then
//! inaccurate once the artificial viscosity alpha c0 h grows, so the
//! smallest ok c0 is where compression ends, if the run there is accurate.
//! From a first probe (10 U by default) the search steps by sqrt(10) up
//! (while compressed) or down (while not) to a bracket, then narrows it on
//! log c0 to the relative tolerance: where two settled disordered trials
//! give the disordered law (eps_stat - eps0 = k (U / c0)^m), its next probe
//! is where the law puts the bound, kept inside the bracket by a factor
//! sqrt(1 + tol), so the bracket closes in about two probes; otherwise at
//! the geometric middle (a plain bisection). Either way the answer is
//! bracketed to the tolerance by trials, not by the law.

use anyhow::Result;
use serde::Serialize;

use super::trial::{Starts, Trial};
use crate::solver::Class;

/// Which runs of a trial the search reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Regime {
    /// The perfect lattice (the paper's ordered regime, while it lasts).
    Ordered,
    /// The jittered seeds pooled: the stationary, disordered state.
    Disordered,
}

impl Regime {
    /// The class the search reads (a trial has the runs of its regime).
    pub fn class(self, t: &Trial) -> Class {
        match self {
            Regime::Ordered => t.perfect.as_ref().map(|r| r.class),
            Regime::Disordered => t.pooled.as_ref().map(|p| p.class),
        }
        .expect("a trial of the search's regime")
    }

    /// The starts a trial of this regime runs.
    pub fn starts(self) -> Starts {
        match self {
            Regime::Ordered => Starts::Perfect,
            Regime::Disordered => Starts::Seeds,
        }
    }
}

/// A probe's c0 (in U) and its class.
type Probe = (f64, Class);

fn compressed(c: Class) -> bool {
    matches!(c, Class::OverCompressed | Class::Failed)
}

/// Where the search ended.
#[derive(Debug, Clone, Serialize)]
pub struct Bracket {
    pub regime: Regime,
    /// The smallest c0 found not compressed (ok or inaccurate), and its
    /// class; None: compressed at every c0 up to the top.
    pub not_compressed: Option<(f64, Class)>,
    /// The largest c0 found compressed below it, and its class; None: not
    /// compressed down to the bottom.
    pub compressed: Option<(f64, Class)>,
    /// The smallest c0 ok: `not_compressed` when that is ok.
    pub c0_min_ok: Option<f64>,
    /// The c0s probed, in order.
    pub probes: Vec<f64>,
}

/// How the search moves: where it starts, its bounds and tolerance (all
/// c0 in absolute units).
#[derive(Debug, Clone, Copy)]
pub struct Steps {
    pub first: f64,
    pub lo: f64,
    pub hi: f64,
    pub rel_tol: f64,
    /// For the disordered regime: the lattice's own compaction eps0+ and
    /// the bound on eps_stat, for the law's probes (None: plain bisection).
    pub law: Option<(f64, f64)>,
}

/// The next probe inside (l, h): where the law through the two settled
/// trials nearest the bracket puts the bound, or the geometric middle.
fn next_probe(l: f64, h: f64, steps: &Steps, settled: &[(f64, f64)]) -> f64 {
    let mid = (h * l).sqrt();
    let Some((eps0, bound)) = steps.law else {
        return mid;
    };
    let mut pts: Vec<(f64, f64)> = settled
        .iter()
        .filter(|p| p.1 - eps0 > 0.0)
        .map(|&(c, e)| (c.ln(), (e - eps0).ln()))
        .collect();
    // The two nearest the bracket's middle, in log c0.
    pts.sort_by(|a, b| (a.0 - mid.ln()).abs().total_cmp(&(b.0 - mid.ln()).abs()));
    let [(x1, y1), (x2, y2), ..] = pts[..] else {
        return mid;
    };
    let slope = (y2 - y1) / (x2 - x1);
    if !(slope < 0.0 && slope.is_finite() && bound - eps0 > 0.0) {
        return mid;
    }
    let c = (x1 + ((bound - eps0).ln() - y1) / slope).exp();
    let q = (1.0 + steps.rel_tol).sqrt();
    if c.is_finite() {
        c.clamp(l * q, h / q)
    } else {
        mid
    }
}

/// The search's first probe: the one its path starts from whatever the
/// classes (the engine queues it before the search asks).
pub fn first(steps: &Steps) -> f64 {
    steps.first.clamp(steps.lo, steps.hi)
}

/// Search with `trial` running one c0 (cached: a c0 asked twice is run
/// once).
pub fn search(
    regime: Regime,
    steps: Steps,
    trial: &mut dyn FnMut(f64) -> Result<Trial>,
) -> Result<Bracket> {
    let factor = 10f64.sqrt();
    let mut probes = Vec::new();
    // (c0, eps_stat) of the settled disordered trials, for the law.
    let mut settled: Vec<(f64, f64)> = Vec::new();
    let mut class_at =
        |c: f64, probes: &mut Vec<f64>, settled: &mut Vec<(f64, f64)>| -> Result<Class> {
            probes.push(c);
            let t = trial(c)?;
            if let (Regime::Disordered, Some(p)) = (regime, &t.pooled) {
                if p.settled() {
                    settled.push((c, p.eps_stat));
                }
            }
            Ok(regime.class(&t))
        };
    let first = first(&steps);
    let k = class_at(first, &mut probes, &mut settled)?;
    let (mut lo, mut hi): (Option<Probe>, Option<Probe>);
    if compressed(k) {
        lo = Some((first, k));
        hi = None;
        let mut c = first;
        while c * factor <= steps.hi * (1.0 + 1e-12) {
            c *= factor;
            let k = class_at(c, &mut probes, &mut settled)?;
            if compressed(k) {
                lo = Some((c, k));
            } else {
                hi = Some((c, k));
                break;
            }
        }
    } else {
        hi = Some((first, k));
        lo = None;
        let mut c = first;
        while c / factor >= steps.lo * (1.0 - 1e-12) {
            c /= factor;
            let k = class_at(c, &mut probes, &mut settled)?;
            if compressed(k) {
                lo = Some((c, k));
                break;
            }
            hi = Some((c, k));
        }
    }
    if let (Some(l), Some(h)) = (lo.as_mut(), hi.as_mut()) {
        // At most 64 halvings of ln(h / l): the tolerance is checked to be
        // representable (Search::check), this only guards the loop.
        for _ in 0..64 {
            if h.0 / l.0 <= 1.0 + steps.rel_tol {
                break;
            }
            let mid = next_probe(l.0, h.0, &steps, &settled);
            let k = class_at(mid, &mut probes, &mut settled)?;
            if compressed(k) {
                *l = (mid, k);
            } else {
                *h = (mid, k);
            }
        }
    }
    Ok(Bracket {
        regime,
        c0_min_ok: hi.filter(|h| h.1 == Class::Ok).map(|h| h.0),
        not_compressed: hi,
        compressed: lo,
        probes,
    })
}
