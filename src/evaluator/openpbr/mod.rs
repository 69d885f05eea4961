//! `openpbr`: OpenPBR Surface as MaterialX 1.39 builds it (`open_pbr_surface`, nodedef
//! 1.1.1, in libraries/bxdf/open_pbr_surface.mtlx of MaterialX v1.39.5, with the closures of
//! libraries/pbrlib/genglsl), fitted to the fabric: the fuzz layer over a dielectric
//! specular layer over a diffuse base.
//!
//! - fuzz: MaterialX's `sheen_bsdf` in its `zeltner` mode, Zeltner, Burley and Chiang's
//!   linearly transformed cosine fit of a fibre volume (2022; [`zeltner`]) with
//!   r = fuzz_roughness; it adds `fuzz_weight · fuzz_color · E(n·v) · D_LTC(l)` and passes
//!   `1 − fuzz_weight · E(n·v)` of what lies below (grey: the colour is not in it);
//! - specular: `dielectric_bsdf`, anisotropic GGX with
//!   `αx = r² √(2/(1 + (1 − a)²))`, `αy = (1 − a) αx` along the tangent, the Smith G2 of the
//!   mean α, the exact dielectric Fresnel at ior 1.5 and the energy compensation
//!   `1 + F (1 − Ess)/Ess`; it passes `1 − E_spec(n·v)` of the diffuse below;
//! - base: `base_color · n·l / π` (Oren–Nayar at base_diffuse_roughness 0).
//!
//! Held at the node's defaults, not fitted: base_weight 1, base_metalness 0,
//! base_diffuse_roughness 0, specular_weight 1, specular_color white, specular_ior 1.5, no
//! coat, no transmission, no subsurface. The fuzz's direction dependence sits on n·v only,
//! so the model is not reciprocal.

pub mod zeltner;

use super::stock::lobes::ggx_anisotropic_d;
use super::stock::{StockModel, StockParameter, fabric_colour, no_derived};
use super::{EvaluatorUnit, Parsed};
use crate::model::Fabric;
use glam::DVec3;
use std::f64::consts::PI;

/// The unit's entry in the registry.
pub const UNIT: EvaluatorUnit = EvaluatorUnit {
    name: "openpbr",
    syntax: "openpbr",
    summary: "OpenPBR Surface's fuzz over its anisotropic specular (MaterialX 1.39), fitted to the fabric",
    parse,
    report: None,
};

fn parse(parameter: Option<&str>) -> Parsed {
    super::stock::parse(&MODEL, &UNIT, parameter)
}

/// The node's inputs, as MaterialX names them.
const PARAMETERS: &[StockParameter] = &[
    StockParameter::new("base_color.r", 0.0, 1.0),
    StockParameter::new("base_color.g", 0.0, 1.0),
    StockParameter::new("base_color.b", 0.0, 1.0),
    // The specular lobe of a cloth, not a mirror: a floor on α (r = 0.05, α = 0.0025).
    StockParameter::new("specular_roughness", 0.05, 1.0),
    StockParameter::new("specular_roughness_anisotropy", 0.0, 1.0),
    StockParameter::new("fuzz_weight", 0.0, 1.0),
    StockParameter::new("fuzz_color.r", 0.0, 1.0),
    StockParameter::new("fuzz_color.g", 0.0, 1.0),
    StockParameter::new("fuzz_color.b", 0.0, 1.0),
    // MaterialX clamps the fuzz roughness to [0.01, 1].
    StockParameter::new("fuzz_roughness", 0.01, 1.0),
];

/// `cloth_stock_f` of open_pbr_surface over the stock block.
#[cfg(feature = "runtime")]
pub const FILE: crate::shader::ShaderFile = crate::shader::ShaderFile {
    name: "evaluator/openpbr",
    path: "src/evaluator/openpbr/openpbr.wgsl",
    source: include_str!("openpbr.wgsl"),
};

/// The model.
pub static MODEL: StockModel = StockModel {
    name: "openpbr",
    title: "OpenPBR Surface in MaterialX 1.39 (open_pbr_surface)",
    parameters: PARAMETERS,
    start,
    derive: no_derived,
    eval,
    reciprocal: false,
    conserves_energy: true,
    #[cfg(feature = "runtime")]
    wgsl: &FILE,
};

fn start(fabric: &Fabric) -> Vec<f64> {
    let [r, g, b] = fabric_colour(fabric);
    vec![r, g, b, 0.5, 0.3, 0.8, r.sqrt(), g.sqrt(), b.sqrt(), 0.5]
}

/// The index of refraction of the specular layer (the node's default).
const SPECULAR_IOR: f64 = 1.5;
/// MaterialX's smallest GGX α (`M_FLOAT_EPS`).
const ALPHA_EPSILON: f64 = 1e-6;

/// The exact dielectric Fresnel reflectance at cos θ = `c` for relative index `eta`
/// (`mx_fresnel_dielectric`; total internal reflection gives 1).
pub fn fresnel_dielectric(c: f64, eta: f64) -> f64 {
    let g2 = eta * eta + c * c - 1.0;
    if g2 < 0.0 {
        return 1.0;
    }
    let g = g2.sqrt();
    let a = (g - c) / (g + c);
    let b = ((g + c) * c - 1.0) / ((g - c) * c + 1.0);
    0.5 * a * a * (1.0 + b * b)
}

/// MaterialX's fit of GGX's directional albedo (`mx_ggx_dir_albedo_analytic`):
/// `F0 · A + F90 · B` at n·v = `x` and α = `y`.
pub fn ggx_dir_albedo(x: f64, y: f64, f0: f64, f90: f64) -> f64 {
    const C: [[f64; 4]; 9] = [
        [0.1003, 0.9345, 1.0, 1.0],
        [-0.6303, -2.323, -1.765, 0.2281],
        [9.748, 2.229, 8.263, 15.94],
        [-2.038, -3.748, 11.53, -55.83],
        [29.34, 1.424, 28.96, 13.08],
        [-8.245, -0.7684, -7.507, 41.26],
        [-26.44, 1.436, -36.11, 54.9],
        [19.99, 0.2913, 15.86, 300.2],
        [-5.448, 0.6286, 33.37, -285.1],
    ];
    let terms = [
        1.0,
        x,
        y,
        x * y,
        x * x,
        y * y,
        x * x * y,
        x * y * y,
        x * x * y * y,
    ];
    let r: [f64; 4] = std::array::from_fn(|i| C.iter().zip(terms).map(|(c, t)| c[i] * t).sum());
    let a = (r[0] / r[2]).clamp(0.0, 1.0);
    let b = (r[1] / r[3]).clamp(0.0, 1.0);
    f0 * a + f90 * b
}

/// F of the node (`cloth_stock_f` of openpbr.wgsl is its twin).
fn eval(p: &[f64], _: &[f64], l: DVec3, v: DVec3, h: DVec3) -> DVec3 {
    let base = DVec3::new(p[0], p[1], p[2]);
    let (roughness, anisotropy, fuzz_weight) = (p[3], p[4], p[5]);
    let fuzz_colour = DVec3::new(p[6], p[7], p[8]);
    let fuzz_roughness = p[9].clamp(0.01, 1.0);

    // The dielectric specular layer.
    let r2 = roughness * roughness;
    let ax = (r2 * (2.0 / (1.0 + (1.0 - anisotropy).powi(2))).sqrt()).clamp(ALPHA_EPSILON, 1.0);
    let ay = ((1.0 - anisotropy) * ax).clamp(ALPHA_EPSILON, 1.0);
    let mean_alpha = (ax * ay).sqrt();
    let d = ggx_anisotropic_d(ax, ay, DVec3::X, DVec3::Y, h);
    let a2 = mean_alpha * mean_alpha;
    let lambda = |c: f64| (a2 + (1.0 - a2) * c * c).sqrt();
    let g2 = 2.0 * l.z * v.z / (lambda(l.z) * v.z + lambda(v.z) * l.z);
    let fresnel = fresnel_dielectric(v.dot(h), SPECULAR_IOR);
    let ess = ggx_dir_albedo(v.z, mean_alpha, 1.0, 1.0);
    let compensation = 1.0 + fresnel * (1.0 - ess) / ess;
    let specular = d * fresnel * g2 * compensation / (4.0 * v.z);
    let f0 = ((SPECULAR_IOR - 1.0) / (SPECULAR_IOR + 1.0)).powi(2);
    let specular_throughput = 1.0 - ggx_dir_albedo(v.z, mean_alpha, f0, 1.0) * compensation;
    let below_fuzz = DVec3::splat(specular) + base * (l.z / PI) * specular_throughput;

    // The fuzz layer on top.
    let albedo = zeltner::dir_albedo(v.z, fuzz_roughness);
    let fuzz = fuzz_colour * (fuzz_weight * albedo * zeltner::ltc_brdf(l, v, fuzz_roughness));
    fuzz + below_fuzz * (1.0 - fuzz_weight * albedo)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::evaluator::stock::StockMaterial;

    #[test]
    fn the_fresnel_is_four_percent_at_normal_incidence_and_one_at_grazing() {
        assert!((fresnel_dielectric(1.0, 1.5) - 0.04).abs() < 1e-12);
        assert!((fresnel_dielectric(1e-9, 1.5) - 1.0).abs() < 1e-6);
    }

    #[test]
    fn the_ggx_albedo_fit_is_near_one_for_white_smooth_ggx_and_falls_with_roughness() {
        let smooth = ggx_dir_albedo(0.8, 0.05, 1.0, 1.0);
        let rough = ggx_dir_albedo(0.8, 1.0, 1.0, 1.0);
        assert!(smooth > 0.95 && rough < smooth, "{smooth} {rough}");
    }

    #[test]
    fn without_fuzz_a_black_base_reflects_only_the_specular_and_a_full_fuzz_darkens_it() {
        let material = |values: &[f64]| StockMaterial::new(&MODEL, values);
        let (wi, wo) = (DVec3::new(0.6, 0.0, 0.8), DVec3::new(-0.6, 0.0, 0.8));
        let bare = material(&[0.0, 0.0, 0.0, 0.4, 0.0, 0.0, 1.0, 1.0, 1.0, 0.5]).eval(wi, wo);
        assert!(bare.x > 0.0 && bare.x == bare.y && bare.y == bare.z);
        let black_fuzz = material(&[0.0, 0.0, 0.0, 0.4, 0.0, 1.0, 0.0, 0.0, 0.0, 0.5]).eval(wi, wo);
        let albedo = zeltner::dir_albedo(0.8, 0.5);
        assert!((black_fuzz - bare * (1.0 - albedo)).abs().max_element() < 1e-15);
    }
}
