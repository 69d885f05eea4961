//! `filament`: Filament's cloth shading model (google/filament, `shading_model_cloth.fs` and
//! `brdf.fs`; docs/Materials.md.html, "Cloth model"), with a subsurface colour, fitted to the
//! fabric:
//!
//! - sheen: `Fr = D_Charlie(α, n·h) · V_Neubelt(n·v, n·l) · sheenColor`, α the squared
//!   perceptual roughness (clamped below at 0.045, desktop), sin²θh kept ≥ 2⁻⁷; no Fresnel;
//! - diffuse: `Fd = baseColor/π · Fd_Wrap(n·l, ½) · saturate(subsurfaceColor + n·l)`,
//!   `Fd_Wrap(x, w) = saturate((x + w)/(1 + w)²)`;
//! - `F = Fd + Fr · n·l` (the wrapped diffuse replaces the cosine, so the model is not
//!   reciprocal).

use super::stock::lobes::{charlie_d, neubelt_visibility};
use super::stock::{StockModel, StockParameter, fabric_colour, no_derived};
use super::{EvaluatorUnit, Parsed};
use crate::model::Fabric;
use glam::DVec3;
use std::f64::consts::PI;

/// The unit's entry in the registry.
pub const UNIT: EvaluatorUnit = EvaluatorUnit {
    name: "filament",
    syntax: "filament",
    summary: "Filament's cloth model (sheen colour, subsurface colour), fitted to the fabric",
    parse,
    report: None,
};

fn parse(parameter: Option<&str>) -> Parsed {
    super::stock::parse(&MODEL, &UNIT, parameter)
}

/// Filament's smallest perceptual roughness on desktop (`MIN_PERCEPTUAL_ROUGHNESS`).
pub const MIN_PERCEPTUAL_ROUGHNESS: f64 = 0.045;
/// Filament's floor of sin²θh in `D_Charlie` (a half float's precision).
const SIN2_FLOOR: f64 = 0.0078125;

/// The material's inputs, as a Filament `.mat` names them.
const PARAMETERS: &[StockParameter] = &[
    StockParameter::new("baseColor.r", 0.0, 1.0),
    StockParameter::new("baseColor.g", 0.0, 1.0),
    StockParameter::new("baseColor.b", 0.0, 1.0),
    StockParameter::new("roughness", MIN_PERCEPTUAL_ROUGHNESS, 1.0),
    StockParameter::new("sheenColor.r", 0.0, 1.0),
    StockParameter::new("sheenColor.g", 0.0, 1.0),
    StockParameter::new("sheenColor.b", 0.0, 1.0),
    StockParameter::new("subsurfaceColor.r", 0.0, 1.0),
    StockParameter::new("subsurfaceColor.g", 0.0, 1.0),
    StockParameter::new("subsurfaceColor.b", 0.0, 1.0),
];

/// `cloth_stock_f` of Filament's cloth model over the stock block.
#[cfg(feature = "runtime")]
pub const FILE: crate::shader::ShaderFile = crate::shader::ShaderFile {
    name: "evaluator/filament",
    path: "src/evaluator/filament/filament.wgsl",
    source: include_str!("filament.wgsl"),
};

/// The model.
pub static MODEL: StockModel = StockModel {
    name: "filament",
    title: "Filament cloth (shading_model_cloth.fs)",
    parameters: PARAMETERS,
    start,
    derive: no_derived,
    eval,
    reciprocal: false,
    conserves_energy: false,
    #[cfg(feature = "runtime")]
    wgsl: &FILE,
};

/// Filament's own defaults where it has them: sheenColor = √baseColor.
fn start(fabric: &Fabric) -> Vec<f64> {
    let [r, g, b] = fabric_colour(fabric);
    vec![r, g, b, 0.6, r.sqrt(), g.sqrt(), b.sqrt(), 0.2, 0.2, 0.2]
}

/// F of the cloth model (`cloth_stock_f` of filament.wgsl is its twin).
fn eval(p: &[f64], _: &[f64], l: DVec3, v: DVec3, h: DVec3) -> DVec3 {
    let base = DVec3::new(p[0], p[1], p[2]);
    let alpha = p[3] * p[3];
    let sheen = DVec3::new(p[4], p[5], p[6]);
    let subsurface = DVec3::new(p[7], p[8], p[9]);
    let fr = sheen * (charlie_d(alpha, h.z, SIN2_FLOOR) * neubelt_visibility(v.z, l.z));
    let wrap = ((l.z + 0.5) / 2.25).clamp(0.0, 1.0);
    let fd = base / PI * wrap * (subsurface + DVec3::splat(l.z)).clamp(DVec3::ZERO, DVec3::ONE);
    fd + fr * l.z
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::evaluator::stock::StockMaterial;

    #[test]
    fn a_white_subsurface_gives_the_wrapped_diffuse_and_a_black_sheen_no_lobe() {
        let m = StockMaterial::new(&MODEL, &[0.6, 0.4, 0.2, 0.5, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0]);
        let (wi, wo) = (DVec3::new(0.6, 0.0, 0.8), DVec3::Z);
        let expected = DVec3::new(0.6, 0.4, 0.2) / PI * (1.3 / 2.25);
        assert!((m.eval(wi, wo) - expected).abs().max_element() < 1e-12);
    }

    #[test]
    fn the_sheen_lobe_is_charlie_times_neubelt_times_the_cosine() {
        let m = StockMaterial::new(&MODEL, &[0.0, 0.0, 0.0, 0.5, 1.0, 0.5, 0.25, 0.0, 0.0, 0.0]);
        let (wi, wo) = (DVec3::new(0.6, 0.0, 0.8), DVec3::new(-0.6, 0.0, 0.8));
        // h = n: sin²θh = 0 is floored at 2⁻⁷; V = 1/(4 (1.6 − 0.64)).
        let d = (2.0 + 4.0) * SIN2_FLOOR.powf(2.0) / (2.0 * PI);
        let lobe = d / (4.0 * 0.96) * 0.8;
        let f = m.eval(wi, wo);
        assert!(
            (f - DVec3::new(1.0, 0.5, 0.25) * lobe).abs().max_element() < 1e-15,
            "{f}"
        );
    }
}
