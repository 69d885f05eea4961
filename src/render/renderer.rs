//! The render pipelines: [`Renderer`] records a frame (or the G-buffer of the CPU
//! reference) into targets it is given, with the texture formats those targets must have
//! and whether the device can render to them. Knows nothing of offscreen targets or
//! read-back, so that the viewer and [`super::Headless`] share it.

use super::FrameSettings;
use super::environment_map::{EnvironmentFrame, GpuEnvironment, lighting_group, lighting_layout};
use super::frame::FrameUniform;
use super::image;
use super::pipelines::{Pipelines, mesh_pipeline, shader_module};
use super::targets::{GBUFFER_FORMAT, check_gbuffer_support, linear_format};
use crate::gpu::{GpuBrdf, GpuContext, GpuError, GpuSampleTaps};
use crate::scene::mesh::Mesh;
use std::collections::HashMap;
use wgpu::util::DeviceExt;

/// The registered module of the render shader, which requires a [`GpuBrdf::wgsl`] (the
/// generated module [`crate::shader::BRDF`]) and the fabric sampler.
pub const RENDER_MODULE: &str = "render/renderer";

/// A `cloth_brdf` that returns 0, for the G-buffer pipeline (which never calls it).
pub(crate) const STUB_BRDF_WGSL: &str =
    "fn cloth_brdf(wi: vec3<f32>, wo: vec3<f32>) -> vec3<f32> { return vec3<f32>(0.0); }\n";

/// The targets of one frame. `linear` may be given only when the renderer was made with a
/// linear output (of [`Renderer::linear_format`]); without it the frame is the display image
/// alone, as a real-time frame. `depth` is [`DEPTH_FORMAT`](super::DEPTH_FORMAT); all of `size`.
pub struct FrameTargets<'a> {
    pub color: &'a wgpu::TextureView,
    pub linear: Option<&'a wgpu::TextureView>,
    pub depth: &'a wgpu::TextureView,
    /// Width and height in pixels (for the aspect ratio).
    pub size: (u32, u32),
}

/// The targets of a G-buffer pass: three [`GBUFFER_FORMAT`] views (position with
/// coverage in w, tangent, normal) and a depth view, all of `size`.
pub struct GBufferTargets<'a> {
    pub position: &'a wgpu::TextureView,
    pub tangent: &'a wgpu::TextureView,
    pub normal: &'a wgpu::TextureView,
    pub depth: &'a wgpu::TextureView,
    pub size: (u32, u32),
}

/// A BRDF ready for [`Renderer`]: the pipelines of its shader and its bind group.
#[derive(Clone)]
pub struct PreparedBrdf {
    pipelines: Pipelines,
    group: wgpu::BindGroup,
    label: String,
}

/// The cloth render pipeline: a mesh, a [`GpuBrdf`], the uniforms of a frame.
///
/// The pipelines of each distinct BRDF shader are built once and kept, so switching between BRDFs
/// already seen (fabrics of one table layout, lookup/direct) costs no shader compilation.
pub struct Renderer {
    color_format: wgpu::TextureFormat,
    /// The format of the linear-radiance output, if any.
    linear_format: Option<wgpu::TextureFormat>,
    /// The shader applies the sRGB transfer function (the colour format does not).
    encode_srgb: bool,
    frame_layout: wgpu::BindGroupLayout,
    frame_buffer: wgpu::Buffer,
    frame_group: wgpu::BindGroup,
    vertices: wgpu::Buffer,
    indices: wgpu::Buffer,
    index_count: u32,
    lighting_layout: wgpu::BindGroupLayout,
    /// The environment map and the fabric's sample taps (@group(2)).
    lighting_group: wgpu::BindGroup,
    /// The samples per pixel of the taps in `lighting_group` (0 until
    /// [`Renderer::set_environment`]).
    tap_samples: u32,
    /// [`GpuEnvironment::dimensions`] of the map in `lighting_group`; `None` until
    /// [`Renderer::set_environment`] (frames then have no environment light, whatever their
    /// settings ask).
    environment: Option<EnvironmentFrame>,
    /// The current BRDF's pipelines (set by `new`), kept out of the map so that a frame
    /// does not hash the shader source to find them.
    current: Option<PreparedBrdf>,
    /// The BRDF of the right half of the display, when comparing ([`Renderer::set_split`]).
    split: Option<PreparedBrdf>,
    /// Pipelines by shader source.
    pipelines: HashMap<String, Pipelines>,
    gbuffer_pipeline: Option<wgpu::RenderPipeline>,
}

impl Renderer {
    /// A renderer drawing `mesh` shaded by `brdf` into targets of `color_format` (tone
    /// mapped; sRGB-encoded by the format if it is an `…Srgb` format, else by the shader),
    /// plus a linear-radiance target of [`linear_format`] when `linear_output` (see
    /// [`Renderer::linear_format`]).
    pub fn new(
        context: &GpuContext,
        color_format: wgpu::TextureFormat,
        linear_output: bool,
        mesh: &Mesh,
        brdf: &dyn GpuBrdf,
    ) -> Result<Self, GpuError> {
        if mesh.vertices.is_empty() || mesh.indices.len() < 3 {
            return Err(GpuError::Invalid {
                name: "mesh".into(),
                message: "has no triangles".into(),
            });
        }
        let device = &context.device;
        let black = GpuEnvironment::black(context)?;
        let placeholder = GpuSampleTaps::placeholder(context)?;
        let lighting_layout = context.checked(|| lighting_layout(context))?;
        let lighting_group =
            context.checked(|| lighting_group(context, &lighting_layout, &black, &placeholder))?;
        let (frame_layout, frame_buffer, frame_group, vertices, indices) =
            context.checked(|| {
                let frame_layout =
                    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                        label: Some("render frame"),
                        entries: &[wgpu::BindGroupLayoutEntry {
                            binding: 0,
                            visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
                            ty: wgpu::BindingType::Buffer {
                                ty: wgpu::BufferBindingType::Uniform,
                                has_dynamic_offset: false,
                                min_binding_size: wgpu::BufferSize::new(std::mem::size_of::<
                                    FrameUniform,
                                >(
                                )
                                    as u64),
                            },
                            count: None,
                        }],
                    });
                let frame_buffer = device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("render frame"),
                    size: std::mem::size_of::<FrameUniform>() as u64,
                    usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                });
                let frame_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some("render frame"),
                    layout: &frame_layout,
                    entries: &[wgpu::BindGroupEntry {
                        binding: 0,
                        resource: frame_buffer.as_entire_binding(),
                    }],
                });
                let (vertices, indices) = mesh_buffers(device, mesh);
                (frame_layout, frame_buffer, frame_group, vertices, indices)
            })?;
        let mut renderer = Self {
            color_format,
            linear_format: linear_output.then(|| linear_format(context)),
            encode_srgb: !color_format.is_srgb(),
            frame_layout,
            frame_buffer,
            frame_group,
            vertices,
            indices,
            index_count: mesh.indices.len() as u32,
            lighting_layout,
            lighting_group,
            tap_samples: 0,
            environment: None,
            current: None,
            split: None,
            pipelines: HashMap::new(),
            gbuffer_pipeline: None,
        };
        renderer.set_brdf(context, brdf)?;
        Ok(renderer)
    }

    /// `brdf` made ready to draw: its pipelines (built unless a BRDF with the same shader
    /// was prepared before) and its bind group.
    pub fn prepare_brdf(
        &mut self,
        context: &GpuContext,
        brdf: &dyn GpuBrdf,
    ) -> Result<PreparedBrdf, GpuError> {
        let source = render_wgsl(&brdf.wgsl());
        let pipelines = match self.pipelines.get(&source) {
            Some(pipelines) => pipelines.clone(),
            None => {
                let pipelines = context.checked(|| {
                    Pipelines::build(
                        context,
                        &source,
                        brdf.bind_group_layout(),
                        [&self.frame_layout, &self.lighting_layout],
                        self.color_format,
                        self.linear_format,
                    )
                })?;
                self.pipelines.insert(source, pipelines.clone());
                pipelines
            }
        };
        Ok(PreparedBrdf {
            pipelines,
            group: brdf.bind_group().clone(),
            label: brdf.label(),
        })
    }

    /// Shades with `brdf` from now on (builds its pipeline unless one for the same shader
    /// was built before).
    pub fn set_brdf(&mut self, context: &GpuContext, brdf: &dyn GpuBrdf) -> Result<(), GpuError> {
        self.current = Some(self.prepare_brdf(context, brdf)?);
        Ok(())
    }

    /// Shades the right half of the display by `right` (prepared by this renderer), the
    /// left by the current BRDF, for side-by-side comparison; `None` shades it all by the
    /// current one.
    pub fn set_split(&mut self, right: Option<PreparedBrdf>) {
        self.split = right;
    }

    /// Lights the cloth with `environment` from now on, through the fabric's sample `taps`
    /// (built for the frames' [`FrameSettings::environment_samples`], which
    /// [`Renderer::check_settings`] checks; set the taps again when the fabric changes).
    pub fn set_environment(
        &mut self,
        context: &GpuContext,
        environment: &GpuEnvironment,
        taps: &GpuSampleTaps,
    ) -> Result<(), GpuError> {
        self.lighting_group = context
            .checked(|| lighting_group(context, &self.lighting_layout, environment, taps))?;
        self.tap_samples = taps.samples();
        self.environment = Some(environment.frame().clone());
        Ok(())
    }

    /// Whether frames of `settings` can be drawn: their environment samples per pixel, if
    /// any, must be those the taps of [`Renderer::set_environment`] were built for (the
    /// taps are K strata that together tile the hemisphere; a part of them misses part of F).
    pub fn check_settings(&self, settings: &FrameSettings) -> Result<(), GpuError> {
        let samples = settings.environment_samples;
        if self.environment.is_some() && samples > 0 && samples != self.tap_samples {
            return Err(GpuError::Invalid {
                name: "environment samples".into(),
                message: format!(
                    "{samples} per pixel, but the fabric's sample taps were built for {}",
                    self.tap_samples
                ),
            });
        }
        Ok(())
    }

    /// The label of the current BRDF ([`GpuBrdf::label`]).
    pub fn brdf_label(&self) -> &str {
        self.current.as_ref().map_or("", |brdf| &brdf.label)
    }

    /// The format its linear-radiance target must have (`None`: made without one).
    pub fn linear_format(&self) -> Option<wgpu::TextureFormat> {
        self.linear_format
    }

    fn write_uniforms(&self, queue: &wgpu::Queue, settings: &FrameSettings, size: (u32, u32)) {
        let aspect = size.0.max(1) as f32 / size.1.max(1) as f32;
        let uniform = FrameUniform::new(
            settings,
            aspect,
            self.encode_srgb,
            self.environment.as_ref().map(|e| (e, self.tap_samples)),
        );
        queue.write_buffer(&self.frame_buffer, 0, bytemuck::bytes_of(&uniform));
    }

    /// Records one frame: clears the targets (colour to `settings.background`, linear
    /// radiance and coverage to 0, depth to 1), draws the environment behind the cloth when
    /// it lights the frame, and draws the cloth. The frame's uniforms
    /// are written through `queue` and take effect at the next submit, so submit each frame
    /// before encoding the next. `timestamps` brackets the pass with GPU timestamp writes.
    pub fn encode(
        &self,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        targets: &FrameTargets<'_>,
        settings: &FrameSettings,
        timestamps: Option<wgpu::RenderPassTimestampWrites<'_>>,
    ) {
        self.write_uniforms(queue, settings, targets.size);
        let background = settings.background.map(|c| {
            let c = c.clamp(0.0, 1.0) as f64;
            // An …Srgb target encodes the clear value: give it the linear value.
            if self.encode_srgb {
                c
            } else {
                image::srgb_decode(c as f32) as f64
            }
        });
        let clear = |color: wgpu::Color, view| {
            Some(wgpu::RenderPassColorAttachment {
                view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(color),
                    store: wgpu::StoreOp::Store,
                },
            })
        };
        let mut attachments = vec![clear(
            wgpu::Color {
                r: background[0],
                g: background[1],
                b: background[2],
                a: 1.0,
            },
            targets.color,
        )];
        if let Some(linear) = targets.linear {
            attachments.push(clear(wgpu::Color::TRANSPARENT, linear));
        }
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("cloth"),
            color_attachments: &attachments,
            depth_stencil_attachment: Some(depth_attachment(targets.depth)),
            timestamp_writes: timestamps,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        let current = self.current.as_ref().expect("Renderer::new sets a BRDF");
        pass.set_bind_group(0, &current.group, &[]);
        pass.set_bind_group(1, &self.frame_group, &[]);
        pass.set_bind_group(2, &self.lighting_group, &[]);
        let linear = targets.linear.is_some();
        let needs_linear = "a linear target needs a renderer made with a linear output";
        if self.environment.is_some() && settings.environment_samples > 0 {
            let pipelines = &current.pipelines;
            let background = match linear {
                true => pipelines.background_linear.as_ref().expect(needs_linear),
                false => &pipelines.background,
            };
            pass.set_pipeline(background);
            pass.draw(0..3, 0..1);
        }
        pass.set_vertex_buffer(0, self.vertices.slice(..));
        pass.set_index_buffer(self.indices.slice(..), wgpu::IndexFormat::Uint32);
        let (width, height) = targets.size;
        // Each half drawn once, under its own scissor: a second draw of the same mesh would
        // fail the depth test the first one wrote.
        let left = if self.split.is_some() {
            width / 2
        } else {
            width
        };
        let halves = [
            Some((current, (0, left))),
            self.split
                .as_ref()
                .map(|right| (right, (left, width - left))),
        ];
        for (brdf, (x, w)) in halves.into_iter().flatten() {
            if w == 0 || height == 0 {
                continue;
            }
            let pipelines = &brdf.pipelines;
            pass.set_pipeline(match linear {
                true => pipelines.display_linear.as_ref().expect(needs_linear),
                false => &pipelines.display,
            });
            pass.set_bind_group(0, &brdf.group, &[]);
            pass.set_scissor_rect(x, 0, w, height);
            pass.draw_indexed(0..self.index_count, 0, 0..1);
        }
    }

    /// Records the G-buffer of the view: per pixel the world position (w = 1 where the cloth
    /// covers it, cleared to 0) and the shading frame's tangent and normal exactly as the
    /// render pass computes them, for shading the same pixels on the CPU.
    pub fn encode_gbuffer(
        &mut self,
        context: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        targets: &GBufferTargets<'_>,
        settings: &FrameSettings,
    ) -> Result<(), GpuError> {
        if self.gbuffer_pipeline.is_none() {
            check_gbuffer_support(context)?;
            let source = render_wgsl(STUB_BRDF_WGSL);
            let formats: [Option<wgpu::ColorTargetState>; 3] =
                std::array::from_fn(|_| Some(GBUFFER_FORMAT.into()));
            let pipeline = context.checked(|| {
                let module = shader_module(context, &source);
                mesh_pipeline(
                    context,
                    &self.frame_layout,
                    &module,
                    [None, None],
                    "fs_gbuffer",
                    &formats,
                )
            })?;
            self.gbuffer_pipeline = Some(pipeline);
        }
        self.write_uniforms(&context.queue, settings, targets.size);
        let clear = |view| {
            Some(wgpu::RenderPassColorAttachment {
                view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                    store: wgpu::StoreOp::Store,
                },
            })
        };
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("gbuffer"),
            color_attachments: &[
                clear(targets.position),
                clear(targets.tangent),
                clear(targets.normal),
            ],
            depth_stencil_attachment: Some(depth_attachment(targets.depth)),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(self.gbuffer_pipeline.as_ref().expect("built above"));
        pass.set_bind_group(1, &self.frame_group, &[]);
        pass.set_vertex_buffer(0, self.vertices.slice(..));
        pass.set_index_buffer(self.indices.slice(..), wgpu::IndexFormat::Uint32);
        pass.draw_indexed(0..self.index_count, 0, 0..1);
        Ok(())
    }
}

/// The render module for a BRDF's WGSL: the BRDF, the fabric sampler's functions, then
/// shaders/render/renderer.wgsl.
pub fn render_wgsl(brdf_wgsl: &str) -> String {
    crate::shader::Composer::new()
        .module(crate::shader::BRDF, brdf_wgsl)
        .module(
            crate::shader::SAMPLER_CONSTANTS,
            crate::sampling::Sampler::wgsl_constants(),
        )
        .compose(&[RENDER_MODULE])
        .expect("the render shader composes (validated in the tests)")
}

fn depth_attachment(view: &wgpu::TextureView) -> wgpu::RenderPassDepthStencilAttachment<'_> {
    wgpu::RenderPassDepthStencilAttachment {
        view,
        depth_ops: Some(wgpu::Operations {
            load: wgpu::LoadOp::Clear(1.0),
            store: wgpu::StoreOp::Store,
        }),
        stencil_ops: None,
    }
}

fn mesh_buffers(device: &wgpu::Device, mesh: &Mesh) -> (wgpu::Buffer, wgpu::Buffer) {
    let vertices = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("cloth vertices"),
        contents: bytemuck::cast_slice(&mesh.vertices),
        usage: wgpu::BufferUsages::VERTEX,
    });
    let indices = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("cloth indices"),
        contents: bytemuck::cast_slice(&mesh.indices),
        usage: wgpu::BufferUsages::INDEX,
    });
    (vertices, indices)
}
