//! What is wrong with a scene: the errors of reading and parsing a scene file, and the checks
//! that name the field outside what clothbake accepts.

use super::MAX_SCENE_FILE_BYTES;
use std::path::PathBuf;

/// What is wrong with a scene's text: TOML that does not read as a scene, or a field outside
/// what clothbake accepts.
#[derive(Debug, thiserror::Error)]
pub enum SceneParseError {
    #[error("{0}")]
    Toml(#[from] toml::de::Error),
    #[error("field '{field}': {message}")]
    Field { field: String, message: String },
}

pub(super) fn field_error(field: impl Into<String>, message: impl Into<String>) -> SceneParseError {
    SceneParseError::Field {
        field: field.into(),
        message: message.into(),
    }
}

pub(super) fn check_range(
    field: &str,
    value: f64,
    lo: f64,
    hi: f64,
) -> Result<(), SceneParseError> {
    if value.is_finite() && (lo..=hi).contains(&value) {
        Ok(())
    } else {
        Err(field_error(
            field,
            format!("must be a number in [{lo}, {hi}], got {value}"),
        ))
    }
}

pub(super) fn check_vector(
    field: &str,
    value: [f64; 3],
    bound: f64,
) -> Result<(), SceneParseError> {
    if value.iter().all(|v| v.is_finite() && v.abs() <= bound) {
        Ok(())
    } else {
        Err(field_error(
            field,
            format!("every component must be a finite number within ±{bound}, got {value:?}"),
        ))
    }
}

pub(super) fn check_color(field: &str, value: [f64; 3]) -> Result<(), SceneParseError> {
    if value
        .iter()
        .all(|v| v.is_finite() && (0.0..=1e6).contains(v))
    {
        Ok(())
    } else {
        Err(field_error(
            field,
            format!("every component must be in [0, 1e6], got {value:?}"),
        ))
    }
}

/// Why a scene file was rejected.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    #[error("scene file {path}: {source}")]
    Read {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("scene file {path}: is {size} bytes, over the {MAX_SCENE_FILE_BYTES}-byte limit")]
    TooLarge { path: PathBuf, size: u64 },
    #[error("scene file {path}: {source}")]
    Invalid {
        path: PathBuf,
        source: SceneParseError,
    },
}
