//! A scene's errors, and the guards every field shares: each error names the
//! field, its flag and the fix.

use crate::format::fmt_value;

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
    /// [`SceneError::Invalid`] naming where the value came from (a scene
    /// file, a sweep's field) instead of the flag: see
    /// [`SceneError::from_origin`].
    #[error("invalid `{field}` ({origin}): {message}")]
    InvalidFrom {
        field: &'static str,
        origin: String,
        message: String,
    },
}

impl SceneError {
    /// The field an invalid value is in.
    pub fn field(&self) -> Option<&'static str> {
        match self {
            SceneError::Invalid { field, .. } | SceneError::InvalidFrom { field, .. } => {
                Some(field)
            }
            _ => None,
        }
    }

    /// This error naming where its value came from (`scene file s.toml`,
    /// `sweep field `n` (flag --n)`) in place of the field's flag: a value
    /// read from a file is not labelled with a flag the user never typed.
    pub fn from_origin(self, origin: impl Into<String>) -> SceneError {
        match self {
            SceneError::Invalid { field, message, .. }
            | SceneError::InvalidFrom { field, message, .. } => SceneError::InvalidFrom {
                field,
                origin: origin.into(),
                message,
            },
            other => other,
        }
    }

    /// The flag that sets `field` in a scene (`n_layers`: `n`).
    pub fn flag_of(field: &'static str) -> &'static str {
        flag_of(field)
    }

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
        "horizon_span" => "horizon-span",
        "viscous_dt" => "viscous-dt",
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
    use super::flag_of;

    /// Every field of a scene is named by its flag as the command line
    /// spells it (`_` as `-`, `n_layers` as `n`): a field added to the
    /// scene without its arm above fails here, not in a user's message.
    #[test]
    fn every_scene_field_is_named_by_its_flag() {
        let scene = crate::config::Scene::load(None, toml::Table::new()).unwrap();
        let table = toml::Table::try_from(&scene).unwrap();
        assert!(table.len() > 20, "{table:?}");
        for key in table.keys() {
            let field: &'static str = Box::leak(key.clone().into_boxed_str());
            let flag = if key == "n_layers" {
                "n".to_string()
            } else {
                key.replace('_', "-")
            };
            assert_eq!(flag_of(field), flag, "field {key}");
        }
    }
}
