//! Seeded sets of direction pairs on which errors are measured: uniform over the pair of
//! upper hemispheres, and "highlight" pairs on the specular cones of tangent samples, where
//! the narrow surface lobe peaks. Seeded and platform independent, so every run measures
//! the same pairs.

use crate::model::Fabric;
use crate::model::curve::{Integration, curve_pieces};
use glam::DVec3;
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64;

/// A direction uniform in solid angle over the upper hemisphere (z > 0).
pub fn uniform_hemisphere(rng: &mut impl Rng) -> DVec3 {
    // z uniform in (0, 1] gives uniform solid angle; 1 − u keeps z away from 0 exactly.
    let z: f64 = 1.0 - rng.random::<f64>();
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = std::f64::consts::TAU * rng.random::<f64>();
    DVec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// `count` pairs `(wi, wo)`, each direction uniform over the upper hemisphere.
pub fn uniform_pairs(count: usize, seed: u64) -> Vec<(DVec3, DVec3)> {
    let mut rng = Pcg64::seed_from_u64(seed);
    (0..count)
        .map(|_| (uniform_hemisphere(&mut rng), uniform_hemisphere(&mut rng)))
        .collect()
}

/// `count` pairs on the specular cones of `fabric`'s tangent samples: a thread is picked in
/// proportion to its coverage, a tangent offset α along its curve (uniform in arc length),
/// `wi` uniform over the upper hemisphere, and `wo` on the cone `wo·t(α) = −wi·t(α)`
/// (θh = 0 for that sample) at a random azimuth facing the sample (wo·n > 0) and above the
/// horizon. Pairs for which no such `wo` is found in a few tries are drawn again.
pub fn highlight_pairs(fabric: &Fabric, count: usize, seed: u64) -> Vec<(DVec3, DVec3)> {
    let mut rng = Pcg64::seed_from_u64(seed);
    let threads = fabric.threads();
    let pieces = threads.map(|t| curve_pieces(t, &fabric.options, Integration::Direct));
    let total_coverage = threads[0].coverage + threads[1].coverage;
    let mut pairs = Vec::with_capacity(count);
    while pairs.len() < count {
        let j = if total_coverage > 0.0
            && rng.random::<f64>() * total_coverage >= threads[0].coverage
        {
            1
        } else {
            0
        };
        let (t0, b) = crate::model::thread_axes(j);
        let mut pick = rng.random::<f64>();
        let piece = pieces[j]
            .iter()
            .find(|p| {
                pick -= p.weight;
                pick < 0.0
            })
            .or(pieces[j].last());
        let alpha = piece.map_or(0.0, |p| p.start + (p.end - p.start) * rng.random::<f64>());
        let t = alpha.cos() * t0 + alpha.sin() * DVec3::Z;
        let n = -alpha.sin() * t0 + alpha.cos() * DVec3::Z;
        let wi = uniform_hemisphere(&mut rng);
        let sin_theta = wi.dot(t);
        let cos_theta = (1.0 - sin_theta * sin_theta).max(0.0).sqrt();
        for _ in 0..8 {
            let phi = (rng.random::<f64>() - 0.5) * std::f64::consts::PI;
            let wo = -sin_theta * t + cos_theta * (phi.cos() * n + phi.sin() * b);
            if wo.z > 1e-6 {
                pairs.push((wi, wo.normalize()));
                break;
            }
        }
    }
    pairs
}
