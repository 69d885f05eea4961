//! What can be wrong with an environment map, and the sizes one may have: shared by the
//! file readers ([`crate::formats::environment_map`]), which check a header's size before
//! allocating, and [`super::Environment`], which checks texels however they came.

use std::path::PathBuf;

/// Largest width or height accepted, in texels: a 16K equirectangular map.
pub const MAX_SIDE: u32 = 16384;

/// Largest number of level-0 texels accepted: a 16384×8192 map, the largest equirectangular
/// size in common use. It bounds what an untrusted header can make us allocate (1.5 GiB of
/// f32 RGB, plus a third of that for the mip chain).
pub const MAX_TEXELS: u64 = 16384 * 8192;

/// What is wrong with a map's size or texels, wherever they came from.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ContentError {
    /// A side is zero or above [`MAX_SIDE`], or there are more than [`MAX_TEXELS`] texels.
    #[error(
        "{width}x{height} texels: each side must be 1..={MAX_SIDE} and the map at most {MAX_TEXELS} texels"
    )]
    Size { width: u64, height: u64 },
    /// The texel slice does not hold `width·height` texels.
    #[error("{count} texels given for a {width}x{height} map")]
    Count {
        width: u32,
        height: u32,
        count: usize,
    },
    /// A texel is not finite or has a negative channel.
    #[error("texel ({col}, {row}) holds {value:?}: radiance must be finite and non-negative")]
    Texel { col: u32, row: u32, value: [f32; 3] },
    /// A file's texel is more negative than the map's mean radiance: signed data, not the
    /// small negative residue that [`Environment::load`](super::Environment::load) clamps.
    #[error(
        "texel ({col}, {row}) holds {value:?}, more negative than the map's mean radiance \
         {mean:.3e}: not a radiance map"
    )]
    Negative {
        col: u32,
        row: u32,
        value: [f32; 3],
        mean: f64,
    },
}

/// Why an environment could not be made or read.
#[derive(Debug, thiserror::Error)]
pub enum EnvironmentError {
    /// The file could not be opened or read.
    #[error("environment {path}: {source}")]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    /// The file name ends in neither `.hdr` nor `.exr`.
    #[error(
        "environment {path}: unknown extension, expected .hdr (Radiance RGBE) or .exr (OpenEXR)"
    )]
    UnknownExtension { path: PathBuf },
    /// The Radiance decoder rejected the file: a bad header, truncated or corrupt pixels.
    #[error(
        "environment {path}: not a readable Radiance .hdr file (truncated or corrupt): {source}"
    )]
    Hdr {
        path: PathBuf,
        source: hdr_image::ImageError,
    },
    /// The OpenEXR reader rejected the file: a bad header, truncated or corrupt pixels.
    #[error("environment {path}: not a readable OpenEXR file (truncated or corrupt): {source}")]
    Exr {
        path: PathBuf,
        source: exr::error::Error,
    },
    /// The file is readable but not usable as an environment (no RGB layer, subsampled
    /// channels, an oversized header).
    #[error("environment {path}: {message}")]
    Invalid { path: PathBuf, message: String },
    /// The file's size or texels are out of bounds.
    #[error("environment {path}: {problem}")]
    Content {
        path: PathBuf,
        problem: ContentError,
    },
    /// Texels given to [`Environment::from_texels`](super::Environment::from_texels) are out of bounds.
    #[error("environment texels: {0}")]
    Texels(ContentError),
    /// An empty `--env` word.
    #[error(
        "environment source is empty: give none, default, studio, sky, overcast, interior, uniform or a file path"
    )]
    EmptySource,
}

/// Sides 1..=MAX_SIDE and at most MAX_TEXELS texels (u64 so that a header's sizes cannot
/// overflow the product).
pub(crate) fn check_size(width: u64, height: u64) -> Result<(), ContentError> {
    let side = 1..=MAX_SIDE as u64;
    if !side.contains(&width) || !side.contains(&height) || width * height > MAX_TEXELS {
        return Err(ContentError::Size { width, height });
    }
    Ok(())
}
