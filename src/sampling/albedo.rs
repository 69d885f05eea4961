//! The directional albedo of a fabric estimated with its sampler: one outgoing direction,
//! a curve over elevations (`clothbake albedo`), and a map over the hemisphere of outgoing
//! directions; and the Hammersley points they draw with.

use super::{Sampler, azimuth_of, direction, grid_elevation, grid_row};
use glam::DVec3;
use rayon::prelude::*;
use std::f64::consts::TAU;

/// The directional albedo `∫ F(wi, wo) dwi` (RGB) over the upper hemisphere for `wo`,
/// estimated by importance sampling with `samples` stratified draws (a 2D grid in u1, u2,
/// u3 by the Hammersley rule) of `sampler`, F by `f`. Also returns the standard deviation of
/// the mean channel of one weight F/pdf, which bounds the estimate's error.
pub fn directional_albedo(
    sampler: &Sampler,
    f: impl Fn(DVec3, DVec3) -> DVec3,
    wo: DVec3,
    samples: usize,
) -> (DVec3, f64) {
    let mut sum = DVec3::ZERO;
    let (mut mean, mut m2) = (0.0, 0.0);
    for k in 0..samples {
        let u = hammersley(k as u32, samples as u32);
        let weight = sampler
            .sample(wo, u)
            .map(|s| f(s.wi, wo) / s.pdf)
            .unwrap_or(DVec3::ZERO);
        sum += weight;
        // Welford's running variance of the channel mean.
        let x = (weight.x + weight.y + weight.z) / 3.0;
        let delta = x - mean;
        mean += delta / (k + 1) as f64;
        m2 += delta * (x - mean);
    }
    let n = samples.max(1) as f64;
    (sum / n, (m2 / (n - 1.0).max(1.0)).sqrt())
}

/// Point `k` of an `n`-point 3D Hammersley set: (k + ½)/n, the base-2 radical inverse of k,
/// the base-3 radical inverse of k; all in [0, 1).
pub fn hammersley(k: u32, n: u32) -> [f64; 3] {
    let radical = |mut k: u32, base: u32| {
        let (mut inv, mut f) = (0.0, 1.0 / base as f64);
        while k > 0 {
            inv += (k % base) as f64 * f;
            k /= base;
            f /= base as f64;
        }
        inv
    };
    [(k as f64 + 0.5) / n as f64, radical(k, 2), radical(k, 3)]
}

/// Outgoing elevations (degrees) at which [`albedo_curve`] measures the albedo.
pub const ALBEDO_ELEVATIONS_DEG: [f64; 11] = [
    1.0, 2.0, 5.0, 10.0, 20.0, 30.0, 45.0, 60.0, 75.0, 85.0, 90.0,
];
/// Outgoing azimuths per elevation, evenly spaced from thread 1.
pub const ALBEDO_AZIMUTHS: usize = 8;

/// The directional albedo at one outgoing elevation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AlbedoRow {
    pub elevation_deg: f64,
    /// Mean over the azimuths of ∫F dwi (RGB).
    pub mean: DVec3,
    /// The largest channel mean of ∫F dwi over the azimuths, and the azimuth (degrees).
    pub max: (f64, f64),
    /// The largest standard error (channel mean) of one azimuth's estimate.
    pub standard_error: f64,
}

/// The directional albedo `∫ F(wi, wo) dwi` of a fabric over outgoing elevation
/// ([`ALBEDO_ELEVATIONS_DEG`] × [`ALBEDO_AZIMUTHS`] azimuths), by importance sampling with
/// `samples` draws per direction; directions in parallel, deterministic.
pub fn albedo_curve(
    sampler: &Sampler,
    f: impl Fn(DVec3, DVec3) -> DVec3 + Sync,
    samples: usize,
) -> Vec<AlbedoRow> {
    ALBEDO_ELEVATIONS_DEG
        .iter()
        .map(|&elevation| {
            let estimates: Vec<(DVec3, f64, f64)> = (0..ALBEDO_AZIMUTHS)
                .into_par_iter()
                .map(|k| {
                    let azimuth = 360.0 * k as f64 / ALBEDO_AZIMUTHS as f64;
                    let wo = direction(elevation.to_radians(), azimuth.to_radians());
                    let (albedo, sigma) = directional_albedo(sampler, &f, wo, samples);
                    (albedo, sigma / (samples as f64).sqrt(), azimuth)
                })
                .collect();
            let mean = estimates.iter().map(|e| e.0).sum::<DVec3>() / estimates.len() as f64;
            let channel_mean = |v: DVec3| (v.x + v.y + v.z) / 3.0;
            let max = estimates
                .iter()
                .map(|e| (channel_mean(e.0), e.2))
                .fold((f64::MIN, 0.0), |a, b| if b.0 > a.0 { b } else { a });
            let standard_error = estimates.iter().map(|e| e.1).fold(0.0, f64::max);
            AlbedoRow {
                elevation_deg: elevation,
                mean,
                max,
                standard_error,
            }
        })
        .collect()
}

/// Rows (outgoing elevations) of an [`AlbedoMap`]: row i at elevation 90°·(i/(rows − 1))^1.5,
/// dense at the horizon where the albedo changes fastest (as the sampler's nodes), row 0 at
/// [`GRAZING_NODE_DEG`] (F vanishes at exactly 0°). A fetch's row coordinate is
/// (elevation/90°)^(2/3)·(rows − 1).
pub const ALBEDO_MAP_ELEVATIONS: usize = 33;
/// Columns (outgoing azimuths) of an [`AlbedoMap`]: column j at 360°·j/(columns − 1), so the
/// last column repeats the first and a clamped bilinear fetch wraps the azimuth.
pub const ALBEDO_MAP_AZIMUTHS: usize = 65;

/// The directional albedo `∫ F(wi, wo) dwi` (RGB) on a grid of outgoing directions in the
/// cloth frame: what a uniform ambient radiance `L_a` reflects, `L_o(wo) = L_a · albedo(wo)`
/// (the model's F holds every cosine). Row-major, [`ALBEDO_MAP_AZIMUTHS`] columns of azimuth
/// from thread 1 (x) towards thread 2 (y) per row of elevation ([`ALBEDO_MAP_ELEVATIONS`]).
#[derive(Clone, Debug, PartialEq)]
pub struct AlbedoMap {
    pub rgb: Vec<[f32; 3]>,
    /// The largest standard error (channel mean) of one node's estimate.
    pub standard_error: f64,
}

impl AlbedoMap {
    /// The map of F = `f`, each node by [`directional_albedo`] with `samples` draws of
    /// `sampler`; nodes in parallel, deterministic.
    pub fn build(
        sampler: &Sampler,
        f: impl Fn(DVec3, DVec3) -> DVec3 + Sync,
        samples: usize,
    ) -> Self {
        let nodes: Vec<([f32; 3], f64)> = (0..ALBEDO_MAP_ELEVATIONS * ALBEDO_MAP_AZIMUTHS)
            .into_par_iter()
            .map(|n| {
                let (i, j) = (n / ALBEDO_MAP_AZIMUTHS, n % ALBEDO_MAP_AZIMUTHS);
                let elevation = grid_elevation(i, ALBEDO_MAP_ELEVATIONS);
                let azimuth = TAU * j as f64 / (ALBEDO_MAP_AZIMUTHS - 1) as f64;
                let (albedo, sigma) =
                    directional_albedo(sampler, &f, direction(elevation, azimuth), samples);
                (albedo.as_vec3().to_array(), sigma / (samples as f64).sqrt())
            })
            .collect();
        Self {
            rgb: nodes.iter().map(|n| n.0).collect(),
            standard_error: nodes.iter().map(|n| n.1).fold(0.0, f64::max),
        }
    }

    /// The map's bilinear interpolation at `wo` (unit, wo.z ≥ 0), as a GPU's clamped
    /// bilinear fetch of the map as a texture reads it.
    pub fn at(&self, wo: DVec3) -> DVec3 {
        let y = grid_row(wo, ALBEDO_MAP_ELEVATIONS);
        let x = azimuth_of(wo) / TAU * (ALBEDO_MAP_AZIMUTHS - 1) as f64;
        let (i0, j0) = (
            (y as usize).min(ALBEDO_MAP_ELEVATIONS - 2),
            (x as usize).min(ALBEDO_MAP_AZIMUTHS - 2),
        );
        let (fy, fx) = (y - i0 as f64, x - j0 as f64);
        let node =
            |i: usize, j: usize| DVec3::from(self.rgb[i * ALBEDO_MAP_AZIMUTHS + j].map(f64::from));
        (node(i0, j0) * (1.0 - fx) + node(i0, j0 + 1) * fx) * (1.0 - fy)
            + (node(i0 + 1, j0) * (1.0 - fx) + node(i0 + 1, j0 + 1) * fx) * fy
    }
}

/// The albedo curve as a text table (what `clothbake albedo` prints for one fabric).
pub fn describe_albedo(name: &str, rows: &[AlbedoRow], samples: usize) -> String {
    use std::fmt::Write;
    let mut out = format!(
        "{name}: directional albedo ∫F dwi over outgoing elevation (mean of {ALBEDO_AZIMUTHS} \
         azimuths, {samples} importance samples each)\n  elevation        R        G        B   \
         max (RGB mean) at azimuth   std. error\n"
    );
    for row in rows {
        let _ = writeln!(
            out,
            "  {:>8.0}° {:>8.4} {:>8.4} {:>8.4}   {:>8.4} at {:>5.1}°        {:.1e}",
            row.elevation_deg,
            row.mean.x,
            row.mean.y,
            row.mean.z,
            row.max.0,
            row.max.1,
            row.standard_error
        );
    }
    if let Some(top) = rows.iter().max_by(|a, b| a.max.0.total_cmp(&b.max.0)) {
        let _ = writeln!(
            out,
            "  maximum: {:.4} (RGB mean) at elevation {:.0}°, azimuth {:.1}°",
            top.max.0, top.elevation_deg, top.max.1
        );
    }
    out
}
