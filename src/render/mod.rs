//! Rendering cloth with a [`GpuBrdf`]: a draped sheet (or a user's mesh) whose thread frame
//! follows its UVs, lit by directional and point lights, seen by an orbit camera, tone mapped.
//!
//! - [`Renderer`]: the render pipeline for one colour format; records a frame into any
//!   colour target (a window's surface texture or an offscreen texture) and, optionally, a
//!   linear-radiance target. Reusable by an interactive viewer.
//! - [`Headless`]: offscreen targets and read-back around a [`Renderer`]: linear radiance,
//!   8-bit display image, GPU time per frame, and the G-buffer of the CPU reference.
//! - [`mod@reference`]: the same view shaded on the CPU by direct evaluation (and the
//!   environment light by multiple importance sampling).
//! - [`job`]: the `render` command: every fabric of a scene to PNG, timed, optionally
//!   against the CPU reference.
//! - [`image`]: tone mapping, image error metrics, heat maps, PNG/EXR files.
//!
//! Shading (shaders/render/renderer.wgsl): per pixel, the frame (t, b = n × t, n) from the
//! interpolated vertex normal and tangent, re-orthonormalised, flipped to the side facing the
//! viewer (two-sided cloth); wi and wo in that frame; radiance `L = Σ_lights E·F(wi, wo)`
//! with `E` the light's perpendicular irradiance at the point (directional: colour ×
//! irradiance; point: colour × I/d²), plus the environment light by filtered importance
//! sampling ([`GpuEnvironment`], K samples of the fabric's sampler per pixel, each read from
//! the mip level whose texels match the sample's share of the hemisphere). No shadows.
//!
//! The parts of this module, one concern to a file: [`Camera`] (camera.rs), [`LightSource`]
//! (lights.rs), the environment map and lighting group ([`GpuEnvironment`],
//! environment_map.rs), [`FrameSettings`] and its uniform packing (frame.rs), [`Renderer`] and the
//! texture formats (renderer.rs), [`Headless`] and the read-back (headless.rs), frame
//! timing (timing.rs). Everything public is re-exported here.
//!
//! [`GpuBrdf`]: crate::gpu::GpuBrdf

pub mod drape_loss;
pub mod image;
pub mod job;
pub mod reference;

mod camera;
mod environment_map;
mod frame;
mod headless;
mod lights;
mod pipelines;
mod renderer;
mod targets;
mod timing;

pub use camera::Camera;
pub use environment_map::GpuEnvironment;
pub use frame::{BACKGROUND, FrameSettings};
pub use headless::{
    GBuffer, HEADLESS_COLOR_FORMAT, Headless, MAX_IMAGE_SIDE, RenderOutput, read_texture,
};
pub use lights::LightSource;
#[cfg(test)]
pub(crate) use renderer::STUB_BRDF_WGSL;
pub use renderer::{
    FrameTargets, GBufferTargets, PreparedBrdf, RENDER_MODULE, Renderer, render_wgsl,
};
pub(crate) use targets::target;
pub use targets::{
    DEPTH_FORMAT, GBUFFER_FORMAT, LINEAR_FORMAT, LINEAR_FORMAT_F16, float32_renderable,
    linear_format,
};
pub(crate) use timing::PassTimestamps;
pub use timing::{FrameTiming, TimingSource, median};
