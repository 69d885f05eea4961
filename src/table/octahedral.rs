//! The hemi-octahedral map: the upper hemisphere onto the unit square, continuous, with the
//! horizon on the square's boundary and the pole at its centre.
//!
//! A unit direction w with w.z ≥ 0 is projected onto the octahedron |x| + |y| + z = 1,
//! `p = (w.x, w.y) / (|w.x| + |w.y| + w.z)`, a diamond |p.x| + |p.y| ≤ 1, which a 45°
//! rotation turns into the square `s = (p.x + p.y, p.x − p.y) ∈ [−1, 1]²`; texture
//! coordinates are `(s + 1)/2 ∈ [0, 1]²`. Every point of the square maps back to a direction
//! with z ≥ 0, so texel centres never fall outside the domain.

use glam::{DVec2, DVec3};

/// Texture coordinates in [0, 1]² of a direction with `w.z ≥ 0` (a lower direction is
/// mapped as its reflection through the horizon).
pub fn encode(w: DVec3) -> DVec2 {
    let norm = w.x.abs() + w.y.abs() + w.z.abs();
    let p = DVec2::new(w.x, w.y) / norm;
    (DVec2::new(p.x + p.y, p.x - p.y) + 1.0) * 0.5
}

/// The unit direction at texture coordinates `uv` ∈ [0, 1]².
pub fn decode(uv: DVec2) -> DVec3 {
    let s = uv * 2.0 - 1.0;
    let p = DVec2::new(s.x + s.y, s.x - s.y) * 0.5;
    DVec3::new(p.x, p.y, 1.0 - p.x.abs() - p.y.abs()).normalize()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip_and_boundaries() {
        for (x, y, z) in [
            (0.3, -0.2, 0.9),
            (0.0, 0.0, 1.0),
            (1.0, 0.0, 0.0),
            (-0.5, -0.5, 0.1),
        ] {
            let w = DVec3::new(x, y, z).normalize();
            assert!((decode(encode(w)) - w).length() < 1e-12, "{w}");
        }
        assert!((encode(DVec3::Z) - DVec2::splat(0.5)).length() < 1e-15);
        // The horizon lies on the square's boundary.
        let uv = encode(DVec3::new(0.6, 0.8, 0.0));
        assert!(uv.min_element().abs() < 1e-15 || (uv.max_element() - 1.0).abs() < 1e-15);
    }
}
