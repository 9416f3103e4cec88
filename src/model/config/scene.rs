//! A scene's fields, their defaults and the small enums they take.

use std::str::FromStr;

use serde::{Deserialize, Serialize};

use super::h_over_d::de_scene_h_over_d;
use super::{discretisation, kernel_info, C0Spec, SceneError};
use crate::kernel::{DiscretisationInfo, KernelInfo, Lattice};

/// Default artificial viscosity. The paper takes alpha in (0, 0.25) and its
/// c0 formulas depend on it; 0.1 is the usual middle of that range. (31)
/// also acts on the shear, as an added viscosity of about alpha c0 h / 8
/// (half of it: approaching pairs only), so its cost in accuracy grows with
/// c0: measured at N = 10, Re = 10 with Monaghan's kernel, the L_inf error
/// of the start-up goes from 2.2e-3 (alpha = 0) to 4.7e-3 (0.1) with the
/// derived c0 = 0.12 U, but from 1.4e-3 to 5.6e-2 with c0 = 10 U.
pub const DEFAULT_ALPHA: f64 = 0.1;

/// What makes a run `inaccurate` or `over-compressed`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ClassRules {
    /// A run is `inaccurate` when the largest error of its mean flow over
    /// its window (per band, the mean over the frames of u - u_analytic,
    /// docs/stationary.md) exceeds this (relative to U). 5 %: the
    /// best runs at N = 10 stay within 0.2-2 % (Monaghan, Morris at Re = 1,
    /// discretisation and wall slip), so 5 % is clearly beyond discretisation
    /// error, and small enough that a profile off by more is visibly wrong.
    #[serde(default = "default_linf_bound")]
    pub linf_bound: f64,
    /// A run is `over-compressed` when its window's compaction (the mean
    /// over its frames of the 99th percentile of eps) exceeds the kernel's
    /// own lattice pulsation eps0 (the true maximum of eps(t) under ideal
    /// shear, `KernelInfo.eps.max`: eps(0.5 T) for the paper's kernels) by
    /// more than this: the density tolerance delta. 1 %: the usual weakly compressible tolerance (Mach
    /// 0.1); eps0 itself is no fault of c0, it is there at any c0.
    #[serde(default = "default_eps_margin")]
    pub eps_margin: f64,
}

fn default_linf_bound() -> f64 {
    0.05
}
fn default_eps_margin() -> f64 {
    0.01
}

impl Default for ClassRules {
    fn default() -> Self {
        ClassRules {
            linf_bound: default_linf_bound(),
            eps_margin: default_eps_margin(),
        }
    }
}

impl ClassRules {
    /// The compaction above which a run on discretisation `disc` is
    /// over-compressed: its own lattice's maximum compaction eps0 (there at
    /// any c0; 0 for a lattice that never compacts) plus the margin.
    pub fn eps_bound(&self, disc: &DiscretisationInfo) -> f64 {
        disc.eps.max.value.max(0.0) + self.eps_margin
    }
}

/// One scene, as written in TOML. Lengths in any unit, consistently.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    /// Kernel name, as in kernels/NAME.toml.
    pub kernel: String,
    /// N: fluid layers n = -(N-1) ..= N-1, half-width B = N dy.
    pub n_layers: u32,
    /// The starting lattice, by name (`Lattice::ALL`; the paper's,
    /// `triangular`, by default).
    #[serde(default)]
    pub lattice: Lattice,
    /// Smoothing length h in units of d: a number or an exact rational
    /// string ("13/10"). With `lattice` it must name a generated
    /// discretisation of the kernel (`kernels/discretisations.toml`).
    #[serde(default = "one", deserialize_with = "de_scene_h_over_d")]
    pub h_over_d: f64,
    /// Columns of the periodic strip: by default the fewest whole columns
    /// wider than the support's diameter 2 R h (the least the scene needs);
    /// more to see whether a statistic depends on the strip's width.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub columns: Option<u32>,
    /// Particle spacing d.
    #[serde(default = "one")]
    pub d: f64,
    /// Centre-line speed U of the steady profile.
    #[serde(default = "one")]
    pub u: f64,
    /// Reynolds number U B / nu; give this or `p`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub re: Option<f64>,
    /// Body force per unit mass along +x; give this or `re`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub p: Option<f64>,
    /// Rest density.
    #[serde(default = "one")]
    pub rho0: f64,
    /// Artificial viscosity coefficient of (31).
    #[serde(default = "default_alpha")]
    pub alpha: f64,
    /// Sound speed: a number or a rule, see [`C0Spec`].
    #[serde(default)]
    pub c0: C0Spec,
    /// Start from rest (the start-up problem) or from the steady profile (7).
    #[serde(default)]
    pub initial: Initial,
    /// End time; by default long enough for the start-up's slowest mode to
    /// fall below `decay_tol` U.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub t_end: Option<f64>,
    #[serde(default = "default_decay_tol")]
    pub decay_tol: f64,
    /// `fixed`: run to t_end; `stationary`: run past the start-up until the
    /// disorder's statistics are stationary (docs/stationary.md), t_end
    /// then unset.
    #[serde(default, skip_serializing_if = "HorizonKind::is_fixed")]
    pub horizon: HorizonKind,
    /// In a stationary horizon, the first checkpoint's span after the
    /// start-up, in shear times B / U (docs/stationary.md: 64); its window
    /// is the later half. Doubling it is how a test checks that the answer
    /// does not depend on the horizon.
    #[serde(
        default = "default_horizon_span",
        skip_serializing_if = "is_default_horizon_span"
    )]
    pub horizon_span: f64,
    /// Time between diagnostics; by default t_end / 20.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub output_interval: Option<f64>,
    /// EOS exponent: 1 is (13), above 1 the Tait form.
    #[serde(default = "one")]
    pub gamma: f64,
    /// Keep negative pressures (tension) instead of clipping them to 0 as (13).
    #[serde(default)]
    pub allow_negative_pressure: bool,
    #[serde(default)]
    pub pressure_form: PressureForm,
    /// The velocity the wall particles show the fluid's viscous term: `zero`
    /// (the paper's walls, at rest) or `mirrored` (the fluid's velocity
    /// mirrored through y = B, Morris, Fox and Zhu 1997).
    #[serde(default)]
    pub wall_velocity: WallVelocity,
    /// The viscous term as (14) with the right sign (`none`), or divided by
    /// its own sum on the perfect lattice (`lattice`), so that it is exact
    /// for a quadratic velocity there (see [`ViscousNormalisation`]).
    #[serde(default, skip_serializing_if = "ViscousNormalisation::is_none")]
    pub viscous_normalisation: ViscousNormalisation,
    /// A run fails when the fluid's compaction eps = rho/rho0 - 1 exceeds this.
    #[serde(default = "default_eps_limit")]
    pub eps_limit: f64,
    /// Random displacement of each fluid particle at the start, uniform in
    /// [-jitter, jitter] d per component (deterministic): an imperfect
    /// lattice, which only pressure can restore.
    #[serde(default)]
    pub jitter: f64,
    /// Seed of the jitter's generator: one perturbed lattice per seed.
    #[serde(default)]
    pub jitter_seed: u32,
    /// A run is `inaccurate` above this L_inf error (relative to U), see
    /// [`ClassRules::linf_bound`].
    #[serde(default = "default_linf_bound")]
    pub linf_bound: f64,
    /// A run is `over-compressed` when its compaction exceeds the kernel's
    /// eps0 by more than this, see [`ClassRules::eps_margin`].
    #[serde(default = "default_eps_margin")]
    pub eps_margin: f64,
    /// The time step's factors: dt <= cfl h / (c0 + |v|max) and
    /// viscous_dt h^2 / nu (docs/timestep.md). By default (None) each is
    /// the kernel's own: cfl half the largest factor at which the kernel's
    /// pressure term is stable on its lattice, at most 1
    /// ([`crate::problem::cost::default_cfl`]); viscous_dt 0.85 of the
    /// largest at which its viscous term is
    /// ([`crate::problem::cost::default_viscous_dt`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cfl: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub viscous_dt: Option<f64>,
    /// Neighbour-list skin in units of h (performance only).
    #[serde(default = "default_skin")]
    pub skin: f64,
    /// Refuse a run whose estimated wall time (one core) exceeds this many
    /// seconds: a time step far smaller than intended should be an error,
    /// not an hours-long run.
    #[serde(default = "default_max_run_s")]
    pub max_run_s: f64,
}

fn default_max_run_s() -> f64 {
    3600.0
}

fn one() -> f64 {
    1.0
}
fn default_alpha() -> f64 {
    DEFAULT_ALPHA
}
/// The CFL factor where the kernel's stable factor is unknown: 0.5,
/// measured stable with the window's statistics within the seeds' noise
/// of 0.25's on every shipped kernel and discretisation tried
/// (docs/timestep.md).
pub const FALLBACK_CFL: f64 = 0.5;
/// The viscous factor where the kernel's stable factor is unknown (Morris,
/// Fox and Zhu 1997).
pub const FALLBACK_VISCOUS_DT: f64 = 0.125;
fn default_horizon_span() -> f64 {
    64.0
}
fn is_default_horizon_span(v: &f64) -> bool {
    *v == default_horizon_span()
}
fn default_decay_tol() -> f64 {
    1e-3
}
/// Ten times weakly compressible (1 %) and above the largest lattice
/// pulsation of the paper's kernels (6 % for the composite one): a fluid
/// compacted by 20 % has lost its lattice.
fn default_eps_limit() -> f64 {
    0.2
}
fn default_skin() -> f64 {
    0.3
}

/// The run-length rule a scene asks for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum HorizonKind {
    /// Run to t_end (the scene's, or the start-up's decay by default).
    #[default]
    Fixed,
    /// Run until the window's statistics are stationary (at most to the cap).
    Stationary,
}

impl HorizonKind {
    pub fn is_fixed(&self) -> bool {
        *self == HorizonKind::Fixed
    }
}

impl FromStr for HorizonKind {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "fixed" => Ok(HorizonKind::Fixed),
            "stationary" => Ok(HorizonKind::Stationary),
            _ => Err(format!(
                "unknown horizon {s:?}: use fixed (run to t_end) or stationary (run until the \
                 statistics are stationary, docs/stationary.md)"
            )),
        }
    }
}

impl std::fmt::Display for HorizonKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            HorizonKind::Fixed => "fixed",
            HorizonKind::Stationary => "stationary",
        })
    }
}

/// The start of a run.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Initial {
    /// At rest: the start-up problem, compared with its series solution.
    #[default]
    Rest,
    /// The steady profile (7), compared with (7).
    Steady,
}

impl FromStr for Initial {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "rest" => Ok(Initial::Rest),
            "steady" => Ok(Initial::Steady),
            _ => Err(format!("unknown initial state {s:?}: use rest or steady")),
        }
    }
}

/// The pressure acceleration's form.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum PressureForm {
    /// The paper's (12): -(m / rho_i^2) sum (P_i + P_j) grad W.
    #[default]
    Paper,
    /// -m sum (P_i / rho_i^2 + P_j / rho_j^2) grad W (momentum conserving).
    Symmetric,
}

/// The velocity wall particles show the fluid's viscous term. The walls
/// never move either way.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum WallVelocity {
    /// u = 0, the paper's model: the wall layers are fluid at rest. The
    /// deeper wall layers, at rest too, drag less than the flow continued
    /// past y = B would: the fluid slips a little at the walls.
    #[default]
    Zero,
    /// The fluid's velocity mirrored through the no-slip plane y = B, pair
    /// by pair (Morris, Fox and Zhu 1997): a wall particle at depth D shows
    /// a fluid particle at distance g from the plane the velocity
    /// -(D / g) v. The factor 1 + D / g on the velocity difference is capped
    /// at its largest value on the undisturbed lattice (the number of wall
    /// layers), which binds only for a particle nearer the plane than one
    /// layer spacing.
    Mirrored,
}

/// How the viscous term is scaled.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ViscousNormalisation {
    /// The Laplacian (14) with the right sign, as the paper writes it.
    #[default]
    None,
    /// Divided by lambda = L_yy / (1 + eps(0))^2, what the operator gives
    /// for u = y^2 / 2 at a particle of the perfect lattice (the continuum
    /// gives 1): the lattice's discrete second moment L_yy = -A sum y_j^2
    /// W'(r_j) / r_j (A = d dy) and the volumes m / rho of its summation
    /// density rho0 (1 + eps(0)). Computed from the kernel and the
    /// discretisation, not fitted: with h = 13/10 d on the square lattice
    /// Wendland C2 has lambda = 0.9538, so without it the fluid is 4.6 %
    /// less viscous than asked and its steady profile 4.8 % too fast
    /// (bench/peers/ACCURACY.md).
    Lattice,
}

impl ViscousNormalisation {
    pub fn is_none(&self) -> bool {
        *self == ViscousNormalisation::None
    }
}

impl FromStr for ViscousNormalisation {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "none" => Ok(ViscousNormalisation::None),
            "lattice" => Ok(ViscousNormalisation::Lattice),
            _ => Err(format!(
                "unknown viscous normalisation {s:?}: use none (the paper's Laplacian) or lattice"
            )),
        }
    }
}

impl FromStr for WallVelocity {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "zero" => Ok(WallVelocity::Zero),
            "mirrored" => Ok(WallVelocity::Mirrored),
            _ => Err(format!(
                "unknown wall velocity {s:?}: use zero (the paper's walls) or mirrored"
            )),
        }
    }
}

impl Scene {
    pub fn to_toml(&self) -> String {
        toml::to_string(self).expect("a scene serialises")
    }

    /// The kernel's data from the registry, or an error listing the known ones.
    pub fn kernel_info(&self) -> Result<&'static KernelInfo, SceneError> {
        kernel_info(&self.kernel)
    }

    /// The scene's discretisation of `info` (see [`discretisation`]).
    pub fn discretisation(
        &self,
        info: &'static KernelInfo,
    ) -> Result<&'static DiscretisationInfo, SceneError> {
        discretisation(info, self.lattice, self.h_over_d)
    }

    /// The bounds that classify a run of this scene.
    pub fn classes(&self) -> ClassRules {
        ClassRules {
            linf_bound: self.linf_bound,
            eps_margin: self.eps_margin,
        }
    }
}
