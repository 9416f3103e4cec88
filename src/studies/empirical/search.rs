//! The search for the smallest c0 that does not over-compress: in c0 the
//! classes run over-compressed (or failed) at small c0, then ok, then
//! inaccurate once the artificial viscosity alpha c0 h grows, so the
//! smallest ok c0 is where compression ends, if the run there is accurate.
//! From a first probe (10 U by default) the search steps by sqrt(10) up
//! (while compressed) or down (while not) to a bracket, then narrows it on
//! log c0 to the relative tolerance: where two settled disordered trials
//! give the disordered law (eps_stat - eps0 = k (U / c0)^m), its next probe
//! is where the law puts the bound, kept a factor 1 + tol inside the
//! bracket; otherwise at the geometric middle (a plain bisection). Kept so,
//! a probe moves an end of the bracket by at least 1 + tol, and one at the
//! edge closes the bracket if its class falls on the near side: a law that
//! keeps missing to one side (as one fitted through trials on one side of
//! the bound does) closes the bracket in steps of 1 + tol. A bracket within
//! (1 + tol)^2 takes its probe where either class closes it (the law's c0
//! moved into that window): one probe more. Either way the answer is
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
/// trials nearest the bracket puts the bound, moved into the window
/// [`closing`] gives, or without one into [`moving`]'s; or the geometric
/// middle.
fn next_probe(l: f64, h: f64, steps: &Steps, settled: &[(f64, f64)]) -> f64 {
    let mid = (h * l).sqrt();
    let Some((eps0, bound)) = steps.law else {
        return mid;
    };
    let window = closing(l, h, steps.rel_tol);
    if window.is_none() && h / l <= (1.0 + steps.rel_tol).powi(2) {
        // Within (1 + tol)^2 but no window left by the margin: the middle.
        return mid;
    }
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
    let (from, to) = window.unwrap_or_else(|| moving(l, h, steps.rel_tol));
    if c.is_finite() {
        c.clamp(from, to)
    } else {
        mid
    }
}

/// For a bracket (l, h) wider than (1 + tol)^2: the c0 at least a factor
/// 1 + tol from each end, [l (1 + tol), h / (1 + tol)], widened by 1e-9 on
/// each side so that a probe at an edge whose class puts it on that edge's
/// side (not compressed at the lower, compressed at the upper) passes the
/// search's test after the rounding (the middle when the margin leaves
/// nothing between them).
fn moving(l: f64, h: f64, rel_tol: f64) -> (f64, f64) {
    let (t, margin) = (1.0 + rel_tol, 1.0 + 1e-9);
    let (from, to) = (l * t / margin, h / t * margin);
    if from <= to {
        (from, to)
    } else {
        let mid = (l * h).sqrt();
        (mid, mid)
    }
}

/// The c0 at which one probe closes the bracket (l, h) to the tolerance
/// whatever its class: [h / (1 + tol), l (1 + tol)], narrowed by 1e-9 on
/// each side so that the search's test (h / l <= 1 + tol) holds after the
/// rounding of the divisions; None when the bracket is wider than
/// (1 + tol)^2 (less the margin).
fn closing(l: f64, h: f64, rel_tol: f64) -> Option<(f64, f64)> {
    let (t, margin) = (1.0 + rel_tol, 1.0 + 1e-9);
    let (from, to) = (h / t * margin, l * t / margin);
    (from <= to).then_some((from, to))
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

/// The ok band above the smallest ok c0, as far as the recommendation
/// needs it: ok at the smallest ok c0 `lo`, the band reaches at least
/// `hi_ok`, and (when searched) ends below `above`.
#[derive(Debug, Clone, Serialize)]
pub struct OkBand {
    /// The smallest ok c0 (the disordered search's answer).
    pub lo: f64,
    /// The largest c0 found ok above it.
    pub hi_ok: f64,
    /// The smallest c0 found not ok above `hi_ok`, and its class; None:
    /// ok at `lo` x the margin, where the band was not searched further.
    pub above: Option<(f64, Class)>,
    /// The c0s found ok from `lo` to `hi_ok`, ascending.
    pub ok: Vec<f64>,
    /// The c0s probed and found not ok, ascending, with their classes:
    /// any below `hi_ok` means the classes alternate inside the band (the
    /// seeds' noise, where the statistics sit near a bound).
    pub not_ok: Vec<(f64, Class)>,
    /// The c0s probed, in order.
    pub probes: Vec<f64>,
}

impl OkBand {
    /// The recommended c0: `lo` x the margin when that is ok (`above`
    /// None); otherwise the c0 found ok farthest (in log c0) from the
    /// band's nearer edge, which is its geometric centre sqrt(lo hi_ok)
    /// whenever the run there was ok, as it is in a band whose classes
    /// do not alternate.
    pub fn recommended(&self) -> f64 {
        if self.above.is_none() {
            return self.hi_ok;
        }
        let edge = |c: f64| (c / self.lo).ln().min((self.hi_ok / c).ln());
        self.ok.iter().copied().fold(
            self.lo,
            |best, c| if edge(c) > edge(best) { c } else { best },
        )
    }
}

/// The ok band above `lo` (a c0 the disordered search found ok): `lo` x
/// `margin` first; when that is not ok, a plain bisection on log c0
/// between them to the relative tolerance for where the band ends (in c0
/// the classes run ok, then inaccurate once the artificial viscosity
/// alpha c0 h grows: a c0 not ok above `lo` is taken as above the band),
/// and a probe at the band's geometric centre for the recommendation.
pub fn ok_band(
    regime: Regime,
    lo: f64,
    margin: f64,
    rel_tol: f64,
    trial: &mut dyn FnMut(f64) -> Result<Trial>,
) -> Result<OkBand> {
    let mut probes = Vec::new();
    let mut ok = vec![lo];
    let first = lo * margin;
    let mut class_at = |c: f64, probes: &mut Vec<f64>| -> Result<Class> {
        probes.push(c);
        Ok(regime.class(&trial(c)?))
    };
    let k = if first == lo {
        Class::Ok
    } else {
        class_at(first, &mut probes)?
    };
    if k == Class::Ok {
        if first != lo {
            ok.push(first);
        }
        return Ok(OkBand {
            lo,
            hi_ok: first,
            above: None,
            ok,
            not_ok: Vec::new(),
            probes,
        });
    }
    let mut not_ok = vec![(first, k)];
    let (mut l, mut h) = (lo, (first, k));
    // At most 64 halvings: Search::check keeps the tolerance representable.
    for _ in 0..64 {
        if h.0 / l <= 1.0 + rel_tol {
            break;
        }
        let mid = (l * h.0).sqrt();
        let k = class_at(mid, &mut probes)?;
        if k == Class::Ok {
            l = mid;
            ok.push(mid);
        } else {
            h = (mid, k);
            not_ok.push(h);
        }
    }
    // The band's centre, for the recommendation.
    let centre = (lo * l).sqrt();
    if centre > lo && centre < l && !probes.contains(&centre) {
        match class_at(centre, &mut probes)? {
            Class::Ok => {
                ok.push(centre);
                ok.sort_by(f64::total_cmp);
            }
            k => not_ok.push((centre, k)),
        }
    }
    not_ok.sort_by(|a, b| a.0.total_cmp(&b.0));
    Ok(OkBand {
        lo,
        hi_ok: l,
        above: Some(h),
        ok,
        not_ok,
        probes,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::studies::empirical::trial::Pooled;

    /// A disordered trial at `c`: over-compressed below `c_star`, ok from
    /// it, every seed settled with the pooled eps_stat `eps`.
    fn trial_at(c: f64, c_star: f64, eps: f64) -> Trial {
        Trial {
            c0: c,
            c0_over_u: c,
            perfect: None,
            pooled: Some(Pooled {
                class: if c < c_star {
                    Class::OverCompressed
                } else {
                    Class::Ok
                },
                failure: None,
                eps_stat: eps,
                linf_stat: 0.0,
                eps_stat_min: eps,
                eps_stat_max: eps,
                seeds: 3,
                stationary: 3,
                disordered: 3,
                t_disorder: None,
            }),
            seeds: Vec::new(),
        }
    }

    /// With the ok band ending at `top`, from below the margin to above
    /// it: the recommendation is the smallest ok c0 times the margin when
    /// the band reaches it, else the band's geometric centre (with classes
    /// that alternate, the ok trial farthest from the nearer edge); the band's end is
    /// bracketed to the tolerance by trials, and a margin of 1 runs
    /// nothing.
    #[test]
    fn the_recommendation_stays_inside_the_ok_band() {
        let (lo, margin) = (20.0, 1.5);
        for tol in [1e-3, 0.01, 0.1, 0.5] {
            for k in 0..60 {
                let top = lo * 1.01f64.powi(k);
                let mut asked = Vec::new();
                let b = ok_band(Regime::Disordered, lo, margin, tol, &mut |c| {
                    asked.push(c);
                    let mut t = trial_at(c, lo, 0.0);
                    if c >= top {
                        t.pooled.as_mut().unwrap().class = Class::Inaccurate;
                    }
                    Ok(t)
                })
                .unwrap();
                assert_eq!(asked, b.probes);
                let rec = b.recommended();
                assert!(
                    rec >= lo && rec < top.max(lo * 1.0000001),
                    "{tol} {top}: {b:?}"
                );
                assert!(b.ok.iter().all(|&c| c < top || c == lo) && b.ok.contains(&rec));
                match b.above {
                    None => {
                        assert!(top > lo * margin, "{tol} {top}: {b:?}");
                        assert_eq!(rec, lo * margin);
                    }
                    Some((c, class)) => {
                        assert_eq!(class, Class::Inaccurate);
                        assert!(b.hi_ok < top || b.hi_ok == lo, "{tol} {top}: {b:?}");
                        assert!(top <= c && c / b.hi_ok <= 1.0 + tol, "{tol} {top}: {b:?}");
                        // The band's centre; no class alternates.
                        assert!((rec / (lo * b.hi_ok).sqrt() - 1.0).abs() < 1e-12);
                        assert!(b.not_ok.iter().all(|&(c, _)| c > b.hi_ok), "{b:?}");
                    }
                }
            }
        }
        let b = ok_band(Regime::Disordered, lo, 1.0, 0.1, &mut |_| unreachable!()).unwrap();
        assert_eq!((b.recommended(), b.probes.len()), (lo, 0));
        // Classes that alternate (the seeds' noise): not ok at the centre
        // only, the recommendation is still a c0 found ok, the one farthest
        // from the nearer edge.
        let top = lo * 1.3;
        let band = |flip: f64| {
            ok_band(Regime::Disordered, lo, margin, 0.1, &mut |c| {
                let mut t = trial_at(c, lo, 0.0);
                if c >= top || c == flip {
                    t.pooled.as_mut().unwrap().class = Class::Inaccurate;
                }
                Ok(t)
            })
            .unwrap()
        };
        let plain = band(f64::NAN);
        let centre = (lo * plain.hi_ok).sqrt();
        assert_eq!(plain.recommended(), centre);
        let b = band(centre);
        let rec = b.recommended();
        assert_eq!((b.hi_ok, b.probes.last()), (plain.hi_ok, Some(&centre)));
        assert!(b.ok.contains(&rec) && rec > lo && rec < b.hi_ok, "{b:?}");
        assert!(b.not_ok.iter().any(|&(c, _)| c == centre && c < b.hi_ok));
        let edge = |c: f64| (c / lo).ln().min((b.hi_ok / c).ln());
        assert!(b.ok.iter().all(|&c| edge(c) <= edge(rec)), "{b:?}");
    }

    /// Any c0 in the window [`closing`] gives closes the bracket: both
    /// brackets it leaves pass the search's own test, at tolerances from
    /// the smallest allowed up, for brackets up to (1 + tol)^2 wide.
    #[test]
    fn a_probe_in_the_closing_window_ends_the_search() {
        for tol in [1e-3f64, 0.01, 0.1, 1.0, 10.0] {
            let t = 1.0 + tol;
            for l in [1e-3, 0.37, 1.0, 27.244327383688052, 1e4] {
                for k in 1..=50 {
                    // Ratios from just above 1 + tol to just below
                    // (1 + tol)^2 (at it, the margin leaves no window).
                    let h = l * t.powf(1.0 + 0.999 * k as f64 / 50.0);
                    let (from, to) = closing(l, h, tol).expect("a window up to (1 + tol)^2");
                    for c in [from, (from * to).sqrt(), to] {
                        assert!(l < c && c < h, "inside ({l}, {h}): {c}");
                        assert!(c / l <= t && h / c <= t, "tol {tol}, ({l}, {h}) at {c}");
                    }
                }
                assert!(closing(l, l * t * t * 1.001, tol).is_none());
            }
        }
    }

    /// With a law that misplaces the bound by a factor (low or high), the
    /// search ends within the tolerance, and a bracket within (1 + tol)^2
    /// takes one probe more, not a chain creeping from one side; with an
    /// exact law, no more probes than plain bisection from the same
    /// bracket; with a law 5 % off, at most one more than with an exact
    /// one.
    #[test]
    fn a_biased_law_does_not_make_the_search_creep() {
        let (eps0, bound) = (2e-3, 1.2e-2);
        let steps = Steps {
            first: 10.0,
            lo: 0.01,
            hi: 100.0,
            rel_tol: 0.1,
            law: Some((eps0, bound)),
        };
        let t = 1.0 + steps.rel_tol;
        for k in 0..40 {
            let c_star = 10.5 * (1.05f64).powi(k);
            let run = |bias: f64| {
                // eps_stat - eps0 = (bound - eps0) (bias c* / c)^1.6: the
                // law through any two trials puts the bound at bias c*.
                let eps = |c: f64| eps0 + (bound - eps0) * (bias * c_star / c).powf(1.6);
                search(Regime::Disordered, steps, &mut |c| {
                    Ok(trial_at(c, c_star, eps(c)))
                })
                .expect("synthetic trials")
            };
            let exact = run(1.0).probes.len();
            for bias in [0.5, 0.8, 0.95, 1.0, 1.05, 1.25, 2.0] {
                let b = run(bias);
                let (l, h) = (b.compressed.unwrap().0, b.not_compressed.unwrap().0);
                assert!(
                    l < c_star && c_star <= h && h / l <= t,
                    "{bias} {c_star}: {b:?}"
                );
                // Replay the brackets: once within (1 + tol)^2, the next
                // probe is the last.
                let (mut lo, mut hi) = (f64::NAN, f64::NAN);
                for (n, &c) in b.probes.iter().enumerate() {
                    if hi / lo <= t * t {
                        assert_eq!(n + 1, b.probes.len(), "{bias} {c_star}: {b:?}");
                    }
                    if c < c_star {
                        lo = if lo.is_nan() { c } else { lo.max(c) };
                    } else {
                        hi = if hi.is_nan() { c } else { hi.min(c) };
                    }
                }
                if (bias - 1.0f64).abs() <= 0.05 + 1e-12 {
                    assert!(b.probes.len() <= exact + 1, "{bias} {c_star}: {b:?}");
                }
                if bias == 1.0 {
                    // From the first bracket, plain bisection needs
                    // ceil(log2(ln(h / l) / ln(1 + tol))) probes.
                    let first = b.probes.iter().position(|&c| c >= c_star).unwrap();
                    let bracket = b.probes[first] / b.probes[first - 1];
                    let bisect = (bracket.ln() / t.ln()).log2().ceil() as usize;
                    assert!(b.probes.len() - first - 1 <= bisect, "{c_star}: {b:?}");
                }
            }
        }
    }
}
