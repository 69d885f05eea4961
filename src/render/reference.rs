//! The CPU reference of a rendered view: every pixel the cloth covers shaded by the direct
//! evaluation of F (the ground truth, docs/model.md#direct-evaluation) from the G-buffer of the
//! same view, so that the comparison with a GPU render measures shading error alone (both start
//! from the same rasterised positions and frames). The environment light, where there is one, is
//! integrated against the full-resolution map (no mip filtering): its compact bright sources
//! ([`crate::lighting::bright_sources`]) texel block by texel block, the rest by Monte Carlo.

use super::image::LinearImage;
use super::{FrameSettings, GBuffer};
use crate::lighting::Environment;
use crate::lighting::bright_sources::MAX_SOURCES;
use crate::model::Patch;
use crate::sampling::EnvironmentSampler;
use crate::sampling::{Sampler, hammersley};
use glam::DVec3;
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64;
use rayon::prelude::*;

/// The environment term of the reference: `∫ L_env(wi) F(wi, wo) dwi` per pixel, with the
/// map split into its compact bright sources and a residual (the split is exact: the two
/// add up to the map). A source's part is the sum of `E·F` over its
/// [`parts`](crate::lighting::DistantSource::parts), blocks of its texels: a 0.5° sun of
/// radiance 3.5·10⁴ left to random draws would make the reference the noisiest image in the
/// comparison. The residual's part is estimated with `samples` pairs of draws, one from the
/// fabric's `sampler` and one from the residual's own brightness, combined by multiple
/// importance sampling (Veach's balance heuristic), so that neither a narrow lobe of F nor a
/// bright region of the map is left to chance. The draws are a Hammersley set shifted per
/// pixel, so that neighbouring pixels' errors are independent; `L_env` is read from level 0
/// (no filtering).
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
    let split = environment.map(|env| env.map.split_bright_sources(MAX_SOURCES));
    let distribution = split
        .as_ref()
        .map(|split| EnvironmentSampler::new(&split.residual));
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
            // World directions to and from the map's (the environment's rotation).
            let turn = glam::DQuat::from_rotation_y(settings.environment_rotation as f64);
            let mut sum = DVec3::ZERO;
            if let (Some(env), Some(split), Some(distribution)) =
                (environment, &split, &distribution)
                && wo.z > 0.0
            {
                let residual = &split.residual;
                let shift = pixel_shift(i);
                let mut light = DVec3::ZERO;
                for k in 0..env.samples {
                    let u = hammersley(k, env.samples);
                    let u = [0, 1, 2].map(|c| (u[c] + shift[c]).fract());
                    // Balance heuristic, one draw of each technique: each contributes
                    // L·F/(p_fabric + p_map) at its own direction.
                    if let Some(s) = env.sampler.sample(wo, u) {
                        let map = turn.inverse() * (t * s.wi.x + b * s.wi.y + n * s.wi.z);
                        let p = s.pdf + distribution.pdf(map);
                        light += residual.radiance(map, 0.0) * brdf(s.wi, wo) / p;
                    }
                    let (map, map_pdf) = distribution.sample([u[2], (u[0] + 0.5).fract()]);
                    let wi = local(turn * map);
                    if wi.z > 0.0 && map_pdf > 0.0 {
                        let p = map_pdf + env.sampler.pdf(wo, wi);
                        light += residual.radiance(map, 0.0) * brdf(wi, wo) / p;
                    }
                }
                sum += light / env.samples.max(1) as f64;
                for &(direction, irradiance) in split.sources.iter().flat_map(|s| &s.parts) {
                    let wi = local(turn * direction);
                    if wi.z > 0.0 {
                        sum += irradiance * brdf(wi, wo);
                    }
                }
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
