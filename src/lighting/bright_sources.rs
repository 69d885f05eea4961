//! Compact bright sources of an environment (the sun, lamps) taken out of the map as distant
//! lights, leaving a soft residual map.
//!
//! # Why
//!
//! A renderer lights cloth from a map with K directions per pixel drawn from the fabric's
//! sampler, each read from the prefiltered map. When a few compact sources carry much of the
//! light (a 0.5° sun of radiance 3.5·10⁴ over a sky near 1 carries much of it), those K
//! directions rarely meet them, and the image is far off at any affordable K. A compact
//! source is instead what a directional light already is: one table lookup gives it exactly,
//! up to its size. So the map is split into `L = L_residual + Σ_sources L_source`, the
//! sources become directional lights, and the residual, whose radiance is bounded by the
//! threshold below, is left to the K samples, where it is low-variance.
//!
//! # The split
//!
//! Texels of level 0 brighter than `THRESHOLD_OVER_MEAN` times the map's mean luminance
//! (mean of RGB, solid-angle weighted) are grouped into connected regions (8-neighbours,
//! wrapping in u). A region of angular radius above [`MAX_SOURCE_RADIUS_DEG`] is not a
//! compact source (a window, the aureole around the sun): its own brightest part is looked
//! for again at four times the threshold, until what remains is compact or nothing is left.
//! Each compact region keeps, per texel, the radiance up to its threshold in the residual
//! (scaled to luminance τ, keeping the colour), and gives the excess to its light:
//!
//! ```text
//! E_source = Σ_texels (L − L·τ/Y)·Ω_texel        (RGB irradiance, perpendicular)
//! ω_source ∝ Σ_texels (Y − τ)·Ω_texel·ω_texel     (its centroid)
//! ```
//!
//! so that nothing is lost or counted twice: the residual's and the lights' irradiances
//! add up to the map's. The [`MAX_SOURCES`] most powerful regions become lights, and only
//! those that carry at least [`MIN_SOURCE_SHARE`] of the map's power; the others stay in the
//! residual.

use glam::{DVec2, DVec3, Vec3};
use rayon::prelude::*;
use std::collections::BTreeMap;
use std::f64::consts::PI;

use super::{Environment, Level, equirect_direction};

/// Texels brighter than this multiple of the map's mean luminance may belong to a source:
/// high enough that the studio's soft boxes and a clear sky's aureole stay in the residual,
/// low enough that the interior's lamps are found (the built-in maps' peaks over their
/// means: docs/notebook/2026-12-07-figures-from-comments-issue-47.md).
pub const THRESHOLD_OVER_MEAN: f64 = 16.0;

/// The widest source taken as one directional light, in degrees of angular radius: a
/// light that wide gives a highlight about as wide as the satins' 2.5° lobe, where shading
/// it from its centre starts to show.
pub const MAX_SOURCE_RADIUS_DEG: f64 = 3.0;

/// At most this many sources become lights: one table lookup each per pixel.
pub const MAX_SOURCES: usize = 8;

/// A source carrying less than this share of the map's power stays in the residual: a
/// light per pixel for it would cost more than the error it removes.
pub const MIN_SOURCE_SHARE: f64 = 0.005;

/// A compact source taken out of a map: a directional light.
#[derive(Clone, Debug, PartialEq)]
pub struct DistantSource {
    /// Unit direction towards it (its centroid, weighted by the radiance taken).
    pub direction: DVec3,
    /// RGB perpendicular irradiance it gives: `E` with `L_o = E·F(wi, wo)`.
    pub irradiance: DVec3,
    /// Largest angle from `direction` to a texel of it (centre plus half a texel), radians.
    pub angular_radius: f64,
    /// Radius of the uniform disk with the source's spread, radians: `√(2·⟨θ²⟩)`, θ the
    /// angle of a texel from `direction` weighted by its excess (a uniform disk of radius
    /// r has ⟨θ²⟩ = r²/2). The renderer sets the source over this disk at the horizon
    /// ([`disk_above_horizon`]).
    pub disk_radius: f64,
    /// The same light as at most [`MAX_PARTS`] pieces, `(direction, irradiance)`: its texels
    /// gathered in blocks of 2ᵏ×2ᵏ, each at its own centroid. Their irradiances sum to
    /// `irradiance`; a reference integrates F over the source's extent with them.
    pub parts: Vec<(DVec3, DVec3)>,
}

/// Most pieces a source is kept as ([`DistantSource::parts`]): with the 3° sources at most,
/// blocks of at most 0.4° (under a fifth of the satins' lobe) at any map size.
pub const MAX_PARTS: usize = 64;

/// A map split into compact sources and what remains.
#[derive(Clone, Debug, PartialEq)]
pub struct SplitEnvironment {
    /// The map without its sources: texels of the sources are scaled down to their
    /// region's threshold.
    pub residual: Environment,
    /// The sources, most powerful first; at most [`MAX_SOURCES`].
    pub sources: Vec<DistantSource>,
}

/// A connected region of bright texels (indices into level 0) and the luminance above
/// which it was found.
struct Region {
    texels: Vec<usize>,
    threshold: f64,
}

fn luminance(t: [f32; 3]) -> f64 {
    (t[0] as f64 + t[1] as f64 + t[2] as f64) / 3.0
}

/// The connected regions (8-neighbours, wrapping in u) of the texels in `members`, which
/// must be sorted.
fn connected_regions(level: &Level, members: &[usize]) -> Vec<Vec<usize>> {
    let (width, height) = (level.width() as usize, level.height() as usize);
    let mut seen = vec![false; members.len()];
    let slot = |index: usize| members.binary_search(&index).ok();
    let mut regions = Vec::new();
    for start in 0..members.len() {
        if seen[start] {
            continue;
        }
        seen[start] = true;
        let mut region = vec![members[start]];
        let mut next = 0;
        while next < region.len() {
            let index = region[next];
            next += 1;
            let (col, row) = (index % width, index / width);
            for dr in [-1i64, 0, 1] {
                let r = row as i64 + dr;
                if r < 0 || r >= height as i64 {
                    continue;
                }
                for dc in [-1i64, 0, 1] {
                    let c = (col as i64 + dc).rem_euclid(width as i64) as usize;
                    if let Some(s) = slot(r as usize * width + c)
                        && !seen[s]
                    {
                        seen[s] = true;
                        region.push(members[s]);
                    }
                }
            }
        }
        region.sort_unstable();
        regions.push(region);
    }
    regions
}

/// The centre direction of texel `index` of `level`.
fn texel_direction(level: &Level, index: usize) -> DVec3 {
    let width = level.width() as usize;
    equirect_direction(DVec2::new(
        ((index % width) as f64 + 0.5) / level.width() as f64,
        ((index / width) as f64 + 0.5) / level.height() as f64,
    ))
}

/// The region's light: its excess over the threshold, its centroid, its radius and its parts.
fn source_of(level: &Level, region: &Region) -> DistantSource {
    let width = level.width() as usize;
    // Per texel: its direction, the RGB irradiance of its excess, and the excess luminance
    // times its solid angle (the centroid's weight).
    let excess: Vec<(usize, DVec3, DVec3, f64)> = region
        .texels
        .iter()
        .map(|&index| {
            let texel = level.texels()[index];
            let y = luminance(texel);
            let solid_angle = level.texel_solid_angle((index / width) as u32);
            let rgb = DVec3::new(texel[0] as f64, texel[1] as f64, texel[2] as f64);
            let irradiance = rgb * (1.0 - region.threshold / y) * solid_angle;
            let weight = (y - region.threshold) * solid_angle;
            (index, texel_direction(level, index), irradiance, weight)
        })
        .collect();
    let irradiance: DVec3 = excess.iter().map(|e| e.2).sum();
    let direction = excess
        .iter()
        .map(|e| e.1 * e.3)
        .sum::<DVec3>()
        .normalize_or(DVec3::Y);
    // Half a texel's diagonal at the equator: the angle a texel's centre can be off its edge.
    let half_texel = 0.5 * (PI / level.height() as f64) * 2f64.sqrt();
    // Each texel's angle from the centroid, and its weight.
    let angles: Vec<(f64, f64)> = excess
        .iter()
        .map(|e| (e.1.dot(direction).clamp(-1.0, 1.0).acos(), e.3))
        .collect();
    let angular_radius = angles.iter().map(|a| a.0).fold(0.0, f64::max) + half_texel;
    let (moment, total_weight) = angles.iter().fold((0.0, 0.0), |(m, t), &(angle, w)| {
        (m + w * angle * angle, t + w)
    });
    let mean_square_angle = moment / f64::max(total_weight, f64::MIN_POSITIVE);
    let disk_radius = (2.0 * mean_square_angle).sqrt();
    // The smallest blocks of 2ᵏ×2ᵏ texels that leave at most MAX_PARTS pieces (a block that
    // straddles the seam is two pieces, which only happens once blocks are large), in the
    // blocks' order, so that the parts are the same on every run.
    let mut shift = 0;
    let parts = loop {
        let mut blocks: BTreeMap<(usize, usize), (DVec3, DVec3)> = BTreeMap::new();
        for &(index, dir, e, weight) in &excess {
            let block = blocks
                .entry(((index / width) >> shift, (index % width) >> shift))
                .or_default();
            block.0 += dir * weight;
            block.1 += e;
        }
        if blocks.len() <= MAX_PARTS {
            break blocks
                .into_values()
                .map(|(centroid, e)| (centroid.normalize_or(direction), e))
                .collect();
        }
        shift += 1;
    };
    DistantSource {
        direction,
        irradiance,
        angular_radius,
        disk_radius,
        parts,
    }
}

/// The compact regions of the texels above `threshold` among `candidates` (sorted), with
/// their sources, raising the threshold four-fold inside any region that is too wide.
fn compact_regions(
    level: &Level,
    candidates: &[usize],
    threshold: f64,
    out: &mut Vec<(Region, DistantSource)>,
) {
    let members: Vec<usize> = candidates
        .iter()
        .copied()
        .filter(|&i| luminance(level.texels()[i]) > threshold)
        .collect();
    for texels in connected_regions(level, &members) {
        let region = Region { texels, threshold };
        let source = source_of(level, &region);
        if source.angular_radius <= MAX_SOURCE_RADIUS_DEG.to_radians() {
            out.push((region, source));
        } else {
            compact_regions(level, &region.texels, 4.0 * threshold, out);
        }
    }
}

impl Environment {
    /// The map split into at most `max_sources` compact bright sources and a residual (see
    /// the module documentation). With `max_sources` = 0, or a map without such sources,
    /// the residual is the map itself.
    pub fn split_bright_sources(&self, max_sources: usize) -> SplitEnvironment {
        let level = &self.levels()[0];
        let mean = self.mean_radiance().element_sum() / 3.0;
        let threshold = THRESHOLD_OVER_MEAN * mean;
        let mut regions = Vec::new();
        if max_sources > 0 && threshold > 0.0 {
            let candidates: Vec<usize> = (0..level.texels().len())
                .into_par_iter()
                .filter(|&i| luminance(level.texels()[i]) > threshold)
                .collect();
            compact_regions(level, &candidates, threshold, &mut regions);
        }
        let power = 4.0 * PI * mean;
        let mut found: Vec<(Region, DistantSource)> = regions
            .into_iter()
            .filter(|(_, source)| source.irradiance.element_sum() / 3.0 >= MIN_SOURCE_SHARE * power)
            .collect();
        // Most powerful first; ties (symmetric maps) by direction, so the order is the same
        // on every run.
        found.sort_by(|(_, a), (_, b)| {
            let key = |s: &DistantSource| s.irradiance.element_sum();
            key(b).total_cmp(&key(a)).then(
                a.direction
                    .to_array()
                    .partial_cmp(&b.direction.to_array())
                    .unwrap_or(std::cmp::Ordering::Equal),
            )
        });
        found.truncate(max_sources);
        if found.is_empty() {
            return SplitEnvironment {
                residual: self.clone(),
                sources: Vec::new(),
            };
        }
        let mut texels = level.texels().to_vec();
        for (region, _) in &found {
            for &index in &region.texels {
                let y = luminance(texels[index]);
                let scale = (region.threshold / y) as f32;
                texels[index] = texels[index].map(|v| v * scale);
            }
        }
        let residual = Environment::from_texels(level.width(), level.height(), texels)
            .expect("scaling valid texels down keeps them valid");
        SplitEnvironment {
            residual,
            sources: found.into_iter().map(|(_, source)| source).collect(),
        }
    }
}

/// The part of a source's disk above the local horizon, for a source lit as one directional
/// light: its centre in direction `wi` (unit, local frame, z the normal), its angular radius
/// r given as `sin_radius`. Returns the direction of the visible part's centroid and the
/// visible fraction of the disk's solid angle; the source then gives
/// `fraction · E · F(centroid, wo)`. Lit at its centre alone, a source would go out at once
/// as its centre sets; the reference, which integrates the disk, sees it set over its
/// diameter (a 1.9° lamp across a fold of velvet).
///
/// Derivation, for r of a few degrees: in the disk's tangent plane, with y the offset
/// towards the zenith in units of r, a point of the disk is at elevation h + r·y (h the
/// centre's elevation), so the horizon cuts the unit disk at y = −d, d = h/r. The part
/// above is the circular segment y > −d: area A = π − acos d + d·√(1 − d²), so the
/// fraction is A/π, and centroid ȳ = ⅔·(1 − d²)^{3/2} / A. F grows about linearly with
/// elevation over a few degrees, so its mean over the segment is F at elevation
/// h + r·ȳ = r·(d + ȳ), at the centre's azimuth.
///
/// Twin of `source_disk_above_horizon` (shaders/lighting/source_disk.wgsl).
pub fn disk_above_horizon(wi: Vec3, sin_radius: f32) -> (Vec3, f32) {
    if wi.z >= sin_radius {
        return (wi, 1.0);
    }
    if wi.z <= -sin_radius {
        return (wi, 0.0);
    }
    let radius = sin_radius.asin();
    let d = (wi.z.asin() / radius).clamp(-1.0, 1.0);
    let s = (1.0 - d * d).max(0.0).sqrt();
    let area = std::f32::consts::PI - d.acos() + d * s;
    let centroid = (2.0 / 3.0) * s * s * s / area.max(1e-12);
    let elevation = radius * (d + centroid);
    let horizontal = wi.truncate() / wi.truncate().length().max(1e-12);
    (
        (horizontal * elevation.cos()).extend(elevation.sin()),
        area / std::f32::consts::PI,
    )
}

impl std::fmt::Display for SplitEnvironment {
    /// The sources in a few words: "2 bright sources lit as lights (E = 2.080 at 0.37°, …)",
    /// E the mean of the RGB irradiance, the angle the source's radius.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let n = self.sources.len();
        if n == 0 {
            return f.write_str("no compact bright source");
        }
        let plural = if n == 1 { "" } else { "s" };
        write!(f, "{n} bright source{plural} lit as light{plural} (")?;
        for (i, s) in self.sources.iter().enumerate() {
            let separator = if i == 0 { "" } else { ", " };
            write!(
                f,
                "{separator}E = {:.3} at {:.2}°",
                s.irradiance.element_sum() / 3.0,
                s.angular_radius.to_degrees()
            )?;
        }
        f.write_str(")")
    }
}
