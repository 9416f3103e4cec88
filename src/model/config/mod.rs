//! The configuration layer, the lowest of `src/`: a scene fixes one run (the
//! kernel, the lattice, the flow, the sound speed c0 as a number or a typed
//! rule, the start and the end). It is read from TOML (the embedded default,
//! then a scene file, then flags, each overriding field by field) and
//! resolved against the kernel by `crate::problem` into the numbers the
//! solver uses. Every invalid value gets an error naming the field, its flag
//! and the fix. Imports nothing from the problem, the solver or above.
//!
//! One job per file: [`scene`] the fields and their defaults, [`overlay`]
//! reading TOML in layers, [`c0_spec`] the c0 rule as a typed value,
//! [`h_over_d`] h/d as one exact type,
//! [`lookup`] the kernel and discretisation a scene names, [`error`] the
//! errors and the guards shared by every field, [`bounds`] the bound of
//! every count a command takes (seeds, threads, points, repeats).

pub mod bounds;
pub mod c0_spec;
pub mod error;
pub mod h_over_d;
pub mod lookup;
pub mod overlay;
pub mod scene;

pub use c0_spec::{
    c0_help, c0_syntax, entry_of, C0Rule, C0Spec, RuleEntry, RuleFlow, RuleKind,
    DEFAULT_TECHNICAL_EPS0, MORRIS_DELTA, RULE10, RULES,
};
pub use error::{check_alpha, SceneError};
pub(crate) use error::{invalid, positive};
pub use h_over_d::HOverD;
pub use lookup::{discretisation, kernel_info};
pub use overlay::{overlay, DEFAULT_SCENE};
pub use scene::{
    ClassRules, HorizonKind, Initial, PressureForm, Scene, ViscousNormalisation, WallVelocity,
    DEFAULT_ALPHA,
};
