//! The problem layer: a scene resolved against its kernel into every number
//! the solver reads, once. Above the configuration (`crate::config`), below
//! the solver; imports neither the solver nor anything above it.
//!
//! - [`channel`]: the lattice and the flow (B, p, nu, Re), which need no c0;
//! - [`c0`]: c0 by any rule from a channel, and the table of every rule;
//! - [`cost`]: the time-step limits and the run-time estimate.

mod blame;
pub mod c0;
pub mod channel;
pub mod cost;
pub mod horizon;
pub mod lattice;

use serde::Serialize;

use crate::analytic::Poiseuille;
use crate::config::{invalid, positive, C0Spec, Scene};
/// The configuration's value types a problem carries, for the solver, which
/// reads the problem only.
pub use crate::config::{
    ClassRules, Initial, PressureForm, SceneError, ViscousNormalisation, WallVelocity,
};
use crate::format::fmt_value;
use crate::kernel::{DiscretisationInfo, Kernel, KernelInfo, KernelVisitor};
use crate::kernels;
pub use blame::IMPLAUSIBLE_RUN_S;
use blame::{blame_run_time, c0_inputs};
pub(crate) use blame::{derived, with};
use channel::Channel;
use horizon::{Horizon, HorizonKind};
pub use lattice::Eos;
use lattice::LatticeGeometry;

/// A scene resolved against its kernel: every number the solver uses.
#[derive(Debug, Clone, Serialize)]
pub struct Problem {
    /// The scene as given (written beside a run's outputs as `scene.toml`).
    pub scene: Scene,
    #[serde(skip)]
    pub kernel: &'static KernelInfo,
    pub lattice: LatticeGeometry,
    /// The generator's derivation for the scene's lattice and h/d.
    #[serde(skip)]
    pub discretisation: &'static DiscretisationInfo,
    /// Walls at y = ±B, U, nu and p.
    pub flow: Poiseuille,
    pub re: f64,
    pub rho0: f64,
    /// Particle mass: the area per particle dy d times rho0 ((11):
    /// (sqrt 3 / 2) d^2 rho0 on the triangular lattice, d^2 rho0 on the square).
    pub mass: f64,
    /// Dynamic viscosity rho0 nu (10).
    pub mu: f64,
    pub c0: f64,
    /// The rule c0 came from, in scene syntax with the model named
    /// (e.g. `0.5*derived:full`), or `value`.
    pub c0_rule: String,
    /// Artificial viscosity coefficient of (31), in [0, 1].
    pub alpha: f64,
    /// EOS exponent (1: the paper's (13)).
    pub gamma: f64,
    pub allow_negative_pressure: bool,
    pub pressure_form: PressureForm,
    pub wall_velocity: WallVelocity,
    pub viscous_normalisation: ViscousNormalisation,
    /// The factor on the viscous term: 1 (`none`), or 1 / lambda of
    /// [`Lattice::viscous_lattice_sum`] (`lattice`).
    pub viscous_scale: f64,
    /// Random initial displacement of the fluid, in d.
    pub jitter: f64,
    /// Neighbour-list skin in h.
    pub skin: f64,
    /// A run fails when the fluid's compaction exceeds this.
    pub eps_limit: f64,
    /// The end time: the scene's (or the start-up's decay) in a fixed
    /// horizon, the cap in a stationary one.
    pub t_end: f64,
    pub output_interval: f64,
    /// When the run may stop and which window judges it.
    pub horizon: Horizon,
    /// The time step's factors (the scene's `cfl` and `viscous_dt`).
    pub dt_factors: cost::DtFactors,
    pub initial: Initial,
    /// A run fails when a fluid speed exceeds 10 U + c0: no flow of this
    /// problem comes near it (the flow is at most U, the acoustic pulsation a
    /// fraction of c0).
    pub v_limit: f64,
}

impl Problem {
    /// Check the scene and compute everything the solver needs for kernel
    /// `info`.
    pub fn resolve(scene: &Scene, info: &'static KernelInfo) -> Result<Problem, SceneError> {
        check_fields(scene)?;
        let channel = Channel::resolve(scene, info)?;
        channel.check_derived(scene)?;
        let flow_in = channel.flow_inputs(scene);
        let horizon = resolve_horizon(scene, &channel)?;
        let t_end = horizon.cap();
        derived(
            "t_end",
            t_end,
            &with(&flow_in, &[("decay_tol", scene.decay_tol)]),
        )?;
        let (c0, c0_rule) = c0::resolve(&scene.c0, info, &channel, scene.alpha).map_err(|e| {
            // A rule without a positive c0 at an extreme input (Re =
            // 1e21 gives A = 1e-20): the input is named, not c0.
            let mut inputs = with(&flow_in, &[("n_layers", f64::from(scene.n_layers))]);
            inputs.push(("alpha", scene.alpha.max(1e-3)));
            let extreme = inputs
                .iter()
                .any(|(_, v)| *v != 0.0 && v.abs().log10().abs() > 10.0);
            match (&scene.c0, extreme) {
                (C0Spec::Rule { .. }, true) => {
                    derived(&format!("c0 by {}", scene.c0), -1.0, &inputs).unwrap_err()
                }
                _ => e,
            }
        })?;
        let est = cost::Estimate::new(&channel, c0, t_end);
        let c0_in = c0_inputs(scene, c0, &flow_in);
        let dt_in = with(&with(&flow_in, &[("h_over_d", scene.h_over_d)]), &c0_in);
        derived("the time step dt", est.time_step.dt, &dt_in)?;
        // t_end and the output interval are inputs where the scene gives
        // them; derived (from the flow, decay_tol and t_end), their inputs
        // are already listed and take the blame.
        let step_in = match scene.t_end {
            Some(_) => with(&dt_in, &[("t_end", t_end)]),
            None => with(&dt_in, &[("decay_tol", scene.decay_tol)]),
        };
        derived("the step count t_end / dt", est.steps, &step_in)?;
        positive("max_run_s", scene.max_run_s)?;
        cost::check_run_time(
            &channel,
            info.support,
            scene.skin,
            c0,
            t_end,
            scene.max_run_s,
        )
        .map_err(|e| blame_run_time(e, scene, &channel, c0, t_end, info.support))?;
        let output_interval = match (scene.output_interval, horizon.kind) {
            (Some(dt), _) => {
                positive("output_interval", dt)?;
                dt
            }
            (None, HorizonKind::Fixed) => t_end / 20.0,
            (None, HorizonKind::Stationary) => default_interval(&channel, scene.horizon_span),
        };
        let interval_in = match scene.output_interval {
            Some(_) => with(&step_in, &[("output_interval", output_interval)]),
            None => step_in.clone(),
        };
        derived("the output interval", output_interval, &interval_in)?;
        cost::check_memory(&channel, info.support, scene.skin, t_end, output_interval)?;
        let Channel {
            lattice,
            discretisation,
            flow,
            re,
            dt_factors,
        } = channel;
        let d = lattice.d;
        let mass = lattice.area() * scene.rho0;
        derived("the particle mass", mass, &[("d", d), ("rho0", scene.rho0)])?;
        let mu = scene.rho0 * flow.nu;
        derived(
            "the dynamic viscosity mu",
            mu,
            &with(&flow_in, &[("rho0", scene.rho0)]),
        )?;
        let rho_in = with(
            &with(&[("rho0", scene.rho0)], &c0_in),
            &[("gamma", scene.gamma)],
        );
        let rho0 = scene.rho0;
        derived("the pressure scale c0^2 rho0", c0 * c0 * rho0, &rho_in)?;
        derived("1 / rho0^2 (of P / rho^2)", 1.0 / (rho0 * rho0), &rho_in)?;
        let eos_in = [("gamma", scene.gamma), ("eps_limit", scene.eps_limit)];
        let eos = (1.0 + scene.eps_limit).powf(scene.gamma) * c0 * c0 * rho0 / scene.gamma;
        derived("the EOS pressure at the compaction limit", eos, &eos_in)?;
        let v_limit = 10.0 * scene.u + c0;
        derived(
            "the speed limit 10 U + c0",
            v_limit,
            &with(&[("u", scene.u)], &c0_in),
        )?;
        let viscous_scale = match scene.viscous_normalisation {
            ViscousNormalisation::None => 1.0,
            ViscousNormalisation::Lattice => {
                let lambda = viscous_lattice_sum(info, &lattice);
                if !(lambda > 0.0 && lambda.is_normal()) {
                    // E.g. a kernel whose gradient vanishes at every
                    // neighbour: the lattice has no viscous term to scale.
                    return Err(invalid(
                        "viscous_normalisation",
                        format!(
                            "kernel {} on the {} has a viscous lattice sum of {lambda}, not a \
                             positive number to divide by: use none",
                            info.name,
                            discretisation.label()
                        ),
                    ));
                }
                1.0 / lambda
            }
        };
        Ok(Problem {
            scene: scene.clone(),
            kernel: info,
            lattice,
            discretisation,
            re,
            rho0: scene.rho0,
            mass,
            mu,
            flow,
            c0,
            c0_rule,
            alpha: scene.alpha,
            gamma: scene.gamma,
            allow_negative_pressure: scene.allow_negative_pressure,
            pressure_form: scene.pressure_form,
            wall_velocity: scene.wall_velocity,
            viscous_normalisation: scene.viscous_normalisation,
            viscous_scale,
            jitter: scene.jitter,
            skin: scene.skin,
            eps_limit: scene.eps_limit,
            t_end,
            output_interval,
            horizon,
            dt_factors,
            initial: scene.initial,
            v_limit,
        })
    }

    /// The section 4 set-up for kernel `info` on discretisation `disc`
    /// (the paper's: triangular, h = d) with N = `n_layers`, whose particles
    /// the ideal shear moves (`solver::ideal_shear`): only the density is
    /// used, so c0 and the EOS play no part.
    pub fn ideal_shear(
        info: &'static KernelInfo,
        disc: &DiscretisationInfo,
        n_layers: u32,
    ) -> Result<Problem, SceneError> {
        let scene = Scene {
            kernel: info.name.to_string(),
            n_layers,
            lattice: disc.lattice,
            h_over_d: disc.h_over_d,
            d: 1.0,
            u: 1.0,
            re: Some(10.0),
            p: None,
            c0: C0Spec::Value(1.0),
            initial: Initial::Steady,
            ..Scene::builtin()
        };
        Problem::resolve(&scene, info)
    }

    /// A run to t_end must take at least one time step (the starting one,
    /// [`cost::Estimate`]): a shorter t_end covers no flow (t_end = 1e-300
    /// moves no particle by one bit), and its "ok" would say nothing. Err
    /// naming `t_end`, or `decay_tol` when t_end is the start-up's decay
    /// time. Asked by every run to t_end (`run`, a sweep's points, the
    /// searches), not by a bench's fixed number of steps.
    pub fn check_duration(&self) -> Result<(), SceneError> {
        let est = cost::Estimate::new(&self.channel(), self.c0, self.t_end);
        let dt = est.time_step.dt;
        if self.t_end >= dt {
            return Ok(());
        }
        let (field, given) = match self.scene.t_end {
            Some(_) => ("t_end", String::new()),
            None => (
                "decay_tol",
                format!(
                    " (the start-up's decay time to decay_tol = {}; a smaller decay_tol runs longer)",
                    fmt_value(self.scene.decay_tol)
                ),
            ),
        };
        Err(invalid(
            field,
            format!(
                "t_end = {}{given} is shorter than one time step, dt = {} (the {} limit at c0 = {}): \
                 the run would cover no flow; give t_end >= {} (or leave t_end out: the start-up's \
                 decay time)",
                match self.scene.t_end {
                    Some(t) => fmt_value(t),
                    None => crate::format::fmt_num(self.t_end),
                },
                crate::format::fmt_num(dt),
                est.time_step.limit.name(),
                crate::format::fmt_num(self.c0),
                // dt rounded up at 3 digits: the value suggested passes
                crate::format::fmt_num({
                    let unit = 10f64.powf(dt.log10().floor() - 2.0);
                    (dt / unit).ceil() * unit
                })
            ),
        ))
    }

    /// The largest viscous factor at which this problem's viscous term is
    /// stable on its perfect lattice ([`viscous_stable_factor`]).
    pub fn viscous_stable_factor(&self) -> f64 {
        viscous_stable_factor(self.kernel, &self.lattice, self.viscous_normalisation)
    }

    /// The largest CFL factor at which this problem's pressure term is
    /// stable on its perfect lattice ([`acoustic_stable_factor`]).
    pub fn acoustic_stable_factor(&self) -> f64 {
        acoustic_stable_factor(self.kernel, &self.lattice, self.eos())
    }

    /// The equation of state and pressure form of this problem's fluid.
    pub fn eos(&self) -> Eos {
        Eos::new(self.gamma, self.allow_negative_pressure, self.pressure_form)
    }

    /// The problem's channel: its lattice and flow.
    pub fn channel(&self) -> Channel {
        Channel {
            lattice: self.lattice,
            discretisation: self.discretisation,
            flow: self.flow,
            re: self.re,
            dt_factors: self.dt_factors,
        }
    }

    /// Whether the artificial viscosity (31) acts: the force pass's switch
    /// and the flop count both ask this.
    pub fn has_artificial_viscosity(&self) -> bool {
        self.alpha > 0.0
    }

    /// Whether the walls show the fluid its mirrored velocity.
    pub fn mirrored_walls(&self) -> bool {
        self.wall_velocity == WallVelocity::Mirrored
    }
}

/// The frames of a stationary horizon: every t_s / 4 (t_s = B / U), or
/// finer for a span so short that its first window would hold fewer than
/// 32 frames.
fn default_interval(channel: &Channel, span: f64) -> f64 {
    let t_s = channel.flow.b / channel.flow.u;
    (t_s / horizon::FRAMES_PER_SHEAR_TIME).min(span * t_s / 64.0)
}

/// The scene's horizon: to its t_end (`fixed`), or checkpoints after the
/// start-up (`stationary`, which sets the end itself: a t_end beside it is
/// an error).
fn resolve_horizon(scene: &Scene, channel: &Channel) -> Result<Horizon, SceneError> {
    let flow = &channel.flow;
    let shear_time = flow.b / flow.u;
    let t_startup = match scene.initial {
        Initial::Rest => {
            let mut s = scene.clone();
            s.t_end = None;
            channel.t_end(&s)?
        }
        Initial::Steady => 0.0,
    };
    match scene.horizon {
        HorizonKind::Fixed => Ok(Horizon::fixed(t_startup, shear_time, channel.t_end(scene)?)),
        HorizonKind::Stationary => {
            if let Some(t) = scene.t_end {
                return Err(invalid(
                    "t_end",
                    format!(
                        "{} with horizon = \"stationary\": that horizon ends the run itself (when \
                         its statistics are stationary, at most 4 horizon spans after the start-up); remove t_end, or use horizon = \"fixed\"",
                        fmt_value(t)
                    ),
                ));
            }
            let interval = match scene.output_interval {
                Some(dt) => {
                    positive("output_interval", dt)?;
                    dt
                }
                None => default_interval(channel, scene.horizon_span),
            };
            let (lo, hi) = horizon::SPAN_RANGE;
            if !(lo..=hi).contains(&scene.horizon_span) {
                return Err(invalid(
                    "horizon_span",
                    format!(
                        "{} shear times B / U must be from {lo} to {hi} (64 by default): the \
                         first checkpoint's span after the start-up",
                        fmt_value(scene.horizon_span)
                    ),
                ));
            }
            let span = scene.horizon_span * shear_time;
            if interval > span / 64.0 {
                return Err(invalid(
                    "output_interval",
                    format!(
                        "{} is too coarse for horizon = \"stationary\": its first window holds \
                         half the span, {}, which needs at least 32 frames; use at most {} or \
                         leave it unset ({} by default)",
                        fmt_value(interval),
                        fmt_value(span / 2.0),
                        fmt_value(span / 64.0),
                        fmt_value(default_interval(channel, scene.horizon_span))
                    ),
                ));
            }
            Ok(Horizon::stationary(
                t_startup,
                shear_time,
                scene.horizon_span,
                interval,
            ))
        }
    }
}

/// The largest factor of the viscous limit, dt <= F h^2 / nu, at which the
/// viscous term of kernel `info` on the perfect `lattice` is stable
/// ([`LatticeGeometry::viscous_stable_factor`]), for the term as the scene
/// scales it: `normalisation` `lattice` divides the term by its lattice sum
/// lambda, and so multiplies the factor by lambda (NaN, unknown, for a
/// lambda that is not a positive number, which the problem refuses). The
/// default viscous factor is 0.85 of it, or 0.125 where it is unknown
/// ([`cost::default_viscous_dt`]).
pub fn viscous_stable_factor(
    info: &'static KernelInfo,
    lattice: &LatticeGeometry,
    normalisation: ViscousNormalisation,
) -> f64 {
    let f = stable_factor(Term::Viscous, info, lattice);
    match normalisation {
        ViscousNormalisation::None => f,
        ViscousNormalisation::Lattice => {
            // A sum that is not a positive number is refused by
            // `Problem::new`; until then the factor is unknown.
            let lambda = viscous_lattice_sum(info, lattice);
            if lambda > 0.0 && lambda.is_normal() {
                f * lambda
            } else {
                f64::NAN
            }
        }
    }
}

/// The largest factor of the CFL limit, dt <= CFL h / (c0 + |v|max), at
/// which the pressure term of kernel `info` on the perfect `lattice` is
/// stable ([`LatticeGeometry::acoustic_stable_factor`]; NaN for a kernel
/// not compiled in). `c0` and `run` warn above it
/// ([`cost::cfl_warning`]).
pub fn acoustic_stable_factor(
    info: &'static KernelInfo,
    lattice: &LatticeGeometry,
    eos: Eos,
) -> f64 {
    stable_factor(Term::Pressure(eos), info, lattice)
}

/// The term a stable factor is of.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Term {
    Viscous,
    Pressure(Eos),
}

/// The stable factor of `term` for kernel `info` on `lattice`, each
/// computed once a process: a grid over the wave vectors for each kernel
/// and lattice, and every run of a search or sweep resolves its scene.
fn stable_factor(term: Term, info: &'static KernelInfo, lattice: &LatticeGeometry) -> f64 {
    struct Factor<'a>(Term, &'a LatticeGeometry);
    impl KernelVisitor for Factor<'_> {
        type Output = f64;
        fn visit<K: Kernel>(self) -> f64 {
            match self.0 {
                Term::Viscous => self.1.viscous_stable_factor::<K>(),
                Term::Pressure(eos) => self.1.acoustic_stable_factor::<K>(eos),
            }
        }
    }
    type Key = (Term, &'static str, crate::kernel::Lattice, u64, u64);
    static KNOWN: std::sync::Mutex<Vec<(Key, f64)>> = std::sync::Mutex::new(Vec::new());
    let key = (
        term,
        info.name,
        lattice.kind,
        lattice.d.to_bits(),
        lattice.h.to_bits(),
    );
    let known = |k: &Key| {
        KNOWN
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
            .iter()
            .find(|(q, _)| q == k)
            .map(|&(_, f)| f)
    };
    known(&key).unwrap_or_else(|| {
        let f = kernels::with_kernel(info.name, Factor(term, lattice)).unwrap_or(f64::NAN);
        KNOWN
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
            .push((key, f));
        f
    })
}

/// [`Lattice::viscous_lattice_sum`] for the kernel `info` names.
fn viscous_lattice_sum(info: &'static KernelInfo, lattice: &LatticeGeometry) -> f64 {
    struct Sum<'a>(&'a LatticeGeometry);
    impl KernelVisitor for Sum<'_> {
        type Output = f64;
        fn visit<K: Kernel>(self) -> f64 {
            self.0.viscous_lattice_sum::<K>()
        }
    }
    kernels::with_kernel(info.name, Sum(lattice)).unwrap_or(f64::NAN)
}

/// The scene's own fields that need no kernel: ranges and signs.
pub(crate) fn check_fields(scene: &Scene) -> Result<(), SceneError> {
    positive("d", scene.d)?;
    positive("h_over_d", scene.h_over_d)?;
    positive("u", scene.u)?;
    positive("rho0", scene.rho0)?;
    positive("decay_tol", scene.decay_tol)?;
    positive("eps_limit", scene.eps_limit)?;
    positive("linf_bound", scene.linf_bound)?;
    positive("eps_margin", scene.eps_margin)?;
    if !(0.0..0.5).contains(&scene.jitter) {
        return Err(invalid(
            "jitter",
            format!("{} (in d) must be in [0, 0.5)", fmt_value(scene.jitter)),
        ));
    }
    crate::config::check_alpha(scene.alpha)?;
    // The caps keep a typo out; the bounds that matter are the kernel's
    // stable factors, which `c0` prints and `run` warns above (up to 2.31
    // for the CFL factor, Morris's kernel).
    for (field, v, hi) in [
        ("cfl", scene.cfl, 4.0),
        ("viscous_dt", scene.viscous_dt, 1.0),
    ] {
        let Some(v) = v else { continue };
        if !(v > 0.0 && v <= hi) {
            return Err(invalid(
                field,
                format!(
                    "{} must be in (0, {hi}]: a time-step factor (by default cfl half the \
                     kernel's stable CFL factor, at most 1, and viscous_dt 0.85 of its stable \
                     viscous factor; `c0` prints both, docs/timestep.md)",
                    fmt_value(v)
                ),
            ));
        }
    }
    if !(scene.gamma >= 1.0 && scene.gamma.is_finite()) {
        return Err(invalid(
            "gamma",
            format!(
                "{} must be at least 1 (1 is the paper's (13))",
                fmt_value(scene.gamma)
            ),
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::{kernel_info, C0Spec};

    #[test]
    fn builtin_scene_resolves() {
        let scene = Scene::builtin();
        let info = scene.kernel_info().unwrap();
        let problem = Problem::resolve(&scene, info).unwrap();
        assert!(problem.c0 > 0.0);
        assert!((problem.re - 10.0).abs() < 1e-12);
    }

    #[test]
    fn errors_name_the_field() {
        let info = Scene::builtin().kernel_info().unwrap();
        let check = |edit: &dyn Fn(&mut Scene), field: &str| {
            let mut scene = Scene::builtin();
            edit(&mut scene);
            let err = Problem::resolve(&scene, info).unwrap_err().to_string();
            assert!(err.contains(&format!("`{field}`")), "{err}");
        };
        check(&|s| s.n_layers = 2, "n_layers");
        check(&|s| s.u = 0.0, "u");
        check(&|s| s.re = Some(-1.0), "re");
        check(&|s| s.d = -1.0, "d");
        check(&|s| s.c0 = C0Spec::Value(0.0), "c0");
        check(&|s| s.t_end = Some(0.0), "t_end");
        check(&|s| s.alpha = 1.5, "alpha");
        check(&|s| s.skin = 5.0, "skin");
        check(&|s| s.max_run_s = 1e-9, "max_run_s");
        let err = kernel_info("nope").unwrap_err().to_string();
        assert!(err.contains("monaghan"), "{err}");
    }
}
