//! Distant environment lighting: an equirectangular map of linear RGB radiance with a
//! prefiltered mip chain, read from a Radiance `.hdr` or OpenEXR `.exr` file or generated in
//! code (the built-in [`Environment::studio`] and the white furnace
//! [`Environment::uniform`]), and sampled on the CPU exactly as the GPU samples it.
//!
//! # Equirectangular mapping
//!
//! World space is right-handed with +y up. A unit world direction `d` maps to
//!
//! ```text
//! u = 0.5 + atan2(d.x, -d.z) / (2π)      in [0, 1]; 0 and 1 are the same seam
//! v = acos(clamp(d.y, -1, 1)) / π        in [0, 1]; 0 is straight up (+y)
//! ```
//!
//! so the middle of the map (u = 0.5) looks along -z, u = 0.75 along +x, u = 0.25 along -x
//! and the seam u = 0 ≡ 1 along +z. Back: with `φ = 2π(u - 0.5)` and `θ = πv`,
//! `d = (sin θ sin φ, cos θ, -sin θ cos φ)` ([`equirect_direction`]).
//!
//! Texel (col, row) of a `W`×`H` level covers u in `[col/W, (col+1)/W)` and v in
//! `[row/H, (row+1)/H)`: row 0 is the top row (around +y), texel centres lie at
//! `((col + 0.5)/W, (row + 0.5)/H)`. Texels are stored row-major from row 0.
//!
//! # Sampling
//!
//! [`Environment::radiance`] is the CPU mirror of WGSL's `textureSampleLevel` on this map
//! with a sampler that repeats in u, clamps to the edge in v and filters linearly within
//! and between levels: a shader port must use the same mapping and sampler. Level `l + 1`
//! is `max(1, W_l / 2)`×`max(1, H_l / 2)` (the sizes a GPU gives a mip chain), down to 1×1;
//! each of its texels is the solid-angle-weighted mean of the level-`l` texels it covers
//! (see [`Environment::levels`]), so every level keeps the map's mean radiance.
//!
//! For filtered importance sampling the caller compares the solid angle of a sample with
//! [`Environment::texel_solid_angle`]: a level's texels span four times the solid angle of
//! the level above, so a sample of solid angle `Ωs` reads level `0.5·log2(Ωs / Ωp)`.
//!
//! # Untrusted files
//!
//! Environment files come from users: the dimensions are read from the header and checked
//! against [`MAX_SIDE`](super::MAX_SIDE) and [`MAX_TEXELS`](super::MAX_TEXELS) before any texel is allocated, a truncated or
//! corrupt file is an error naming the file, and so is a texel that is not finite (naming the
//! texel as well). Nothing read from a file panics.
//!
//! Real HDR photographs hold a few slightly negative texels, the residue of filtering and
//! lossy compression (−3e-6 to −0.004 beside a mean radiance near 1, in 3 to 9,000 texels of
//! a 1024 × 512 map), which viewers and renderers clamp. [`Environment::load`] clamps them to
//! zero too and says how many it clamped ([`ClampedNegatives`]); a texel more negative than
//! the map's mean radiance is no such residue but signed data, and is refused by position.

use glam::{DVec2, DVec3};
use rayon::prelude::*;
use std::f64::consts::{PI, TAU};
use std::path::Path;

use super::GeneratedEnvironment;
use super::errors::{ContentError, EnvironmentError, check_size};
use super::mip::Level;
use crate::formats::environment_map::{read_exr, read_hdr};

/// The equirectangular coordinates `(u, v)` of a world direction (see the module
/// documentation). `direction` need not be unit length; a zero or non-finite one maps to
/// `(1, 0.5)` rather than to NaN.
pub fn equirect_uv(direction: DVec3) -> DVec2 {
    let d = direction.normalize_or_zero();
    DVec2::new(
        0.5 + d.x.atan2(-d.z) / TAU,
        d.y.clamp(-1.0, 1.0).acos() / PI,
    )
}

/// The unit world direction at equirectangular coordinates `uv`: the inverse of
/// [`equirect_uv`].
pub fn equirect_direction(uv: DVec2) -> DVec3 {
    let phi = TAU * (uv.x - 0.5);
    let theta = PI * uv.y;
    let (sin_theta, cos_theta) = theta.sin_cos();
    let (sin_phi, cos_phi) = phi.sin_cos();
    DVec3::new(sin_theta * sin_phi, cos_theta, -sin_theta * cos_phi)
}

/// The negative texels of a file that [`Environment::load`] clamped to zero.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClampedNegatives {
    /// Texels with at least one negative channel.
    pub texels: usize,
    /// The most negative channel value among them.
    pub most_negative: f32,
    /// Where it was: column and row of level 0.
    pub col: u32,
    pub row: u32,
}

impl std::fmt::Display for ClampedNegatives {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "clamped {} texel{} with a negative channel to 0 (the most negative, {:.3e}, at \
             ({}, {}))",
            self.texels,
            if self.texels == 1 { "" } else { "s" },
            self.most_negative,
            self.col,
            self.row
        )
    }
}

/// Distant environment lighting: an equirectangular radiance map and its mip chain.
#[derive(Clone, Debug, PartialEq)]
pub struct Environment {
    /// Level 0 at full resolution, then each halved, down to 1×1; never empty.
    levels: Vec<Level>,
    /// What loading the file clamped, if anything.
    clamped: Option<ClampedNegatives>,
}

impl Environment {
    /// An environment from `width`×`height` level-0 texels (row-major, row 0 the top row,
    /// linear RGB radiance). Any aspect ratio is accepted; sides must be 1..=[`MAX_SIDE`](super::MAX_SIDE),
    /// at most [`MAX_TEXELS`](super::MAX_TEXELS) in all, and every value finite and non-negative.
    pub fn from_texels(
        width: u32,
        height: u32,
        texels: Vec<[f32; 3]>,
    ) -> Result<Self, EnvironmentError> {
        Self::build(width, height, texels).map_err(EnvironmentError::Texels)
    }

    fn build(width: u32, height: u32, texels: Vec<[f32; 3]>) -> Result<Self, ContentError> {
        check_size(width as u64, height as u64)?;
        if texels.len() != width as usize * height as usize {
            return Err(ContentError::Count {
                width,
                height,
                count: texels.len(),
            });
        }
        check_texels(width, &texels)?;
        let mut levels = vec![Level::new(width, height, texels)];
        loop {
            let last = &levels[levels.len() - 1];
            if last.width() == 1 && last.height() == 1 {
                break;
            }
            let next = last.downsample();
            levels.push(next);
        }
        Ok(Self {
            levels,
            clamped: None,
        })
    }

    /// Reads an environment file, by extension (case-insensitive): `.hdr` (Radiance RGBE,
    /// the usual `-Y H +X W` orientation; an `EXPOSURE` line is ignored, as most loaders
    /// do) or `.exr` (the first layer with `R`, `G` and `B` channels, any sample type, other
    /// channels ignored). The dimensions are checked before pixels are decoded. Slightly
    /// negative texels are clamped to zero ([`Self::clamped_negatives`] says how many; see
    /// the module documentation); a texel that is not finite is refused by position.
    pub fn load(path: &Path) -> Result<Self, EnvironmentError> {
        let extension = path
            .extension()
            .map(|e| e.to_string_lossy().to_ascii_lowercase());
        let (width, height, mut texels) = match extension.as_deref() {
            Some("hdr") => read_hdr(path)?,
            Some("exr") => read_exr(path)?,
            _ => {
                return Err(EnvironmentError::UnknownExtension {
                    path: path.to_path_buf(),
                });
            }
        };
        let content = |problem| EnvironmentError::Content {
            path: path.to_path_buf(),
            problem,
        };
        let clamped = clamp_negatives(width, &mut texels).map_err(content)?;
        let mut environment = Self::build(width, height, texels).map_err(content)?;
        environment.clamped = clamped;
        Ok(environment)
    }

    /// The negative texels [`Self::load`] clamped to zero; None when there were none (and
    /// for maps not read from a file).
    pub fn clamped_negatives(&self) -> Option<&ClampedNegatives> {
        self.clamped.as_ref()
    }

    /// A constant environment of `radiance` in every direction and channel: with radiance 1
    /// the white furnace, in which an energy-conserving BRDF reflects at most 1. An 8×4 map
    /// is enough: every level of it is constant.
    ///
    /// # Panics
    /// If `radiance` is negative or not finite.
    pub fn uniform(radiance: f32) -> Self {
        assert!(
            radiance.is_finite() && radiance >= 0.0,
            "uniform environment radiance must be finite and non-negative, got {radiance}"
        );
        Self::from_texels(8, 4, vec![[radiance; 3]; 32]).expect("a constant map is valid")
    }

    /// The built-in studio environment, generated in code (no asset) and deterministic,
    /// 512×256 texels, each the value at its centre direction of:
    ///
    /// - a dim backdrop: warm grey at the horizon (0.30, 0.27, 0.23) fading to a cool grey
    ///   overhead (0.15, 0.18, 0.23), and a dark floor (0.045, 0.040, 0.035) below, blended
    ///   with a smoothstep from 0.2 below to 0.05 above the horizon;
    /// - three soft boxes, smooth lobes `peak·colour·exp(k·(cos α − 1))` around a direction
    ///   (α the angle from it; `k` sets the size, about `1/√k` radians across):
    ///   - key: up, front (+z) and left (−x), towards (−0.55, 0.62, 0.56), k = 30, peak 5,
    ///     warm white (1.0, 0.95, 0.88);
    ///   - fill: right (+x), low and front, towards (0.82, 0.25, 0.52), k = 18, peak 1.2,
    ///     cool (0.85, 0.92, 1.0), larger and dimmer;
    ///   - rim: behind (−z) and up, towards (0.2, 0.5, −0.84), k = 45, peak 4, white.
    ///
    /// Everything is smooth on the scale of a texel (the sharpest lobe is about 8.5° across,
    /// a texel 0.7°). Filtered importance sampling of cosine and Phong 10-50 lobes at lod
    /// `0.5·log2(Ωs/Ωp)` converges to the exact integral as samples are added
    /// (`tests/sampling/environment.rs`).
    pub fn studio() -> Self {
        GeneratedEnvironment::Studio.environment()
    }

    /// Level-0 width in texels.
    pub fn width(&self) -> u32 {
        self.levels[0].width()
    }

    /// Level-0 height in texels.
    pub fn height(&self) -> u32 {
        self.levels[0].height()
    }

    /// The mip chain: level 0 at full resolution, each next level `max(1, W/2)`×`max(1, H/2)`
    /// down to 1×1, each texel the mean of the parent texels it covers weighted by their
    /// solid angle (equirectangular rows near the poles cover less of the sphere), so every
    /// level has level 0's mean radiance. Upload these as the GPU texture's mips, rather
    /// than letting the GPU box-filter, to keep the weighting.
    pub fn levels(&self) -> &[Level] {
        &self.levels
    }

    /// The radiance arriving from `direction` (towards the environment; need not be unit
    /// length), filtered at level of detail `lod`: bilinear within a level (repeating in u,
    /// clamped in v), linear between the levels below and above `lod`, which is clamped to
    /// `[0, levels − 1]` (NaN reads as 0). The CPU mirror of `textureSampleLevel`.
    pub fn radiance(&self, direction: DVec3, lod: f64) -> DVec3 {
        let uv = equirect_uv(direction);
        let last = (self.levels.len() - 1) as f64;
        let lod = if lod.is_nan() {
            0.0
        } else {
            lod.clamp(0.0, last)
        };
        let lower = lod.floor();
        let t = lod - lower;
        let index = lower as usize;
        let a = self.levels[index].bilinear(uv);
        if t == 0.0 {
            return a;
        }
        a.lerp(self.levels[index + 1].bilinear(uv), t)
    }

    /// The solid angle of one level-0 texel around `direction`: `(2π/W)·(π/H)·sin θ`, θ the
    /// polar angle (the texel's u-by-v extent times the Jacobian of the mapping). It is 0 at
    /// the poles, where a filtered-importance-sampling LOD of `0.5·log2(Ωs / Ωp)` becomes
    /// infinite and [`Environment::radiance`] clamps it to the last level.
    pub fn texel_solid_angle(&self, direction: DVec3) -> f64 {
        let d = direction.normalize_or_zero();
        let sin_theta = (1.0 - d.y * d.y).max(0.0).sqrt();
        (TAU / self.width() as f64) * (PI / self.height() as f64) * sin_theta
    }

    /// The solid-angle-weighted mean radiance over the sphere (level 0). The irradiance
    /// the environment gives an unoccluded surface is π times this when it is uniform.
    pub fn mean_radiance(&self) -> DVec3 {
        self.levels[0].mean_radiance()
    }
}

/// Clamps a file's slightly negative texels to zero (see the module documentation). Refuses
/// the first texel that is not finite, or the most negative one when it is more negative
/// than the map's mean radiance (over every channel).
fn clamp_negatives(
    width: u32,
    texels: &mut [[f32; 3]],
) -> Result<Option<ClampedNegatives>, ContentError> {
    let at = |index: usize| {
        (
            (index % width as usize) as u32,
            (index / width as usize) as u32,
        )
    };
    if let Some(index) = texels
        .par_iter()
        .position_first(|t| t.iter().any(|v| !v.is_finite()))
    {
        let (col, row) = at(index);
        return Err(ContentError::Texel {
            col,
            row,
            value: texels[index],
        });
    }
    let most_negative = |t: &[f32; 3]| t[0].min(t[1]).min(t[2]);
    let negative = texels.par_iter().filter(|t| most_negative(t) < 0.0).count();
    if negative == 0 {
        return Ok(None);
    }
    let (index, lowest) = texels
        .iter()
        .map(most_negative)
        .enumerate()
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .expect("a negative texel exists");
    let (col, row) = at(index);
    let mean = texels
        .par_iter()
        .map(|t| t.iter().map(|&v| v as f64).sum::<f64>())
        .sum::<f64>()
        / (3 * texels.len()) as f64;
    if -(lowest as f64) > mean {
        return Err(ContentError::Negative {
            col,
            row,
            value: texels[index],
            mean,
        });
    }
    texels.par_iter_mut().for_each(|t| {
        for v in t {
            *v = v.max(0.0);
        }
    });
    Ok(Some(ClampedNegatives {
        texels: negative,
        most_negative: lowest,
        col,
        row,
    }))
}

/// The first texel that is not finite or has a negative channel, if any.
pub(crate) fn check_texels(width: u32, texels: &[[f32; 3]]) -> Result<(), ContentError> {
    match texels
        .par_iter()
        .position_first(|t| t.iter().any(|v| !v.is_finite() || *v < 0.0))
    {
        None => Ok(()),
        Some(index) => Err(ContentError::Texel {
            col: (index % width as usize) as u32,
            row: (index / width as usize) as u32,
            value: texels[index],
        }),
    }
}
