//! The scalar building blocks of the thread scattering function: dielectric Fresnel
//! reflectance, the unit-area lobe Gaussian g and the unit-height reweighting Gaussian u.

use std::f64::consts::PI;

/// Unpolarised Fresnel reflectance of a smooth dielectric, from air into index `eta` ≥ 1, at
/// incidence cosine `cos_i` (clamped to [0, 1]); the exact formula, not Schlick's.
///
/// With Snell's law `sin t = sin i / η`:
/// `rs = (cos i − η cos t)/(cos i + η cos t)`, `rp = (η cos i − cos t)/(η cos i + cos t)`,
/// `F = (rs² + rp²)/2`. It is ((η−1)/(η+1))² at normal incidence and 1 at grazing incidence.
/// For η = 1 there is no interface and F = 0, including the 0/0 limit at grazing.
pub fn fresnel_dielectric(eta: f64, cos_i: f64) -> f64 {
    if eta == 1.0 {
        return 0.0;
    }
    let cos_i = cos_i.clamp(0.0, 1.0);
    let sin2_t = (1.0 - cos_i * cos_i) / (eta * eta);
    let cos_t = (1.0 - sin2_t).max(0.0).sqrt();
    let rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    let rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    0.5 * (rs * rs + rp * rp)
}

/// A unit-area Gaussian of standard deviation `sigma` (radians), prepared once per thread:
/// `g(x) = exp(−x²/(2σ²)) / (σ√(2π))`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UnitAreaGaussian {
    neg_inv_two_var: f64,
    peak: f64,
}

impl UnitAreaGaussian {
    pub fn new(sigma: f64) -> Self {
        Self {
            neg_inv_two_var: -0.5 / (sigma * sigma),
            peak: 1.0 / (sigma * (2.0 * PI).sqrt()),
        }
    }

    #[inline]
    pub fn eval(&self, x: f64) -> f64 {
        self.peak * (x * x * self.neg_inv_two_var).exp()
    }
}

/// A thread's two lobes, the surface lobe g(γs, ·) and the volume lobe g(γv, ·).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ThreadLobes {
    surface: UnitAreaGaussian,
    volume: UnitAreaGaussian,
    /// σv = 2σs (every built-in thread but crepe's second). Then the surface exponent is
    /// exactly four times the volume's, in floating point too (scaling by powers of two
    /// commutes with rounding), and exp(4k·x²) = exp(k·x²)⁴ saves one exp per sample.
    surface_from_volume: bool,
}

impl ThreadLobes {
    /// The lobes of standard deviations `sigma_s` and `sigma_v` (radians).
    pub fn new(sigma_s: f64, sigma_v: f64) -> Self {
        let (surface, volume) = (
            UnitAreaGaussian::new(sigma_s),
            UnitAreaGaussian::new(sigma_v),
        );
        Self {
            surface,
            volume,
            surface_from_volume: surface.neg_inv_two_var == 4.0 * volume.neg_inv_two_var,
        }
    }

    /// (g(γs, θh), g(γv, θh)).
    #[inline]
    pub fn eval(&self, theta_h: f64) -> (f64, f64) {
        let volume = (theta_h * theta_h * self.volume.neg_inv_two_var).exp();
        let surface = if self.surface_from_volume {
            let square = volume * volume;
            square * square
        } else {
            (theta_h * theta_h * self.surface.neg_inv_two_var).exp()
        };
        (self.surface.peak * surface, self.volume.peak * volume)
    }
}

/// The unit-height Gaussian `u(x) = exp(−x²/(2σu²))` that blends the masking terms.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UnitHeightGaussian {
    neg_inv_two_var: f64,
}

impl UnitHeightGaussian {
    pub fn new(sigma: f64) -> Self {
        Self {
            neg_inv_two_var: -0.5 / (sigma * sigma),
        }
    }

    #[inline]
    pub fn eval(&self, x: f64) -> f64 {
        (x * x * self.neg_inv_two_var).exp()
    }
}
