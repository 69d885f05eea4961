//! What changes from frame to frame ([`FrameSettings`]: camera, lights, exposure,
//! background, environment samples) and its packing into the uniform block of
//! shaders/render/renderer.wgsl. The packing is private to the renderer; only its layout has
//! to match the WGSL.

use super::environment_map::EnvironmentFrame;
use super::{Camera, LightSource};
use crate::lighting::bright_sources::MAX_SOURCES;
use crate::scene::{MAX_LIGHTS, Scene};
use bytemuck::{Pod, Zeroable};

/// Everything that changes from frame to frame.
#[derive(Clone, Debug, PartialEq)]
pub struct FrameSettings {
    pub camera: Camera,
    /// At most [`MAX_LIGHTS`]; more are ignored.
    pub lights: Vec<LightSource>,
    /// Radiance scale before tone mapping.
    pub exposure: f32,
    /// Background display colour (sRGB-encoded values in [0, 1]).
    pub background: [f32; 3],
    /// Samples per pixel of the environment light (filtered importance sampling, see
    /// shaders/render/renderer.wgsl); 0: no environment light.
    pub environment_samples: u32,
    /// The environment's rotation about +y, radians: the light arriving from world direction
    /// `d` is the map's from `R_y(−rotation)·d`.
    pub environment_rotation: f32,
}

/// The default background: dark grey.
pub const BACKGROUND: [f32; 3] = [0.06, 0.06, 0.07];

impl FrameSettings {
    /// The camera, lights, exposure and environment samples of a scene.
    pub fn from_scene(scene: &Scene) -> Self {
        Self {
            camera: Camera::orbit(&scene.camera),
            lights: scene.lights.iter().map(LightSource::from_scene).collect(),
            exposure: scene.exposure as f32,
            background: BACKGROUND,
            environment_samples: match scene.environment.source {
                crate::lighting::EnvironmentSource::None => 0,
                _ => scene.environment.samples,
            },
            environment_rotation: 0.0,
        }
    }
}

/// Lights a frame holds: the scene's, then the sources taken out of its environment
/// (WGSL `RenderFrameUniform::lights`).
const FRAME_LIGHTS: usize = MAX_LIGHTS + MAX_SOURCES;

/// One light of [`FrameUniform`] (WGSL `RenderLight`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
struct LightUniform {
    vector: [f32; 4],
    power: [f32; 4],
}

/// The uniform block of shaders/render/renderer.wgsl (`RenderFrameUniform`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub(super) struct FrameUniform {
    view_proj: [[f32; 4]; 4],
    inverse_view_proj: [[f32; 4]; 4],
    eye: [f32; 4],
    params: [f32; 4],
    counts: [u32; 4],
    environment: [f32; 4],
    lights: [LightUniform; FRAME_LIGHTS],
}

impl FrameUniform {
    /// `environment`: the environment map in the lighting group and its sources, if it holds
    /// one (without, the frame has no environment light), and the samples per pixel of the
    /// sample taps there: they are the frame's when its settings ask for environment light
    /// (the renderer checks that the two agree). The sources are lit with the environment,
    /// after the scene's lights.
    pub(super) fn new(
        settings: &FrameSettings,
        aspect: f32,
        encode_srgb: bool,
        environment: Option<(&EnvironmentFrame, u32)>,
    ) -> Self {
        let (environment, samples) = match environment {
            Some((frame, taps)) if settings.environment_samples > 0 => (Some(frame), taps),
            _ => (None, 0),
        };
        let dimensions = environment.map_or([0; 3], |e| e.dimensions);
        let sources = match environment {
            Some(e) if samples > 0 => &e.sources[..e.sources.len().min(MAX_SOURCES)],
            _ => &[],
        };
        let scene_lights = &settings.lights[..settings.lights.len().min(MAX_LIGHTS)];
        let mut lights = [LightUniform::default(); FRAME_LIGHTS];
        let count = scene_lights.len() + sources.len();
        let turn = glam::Quat::from_rotation_y(settings.environment_rotation);
        let uniforms = scene_lights
            .iter()
            .map(|light| match *light {
                LightSource::Directional {
                    direction,
                    irradiance,
                } => LightUniform {
                    vector: direction.extend(0.0).to_array(),
                    power: irradiance.extend(0.0).to_array(),
                },
                LightSource::Point {
                    position,
                    intensity,
                } => LightUniform {
                    vector: position.extend(1.0).to_array(),
                    power: intensity.extend(0.0).to_array(),
                },
            })
            .chain(sources.iter().map(|source| LightUniform {
                vector: (turn * source.direction).extend(0.0).to_array(),
                power: source.irradiance.extend(source.sin_radius).to_array(),
            }));
        for (slot, uniform) in lights.iter_mut().zip(uniforms) {
            *slot = uniform;
        }
        let view_proj = settings.camera.view_proj(aspect);
        Self {
            view_proj: view_proj.to_cols_array_2d(),
            inverse_view_proj: view_proj.inverse().to_cols_array_2d(),
            eye: settings.camera.eye.extend(1.0).to_array(),
            params: [settings.exposure, encode_srgb as u32 as f32, 0.0, 0.0],
            counts: [count as u32, samples, 0, 0],
            environment: [
                dimensions[0] as f32,
                dimensions[1] as f32,
                dimensions[2] as f32,
                settings.environment_rotation,
            ],
            lights,
        }
    }
}
