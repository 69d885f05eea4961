//! Layout `grid4d` (the baseline): a 4D grid over (wi, wo), each direction through the
//! hemi-octahedral map of [`super::octahedral`] at N×N, N = `resolution`.
//!
//! One plane, `grid4d`, of N²×N² texels with channels `reflection`, `transmission1`,
//! `transmission2` (the albedo-free terms of F, already divided by Q): texel (x, y) holds wo
//! at octahedral texel (x mod N, y mod N) and wi at (x div N, y div N), i.e. N×N tiles over
//! wi, each an N×N image over wo. Texel centres are at `(i + ½)/N`, so no texel lies on the
//! horizon. A lookup takes the octahedral coordinates `uv` of wi and wo, the continuous
//! texel coordinates `uv·N − ½`, and interpolates multilinearly between the 16 surrounding
//! texels, clamping indices to [0, N−1] (clamp-to-edge) on every axis. On a GPU: a 2D array
//! texture of N² layers (layer = wi texel x + N·y), bilinear filtering within each layer
//! over wo, and a manual bilinear blend of the 4 layers around wi.

use super::{Plane, PlaneSpec, octahedral, quadrilinear_corners};
use crate::model::{Fabric, Integration, Patch};
use glam::{DVec2, DVec3};
use rayon::prelude::*;

pub fn spec(resolution: u32) -> PlaneSpec {
    let side = resolution as usize * resolution as usize;
    PlaneSpec::new(
        "grid4d".into(),
        side,
        side,
        &["reflection", "transmission1", "transmission2"],
    )
}

/// The direction pair whose value texel (x, y) stores.
pub fn texel_directions(resolution: u32, x: usize, y: usize) -> (DVec3, DVec3) {
    let n = resolution as usize;
    let centre = |i: usize, j: usize| {
        octahedral::decode(DVec2::new(i as f64 + 0.5, j as f64 + 0.5) / n as f64)
    };
    (centre(x / n, y / n), centre(x % n, y % n))
}

/// The terms of every texel, row by row, from the direct evaluation.
pub fn bake(fabric: &Fabric, resolution: u32, on_row: &(dyn Fn() + Sync)) -> Vec<f64> {
    let patch = Patch::new(fabric, Integration::Direct);
    let spec = spec(resolution);
    (0..spec.height)
        .into_par_iter()
        .flat_map_iter(|y| {
            let row: Vec<f64> = (0..spec.width)
                .flat_map(|x| {
                    let (wi, wo) = texel_directions(resolution, x, y);
                    let terms = patch.terms(wi, wo);
                    [
                        terms.reflection,
                        terms.transmission[0],
                        terms.transmission[1],
                    ]
                })
                .collect();
            on_row();
            row
        })
        .collect()
}

/// One axis of a linear interpolation with clamp-to-edge: the two texel indices and the
/// weight of the second, for continuous texel coordinate `x` (texel i's centre at i).
#[inline]
fn axis(x: f64, n: usize) -> (usize, usize, f64) {
    let floor = x.floor();
    let last = n as i64 - 1;
    let i0 = (floor as i64).clamp(0, last) as usize;
    let i1 = (floor as i64 + 1).clamp(0, last) as usize;
    (i0, i1, x - floor)
}

/// The interpolated terms at (wi, wo).
pub fn lookup_terms(plane: &Plane, resolution: u32, wi: DVec3, wo: DVec3) -> [f64; 3] {
    let n = resolution as usize;
    let ci = octahedral::encode(wi) * n as f64 - 0.5;
    let co = octahedral::encode(wo) * n as f64 - 0.5;
    let axes = [axis(ci.x, n), axis(ci.y, n), axis(co.x, n), axis(co.y, n)];
    let mut sum = [0.0f64; 3];
    for (index, weight) in quadrilinear_corners(axes) {
        let texel = plane.texel(index[0] * n + index[2], index[1] * n + index[3]);
        for c in 0..3 {
            sum[c] += weight * texel[c] as f64;
        }
    }
    sum
}
