//! What a run costs: the time-step limits, the starting time step and the
//! steps to the end, and the run-time estimate that guards `max_run_s`. One
//! of each: the problem, the c0 table and the sweep's scheduling all ask
//! here.

use serde::{Deserialize, Serialize};

use super::channel::Channel;
use crate::config::{invalid, SceneError};

/// Seconds per pair evaluation assumed by the run-time estimate: the
/// solver's measured cost (about 8 ns per listed pair and pass for the cubic
/// spline, both passes) rounded up, so the estimate errs long.
pub const EST_S_PER_PAIR_PASS: f64 = 10e-9;

/// The time-step limit that bound a step.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum DtLimit {
    /// 0.25 h / (c0 + |v|max).
    Cfl,
    /// 0.125 h^2 / nu.
    Viscous,
    /// 0.25 sqrt(h / |a|max).
    Force,
}

impl DtLimit {
    pub fn name(self) -> &'static str {
        match self {
            DtLimit::Cfl => "cfl",
            DtLimit::Viscous => "viscous",
            DtLimit::Force => "force",
        }
    }
}

/// The three limits for a state with speeds up to `v_max` and accelerations
/// up to `a_max`, and which binds.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct TimeStep {
    pub cfl: f64,
    pub viscous: f64,
    pub force: f64,
    pub dt: f64,
    pub limit: DtLimit,
}

impl TimeStep {
    pub fn new(h: f64, c0: f64, nu: f64, v_max: f64, a_max: f64) -> TimeStep {
        let cfl = 0.25 * h / (c0 + v_max);
        let viscous = 0.125 * h * h / nu;
        let force = if a_max > 0.0 {
            0.25 * (h / a_max).sqrt()
        } else {
            f64::INFINITY
        };
        let (dt, limit) = [
            (cfl, DtLimit::Cfl),
            (viscous, DtLimit::Viscous),
            (force, DtLimit::Force),
        ]
        .into_iter()
        .fold((f64::INFINITY, DtLimit::Cfl), |best, c| {
            if c.0 < best.0 {
                c
            } else {
                best
            }
        });
        TimeStep {
            cfl,
            viscous,
            force,
            dt,
            limit,
        }
    }
}

/// The starting time step of a channel at sound speed `c0`, U and p taken
/// as the speed and acceleration scales, and the steps it takes to `t_end`.
#[derive(Debug, Clone, Copy)]
pub struct Estimate {
    pub time_step: TimeStep,
    pub steps: f64,
}

impl Estimate {
    pub fn new(channel: &Channel, c0: f64, t_end: f64) -> Estimate {
        let flow = &channel.flow;
        let time_step = TimeStep::new(channel.lattice.h, c0, flow.nu, flow.u, flow.p);
        Estimate {
            time_step,
            steps: (t_end / time_step.dt).ceil(),
        }
    }

    /// Particles (fluid and wall) times steps: the sweep's scheduling weight.
    pub fn particle_steps(&self, channel: &Channel) -> f64 {
        channel.lattice.n_particles() as f64 * self.steps
    }

    /// Estimated wall time on one core: steps x particles x neighbours x two
    /// passes at [`EST_S_PER_PAIR_PASS`].
    pub fn seconds(&self, channel: &Channel, support: f64) -> f64 {
        let lattice = &channel.lattice;
        let particles = lattice.n_particles() as f64;
        let neighbours = std::f64::consts::PI * (support * lattice.h).powi(2)
            / (0.5 * 3f64.sqrt() * lattice.d * lattice.d);
        self.steps * particles * neighbours * 2.0 * EST_S_PER_PAIR_PASS
    }
}

/// Refuse a run estimated to take longer than `max_run_s` on one core.
pub fn check_run_time(
    channel: &Channel,
    support: f64,
    c0: f64,
    t_end: f64,
    max_run_s: f64,
) -> Result<(), SceneError> {
    let est = Estimate::new(channel, c0, t_end);
    let est_s = est.seconds(channel, support);
    if est_s > max_run_s {
        let particles = channel.lattice.n_particles() as f64;
        return Err(invalid(
            "max_run_s",
            format!(
                "the run would take about {} on one core ({:.3e} steps of dt = {:.3e}, bound by the {} limit, \
                 x {particles} particles), over the bound max_run_s = {} s; raise it (--max-run-s), \
                 or shorten t_end, or lower c0 (CFL) / raise Re (viscous)",
                human_seconds(est_s),
                est.steps,
                est.time_step.dt,
                est.time_step.limit.name(),
                max_run_s
            ),
        ));
    }
    Ok(())
}

/// "3.2 s", "1.5 h", "2.1 days".
fn human_seconds(s: f64) -> String {
    if s < 120.0 {
        format!("{s:.1} s")
    } else if s < 7200.0 {
        format!("{:.1} min", s / 60.0)
    } else if s < 172_800.0 {
        format!("{:.1} h", s / 3600.0)
    } else {
        format!("{:.1} days", s / 86400.0)
    }
}
