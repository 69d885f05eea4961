//! Scene files (TOML): the fabrics a scene uses and its error or memory budget, so that
//! `bake --scene` bakes only what the scene needs.
//!
//! ```toml
//! fabrics = ["polyester_satin_charmeuse", "velvet"]  # names in the fabric file
//! fabric_file = "my_fabrics.toml"   # optional; relative to the scene file; default built-in
//! layout = "grid4d"                 # optional; default the default layout
//! [budget]                          # optional; at most one of the two
//! max_error = 0.05                  # relative RMS on uniform and highlight pairs
//! max_bytes_per_fabric = 16777216   # texel bytes per table
//! ```

use crate::table::Layout;
use serde::Deserialize;
use std::path::{Path, PathBuf};

/// Largest scene file read.
pub const MAX_SCENE_FILE_BYTES: u64 = 1 << 20;

/// What a scene asks of the baker.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    pub fabrics: Vec<String>,
    #[serde(default)]
    pub fabric_file: Option<PathBuf>,
    #[serde(default)]
    pub layout: Option<String>,
    #[serde(default)]
    pub budget: Budget,
}

/// A scene's accuracy or memory budget.
#[derive(Clone, Copy, Debug, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Budget {
    pub max_error: Option<f64>,
    pub max_bytes_per_fabric: Option<u64>,
}

/// Why a scene file was rejected.
#[derive(Debug, thiserror::Error)]
#[error("scene file {path}: {message}")]
pub struct SceneError {
    pub path: PathBuf,
    pub message: String,
}

impl Scene {
    /// Reads and validates a scene file; `fabric_file` comes back resolved against the
    /// scene's directory.
    pub fn load(path: &Path) -> Result<Self, SceneError> {
        let fail = |message: String| SceneError {
            path: path.to_path_buf(),
            message,
        };
        let size = std::fs::metadata(path)
            .map_err(|e| fail(e.to_string()))?
            .len();
        if size > MAX_SCENE_FILE_BYTES {
            return Err(fail(format!(
                "is {size} bytes, over the {MAX_SCENE_FILE_BYTES}-byte limit"
            )));
        }
        let text = std::fs::read_to_string(path).map_err(|e| fail(e.to_string()))?;
        let mut scene: Scene = toml::from_str(&text).map_err(|e| fail(e.to_string()))?;
        scene.validate().map_err(fail)?;
        if let Some(file) = &scene.fabric_file {
            let base = path.parent().unwrap_or(Path::new(""));
            scene.fabric_file = Some(base.join(file));
        }
        Ok(scene)
    }

    fn validate(&self) -> Result<(), String> {
        if self.fabrics.is_empty() {
            return Err("field 'fabrics': names no fabric".into());
        }
        if let Some(name) = &self.layout {
            Layout::from_name(name)
                .ok_or_else(|| format!("field 'layout': unknown layout '{name}'"))?;
        }
        match (self.budget.max_error, self.budget.max_bytes_per_fabric) {
            (Some(_), Some(_)) => {
                Err("field 'budget': give max_error or max_bytes_per_fabric, not both".into())
            }
            (Some(e), None) if !(e.is_finite() && e > 0.0) => Err(format!(
                "field 'budget.max_error': must be a positive number, got {e}"
            )),
            (None, Some(0)) => Err("field 'budget.max_bytes_per_fabric': must be positive".into()),
            _ => Ok(()),
        }
    }

    /// The scene's layout, or `default` when it names none.
    pub fn layout_or(&self, default: Layout) -> Layout {
        self.layout
            .as_deref()
            .and_then(Layout::from_name)
            .unwrap_or(default)
    }
}
