//! The disordered regime's law: in the stationary, disordered state the
//! compaction above the lattice's own pulsation follows the Mach-number
//! scaling of weakly compressible SPH, eps_stat - eps0+ = k (U / c0)^m
//! (Monaghan 1994: m = 2), fitted by least squares on ln-ln over the trials
//! whose pooled seeds were stationary, disordered and not failed. For a
//! density tolerance delta it gives c0 = U (k / delta)^(1 / m).

use serde::Serialize;

use super::trial::Trial;
use crate::law::fit::least_squares;

/// A fit of eps_stat - eps0+ = k (U / c0)^m.
#[derive(Debug, Clone, Serialize)]
pub struct DisorderedLaw {
    pub k: f64,
    pub m: f64,
    /// Standard errors of ln k and m (NaN with two points).
    pub ln_k_se: f64,
    pub m_se: f64,
    /// RMS residual in ln eps.
    pub rms: f64,
    /// The points fitted: (c0 / U, eps_stat - eps0+).
    pub points: Vec<(f64, f64)>,
    /// The eps0+ subtracted: the lattice's own compaction (0 if negative).
    pub eps0: f64,
}

impl DisorderedLaw {
    /// c0 / U for the density tolerance `delta` (on eps_stat - eps0+).
    pub fn c0_over_u(&self, delta: f64) -> f64 {
        (self.k / delta).powf(1.0 / self.m)
    }

    /// eps_stat - eps0+ the law gives at `c0_over_u`.
    pub fn eps_at(&self, c0_over_u: f64) -> f64 {
        self.k * c0_over_u.powf(-self.m)
    }

    /// The c0 / U range the law was fitted on.
    pub fn range(&self) -> (f64, f64) {
        let xs = self.points.iter().map(|p| p.0);
        (
            xs.clone().fold(f64::INFINITY, f64::min),
            xs.fold(f64::NEG_INFINITY, f64::max),
        )
    }

    /// Whether `c0_over_u` lies within [`range`](Self::range): outside it
    /// the law is extrapolated, and the disordered state it was fitted on
    /// need not be the one there (well above the compaction's bound it can
    /// quiet over thousands of t: docs/stationary.md).
    pub fn covers(&self, c0_over_u: f64) -> bool {
        let (lo, hi) = self.range();
        (lo..=hi).contains(&c0_over_u)
    }
}

/// Fit the law on the settled trials whose compaction above the lattice's
/// own, eps_stat - eps0+, is at least 1e-3 and at least eps0+ (where the
/// lattice's pulsation or the percentile's floor does not set it): at
/// least 3, spanning a factor 1.5 in c0; None when there are not enough.
pub fn fit(trials: &[&Trial], eps0: f64) -> Option<DisorderedLaw> {
    let mut pts: Vec<(f64, f64)> = trials
        .iter()
        .filter_map(|t| t.pooled.as_ref().map(|p| (t.c0_over_u, p)))
        .filter(|(_, p)| p.settled())
        .map(|(c, p)| (c, p.eps_stat - eps0))
        .filter(|p| p.1 >= 1e-3 && p.1 >= eps0 && p.0 > 0.0)
        .collect();
    pts.sort_by(|a, b| a.0.total_cmp(&b.0));
    pts.dedup_by(|a, b| a.0 == b.0);
    let (lo, hi) = (pts.first()?.0, pts.last()?.0);
    if pts.len() < 3 || hi / lo < 1.5 {
        return None;
    }
    let x: Vec<f64> = pts.iter().map(|p| p.0.ln()).collect();
    let y: Vec<f64> = pts.iter().map(|p| p.1.ln()).collect();
    let f = least_squares(&["ln k", "-m"], &[vec![1.0; x.len()], x], &y).ok()?;
    Some(DisorderedLaw {
        k: f.coef[0].exp(),
        m: -f.coef[1],
        ln_k_se: f.se[0],
        m_se: f.se[1],
        rms: f.rms,
        points: pts,
        eps0,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_law_inverts_for_a_tolerance() {
        let law = DisorderedLaw {
            k: 4.0,
            m: 2.0,
            ln_k_se: 0.0,
            m_se: 0.0,
            rms: 0.0,
            points: vec![(5.0, 0.16), (20.0, 0.01)],
            eps0: 0.0,
        };
        assert!((law.c0_over_u(0.01) - 20.0).abs() < 1e-12);
        assert!((law.eps_at(10.0) - 0.04).abs() < 1e-15);
        assert_eq!(law.range(), (5.0, 20.0));
        assert!(law.covers(5.0) && law.covers(12.0) && law.covers(20.0));
        assert!(!law.covers(4.99) && !law.covers(20.01));
    }
}
