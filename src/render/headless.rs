//! Offscreen rendering: [`Headless`] owns targets of one size around a [`Renderer`],
//! renders timed frames and reads the linear radiance, the display image and the G-buffer
//! back to the CPU. The read-back (copy, map, unpad rows) lives here and nowhere else.

use super::image::{LinearImage, Rgba8Image};
use super::targets::{check_gbuffer_support, target};
use super::{
    DEPTH_FORMAT, FrameSettings, FrameTargets, FrameTiming, GBUFFER_FORMAT, GBufferTargets,
    LINEAR_FORMAT, PassTimestamps, Renderer, TimingSource,
};
use crate::gpu::{GpuBrdf, GpuContext, GpuError};
use crate::scene::mesh::Mesh;
use std::time::Instant;

/// Largest headless image side: bounds the read-back and G-buffer memory (3 × 16 bytes per
/// pixel: 768 MiB at 4096²).
pub const MAX_IMAGE_SIDE: u32 = 4096;

/// What a headless render returns.
#[derive(Clone, Debug)]
pub struct RenderOutput {
    /// Linear radiance, alpha = coverage.
    pub linear: LinearImage,
    /// The tone-mapped image as the GPU wrote it.
    pub display: Rgba8Image,
    pub timing: FrameTiming,
}

/// Per-pixel inputs of the shading, as the render pass computes them (see
/// [`Renderer::encode_gbuffer`]); rows top to bottom.
#[derive(Clone, Debug, Default)]
pub struct GBuffer {
    pub width: u32,
    pub height: u32,
    /// World position; w = 1 where covered.
    pub position: Vec<[f32; 4]>,
    /// Unit tangent (thread 1) of the shading frame.
    pub tangent: Vec<[f32; 4]>,
    /// Unit normal of the shading frame, facing the viewer.
    pub normal: Vec<[f32; 4]>,
}

/// Offscreen rendering: a [`Renderer`] with its own targets of one size, read back to the
/// CPU. The display target is `Rgba8Unorm` (sRGB-encoded by the shader).
pub struct Headless {
    pub renderer: Renderer,
    size: (u32, u32),
    color: wgpu::Texture,
    linear: wgpu::Texture,
    depth: wgpu::Texture,
}

/// The display format of [`Headless`].
pub const HEADLESS_COLOR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;

impl Headless {
    /// Targets of `width`×`height` (each in [1, [`MAX_IMAGE_SIDE`]]) and a renderer of
    /// `mesh` with `brdf`.
    pub fn new(
        context: &GpuContext,
        mesh: &Mesh,
        brdf: &dyn GpuBrdf,
        width: u32,
        height: u32,
    ) -> Result<Self, GpuError> {
        let max = MAX_IMAGE_SIDE.min(context.device.limits().max_texture_dimension_2d);
        for (name, value) in [("width", width), ("height", height)] {
            if !(1..=max).contains(&value) {
                return Err(GpuError::Invalid {
                    name: name.into(),
                    message: format!("must be in [1, {max}], got {value}"),
                });
            }
        }
        let renderer = Renderer::new(context, HEADLESS_COLOR_FORMAT, true, mesh, brdf)?;
        let linear_format = renderer.linear_format().unwrap_or(LINEAR_FORMAT);
        let (color, linear, depth) = context.checked(|| {
            (
                target(context, "display", HEADLESS_COLOR_FORMAT, width, height),
                target(context, "linear", linear_format, width, height),
                target(context, "depth", DEPTH_FORMAT, width, height),
            )
        })?;
        Ok(Self {
            renderer,
            size: (width, height),
            color,
            linear,
            depth,
        })
    }

    /// Renders `frames` timed frames (at least 1) after one untimed warm-up frame, then one
    /// untimed frame that also writes the linear radiance, and reads that back. The timed
    /// frames draw the display image alone, as [`crate::viewer`] does: writing a float
    /// target as well is the reference comparison's cost, not the real-time frame's. Frame
    /// times come from GPU timestamps when the device has them.
    pub fn render(
        &self,
        context: &GpuContext,
        settings: &FrameSettings,
        frames: u32,
    ) -> Result<RenderOutput, GpuError> {
        self.renderer.check_settings(settings)?;
        let device = &context.device;
        let color_view = self.color.create_view(&Default::default());
        let linear_view = self.linear.create_view(&Default::default());
        let depth_view = self.depth.create_view(&Default::default());
        let timer = context
            .timestamps()
            .then(|| PassTimestamps::new(context, "frame timestamps"));
        let mut frame_ms = Vec::new();
        let last = frames.max(1) + 1;
        for frame in 0..=last {
            // Frame 0 warms up, frames 1 to last − 1 are timed, the last writes the linear
            // radiance as well.
            let timed = frame > 0 && frame < last;
            let targets = FrameTargets {
                color: &color_view,
                linear: (frame == last).then_some(&linear_view),
                depth: &depth_view,
                size: self.size,
            };
            let mut encoder = device.create_command_encoder(&Default::default());
            let timer = timer.as_ref().filter(|_| timed);
            let writes = timer.map(PassTimestamps::writes);
            context.checked(|| {
                self.renderer
                    .encode(&context.queue, &mut encoder, &targets, settings, writes)
            })?;
            if let Some(timer) = timer {
                timer.resolve(&mut encoder);
            }
            let start = Instant::now();
            context.queue.submit([encoder.finish()]);
            wait(context)?;
            let wall = start.elapsed().as_secs_f64() * 1e3;
            if timed {
                frame_ms.push(match timer {
                    Some(timer) => timer.read(context)?,
                    None => wall,
                });
            }
        }
        let linear = match self.linear.format() {
            LINEAR_FORMAT => read_texture(context, &self.linear, 16, self.size)?,
            _ => {
                let halves = read_texture(context, &self.linear, 8, self.size)?;
                halves
                    .chunks_exact(2)
                    .flat_map(|h| {
                        half::f16::from_le_bytes([h[0], h[1]])
                            .to_f32()
                            .to_le_bytes()
                    })
                    .collect()
            }
        };
        let display = read_texture(context, &self.color, 4, self.size)?;
        let (width, height) = self.size;
        Ok(RenderOutput {
            linear: LinearImage {
                width,
                height,
                pixels: rgba_f32(&linear),
            },
            display: Rgba8Image {
                width,
                height,
                pixels: bytemuck::cast_slice(&display).to_vec(),
            },
            timing: FrameTiming {
                source: if timer.is_some() {
                    TimingSource::GpuTimestamps
                } else {
                    TimingSource::WallClock
                },
                frame_ms,
            },
        })
    }

    /// The G-buffer of the view `settings` describes (same size, mesh and rasterisation as
    /// [`Headless::render`]).
    pub fn gbuffer(
        &mut self,
        context: &GpuContext,
        settings: &FrameSettings,
    ) -> Result<GBuffer, GpuError> {
        check_gbuffer_support(context)?;
        let (width, height) = self.size;
        let textures = context.checked(|| {
            ["position", "tangent", "normal"]
                .map(|name| target(context, name, GBUFFER_FORMAT, width, height))
        })?;
        let views = textures
            .each_ref()
            .map(|t| t.create_view(&Default::default()));
        let depth_view = self.depth.create_view(&Default::default());
        let mut encoder = context.device.create_command_encoder(&Default::default());
        let targets = GBufferTargets {
            position: &views[0],
            tangent: &views[1],
            normal: &views[2],
            depth: &depth_view,
            size: self.size,
        };
        self.renderer
            .encode_gbuffer(context, &mut encoder, &targets, settings)?;
        context.queue.submit([encoder.finish()]);
        wait(context)?;
        let mut planes = Vec::new();
        for texture in &textures {
            let bytes = read_texture(context, texture, 16, self.size)?;
            planes.push(rgba_f32(&bytes));
        }
        let normal = planes.pop().unwrap_or_default();
        let tangent = planes.pop().unwrap_or_default();
        let position = planes.pop().unwrap_or_default();
        Ok(GBuffer {
            width,
            height,
            position,
            tangent,
            normal,
        })
    }
}

/// RGBA f32 texels from little-endian bytes (no alignment assumed).
fn rgba_f32(bytes: &[u8]) -> Vec<[f32; 4]> {
    bytes
        .chunks_exact(16)
        .map(|t| std::array::from_fn(|c| f32::from_le_bytes(std::array::from_fn(|k| t[4 * c + k]))))
        .collect()
}

fn wait(context: &GpuContext) -> Result<(), GpuError> {
    context
        .device
        .poll(wgpu::PollType::wait_indefinitely())
        .map(|_| ())
        .map_err(|e| GpuError::Wgpu(e.to_string()))
}

/// Maps `buffer` and returns a copy of its bytes.
pub(super) fn map_read(context: &GpuContext, buffer: &wgpu::Buffer) -> Result<Vec<u8>, GpuError> {
    let slice = buffer.slice(..);
    let (sender, receiver) = std::sync::mpsc::channel();
    slice.map_async(wgpu::MapMode::Read, move |r| {
        let _ = sender.send(r);
    });
    wait(context)?;
    receiver
        .recv()
        .map_err(|e| GpuError::Wgpu(e.to_string()))?
        .map_err(|e| GpuError::Wgpu(e.to_string()))?;
    let bytes = slice
        .get_mapped_range()
        .map_err(|e| GpuError::Wgpu(e.to_string()))?
        .to_vec();
    buffer.unmap();
    Ok(bytes)
}

/// Reads a 2D texture of `texel_bytes` per texel back, rows unpadded, top to bottom.
pub fn read_texture(
    context: &GpuContext,
    texture: &wgpu::Texture,
    texel_bytes: u32,
    (width, height): (u32, u32),
) -> Result<Vec<u8>, GpuError> {
    let row = width * texel_bytes;
    let padded =
        row.div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT) * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
    let buffer = context.checked(|| {
        let buffer = context.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("read-back"),
            size: padded as u64 * height as u64,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut encoder = context.device.create_command_encoder(&Default::default());
        encoder.copy_texture_to_buffer(
            texture.as_image_copy(),
            wgpu::TexelCopyBufferInfo {
                buffer: &buffer,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(padded),
                    rows_per_image: Some(height),
                },
            },
            wgpu::Extent3d {
                width,
                height,
                depth_or_array_layers: 1,
            },
        );
        context.queue.submit([encoder.finish()]);
        buffer
    })?;
    let bytes = map_read(context, &buffer)?;
    Ok(bytes
        .chunks_exact(padded as usize)
        .flat_map(|r| &r[..row as usize])
        .copied()
        .collect())
}
