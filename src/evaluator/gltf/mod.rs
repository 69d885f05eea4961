//! `gltf`: glTF 2.0's metallic-roughness material with `KHR_materials_sheen` and
//! `KHR_materials_anisotropy`, as three.js, Babylon.js, Godot and Blender read a `.gltf`,
//! fitted to the fabric. Written from the specification (KhronosGroup/glTF,
//! specification/2.0 Appendix B, "BRDF Implementation") and the two extensions' READMEs:
//!
//! - base: `mix(dielectric, metal, metallic)`, the dielectric `fresnel_mix` of a Lambert
//!   diffuse `baseColor/π` under a specular lobe with f0 = 0.04 (ior 1.5), the metal the
//!   specular lobe times Schlick's Fresnel with f0 = baseColor;
//! - specular: GGX with α = roughness², made anisotropic by the extension:
//!   `αt = mix(α, 1, strength²)` along the direction `anisotropyRotation` turns the tangent
//!   to, `αb = α`, with the height-correlated Smith visibility the extension writes;
//! - sheen: `sheenColor · D_Charlie · V_Charlie` with α = sheenRoughness², over the base
//!   scaled by `min(1 − max3(sheenColor) E(n·v), 1 − max3(sheenColor) E(n·l))`, E the sheen's
//!   directional albedo ([`sheen_albedo`]).
//!
//! The specification gives no test values for these; the unit tests pin the reductions it
//! implies (no sheen and no anisotropy is the core material).

pub mod sheen_albedo;

use super::stock::lobes::{
    charlie_d, charlie_visibility, ggx_anisotropic_d, ggx_anisotropic_v, schlick_weight,
};
use super::stock::{StockModel, StockParameter, fabric_colour};
use super::{EvaluatorUnit, Parsed};
use crate::model::Fabric;
use glam::DVec3;
use std::f64::consts::{FRAC_PI_2, PI};

/// The unit's entry in the registry.
pub const UNIT: EvaluatorUnit = EvaluatorUnit {
    name: "gltf",
    syntax: "gltf",
    summary: "glTF 2.0 PBR with KHR_materials_sheen and KHR_materials_anisotropy, fitted to the fabric",
    parse,
    report: None,
};

fn parse(parameter: Option<&str>) -> Parsed {
    super::stock::parse(&MODEL, &UNIT, parameter)
}

/// The material's inputs, as the glTF JSON names them.
const PARAMETERS: &[StockParameter] = &[
    StockParameter::new("baseColorFactor.r", 0.0, 1.0),
    StockParameter::new("baseColorFactor.g", 0.0, 1.0),
    StockParameter::new("baseColorFactor.b", 0.0, 1.0),
    StockParameter::new("metallicFactor", 0.0, 1.0),
    // α = roughness² must not be 0 (Appendix B); a floor for a cloth's highlight, not a
    // mirror's.
    StockParameter::new("roughnessFactor", 0.05, 1.0),
    StockParameter::new("anisotropyStrength", 0.0, 1.0),
    StockParameter::new("anisotropyRotation", -FRAC_PI_2, FRAC_PI_2),
    StockParameter::new("sheenColorFactor.r", 0.0, 1.0),
    StockParameter::new("sheenColorFactor.g", 0.0, 1.0),
    StockParameter::new("sheenColorFactor.b", 0.0, 1.0),
    StockParameter::new(
        "sheenRoughnessFactor",
        sheen_albedo::MIN_SHEEN_ROUGHNESS,
        1.0,
    ),
];

/// `cloth_stock_f` of the glTF material over the stock block.
#[cfg(feature = "runtime")]
pub const FILE: crate::shader::ShaderFile = crate::shader::ShaderFile {
    name: "evaluator/gltf",
    path: "src/evaluator/gltf/gltf.wgsl",
    source: include_str!("gltf.wgsl"),
};

/// The model.
pub static MODEL: StockModel = StockModel {
    name: "gltf",
    title: "glTF 2.0 (KHR_materials_sheen, KHR_materials_anisotropy)",
    parameters: PARAMETERS,
    start,
    derive,
    eval,
    reciprocal: true,
    conserves_energy: true,
    #[cfg(feature = "runtime")]
    wgsl: &FILE,
};

fn start(fabric: &Fabric) -> Vec<f64> {
    let [r, g, b] = fabric_colour(fabric);
    let sheen = [r, g, b].map(|c| 0.5 * c.sqrt());
    vec![
        r, g, b, 0.0, 0.6, 0.3, 0.0, sheen[0], sheen[1], sheen[2], 0.5,
    ]
}

/// The sheen's directional albedo over μ at the material's sheen roughness.
fn derive(values: &[f64]) -> Vec<f64> {
    sheen_albedo::albedo_row(values[10])
}

/// F = f(wi, wo) cos θi of the material (`cloth_stock_f` of gltf.wgsl is its twin).
fn eval(p: &[f64], derived: &[f64], l: DVec3, v: DVec3, h: DVec3) -> DVec3 {
    let base = DVec3::new(p[0], p[1], p[2]);
    let (metallic, roughness, strength, rotation) = (p[3], p[4], p[5], p[6]);
    let sheen = DVec3::new(p[7], p[8], p[9]);
    let sheen_alpha = p[10] * p[10];

    let alpha = roughness * roughness;
    let at = alpha + (1.0 - alpha) * strength * strength;
    // The anisotropy direction in the tangent plane and the bitangent n × t.
    let t = DVec3::new(rotation.cos(), rotation.sin(), 0.0);
    let b = DVec3::new(-rotation.sin(), rotation.cos(), 0.0);
    let specular = ggx_anisotropic_v(at, alpha, t, b, v, l) * ggx_anisotropic_d(at, alpha, t, b, h);
    let w = schlick_weight(v.dot(h));
    let fresnel = 0.04 + 0.96 * w;
    let dielectric = base / PI * (1.0 - fresnel) + DVec3::splat(specular * fresnel);
    let metal = specular * (base + (DVec3::ONE - base) * w);
    let material = dielectric.lerp(metal, metallic);

    let sheen_brdf =
        sheen * charlie_d(sheen_alpha, h.z, 0.0) * charlie_visibility(sheen_alpha, v.z, l.z);
    let m = sheen.max_element();
    let scaling = (1.0 - m * sheen_albedo::albedo_at(derived, v.z))
        .min(1.0 - m * sheen_albedo::albedo_at(derived, l.z));
    (sheen_brdf + material * scaling) * l.z
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::evaluator::stock::StockMaterial;

    fn material(values: [f64; 11]) -> StockMaterial {
        StockMaterial::new(&MODEL, &values)
    }

    #[test]
    fn without_sheen_or_anisotropy_a_metal_is_ggx_times_its_colour_at_normal_incidence() {
        // At wi = wo = n: D = 1/(π α²), V = 1/4, Fresnel = f0 = baseColor.
        let roughness: f64 = 0.5;
        let m = material([0.9, 0.5, 0.2, 1.0, roughness, 0.0, 0.0, 0.0, 0.0, 0.0, 0.5]);
        let f = m.eval(DVec3::Z, DVec3::Z);
        let alpha2 = roughness.powi(4);
        let expected = DVec3::new(0.9, 0.5, 0.2) / (4.0 * PI * alpha2);
        assert!(
            (f - expected).abs().max_element() < 1e-12 * expected.max_element(),
            "{f}"
        );
    }

    #[test]
    fn a_white_sheen_darkens_the_base_by_its_albedo_and_adds_its_own_lobe() {
        let (wi, wo) = (DVec3::new(0.6, 0.0, 0.8), DVec3::new(-0.28, 0.0, 0.96));
        let bare = material([0.5, 0.5, 0.5, 0.0, 0.7, 0.0, 0.0, 0.0, 0.0, 0.0, 0.4]);
        let sheen = material([0.5, 0.5, 0.5, 0.0, 0.7, 0.0, 0.0, 1.0, 1.0, 1.0, 0.4]);
        let row = sheen_albedo::albedo_row(0.4);
        let scaling = (1.0 - sheen_albedo::albedo_at(&row, 0.96))
            .min(1.0 - sheen_albedo::albedo_at(&row, 0.8));
        let h = (wi + wo).normalize();
        let lobe = charlie_d(0.16, h.z, 0.0) * charlie_visibility(0.16, 0.96, 0.8) * 0.8;
        let expected = bare.eval(wi, wo) * scaling + DVec3::splat(lobe);
        assert!((sheen.eval(wi, wo) - expected).abs().max_element() < 1e-12);
    }

    #[test]
    fn anisotropy_stretches_the_highlight_along_the_rotated_direction() {
        // Half vectors tilted by the same angle along and across the direction: along it
        // (αt larger) the highlight is wider, so F there is larger.
        let tilt = |phi: f64| {
            let (s, c) = (0.3f64.sin(), 0.3f64.cos());
            let h = DVec3::new(s * phi.cos(), s * phi.sin(), c);
            let wo = DVec3::Z;
            (2.0 * wo.dot(h) * h - wo, wo)
        };
        for rotation in [0.0, 0.7] {
            let m = material([0.5, 0.5, 0.5, 1.0, 0.3, 0.8, rotation, 0.0, 0.0, 0.0, 0.5]);
            let (along, across) = (tilt(rotation), tilt(rotation + FRAC_PI_2));
            let (fa, fc) = (m.eval(along.0, along.1), m.eval(across.0, across.1));
            assert!(fa.x > 2.0 * fc.x, "rotation {rotation}: {fa} vs {fc}");
        }
    }
}
