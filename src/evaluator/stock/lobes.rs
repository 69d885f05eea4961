//! The lobes that several engines' stock models share, in f64, each the CPU twin of the
//! function of the same name in `lobes.wgsl` beside this file. Directions are in the patch
//! frame (x the tangent, thread 1; z the normal).

use glam::DVec3;
use std::f64::consts::PI;
use std::ops::{AddAssign, Mul};

/// `∫ f(ω) dω` over the directions above the horizon with azimuth φ in [0, `phi_max`], by the
/// midpoint rule on `n_cos` × `n_phi` cells of equal solid angle in (cos θ, φ): what the stock
/// models' albedos and normalisations are integrated with.
pub fn midpoint_integral<T>(n_cos: usize, n_phi: usize, phi_max: f64, f: impl Fn(DVec3) -> T) -> T
where
    T: Default + AddAssign + Mul<f64, Output = T>,
{
    let mut sum = T::default();
    for i in 0..n_cos {
        let c = (i as f64 + 0.5) / n_cos as f64;
        let s = (1.0 - c * c).sqrt();
        for k in 0..n_phi {
            let phi = phi_max * (k as f64 + 0.5) / n_phi as f64;
            sum += f(DVec3::new(s * phi.cos(), s * phi.sin(), c));
        }
    }
    sum * (phi_max / (n_cos * n_phi) as f64)
}

/// The "Charlie" sheen distribution of Estevez and Kulla (2017), as KHR_materials_sheen
/// writes it: `D(h) = (2 + 1/α) · max(sin²θh, floor)^(1/(2α)) / (2π)`, α the squared sheen
/// roughness. `floor` is 0 in the glTF extension; Filament keeps sin²θh ≥ 2⁻⁷ for half
/// floats.
pub fn charlie_d(alpha: f64, n_dot_h: f64, sin2_floor: f64) -> f64 {
    let sin2 = (1.0 - n_dot_h * n_dot_h).max(sin2_floor);
    (2.0 + 1.0 / alpha) * sin2.powf(0.5 / alpha) / (2.0 * PI)
}

/// Estevez and Kulla's fit of the Charlie distribution's Λ: `Λ(μ) = exp(l(μ))` below
/// μ = ½ and `exp(2 l(½) − l(1 − μ))` above, `l(x) = a/(1 + b xᶜ) + d x + e`, each of a…e
/// interpolated between its value at α = 1 and at α = 0 by `t = (1 − α)²`
/// (KHR_materials_sheen, "Sheen visibility").
pub fn charlie_lambda(alpha: f64, cos: f64) -> f64 {
    let t = (1.0 - alpha) * (1.0 - alpha);
    let mix = |at_one: f64, at_zero: f64| at_one + (at_zero - at_one) * t;
    let (a, b, c) = (
        mix(21.5473, 25.3245),
        mix(3.82987, 3.32435),
        mix(0.19823, 0.16801),
    );
    let (d, e) = (mix(-1.97760, -1.27393), mix(-4.32054, -4.85967));
    let l = |x: f64| a / (1.0 + b * x.powf(c)) + d * x + e;
    let cos = cos.abs();
    if cos < 0.5 {
        l(cos).exp()
    } else {
        (2.0 * l(0.5) - l(1.0 - cos)).exp()
    }
}

/// The Charlie sheen's visibility `V = 1 / ((1 + Λ(n·v) + Λ(n·l)) · 4 (n·v)(n·l))`.
pub fn charlie_visibility(alpha: f64, n_dot_v: f64, n_dot_l: f64) -> f64 {
    1.0 / ((1.0 + charlie_lambda(alpha, n_dot_v) + charlie_lambda(alpha, n_dot_l))
        * 4.0
        * n_dot_v
        * n_dot_l)
}

/// Neubelt and Pettineo's (Ashikhmin's) cloth visibility `V = 1 / (4 (n·l + n·v − (n·l)(n·v)))`,
/// Filament's `V_Neubelt` and Unreal's `Vis_Cloth`.
pub fn neubelt_visibility(n_dot_v: f64, n_dot_l: f64) -> f64 {
    1.0 / (4.0 * (n_dot_l + n_dot_v - n_dot_l * n_dot_v))
}

/// Schlick's Fresnel weight `(1 − |v·h|)⁵`.
pub fn schlick_weight(v_dot_h: f64) -> f64 {
    (1.0 - v_dot_h.abs()).clamp(0.0, 1.0).powi(5)
}

/// The anisotropic GGX distribution with roughness `at` along `t` and `ab` along `b`:
/// `D(h) = 1 / (π at ab ((h·t / at)² + (h·b / ab)² + (h·n)²)²)`.
pub fn ggx_anisotropic_d(at: f64, ab: f64, t: DVec3, b: DVec3, h: DVec3) -> f64 {
    let (x, y) = (h.dot(t) / at, h.dot(b) / ab);
    let s = x * x + y * y + h.z * h.z;
    1.0 / (PI * at * ab * s * s)
}

/// The height-correlated Smith visibility of the anisotropic GGX distribution, as
/// KHR_materials_anisotropy writes it:
/// `V = ½ / ((n·l) |(at t·v, ab b·v, n·v)| + (n·v) |(at t·l, ab b·l, n·l)|)`.
pub fn ggx_anisotropic_v(at: f64, ab: f64, t: DVec3, b: DVec3, v: DVec3, l: DVec3) -> f64 {
    let lambda = |w: DVec3| DVec3::new(at * w.dot(t), ab * w.dot(b), w.z).length();
    0.5 / (l.z * lambda(v) + v.z * lambda(l))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// ∫ D(h) (n·h) dωh over the hemisphere.
    fn projected_area(d: impl Fn(DVec3) -> f64) -> f64 {
        midpoint_integral(4000, 64, 2.0 * PI, |h| d(h) * h.z)
    }

    #[test]
    fn the_charlie_and_ggx_distributions_have_unit_projected_area() {
        for alpha in [0.05, 0.3, 1.0] {
            let area = projected_area(|h| charlie_d(alpha, h.z, 0.0));
            assert!((area - 1.0).abs() < 1e-3, "Charlie α = {alpha}: {area}");
        }
        for (at, ab) in [(0.3, 0.3), (0.6, 0.2), (1.0, 0.5)] {
            let area = projected_area(|h| ggx_anisotropic_d(at, ab, DVec3::X, DVec3::Y, h));
            assert!((area - 1.0).abs() < 2e-3, "GGX {at}, {ab}: {area}");
        }
    }

    #[test]
    fn the_lambda_fit_is_continuous_at_one_half_and_visibilities_are_symmetric() {
        for alpha in [0.01, 0.25, 1.0] {
            let (below, above) = (
                charlie_lambda(alpha, 0.5 - 1e-9),
                charlie_lambda(alpha, 0.5 + 1e-9),
            );
            assert!((below - above).abs() < 1e-6 * below, "{below} {above}");
            let (a, b) = (
                charlie_visibility(alpha, 0.3, 0.8),
                charlie_visibility(alpha, 0.8, 0.3),
            );
            assert!((a - b).abs() <= 1e-15 * a, "{a} {b}");
        }
        assert_eq!(neubelt_visibility(0.3, 0.8), neubelt_visibility(0.8, 0.3));
        // Isotropic anisotropic GGX is the isotropic one: at normal incidence V = 1/4.
        let v = ggx_anisotropic_v(0.3, 0.3, DVec3::X, DVec3::Y, DVec3::Z, DVec3::Z);
        assert!((v - 0.25).abs() < 1e-12);
    }
}
