//! What a run costs: the time-step limits, the starting time step and the
//! steps to the end, and the run-time estimate that guards `max_run_s`. One
//! of each: the problem, the c0 table and the sweep's scheduling all ask
//! here.

use serde::{Deserialize, Serialize};

use super::channel::Channel;
use crate::config::{invalid, SceneError};
use crate::format::fmt_value;
use crate::kernel::Lattice;

/// Seconds per pair evaluation assumed by the run-time estimate: the
/// solver's measured cost (about 8 ns per listed pair and pass for the cubic
/// spline, both passes) rounded up, so the estimate errs long. Measured
/// again (one thread, CPU time, Monaghan, Wendland C2 and the composite
/// kernel, c0 = 10 U, N = 30 to 300): 2.5 to 5.3 ns per listed pair and
/// pass, the per-particle work included, on either lattice at h / d = 1,
/// 13/10, 17/10, 2 and 4; the estimate was 2.3 to 4.2 times the time taken,
/// never short (the most at h >= 2 d, where more pairs share each
/// particle's fixed work).
pub const EST_S_PER_PAIR_PASS: f64 = 10e-9;

/// The time-step limit that bound a step.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum DtLimit {
    /// cfl h / (c0 + |v|max) (the factor: the scene's `cfl`).
    Cfl,
    /// viscous_dt h^2 / nu (the factor: the scene's `viscous_dt`).
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

/// The factors of the three limits: dt <= cfl h / (c0 + |v|max),
/// viscous h^2 / nu, 0.25 sqrt(h / |a|max).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct DtFactors {
    pub cfl: f64,
    pub viscous: f64,
}

impl TimeStep {
    /// The limits with the factors `f`.
    pub fn with(f: DtFactors, h: f64, c0: f64, nu: f64, v_max: f64, a_max: f64) -> TimeStep {
        let cfl = f.cfl * h / (c0 + v_max);
        let viscous = f.viscous * h * h / nu;
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

/// The share of the factor at which a kernel's viscous term is stable on
/// the perfect lattice ([`super::viscous_stable_factor`]) that the default
/// viscous factor takes. Runs from rest at Re = 1 went unstable at no
/// factor below it and by 1.16 times it, and jittered runs kept their
/// window's statistics up to 0.94 of it (docs/timestep.md).
pub const VISCOUS_SHARE: f64 = 0.85;

/// The default viscous factor for a kernel and lattice whose viscous term
/// is stable up to the factor `stable`: [`VISCOUS_SHARE`] of it (0.159 for
/// Monaghan's kernel on the triangular lattice at h = d, 0.22 for
/// Morris's, 0.06 for the composite kernel at h = 1.3 d), or 0.125
/// ([`crate::config::scene::FALLBACK_VISCOUS_DT`]) where `stable` is not
/// a positive finite number (unknown).
pub fn default_viscous_dt(stable: f64) -> f64 {
    if stable > 0.0 && stable.is_finite() {
        VISCOUS_SHARE * stable
    } else {
        crate::config::scene::FALLBACK_VISCOUS_DT
    }
}

/// The share of the factor at which a kernel's pressure term is stable on
/// the perfect lattice ([`super::acoustic_stable_factor`]) that the default
/// CFL factor takes: half, 1.8-1.9x below the onset measured for Wendland
/// C2 (0.9-0.97 of its factor) and about 2x or more below the other
/// kernels' (docs/timestep.md).
pub const CFL_SHARE: f64 = 0.5;

/// The largest default CFL factor: the largest at which the window's
/// statistics were measured against 0.25's (3-8 % apart at 1.0 with 40
/// seeds; docs/timestep.md). It binds Morris's kernel (derived 2.31).
pub const CFL_DEFAULT_MAX: f64 = 1.0;

/// The default CFL factor for a kernel and lattice whose pressure term is
/// stable up to the factor `stable`: [`CFL_SHARE`] of it, at most
/// [`CFL_DEFAULT_MAX`] (0.930 for Monaghan's kernel on the triangular
/// lattice at h = d, 1 for Morris's, 0.51-0.86 for the composite kernel),
/// or 0.5 ([`crate::config::scene::FALLBACK_CFL`]) where `stable` is not
/// a positive finite number (unknown).
pub fn default_cfl(stable: f64) -> f64 {
    if stable > 0.0 && stable.is_finite() {
        (CFL_SHARE * stable).min(CFL_DEFAULT_MAX)
    } else {
        crate::config::scene::FALLBACK_CFL
    }
}

/// A warning when the viscous factor in use, `factor`, is above `stable`,
/// the largest at which the kernel's viscous term is stable on the perfect
/// lattice ([`super::viscous_stable_factor`]); None otherwise. `what`
/// names the kernel and discretisation.
pub fn viscous_dt_warning(factor: f64, stable: f64, what: &str) -> Option<String> {
    (factor > stable).then(|| {
        format!(
            "warning: viscous_dt = {} is above {:.4}, the largest factor at which {what}'s viscous \
             term is stable on the perfect lattice (dt times its fastest damping rate at most 1; \
             docs/timestep.md): expect the lattice to go unstable, or lower viscous_dt \
             (--viscous-dt)",
            fmt_value(factor),
            stable
        )
    })
}

/// A warning when the CFL factor in use, `factor`, is above `stable`, the
/// largest at which the kernel's pressure term is stable on the perfect
/// lattice ([`super::acoustic_stable_factor`]); None otherwise. `what`
/// names the kernel and discretisation.
pub fn cfl_warning(factor: f64, stable: f64, what: &str) -> Option<String> {
    (factor > stable).then(|| {
        format!(
            "warning: cfl = {} is above {:.4}, the largest factor at which {what}'s pressure term \
             is stable on the perfect lattice (dt times its fastest sound wave's frequency at most \
             2; docs/timestep.md): expect the lattice to go unstable, or lower cfl (--cfl)",
            fmt_value(factor),
            stable
        )
    })
}

/// The starting time step of a channel at sound speed `c0` with the
/// scene's factors ([`Channel::dt_factors`]), U and p taken as the speed
/// and acceleration scales, and the steps it takes to `t_end`.
#[derive(Debug, Clone, Copy)]
pub struct Estimate {
    pub time_step: TimeStep,
    pub steps: f64,
}

impl Estimate {
    pub fn new(channel: &Channel, c0: f64, t_end: f64) -> Estimate {
        let flow = &channel.flow;
        let time_step = TimeStep::with(
            channel.dt_factors,
            channel.lattice.h,
            c0,
            flow.nu,
            flow.u,
            flow.p,
        );
        Estimate {
            time_step,
            steps: (t_end / time_step.dt).ceil(),
        }
    }

    /// Particles (fluid and wall) times steps: the sweep's scheduling weight.
    pub fn particle_steps(&self, channel: &Channel) -> f64 {
        channel.lattice.n_particles() as f64 * self.steps
    }

    /// Estimated wall time on one core: steps x particles x neighbours
    /// listed (within (R + `skin`) h: the scene's skin, which the cost
    /// follows, 2.2 times the time at skin 0.9 h as at 0.3 h for h = 4 d)
    /// x two passes at [`EST_S_PER_PAIR_PASS`].
    pub fn seconds(&self, channel: &Channel, support: f64, skin: f64) -> f64 {
        let particles = channel.lattice.n_particles() as f64;
        let neighbours = self.neighbours(channel, support, skin);
        self.steps * particles * neighbours * 2.0 * EST_S_PER_PAIR_PASS
    }

    /// The neighbours listed per particle that [`Estimate::seconds`] counts.
    pub fn neighbours(&self, channel: &Channel, support: f64, skin: f64) -> f64 {
        let lattice = &channel.lattice;
        listed_neighbours(lattice.kind, lattice.d, lattice.h, support, skin)
    }
}

/// Neighbours listed per particle on a lattice of kind `kind` at spacing
/// `d`: the other lattice sites within (R + skin) h, the list's reach (as
/// the solver lists them: itself excluded, closed). Counted site by site up
/// to a reach of [`COUNTED_REACH`] d (the area's pi r^2 / (dy d) misses the
/// count by 10 % at h = 2 d), the area's estimate beyond (where it is within
/// a few d / r); it grows as (h / d)^2.
pub fn listed_neighbours(kind: Lattice, d: f64, h: f64, support: f64, skin: f64) -> f64 {
    // In units of d, so a huge or tiny d cannot overflow the squares.
    let reach = (support + skin) * (h / d);
    let dy = kind.dy(1.0);
    // Far (or NaN, from a non-finite input): the area's estimate.
    if reach.is_nan() || reach > COUNTED_REACH {
        return std::f64::consts::PI * reach.powi(2) / dy;
    }
    let reach2 = reach * reach * (1.0 + super::lattice::CLOSED_TOL);
    let rows = (reach / dy).floor() as i32;
    let mut count = 0u32;
    for n in -rows..=rows {
        let y = f64::from(n) * dy;
        let offset = kind.offset(n);
        // Columns c with |c + offset| <= reach.
        let c_max = (reach + 1.0).ceil() as i32;
        for c in -c_max..=c_max {
            let x = f64::from(c) + offset;
            if x * x + y * y <= reach2 {
                count += 1;
            }
        }
    }
    f64::from(count - 1)
}

/// The largest reach, in d, at which [`listed_neighbours`] counts sites
/// (about 13,000 of them) rather than dividing areas.
pub const COUNTED_REACH: f64 = 64.0;

/// Memory a run may take before it is refused: 2 GiB, so that a sweep's
/// parallel runs fit this project's 24 GiB machines and a laptop.
pub const MAX_RUN_BYTES: f64 = 2.0 * 1024.0 * 1024.0 * 1024.0;

/// Largest particle count (fluid and wall) of a channel: far above what
/// MAX_RUN_BYTES allows, and below where the counts (u32 per layer and
/// column) overflow.
pub const MAX_PARTICLES: f64 = 1e9;

/// Bytes per particle of the solver's state (16 f64 arrays and the u32
/// index arrays of the neighbour search) and per listed pair (the index and
/// the two cached kernel values), with half again for vector growth.
const BYTES_PER_PARTICLE: f64 = 1.5 * (16.0 * 8.0 + 8.0 * 4.0);
const BYTES_PER_PAIR: f64 = 1.5 * (4.0 + 8.0 + 8.0);

/// Bytes of one kept sample: its figures and one profile row per layer
/// (fluid and wall), as kept in memory and as written to the CSV.
fn bytes_per_sample(layers: f64) -> f64 {
    let sample = std::mem::size_of::<[f64; 12]>() as f64;
    let row = std::mem::size_of::<[f64; 6]>() as f64;
    sample + 150.0 + layers * row
}

/// The estimated memory of a run of `particles` particles listing
/// `neighbours` each, keeping `samples` samples of `layers` layers.
pub fn memory_bytes(particles: f64, neighbours: f64, samples: f64, layers: f64) -> f64 {
    particles * (BYTES_PER_PARTICLE + neighbours * BYTES_PER_PAIR)
        + samples * bytes_per_sample(layers)
}

/// "288 MB", "3.1 GB".
pub fn human_bytes(b: f64) -> String {
    if b < 1e6 {
        format!("{:.0} kB", b / 1e3)
    } else if b < 1e9 {
        format!("{:.0} MB", b / 1e6)
    } else if b < 1e12 {
        format!("{:.2} GB", b / 1e9)
    } else {
        format!("{:.2e} GB", b / 1e9)
    }
}

/// Refuse a lattice of more than [`MAX_PARTICLES`] particles before it is
/// built (the counts would overflow, the memory could not be had).
pub fn check_size(
    kind: Lattice,
    n_layers: u32,
    d: f64,
    h: f64,
    support: f64,
    skin: f64,
) -> Result<(), SceneError> {
    let reach = support * h * (1.0 + super::lattice::CLOSED_TOL);
    let dy = kind.dy(d);
    let columns = (2.0 * reach / d).floor() + 1.0;
    let walls = (reach / dy).floor();
    let particles = (2.0 * f64::from(n_layers) - 1.0 + 2.0 * walls) * columns;
    let neighbours = listed_neighbours(kind, d, h, support, skin);
    let bytes = memory_bytes(particles, neighbours, 0.0, 0.0);
    if !(particles <= MAX_PARTICLES && bytes <= MAX_RUN_BYTES) {
        let field = if h / d > 100.0 {
            "h_over_d"
        } else {
            "n_layers"
        };
        return Err(invalid(
            field,
            format!(
                "n_layers = {n_layers} with h = {} d gives {} particles ({} neighbours each), about {} of \
                 memory, over the bound of {} particles and {}: lower --n or --h-over-d",
                fmt_value(h / d),
                fmt_value(particles),
                fmt_value(neighbours.round()),
                human_bytes(bytes),
                fmt_value(MAX_PARTICLES),
                human_bytes(MAX_RUN_BYTES)
            ),
        ));
    }
    Ok(())
}

/// Refuse a run whose kept samples (t_end / output_interval of them), state
/// and neighbour lists would take more than [`MAX_RUN_BYTES`].
pub fn check_memory(
    channel: &Channel,
    support: f64,
    skin: f64,
    t_end: f64,
    output_interval: f64,
) -> Result<(), SceneError> {
    let lattice = &channel.lattice;
    let samples = (t_end / output_interval).ceil() + 2.0;
    let layers = f64::from(lattice.fluid_layers()) + 2.0 * f64::from(lattice.wall_layers);
    let particles = lattice.n_particles() as f64;
    let neighbours = listed_neighbours(lattice.kind, lattice.d, lattice.h, support, skin);
    let bytes = memory_bytes(particles, neighbours, samples, layers);
    if bytes.is_nan() || bytes > MAX_RUN_BYTES {
        let kept = samples * bytes_per_sample(layers);
        let field = if kept > 0.5 * bytes {
            "output_interval"
        } else {
            "n_layers"
        };
        return Err(invalid(
            field,
            format!(
                "the run would take about {} of memory ({} samples kept, t_end / output_interval = {} / {}, \
                 {}; {particles} particles with {} neighbours each, {}), over the bound of {}; raise \
                 --output-interval, or lower --n / --h-over-d, or shorten --t-end",
                human_bytes(bytes),
                fmt_value(samples),
                fmt_value(t_end),
                fmt_value(output_interval),
                human_bytes(kept),
                fmt_value(neighbours.round()),
                human_bytes(bytes - kept),
                human_bytes(MAX_RUN_BYTES)
            ),
        ));
    }
    Ok(())
}

/// Refuse a run estimated to take longer than `max_run_s` on one core.
pub fn check_run_time(
    channel: &Channel,
    support: f64,
    skin: f64,
    c0: f64,
    t_end: f64,
    max_run_s: f64,
) -> Result<(), SceneError> {
    let est = Estimate::new(channel, c0, t_end);
    let est_s = est.seconds(channel, support, skin);
    // A NaN estimate (from an infinite step count) is refused too.
    if est_s.is_nan() || est_s > max_run_s {
        let particles = channel.lattice.n_particles() as f64;
        return Err(invalid(
            "max_run_s",
            format!(
                "the run would take about {} on one core ({:.3e} steps of dt = {:.3e}, bound by the {} limit, \
                 x {particles} particles with {} neighbours each), over the bound max_run_s = {} s; raise it \
                 (--max-run-s), or shorten t_end, or lower c0 (CFL) / raise Re (viscous)",
                human_seconds(est_s),
                est.steps,
                est.time_step.dt,
                est.time_step.limit.name(),
                fmt_value(est.neighbours(channel, support, skin)),
                fmt_value(max_run_s)
            ),
        ));
    }
    Ok(())
}

/// "3.2 s", "1.5 h", "2.1 days".
pub fn human_seconds(s: f64) -> String {
    if s < 120.0 {
        format!("{s:.1} s")
    } else if s < 7200.0 {
        format!("{:.1} min", s / 60.0)
    } else if s < 172_800.0 {
        format!("{:.1} h", s / 3600.0)
    } else if s < 8.64e9 {
        format!("{:.1} days", s / 86400.0)
    } else {
        format!("{:.2e} days", s / 86400.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Lattice sites (offset rows on the triangular lattice) within `reach`
    /// of a site, itself excluded, by brute force over a box.
    fn sites_within(kind: Lattice, d: f64, reach: f64) -> f64 {
        let dy = kind.dy(d);
        let rows = (reach / dy).ceil() as i32 + 1;
        let cols = (reach / d).ceil() as i32 + 1;
        let mut count = 0u32;
        for n in -rows..=rows {
            for c in -cols..=cols {
                let x = (f64::from(c) + kind.offset(n)) * d;
                let y = f64::from(n) * dy;
                if x * x + y * y <= reach * reach * (1.0 + 1e-9) && (n, c) != (0, 0) {
                    count += 1;
                }
            }
        }
        f64::from(count)
    }

    #[test]
    fn listed_neighbours_are_the_count_on_either_lattice() {
        let (d, support, skin) = (0.7, 2.0, 0.3);
        for &kind in Lattice::ALL {
            for h_over_d in [1.0, 13.0 / 10.0, 2.0, 4.0] {
                let h = h_over_d * d;
                let listed = listed_neighbours(kind, d, h, support, skin);
                let count = sites_within(kind, d, (support + skin) * h);
                assert_eq!(listed, count, "{kind:?} h/d = {h_over_d}");
            }
        }
        // By hand, reach 2.3 d (h = d, R = 2, skin 0.3): the triangular
        // lattice's shells at d, sqrt(3) d, 2 d hold 6 each; the square's at
        // d, sqrt(2) d, 2 d hold 4 each and sqrt(5) d holds 8.
        assert_eq!(
            listed_neighbours(Lattice::Triangular, 1.0, 1.0, 2.0, 0.3),
            18.0
        );
        assert_eq!(listed_neighbours(Lattice::Square, 1.0, 1.0, 2.0, 0.3), 20.0);
        // Beyond the counted reach: the area's estimate, one per dy d.
        let far = listed_neighbours(Lattice::Square, 1.0, 100.0, 2.0, 0.3);
        let area = std::f64::consts::PI * 230f64.powi(2);
        assert!((far / area - 1.0).abs() < 1e-12);
        let tri = listed_neighbours(Lattice::Triangular, 1.0, 100.0, 2.0, 0.3);
        assert!((tri * 3f64.sqrt() / 2.0 / area - 1.0).abs() < 1e-12);
    }
}
