//! Reading a scene in layers: the embedded default, then a scene file, then
//! flags, each overriding field by field.

use std::path::Path;

use super::{Scene, SceneError};

/// The built-in scene (src/model/config/default_scene.toml).
pub const DEFAULT_SCENE: &str = include_str!("default_scene.toml");

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
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flags_override_and_re_p_exclude_each_other() {
        let mut over = toml::Table::new();
        over.insert("p".into(), toml::Value::Float(0.01));
        let scene = Scene::load(None, over).unwrap();
        assert_eq!((scene.re, scene.p), (None, Some(0.01)));
    }
}
