//! When no c0 is ok, which limit binds and what would allow one. The
//! classes in c0 run compressed, then ok, then inaccurate: no c0 is ok when
//! the search found compression at every c0 it could try, or when the first
//! c0 that does not compress is already inaccurate. In the second case the
//! artificial viscosity (31) is the suspect: it adds about alpha c0 h / 8
//! to the viscosity nu, a share that grows with c0, so the c0 the
//! compaction needs can be past the c0 the accuracy allows. What would
//! allow a c0 is estimated from that share (alpha, or N at the same Re,
//! scaled so the share at the needed c0 is the share where the runs were
//! accurate) and from the disordered law (the tolerance that the accurate
//! c0 meets), and the alpha estimate is checked with a run.

use anyhow::Result;
use serde::Serialize;

use super::law::DisorderedLaw;
use super::search::Bracket;
use super::trial::{StartRun, Trial};
use crate::config::Scene;
use crate::format::fmt_num;
use crate::problem::channel::Channel;
use crate::solver::Class;

/// Why no c0 is ok, and what would allow one.
#[derive(Debug, Clone, Serialize)]
pub struct Diagnosis {
    /// The limit that binds, in words.
    pub binds: String,
    /// The smallest c0 / U that does not compress (None: none found).
    pub c0_compaction_over_u: Option<f64>,
    /// The largest c0 / U tried whose mean flow was accurate (None: none).
    pub c0_accuracy_over_u: Option<f64>,
    /// alpha c0 h / (8 nu) at the compaction's c0.
    pub av_share: Option<f64>,
    /// Changes that would allow a c0, in words (estimates, and the check).
    pub would: Vec<String>,
    /// The check of the alpha estimate: alpha and the pooled class at the
    /// compaction's c0.
    pub checked_alpha: Option<(f64, Class)>,
    /// The check's runs (the seeds at the compaction's c0 and the checked
    /// alpha), for the runs an answer made.
    #[serde(skip)]
    pub check_runs: Vec<StartRun>,
}

/// The largest c0 of `trials` whose pooled seeds did not fail and whose
/// mean flow was accurate.
fn accurate(scene: &Scene, trials: &[Trial]) -> Option<f64> {
    let bound = scene.classes().linf_bound;
    trials
        .iter()
        .filter_map(|t| t.pooled.as_ref().map(|p| (t.c0, p)))
        .filter(|(_, p)| p.class != Class::Failed && p.linf_stat <= bound)
        .map(|(c, _)| c)
        .fold(None, |m: Option<f64>, c| Some(m.map_or(c, |m| m.max(c))))
}

/// The alpha whose seeds the diagnosis runs at `c_comp`, the smallest c0
/// that does not compress (None without artificial viscosity): the scene's
/// alpha scaled by the largest accurate c0 of `trials` over `c_comp`, at
/// most 1 (0 with no accurate c0). A trial above `c_comp` counts only when
/// it is accurate, and then makes the alpha the scene's own; so the trials
/// below `c_comp` set it, unless one above it is accurate.
pub fn check_alpha(scene: &Scene, c_comp: f64, trials: &[Trial]) -> Option<f64> {
    (scene.alpha > 0.0)
        .then(|| accurate(scene, trials).map_or(0.0, |a| scene.alpha * (a / c_comp).min(1.0)))
}

/// The diagnosis from the search's bracket and trials; `trial(alpha, c0)`
/// gives the seeds' trial at c0 with another alpha (for the check).
pub fn diagnose(
    scene: &Scene,
    channel: &Channel,
    bracket: &Bracket,
    trials: &[Trial],
    law: Option<&DisorderedLaw>,
    trial: &mut dyn FnMut(f64, f64) -> Result<Trial>,
) -> Result<Diagnosis> {
    let u = channel.flow.u;
    let nu = channel.flow.nu;
    let h = channel.lattice.h;
    let rules = scene.classes();
    let share = |alpha: f64, c0: f64| alpha * c0 * h / (8.0 * nu);
    let accurate = accurate(scene, trials);
    let Some((c_comp, _)) = bracket.not_compressed else {
        let top = bracket.compressed.map(|c| c.0).unwrap_or(f64::NAN);
        let mut would = Vec::new();
        if let Some(l) = law {
            would.push(format!(
                "the disordered law (k = {}, m = {}) puts the end of over-compression at about {} \
                 U: search higher (--hi-over-u)",
                fmt_num(l.k),
                fmt_num(l.m),
                fmt_num(l.c0_over_u(rules.eps_margin))
            ));
        }
        would.push(format!(
            "a density tolerance above the compaction seen at {} U (eps_margin larger), if that \
             is acceptable",
            fmt_num(top / u)
        ));
        return Ok(Diagnosis {
            binds: format!(
                "compaction: every c0 up to {} U over-compresses or fails in the disordered state",
                fmt_num(top / u)
            ),
            c0_compaction_over_u: None,
            c0_accuracy_over_u: accurate.map(|c| c / u),
            av_share: None,
            would,
            checked_alpha: None,
            check_runs: Vec::new(),
        });
    };
    let at = trials.iter().find(|t| t.c0 == c_comp);
    let linf = at
        .and_then(|t| t.pooled.as_ref())
        .map_or(f64::NAN, |p| p.linf_stat);
    let s = share(scene.alpha, c_comp);
    let mut would = Vec::new();
    let mut checked_alpha = None;
    let mut check_runs = Vec::new();
    let ratio = accurate.map(|a| a / c_comp);
    // Whether the artificial viscosity is what binds: checked with a run.
    let mut av_binds = scene.alpha > 0.0;
    if let Some(alpha2) = check_alpha(scene, c_comp, trials) {
        let t = trial(alpha2, c_comp)?;
        let p = t.pooled.expect("a trial of the seeds");
        checked_alpha = Some((alpha2, p.class));
        check_runs = t.seeds;
        av_binds = p.linf_stat <= rules.linf_bound;
        if av_binds {
            would.push(format!(
                "alpha at most {} (the share alpha c0 h / (8 nu) at {} U then equals the share \
                 where the runs were accurate), checked: at alpha = {} and c0 = {} U the run is {} \
                 (mean-flow error {} U)",
                fmt_num(alpha2),
                fmt_num(c_comp / u),
                fmt_num(alpha2),
                fmt_num(c_comp / u),
                p.class,
                fmt_num(p.linf_stat)
            ));
        } else {
            would.push(format!(
                "not a smaller alpha: at alpha = {} and c0 = {} U the mean flow is still off by {} \
                 U (checked), so the error is the disordered state's own, not the artificial \
                 viscosity's",
                fmt_num(alpha2),
                fmt_num(c_comp / u),
                fmt_num(p.linf_stat)
            ));
        }
    }
    if let Some(r) = ratio.filter(|r| *r < 1.0 && av_binds) {
        would.push(format!(
            "N at least {} at the same Re (the share falls as h / B = 1 / N), an estimate",
            (f64::from(scene.n_layers) / r).ceil()
        ));
        if let (Some(l), Some(a)) = (law, accurate) {
            would.push(format!(
                "a density tolerance of {} (eps_margin; the disordered law's compaction at the \
                 accurate {} U), an estimate",
                fmt_num(l.eps_at(a / u)),
                fmt_num(a / u)
            ));
        }
    }
    Ok(Diagnosis {
        binds: format!(
            "accuracy: the compaction needs c0 >= {} U, where the mean flow is off by {} U (the \
             bound is {}); the artificial viscosity adds alpha c0 h / (8 nu) = {} of nu there{}",
            fmt_num(c_comp / u),
            fmt_num(linf),
            fmt_num(rules.linf_bound),
            fmt_num(s),
            accurate.map_or("; no c0 tried was accurate".to_string(), |a| format!(
                ", the runs were accurate up to {} U",
                fmt_num(a / u)
            ))
        ),
        c0_compaction_over_u: Some(c_comp / u),
        c0_accuracy_over_u: accurate.map(|c| c / u),
        av_share: Some(s),
        would,
        checked_alpha,
        check_runs,
    })
}
