//! The CPU reference of a rendered view: every pixel the cloth covers shaded by the direct
//! evaluation of F (MODEL.md's ground truth) from the G-buffer of the same view, so that the
//! comparison with a GPU render measures shading error alone (both start from the same
//! rasterised positions and frames).

use super::image::LinearImage;
use super::{FrameSettings, GBuffer};
use crate::model::Patch;
use glam::DVec3;
use rayon::prelude::*;

/// Linear radiance `Σ_lights E·F(wi, wo)` per covered pixel of `gbuffer`, F by `patch` (for
/// the reference, `Patch::new(fabric, Integration::Direct)`), in f64 from the G-buffer's
/// position and frame; alpha = coverage. Pixels in parallel (rayon).
pub fn shade(gbuffer: &GBuffer, settings: &FrameSettings, patch: &Patch) -> LinearImage {
    shade_with(gbuffer, settings, |wi, wo| patch.eval(wi, wo))
}

/// [`shade`] with any F(wi, wo) (unit directions in the local frame, both above the
/// horizon), e.g. the CPU table lookup `Table::lookup`.
pub fn shade_with(
    gbuffer: &GBuffer,
    settings: &FrameSettings,
    brdf: impl Fn(DVec3, DVec3) -> DVec3 + Sync,
) -> LinearImage {
    let eye = settings.camera.eye.as_dvec3();
    let lights = &settings.lights[..settings.lights.len().min(crate::scene::MAX_LIGHTS)];
    let pixels = (0..gbuffer.position.len())
        .into_par_iter()
        .map(|i| {
            let p = gbuffer.position[i];
            if p[3] <= 0.5 {
                return [0.0; 4];
            }
            let position = DVec3::new(p[0] as f64, p[1] as f64, p[2] as f64);
            let v = |a: [f32; 4]| DVec3::new(a[0] as f64, a[1] as f64, a[2] as f64);
            // The stored frame is orthonormal to f32 precision; renormalise in f64.
            let n = v(gbuffer.normal[i]).normalize();
            let t = (v(gbuffer.tangent[i]) - n * n.dot(v(gbuffer.tangent[i]))).normalize();
            let b = n.cross(t);
            let local = |w: DVec3| DVec3::new(w.dot(t), w.dot(b), w.dot(n));
            let wo = local((eye - position).normalize());
            let mut sum = DVec3::ZERO;
            for light in lights {
                let (direction, irradiance) = light.at(position);
                let wi = local(direction);
                if wi.z > 0.0 && wo.z > 0.0 {
                    sum += irradiance * brdf(wi, wo);
                }
            }
            [sum.x as f32, sum.y as f32, sum.z as f32, 1.0]
        })
        .collect();
    LinearImage {
        width: gbuffer.width,
        height: gbuffer.height,
        pixels,
    }
}
