//! The configuration layer, the lowest of `src/`: a scene fixes one run (the
//! kernel, the lattice, the flow, the sound speed c0 as a number or a typed
//! rule, the start and the end). It is read from TOML (the embedded default,
//! then a scene file, then flags, each overriding field by field) and
//! resolved against the kernel by `crate::problem` into the numbers the
//! solver uses. Every invalid value gets an error naming the field, its flag
//! and the fix. Imports nothing from the problem, the solver or above.

use std::fmt;
use std::path::Path;
use std::str::FromStr;

use serde::{Deserialize, Deserializer, Serialize, Serializer};

use crate::format::fmt_value;
use crate::kernel::{DiscretisationInfo, KernelInfo, Lattice};
use crate::kernels;

/// The built-in scene (src/default_scene.toml).
pub const DEFAULT_SCENE: &str = include_str!("default_scene.toml");

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
    /// A run is `inaccurate` when the worst L_inf error of its layer-mean
    /// velocity over the output times exceeds this (relative to U). 5 %: the
    /// best runs at N = 10 stay within 0.2-2 % (Monaghan, Morris at Re = 1,
    /// discretisation and wall slip), so 5 % is clearly beyond discretisation
    /// error, and small enough that a profile off by more is visibly wrong.
    #[serde(default = "default_linf_bound")]
    pub linf_bound: f64,
    /// A run is `over-compressed` when its largest compaction exceeds the
    /// kernel's own lattice pulsation eps0 (the true maximum of eps(t) under
    /// ideal shear, `KernelInfo.eps.max`: eps(0.5 T) for the paper's kernels)
    /// by more than this. 1 %: the usual weakly compressible tolerance (Mach
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
    /// over-compressed: its own lattice's maximum compaction plus the margin.
    pub fn eps_bound(&self, disc: &DiscretisationInfo) -> f64 {
        disc.eps.max.value + self.eps_margin
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
    /// The starting lattice: `triangular` (the paper's) or `square`.
    #[serde(default)]
    pub lattice: Lattice,
    /// Smoothing length h in units of d: a number or an exact rational
    /// string ("13/10"). With `lattice` it must name a generated
    /// discretisation of the kernel (`kernels/discretisations.toml`).
    #[serde(default = "one", deserialize_with = "de_h_over_d")]
    pub h_over_d: f64,
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

/// h/d from TOML: a number, or a string holding a number or an exact
/// rational "P/Q".
fn de_h_over_d<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    #[derive(Deserialize)]
    #[serde(untagged)]
    enum Raw {
        Number(f64),
        Text(String),
    }
    match Raw::deserialize(d)? {
        Raw::Number(v) => Ok(v),
        Raw::Text(t) => parse_h_over_d(&t).map_err(serde::de::Error::custom),
    }
}

/// h/d as a flag or TOML string gives it: a number (`1.3`) or an exact
/// rational `P/Q` (`13/10`, whole P and Q). The rational's f64 is P / Q
/// rounded once (P and Q are exact in f64), so it equals the generated,
/// correctly rounded h/d of the same rational bit for bit; two rationals
/// with denominators below 10^5 differ by far more than the lookup's 1e-12,
/// so matching the f64 matches the exact rational.
pub fn parse_h_over_d(s: &str) -> Result<f64, String> {
    let s = s.trim();
    let bad = || format!("h_over_d {s:?} is neither a number nor a rational P/Q (e.g. 13/10)");
    match s.split_once('/') {
        Some((p, q)) => {
            let p: u64 = p.trim().parse().map_err(|_| bad())?;
            let q: u64 = q.trim().parse().map_err(|_| bad())?;
            if q == 0 || p >= 1 << 53 || q >= 1 << 53 {
                return Err(bad());
            }
            Ok(p as f64 / q as f64)
        }
        None => s.parse().map_err(|_| bad()),
    }
}

/// h/d as a short exact rational for a message ("13/10"), or the number
/// itself when no fraction with a denominator up to 1000 gives it to 1e-12.
pub fn rational_text(v: f64) -> String {
    (1..=1000u32)
        .find_map(|q| {
            let p = (v * f64::from(q)).round();
            ((p / f64::from(q) - v).abs() <= 1e-12 * v.abs()).then_some((p, q))
        })
        .map_or_else(
            || fmt_value(v),
            |(p, q)| {
                if q == 1 {
                    format!("{p}")
                } else {
                    format!("\"{p}/{q}\"")
                }
            },
        )
}

/// The generated discretisation of `info` a scene names (its `lattice` and
/// `h_over_d`), or an error naming the line to add to
/// kernels/discretisations.toml and the command to run.
pub fn discretisation(
    info: &'static KernelInfo,
    lattice: Lattice,
    h_over_d: f64,
) -> Result<&'static DiscretisationInfo, SceneError> {
    // the generator derives 0 < h/d <= 4 (codegen's MAX_H_OVER_D): outside
    // it there is no line to add, only a value to change
    if !(h_over_d > 0.0 && h_over_d <= 4.0) {
        return Err(invalid(
            "h_over_d",
            format!(
                "{} is outside (0, 4], the h/d the generator derives; use a generated one (1, 13/10, ...)",
                fmt_value(h_over_d)
            ),
        ));
    }
    info.discretisation(lattice, h_over_d).ok_or_else(|| {
        let known: Vec<String> = info.discretisations.iter().map(|d| d.label()).collect();
        invalid(
            "h_over_d",
            format!(
                "kernel {} has no generated discretisation with lattice = {:?} and h = {} d \
                 (generated: {}); add to kernels/discretisations.toml\n\n[[discretisation]]\n\
                 lattice = \"{}\"\nh_over_d = {}\n\nthen run `cargo run -p shearsph-codegen -- generate` \
                 and rebuild",
                info.name,
                lattice.name(),
                fmt_value(h_over_d),
                known.join("; "),
                lattice.name(),
                rational_text(h_over_d),
            ),
        )
    })
}
fn default_alpha() -> f64 {
    DEFAULT_ALPHA
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

/// A base rule for c0. U is the steady centre-line speed, B the half-width,
/// F = p the body force per unit mass, nu = p B^2 / (2 U), L = 2 B the
/// distance between the plates.
#[derive(Debug, Clone, PartialEq)]
pub enum C0Rule {
    /// A model derived for the kernel (`derived` is its default model,
    /// `derived:NAME` a named one): Reshetnikova (2024).
    Derived(Option<String>),
    /// The paper's construction with a technical eps0 (`derived-eps`, 0.01 by
    /// default; `derived-eps:0.02`) in place of the kernel's kinematic one,
    /// with the kernel's default model (the paper's closing suggestion).
    DerivedEps(Option<f64>),
    /// c0 = 10 U (Monaghan 1994, JCP 110:399; PySPH examples/poiseuille.py,
    /// SPHinXsys test_2d_poiseuille_flow).
    Rule10,
    /// c^2 = max(U^2/delta, nu U/(L delta), F L/delta), delta = 0.01, L = 2 B
    /// (Morris, Fox and Zhu 1997, JCP 136:214, section 2.2; their Poiseuille
    /// case has the plates at y = 0 and y = L).
    Morris1997,
    /// c0 = 20 max(sqrt(2 F L), U), L = 2 B (GPUSPH
    /// src/problems/Poiseuille.cu: hydrostatic_vel = sqrt(2 driving_force
    /// lz), c0 = 20 fmax(hydrostatic_vel, max_vel), lz the channel height).
    Gpusph,
    /// c0 = coefsound x speedsystem with coefsound = 20 and speedsystem =
    /// sqrt(|g| hswl), the body force as gravity and the fluid depth hswl =
    /// 2 B: c0 = 20 sqrt(2 F B) (DualSPHysics JCaseCtes / GenCase defaults).
    DualSphysics,
    /// c0 = 100 U (TrixiParticles.jl examples/fluid/poiseuille_flow_2d.jl).
    Trixi,
    /// The paper's printed row of Table 2 for the kernel.
    Table2,
}

/// The technical eps0 of `derived-eps` when none is given: 1 %, the usual
/// weakly compressible tolerance the paper's conclusion names.
pub const DEFAULT_TECHNICAL_EPS0: f64 = 0.01;

impl fmt::Display for C0Rule {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            C0Rule::Derived(None) => write!(f, "derived"),
            C0Rule::Derived(Some(m)) => write!(f, "derived:{m}"),
            C0Rule::DerivedEps(None) => write!(f, "derived-eps"),
            C0Rule::DerivedEps(Some(e)) => write!(f, "derived-eps:{e}"),
            C0Rule::Rule10 => write!(f, "rule10"),
            C0Rule::Morris1997 => write!(f, "morris1997"),
            C0Rule::Gpusph => write!(f, "gpusph"),
            C0Rule::DualSphysics => write!(f, "dualsphysics"),
            C0Rule::Trixi => write!(f, "trixi"),
            C0Rule::Table2 => write!(f, "table2"),
        }
    }
}

/// c0 as a number, or a factor times a rule: `3.5`, `derived`,
/// `derived:MODEL`, `rule10`, `table2`, `0.5*derived`, `0.01*rule10`.
#[derive(Debug, Clone, PartialEq)]
pub enum C0Spec {
    Value(f64),
    Rule { factor: f64, rule: C0Rule },
}

impl Default for C0Spec {
    fn default() -> Self {
        C0Spec::Rule {
            factor: 1.0,
            rule: C0Rule::Derived(None),
        }
    }
}

const C0_SYNTAX: &str = "a number, or [FACTOR*]RULE with RULE one of derived, derived:MODEL, \
     derived-eps, derived-eps:EPS0, rule10, morris1997, gpusph, dualsphysics, trixi, table2";

impl FromStr for C0Spec {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        let s = s.trim();
        if let Ok(v) = s.parse::<f64>() {
            return Ok(C0Spec::Value(v));
        }
        let (factor, rule) = match s.split_once('*') {
            Some((f, r)) => {
                let factor = f.trim().parse::<f64>().map_err(|_| {
                    format!(
                        "bad factor {:?} in c0 = {s:?}: expected {C0_SYNTAX}",
                        f.trim()
                    )
                })?;
                (factor, r.trim())
            }
            None => (1.0, s),
        };
        let rule = match rule {
            "derived" => C0Rule::Derived(None),
            "derived-eps" => C0Rule::DerivedEps(None),
            "rule10" => C0Rule::Rule10,
            "morris1997" => C0Rule::Morris1997,
            "gpusph" => C0Rule::Gpusph,
            "dualsphysics" => C0Rule::DualSphysics,
            "trixi" => C0Rule::Trixi,
            "table2" => C0Rule::Table2,
            r => {
                if let Some(e) = r.strip_prefix("derived-eps:") {
                    match e.parse::<f64>() {
                        Ok(eps) if eps > 0.0 && eps.is_finite() => C0Rule::DerivedEps(Some(eps)),
                        _ => {
                            return Err(format!(
                                "bad technical eps0 {e:?} in c0 = {s:?}: give a positive number, \
                                 e.g. derived-eps:0.01"
                            ))
                        }
                    }
                } else {
                    match r.strip_prefix("derived:") {
                        Some(m) if !m.is_empty() => C0Rule::Derived(Some(m.to_string())),
                        _ => return Err(format!("unknown c0 rule {r:?}: expected {C0_SYNTAX}")),
                    }
                }
            }
        };
        Ok(C0Spec::Rule { factor, rule })
    }
}

impl fmt::Display for C0Spec {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            C0Spec::Value(v) => write!(f, "{}", fmt_value(*v)),
            C0Spec::Rule { factor, rule } if *factor == 1.0 => write!(f, "{rule}"),
            C0Spec::Rule { factor, rule } => write!(f, "{}*{rule}", fmt_value(*factor)),
        }
    }
}

impl Serialize for C0Spec {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self {
            C0Spec::Value(v) => s.serialize_f64(*v),
            rule => s.collect_str(rule),
        }
    }
}

impl<'de> Deserialize<'de> for C0Spec {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        // A visitor, not an untagged enum: anything but a number or a
        // string (`c0 = true`, a table) gets our message, not serde's
        // "did not match any variant".
        struct V;
        impl serde::de::Visitor<'_> for V {
            type Value = C0Spec;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                write!(f, "c0 as a number or a rule name ({C0_SYNTAX})")
            }
            fn visit_bool<E: serde::de::Error>(self, v: bool) -> Result<C0Spec, E> {
                Err(E::custom(format!(
                    "c0 must be a number or a rule name: {C0_SYNTAX}; not {v}"
                )))
            }
            fn visit_f64<E: serde::de::Error>(self, v: f64) -> Result<C0Spec, E> {
                Ok(C0Spec::Value(v))
            }
            fn visit_i64<E: serde::de::Error>(self, v: i64) -> Result<C0Spec, E> {
                Ok(C0Spec::Value(v as f64))
            }
            fn visit_u64<E: serde::de::Error>(self, v: u64) -> Result<C0Spec, E> {
                Ok(C0Spec::Value(v as f64))
            }
            fn visit_str<E: serde::de::Error>(self, v: &str) -> Result<C0Spec, E> {
                v.parse().map_err(E::custom)
            }
        }
        d.deserialize_any(V)
    }
}

/// A lattice kind in TOML and JSON: `"triangular"` or `"square"`.
impl Serialize for Lattice {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.name())
    }
}

impl<'de> Deserialize<'de> for Lattice {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let s = String::deserialize(d)?;
        s.parse().map_err(serde::de::Error::custom)
    }
}

/// A scene that cannot run, or cannot be read.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    #[error("invalid `{field}` (flag --{flag}): {message}")]
    Invalid {
        field: &'static str,
        flag: &'static str,
        message: String,
    },
    #[error("unknown kernel {name:?} (field `kernel`, flag --kernel); known kernels: {known}")]
    UnknownKernel { name: String, known: String },
    #[error("{origin}: {message}")]
    Read { origin: String, message: String },
}

impl SceneError {
    /// This error with `flag` as the flag of `field`, for a command whose
    /// own flag sets that field (bench's `--layers` sets `n_layers`): the
    /// message names the flag the user typed.
    pub fn with_flag(self, field: &str, flag: &'static str) -> SceneError {
        match self {
            SceneError::Invalid {
                field: f, message, ..
            } if f == field => SceneError::Invalid {
                field: f,
                flag,
                message: message.replace(&format!("--{}", flag_of(f)), &format!("--{flag}")),
            },
            other => other,
        }
    }
}

/// The flag that sets a scene field.
fn flag_of(field: &'static str) -> &'static str {
    match field {
        "n_layers" => "n",
        "h_over_d" => "h-over-d",
        "t_end" => "t-end",
        "decay_tol" => "decay-tol",
        "output_interval" => "output-interval",
        "allow_negative_pressure" => "allow-negative-pressure",
        "pressure_form" => "pressure-form",
        "wall_velocity" => "wall-velocity",
        "viscous_normalisation" => "viscous-normalisation",
        "eps_limit" => "eps-limit",
        "max_run_s" => "max-run-s",
        "jitter_seed" => "jitter-seed",
        "linf_bound" => "linf-bound",
        "eps_margin" => "eps-margin",
        other => other,
    }
}

pub(crate) fn invalid(field: &'static str, message: impl Into<String>) -> SceneError {
    SceneError::Invalid {
        field,
        flag: flag_of(field),
        message: message.into(),
    }
}

/// Lay `over` onto `base` field by field. `re` and `p` are alternatives:
/// setting one drops the other from below.
pub fn overlay(base: &mut toml::Table, over: toml::Table) {
    for (key, value) in over {
        match key.as_str() {
            "re" => {
                base.remove("p");
            }
            "p" => {
                base.remove("re");
            }
            _ => {}
        }
        base.insert(key, value);
    }
}

impl Scene {
    /// The built-in scene.
    pub fn builtin() -> Scene {
        Scene::load(None, toml::Table::new()).expect("the built-in scene is valid")
    }

    /// The built-in scene, overlaid by the scene file if given, then by
    /// `overrides` (from flags).
    pub fn load(file: Option<&Path>, overrides: toml::Table) -> Result<Scene, SceneError> {
        let mut table: toml::Table = DEFAULT_SCENE
            .parse()
            .expect("the built-in scene is valid TOML");
        let mut origin = "scene (built-in default".to_string();
        if let Some(path) = file {
            let read_err = |message: String| SceneError::Read {
                origin: format!("scene file {}", path.display()),
                message,
            };
            let text = std::fs::read_to_string(path).map_err(|e| read_err(e.to_string()))?;
            let own: toml::Table = text
                .parse()
                .map_err(|e: toml::de::Error| read_err(e.to_string()))?;
            if own.contains_key("re") && own.contains_key("p") {
                return Err(read_err(
                    "gives both `re` and `p`; they fix the same thing (p = 2 U^2 / (Re B)): keep one".into(),
                ));
            }
            overlay(&mut table, own);
            origin.push_str(&format!(", over it the file {}", path.display()));
        }
        if !overrides.is_empty() {
            origin.push_str(", then flags");
        }
        overlay(&mut table, overrides);
        origin.push(')');
        toml::Value::Table(table)
            .try_into()
            .map_err(|e: toml::de::Error| SceneError::Read {
                origin,
                // "... \nin `field`" on one line.
                message: e.to_string().trim().replace('\n', " "),
            })
    }

    /// Parse a whole scene from TOML, with no defaults but the fields'.
    pub fn from_toml(text: &str) -> Result<Scene, SceneError> {
        toml::from_str(text).map_err(|e| SceneError::Read {
            origin: "scene".into(),
            message: e.to_string().trim().to_string(),
        })
    }

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

/// A kernel's data by name, or an error listing the known kernels and
/// suggesting the nearest name.
pub fn kernel_info(name: &str) -> Result<&'static KernelInfo, SceneError> {
    kernels::kernel_info(name).ok_or_else(|| {
        let nearest = kernels::NAMES
            .iter()
            .map(|k| (strsim::levenshtein(name, k), *k))
            .min()
            .filter(|(dist, k)| *dist <= k.len().max(2) / 2)
            .map(|(_, k)| format!("; did you mean {k:?}?"))
            .unwrap_or_default();
        SceneError::UnknownKernel {
            name: name.to_string(),
            known: format!("{}{nearest}", kernels::NAMES.join(", ")),
        }
    })
}

/// Err naming `field` unless `v` is a positive finite number.
pub(crate) fn positive(field: &'static str, v: f64) -> Result<(), SceneError> {
    // Normal, not only positive: a subnormal (below 2.2e-308) has lost its
    // precision and squares to 0.
    if v > 0.0 && v.is_normal() {
        Ok(())
    } else {
        Err(invalid(
            field,
            format!(
                "{} must be a positive finite number (of at least 2.2e-308)",
                fmt_value(v)
            ),
        ))
    }
}

/// The one range check of alpha, for scenes and sweep grids alike.
pub fn check_alpha(alpha: f64) -> Result<(), SceneError> {
    if (0.0..=1.0).contains(&alpha) {
        Ok(())
    } else {
        Err(invalid(
            "alpha",
            format!(
                "{} is outside [0, 1]; the paper takes alpha in (0, 0.25)",
                fmt_value(alpha)
            ),
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn c0_spec_round_trips() {
        for s in [
            "3.5",
            "derived",
            "derived:full",
            "rule10",
            "table2",
            "derived-eps",
            "derived-eps:0.02",
            "morris1997",
            "gpusph",
            "dualsphysics",
            "trixi",
            "0.5*derived",
            "0.01*rule10",
        ] {
            let spec: C0Spec = s.parse().unwrap();
            assert_eq!(spec.to_string(), s);
        }
        assert!("2*nonsense".parse::<C0Spec>().is_err());
        assert!("x*rule10".parse::<C0Spec>().is_err());
        assert!("derived:".parse::<C0Spec>().is_err());
        assert!("derived-eps:0".parse::<C0Spec>().is_err());
        assert!("derived-eps:x".parse::<C0Spec>().is_err());
    }

    #[test]
    fn flags_override_and_re_p_exclude_each_other() {
        let mut over = toml::Table::new();
        over.insert("p".into(), toml::Value::Float(0.01));
        let scene = Scene::load(None, over).unwrap();
        assert_eq!((scene.re, scene.p), (None, Some(0.01)));
    }
}
