//! The CPU reference of a rendered view: every pixel the cloth covers shaded by the direct
//! evaluation of F (the ground truth, docs/model.md#direct-evaluation) from the G-buffer of the
//! same view, so that the comparison with a GPU render measures shading error alone (both start
//! from the same rasterised positions and frames). The environment light, where there is one, is
//! integrated by Monte Carlo against the full-resolution map (no mip filtering).

use super::image::LinearImage;
use super::{FrameSettings, GBuffer};
use crate::lighting::Environment;
use crate::model::Patch;
use crate::sampling::EnvironmentSampler;
use crate::sampling::{Sampler, hammersley};
use glam::DVec3;
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64;
use rayon::prelude::*;

/// The environment term of the reference: `∫ L_env(wi) F(wi, wo) dwi` estimated per pixel
/// with `samples` pairs of draws, one from the fabric's `sampler` and one from the map's own
/// brightness, combined by multiple importance sampling (Veach's balance heuristic), so that
/// neither a narrow lobe of F nor a small bright light of the map is left to chance. The
/// draws are a Hammersley set shifted per pixel, so that neighbouring pixels' errors are
/// independent; `L_env` is read from level 0 of `map` (no filtering).
pub struct ReferenceEnvironment<'a> {
    pub map: &'a Environment,
    pub sampler: &'a Sampler,
    pub samples: u32,
}

/// Linear radiance `Σ_lights E·F(wi, wo)` (plus the environment term) per covered pixel of
/// `gbuffer`, F by `patch` (for the reference, `Patch::new(fabric, Integration::Direct)`),
/// in f64 from the G-buffer's position and frame; alpha = coverage. Pixels in parallel
/// (rayon).
pub fn shade(
    gbuffer: &GBuffer,
    settings: &FrameSettings,
    patch: &Patch,
    environment: Option<&ReferenceEnvironment<'_>>,
) -> LinearImage {
    shade_with(gbuffer, settings, |wi, wo| patch.eval(wi, wo), environment)
}

/// A per-pixel shift in [0, 1)³, seeded by the pixel index.
fn pixel_shift(index: usize) -> [f64; 3] {
    let mut rng = Pcg64::seed_from_u64(index as u64);
    [rng.random(), rng.random(), rng.random()]
}

/// [`shade`] with any F(wi, wo) (unit directions in the local frame, both above the
/// horizon), e.g. the CPU table lookup `Table::lookup`.
pub fn shade_with(
    gbuffer: &GBuffer,
    settings: &FrameSettings,
    brdf: impl Fn(DVec3, DVec3) -> DVec3 + Sync,
    environment: Option<&ReferenceEnvironment<'_>>,
) -> LinearImage {
    let eye = settings.camera.eye.as_dvec3();
    let distribution = environment.map(|env| EnvironmentSampler::new(env.map));
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
            if let (Some(env), Some(distribution)) = (environment, &distribution)
                && wo.z > 0.0
            {
                let shift = pixel_shift(i);
                let mut light = DVec3::ZERO;
                for k in 0..env.samples {
                    let u = hammersley(k, env.samples);
                    let u = [0, 1, 2].map(|c| (u[c] + shift[c]).fract());
                    // Balance heuristic, one draw of each technique: each contributes
                    // L·F/(p_fabric + p_map) at its own direction.
                    if let Some(s) = env.sampler.sample(wo, u) {
                        let world = t * s.wi.x + b * s.wi.y + n * s.wi.z;
                        let p = s.pdf + distribution.pdf(world);
                        light += env.map.radiance(world, 0.0) * brdf(s.wi, wo) / p;
                    }
                    let (world, map_pdf) = distribution.sample([u[2], (u[0] + 0.5).fract()]);
                    let wi = local(world);
                    if wi.z > 0.0 && map_pdf > 0.0 {
                        let p = map_pdf + env.sampler.pdf(wo, wi);
                        light += env.map.radiance(world, 0.0) * brdf(wi, wo) / p;
                    }
                }
                sum += light / env.samples.max(1) as f64;
            }
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
