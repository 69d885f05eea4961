//! `unreal`: Unreal Engine's Cloth shading model (`ClothBxDF` of
//! Engine/Shaders/Private/ShadingModels.ush and the lobes of BRDF.ush, UE 4.26–5; the
//! material pins Base Color, Metallic, Specular, Roughness, Fuzz Color and Cloth), fitted to
//! the fabric, as it lights a punctual light:
//!
//! - `F = n·l (DiffuseColor/π + lerp(Spec1, Spec2, Cloth))`, DiffuseColor = BaseColor
//!   (1 − Metallic), SpecularColor = lerp(0.08 Specular, BaseColor, Metallic);
//! - `Spec1 = D_GGX(a², n·h) Vis_SmithJointApprox(a², n·v, n·l) F_Schlick(SpecularColor, v·h)`,
//!   a² = Roughness⁴;
//! - `Spec2 = D_InvGGX(a², n·h) Vis_Cloth(n·v, n·l) F_Schlick(FuzzColor, v·h)`, the inverted
//!   GGX of asperity scattering, `D_InvGGX = (1 + 4a⁴/d²) / (π (1 + 4a²))` with
//!   d = (n·h − a² n·h) n·h + a²;
//! - `F_Schlick(S, v·h) = saturate(50 S.g) Fc + (1 − Fc) S`, Fc = (1 − v·h)⁵.
//!
//! UE 5's energy-conservation factors on these lobes are left out (their terms are tables
//! of the engine's), as is its `n·v + 1e-5` guard, which only matters at the horizon.

use super::stock::lobes::{neubelt_visibility, schlick_weight};
use super::stock::{StockModel, StockParameter, fabric_colour, no_derived};
use super::{EvaluatorUnit, Parsed};
use crate::model::Fabric;
use glam::DVec3;
use std::f64::consts::PI;

/// The unit's entry in the registry.
pub const UNIT: EvaluatorUnit = EvaluatorUnit {
    name: "unreal",
    syntax: "unreal",
    summary: "Unreal Engine's Cloth shading model (fuzz colour, cloth), fitted to the fabric",
    parse,
    report: None,
};

fn parse(parameter: Option<&str>) -> Parsed {
    super::stock::parse(&MODEL, &UNIT, parameter)
}

/// The material's pins.
const PARAMETERS: &[StockParameter] = &[
    StockParameter::new("BaseColor.r", 0.0, 1.0),
    StockParameter::new("BaseColor.g", 0.0, 1.0),
    StockParameter::new("BaseColor.b", 0.0, 1.0),
    StockParameter::new("Metallic", 0.0, 1.0),
    StockParameter::new("Specular", 0.0, 1.0),
    // a² = Roughness⁴: a floor on the lobe's width, a cloth's highlight, not a mirror's.
    StockParameter::new("Roughness", 0.1, 1.0),
    StockParameter::new("FuzzColor.r", 0.0, 1.0),
    StockParameter::new("FuzzColor.g", 0.0, 1.0),
    StockParameter::new("FuzzColor.b", 0.0, 1.0),
    StockParameter::new("Cloth", 0.0, 1.0),
];

/// `cloth_stock_f` of Unreal's cloth shading model over the stock block.
#[cfg(feature = "runtime")]
pub const FILE: crate::shader::ShaderFile = crate::shader::ShaderFile {
    name: "evaluator/unreal",
    path: "src/evaluator/unreal/unreal.wgsl",
    source: include_str!("unreal.wgsl"),
};

/// The model.
pub static MODEL: StockModel = StockModel {
    name: "unreal",
    title: "Unreal Engine Cloth shading model (ShadingModels.ush)",
    parameters: PARAMETERS,
    start,
    derive: no_derived,
    eval,
    reciprocal: true,
    conserves_energy: false,
    #[cfg(feature = "runtime")]
    wgsl: &FILE,
};

/// The material editor's defaults (Specular 0.5) with the fabric's colour.
fn start(fabric: &Fabric) -> Vec<f64> {
    let [r, g, b] = fabric_colour(fabric);
    vec![r, g, b, 0.0, 0.5, 0.7, r.sqrt(), g.sqrt(), b.sqrt(), 0.5]
}

/// `F_Schlick(S, v·h)` of BRDF.ush.
fn f_schlick(s: DVec3, v_dot_h: f64) -> DVec3 {
    let fc = schlick_weight(v_dot_h);
    DVec3::splat((50.0 * s.y).clamp(0.0, 1.0) * fc) + (1.0 - fc) * s
}

/// `D_InvGGX(a², n·h)` of BRDF.ush.
fn d_inv_ggx(a2: f64, n_dot_h: f64) -> f64 {
    let d = (n_dot_h - a2 * n_dot_h) * n_dot_h + a2;
    (1.0 + 4.0 * a2 * a2 / (d * d)) / (PI * (1.0 + 4.0 * a2))
}

/// `D_GGX(a², n·h)` of BRDF.ush.
fn d_ggx(a2: f64, n_dot_h: f64) -> f64 {
    let d = (n_dot_h * a2 - n_dot_h) * n_dot_h + 1.0;
    a2 / (PI * d * d)
}

/// `Vis_SmithJointApprox(a², n·v, n·l)` of BRDF.ush.
fn vis_smith_joint_approx(a2: f64, n_dot_v: f64, n_dot_l: f64) -> f64 {
    let a = a2.sqrt();
    0.5 / (n_dot_l * (n_dot_v * (1.0 - a) + a) + n_dot_v * (n_dot_l * (1.0 - a) + a))
}

/// F of the cloth shading model (`cloth_stock_f` of unreal.wgsl is its twin).
fn eval(p: &[f64], _: &[f64], l: DVec3, v: DVec3, h: DVec3) -> DVec3 {
    let base = DVec3::new(p[0], p[1], p[2]);
    let (metallic, specular, roughness, cloth) = (p[3], p[4], p[5], p[9]);
    let fuzz = DVec3::new(p[6], p[7], p[8]);
    let a2 = roughness.powi(4);
    let diffuse = base * (1.0 - metallic) / PI;
    let specular_colour = DVec3::splat(0.08 * specular).lerp(base, metallic);
    let v_dot_h = v.dot(h);
    let spec1 = f_schlick(specular_colour, v_dot_h)
        * (d_ggx(a2, h.z) * vis_smith_joint_approx(a2, v.z, l.z));
    let spec2 = f_schlick(fuzz, v_dot_h) * (d_inv_ggx(a2, h.z) * neubelt_visibility(v.z, l.z));
    (diffuse + spec1.lerp(spec2, cloth)) * l.z
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::evaluator::stock::StockMaterial;

    #[test]
    fn the_inverted_ggx_has_unit_projected_area_and_the_ggx_too() {
        // ∫ D(h) (n·h) dωh = 2π ∫₀¹ D(μ) μ dμ, by the midpoint rule.
        let area = |d: &dyn Fn(f64) -> f64| {
            let n = 200_000;
            (0..n)
                .map(|i| {
                    let mu = (i as f64 + 0.5) / n as f64;
                    d(mu) * mu
                })
                .sum::<f64>()
                * 2.0
                * PI
                / n as f64
        };
        for roughness in [0.3f64, 0.6, 1.0] {
            let a2 = roughness.powi(4);
            let ggx = area(&|mu| d_ggx(a2, mu));
            assert!((ggx - 1.0).abs() < 1e-3, "GGX {roughness}: {ggx}");
            let inverted = area(&|mu| d_inv_ggx(a2, mu));
            assert!(
                (inverted - 1.0).abs() < 1e-2,
                "inverted GGX {roughness}: {inverted}"
            );
        }
    }

    #[test]
    fn cloth_zero_is_the_default_lit_model_and_one_is_the_fuzz_lobe() {
        let (wi, wo) = (DVec3::new(0.6, 0.0, 0.8), DVec3::new(-0.28, 0.0, 0.96));
        let h = (wi + wo).normalize();
        let values = |cloth| [0.5, 0.4, 0.3, 0.0, 0.5, 0.6, 0.9, 0.8, 0.7, cloth];
        let material = |cloth| StockMaterial::new(&MODEL, &values(cloth));
        let lit = material(0.0).eval(wi, wo);
        let fuzz = material(1.0).eval(wi, wo);
        let a2 = 0.6f64.powi(4);
        let fc = schlick_weight(wo.dot(h));
        let spec1 =
            (0.04 * (1.0 - fc) + fc) * d_ggx(a2, h.z) * vis_smith_joint_approx(a2, 0.96, 0.8);
        let expected_lit = (DVec3::new(0.5, 0.4, 0.3) / PI + DVec3::splat(spec1)) * 0.8;
        assert!((lit - expected_lit).abs().max_element() < 1e-12, "{lit}");
        let spec2 = (DVec3::splat(fc) + (1.0 - fc) * DVec3::new(0.9, 0.8, 0.7))
            * (d_inv_ggx(a2, h.z) * neubelt_visibility(0.96, 0.8));
        let expected_fuzz = (DVec3::new(0.5, 0.4, 0.3) / PI + spec2) * 0.8;
        assert!((fuzz - expected_fuzz).abs().max_element() < 1e-12, "{fuzz}");
    }
}
