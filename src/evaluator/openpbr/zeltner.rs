//! The fuzz lobe of OpenPBR: Zeltner, Burley and Chiang, "Practical Multiple-Scattering
//! Sheen Using Linearly Transformed Cosines" (SIGGRAPH 2022), as MaterialX 1.39 evaluates it
//! (libraries/pbrlib/genglsl/lib/mx_microfacet_sheen.glsl): the directional albedo of a
//! fibre volume and the LTC that distributes it, both fitted functions of μ = n·v and the
//! roughness r.

use glam::DVec3;
use std::f64::consts::PI;

/// The volume's directional albedo E(μ, r): a Gaussian in μ plus an offset, the fit's
/// `mx_zeltner_sheen_dir_albedo`.
pub fn dir_albedo(mu: f64, r: f64) -> f64 {
    let y = r;
    let s = y * (0.0206607 + 1.58491 * y) / (0.0379424 + y * (1.32227 + y));
    let m = y * (-0.193854 + y * (-1.14885 + y * (1.7932 - 0.95943 * y * y))) / (0.046391 + y);
    let o = y * (0.000654023 + (-0.0207818 + 0.119681 * y) * y) / (1.26264 + y * (-1.92021 + y));
    let z = (mu - m) / s;
    (-0.5 * z * z).exp() / (s * (2.0 * PI).sqrt()) + o
}

/// The LTC's inverse matrix entries a⁻¹ and b⁻¹ at (μ, r) (`mx_zeltner_sheen_ltc_aInv`,
/// `_bInv`).
fn ltc_inverse(mu: f64, r: f64) -> (f64, f64) {
    let (x, y) = (mu, r);
    let a_inv = (2.58126 * x + 0.813703 * y) * y / (1.0 + 0.310327 * x * x + 2.60994 * x * y);
    let b_inv = (1.0 - x).sqrt() * (y - 1.0) * y * y * y
        / (0.0000254053 + 1.71228 * x - 1.71506 * x * y + 1.34174 * y * y);
    (a_inv, b_inv)
}

/// The lobe's distribution of the albedo over light directions, cosine included, which
/// integrates to 1 over the hemisphere: in the frame whose x axis is v's projection on the
/// surface, `w' = M⁻¹ l = (a⁻¹ l.x + b⁻¹ l.z, a⁻¹ l.y, l.z)` and
/// `D(l) = max(w'.z, 0)/π · (a⁻¹/|w'|²)²` (the clamped cosine D₀(w'/|w'|), times the
/// Jacobian `|det M⁻¹| / |w'|³` with det M⁻¹ = a⁻²).
pub fn ltc_brdf(l: DVec3, v: DVec3, r: f64) -> f64 {
    let (a_inv, b_inv) = ltc_inverse(v.z, r);
    let tangential = DVec3::new(v.x, v.y, 0.0);
    // At normal incidence any frame serves: b⁻¹ vanishes there with √(1 − μ).
    let x = if tangential.length_squared() > 0.0 {
        tangential.normalize()
    } else {
        DVec3::X
    };
    let y = DVec3::Z.cross(x);
    let w = DVec3::new(l.dot(x), l.dot(y), l.z);
    let transformed = DVec3::new(a_inv * w.x + b_inv * w.z, a_inv * w.y, w.z);
    let len2 = transformed.length_squared();
    transformed.z.max(0.0) / PI * (a_inv / len2).powi(2)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::evaluator::stock::lobes::midpoint_integral;

    #[test]
    fn the_ltc_distributes_unit_mass_over_the_hemisphere() {
        for (mu, r) in [(0.9f64, 0.3), (0.5, 0.6), (0.2, 1.0)] {
            let v = DVec3::new((1.0 - mu * mu).sqrt(), 0.0, mu);
            let mass = midpoint_integral(800, 400, 2.0 * PI, |l| ltc_brdf(l, v, r));
            // Mass falls below the horizon where the transformed lobe leans past it.
            assert!(mass > 0.8 && mass < 1.0 + 1e-3, "μ {mu} r {r}: {mass}");
        }
    }

    #[test]
    fn the_albedo_lies_in_zero_one() {
        for mu in [0.05, 0.3, 0.7, 1.0] {
            for r in [0.01, 0.3, 0.7, 1.0] {
                let e = dir_albedo(mu, r);
                assert!((0.0..=1.0).contains(&e), "μ {mu} r {r}: {e}");
            }
        }
    }
}
