//! Rendering cloth with a [`GpuBrdf`]: a draped sheet (or a user's mesh) whose thread frame
//! follows its UVs, lit by directional and point lights, seen by an orbit camera, tone mapped.
//!
//! - [`Renderer`]: the render pipeline for one colour format; records a frame into any
//!   colour target (a window's surface texture or an offscreen texture) and, optionally, a
//!   linear-radiance target. Reusable by an interactive viewer.
//! - [`Headless`]: offscreen targets and read-back around a [`Renderer`]: linear radiance,
//!   8-bit display image, GPU time per frame, and the G-buffer of the CPU reference.
//! - [`reference`]: the same view shaded on the CPU by direct evaluation.
//! - [`job`]: the `render` command: every fabric of a scene to PNG, timed, optionally
//!   against the CPU reference.
//! - [`image`]: tone mapping, image error metrics, heat maps, PNG/EXR files.
//! - [`mesh`]: procedural cloth and OBJ loading with per-vertex thread frames.
//!
//! Shading (shaders/render.wgsl): per pixel, the frame (t, b = n × t, n) from the
//! interpolated vertex normal and tangent, re-orthonormalised, flipped to the side facing the
//! viewer (two-sided cloth); wi and wo in that frame; radiance `L = Σ_lights E·F(wi, wo)`
//! with `E` the light's perpendicular irradiance at the point (directional: colour ×
//! irradiance; point: colour × I/d²). No shadows, no ambient light.

pub mod image;
pub mod job;
pub mod mesh;
pub mod reference;

use crate::gpu::{GpuBrdf, GpuContext, GpuError};
use crate::scene::{Light, MAX_LIGHTS, OrbitCamera, Scene};
use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec3};
use image::{LinearImage, Rgba8Image};
use mesh::{Mesh, Vertex};
use std::collections::HashMap;
use std::time::Instant;
use wgpu::util::DeviceExt;

/// The render shader, appended to a [`GpuBrdf::wgsl`].
pub const RENDER_WGSL: &str = include_str!("../../shaders/render.wgsl");

/// A `cloth_brdf` that returns 0, for the G-buffer pipeline (which never calls it).
const STUB_BRDF_WGSL: &str =
    "fn cloth_brdf(wi: vec3<f32>, wo: vec3<f32>) -> vec3<f32> { return vec3<f32>(0.0); }\n";

/// Depth buffer format of every pass.
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// Format of the linear-radiance target (alpha = coverage) where the device can render to
/// it (Vulkan, Metal, DX12); see [`linear_format`].
pub const LINEAR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;
/// The fallback linear format (wgpu's GL backend cannot render to 32-bit float): relative
/// rounding 2^-11, largest value 65504.
pub const LINEAR_FORMAT_F16: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
/// Format of the three G-buffer targets (position, tangent, normal): 32-bit only, as f16
/// positions would move the reference's directions by ~1e-3 rad.
pub const GBUFFER_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;

/// Fails with a clear message where the device cannot render to [`GBUFFER_FORMAT`].
fn check_gbuffer_support(context: &GpuContext) -> Result<(), GpuError> {
    if float32_renderable(context) {
        return Ok(());
    }
    Err(GpuError::Invalid {
        name: "G-buffer (CPU reference)".into(),
        message: "needs Rgba32Float render targets, which this device lacks (wgpu's GL \
                  backend); use Vulkan (lavapipe without a GPU), Metal or DX12"
            .into(),
    })
}

/// Whether the device can render to `Rgba32Float` (tried on a 1×1 texture).
pub fn float32_renderable(context: &GpuContext) -> bool {
    context
        .checked(|| target(context, "probe", wgpu::TextureFormat::Rgba32Float, 1, 1))
        .is_ok()
}

/// The linear-radiance format for this device: [`LINEAR_FORMAT`], else [`LINEAR_FORMAT_F16`].
pub fn linear_format(context: &GpuContext) -> wgpu::TextureFormat {
    if float32_renderable(context) {
        LINEAR_FORMAT
    } else {
        LINEAR_FORMAT_F16
    }
}
/// Largest headless image side: bounds the read-back and G-buffer memory (3 × 16 bytes per
/// pixel: 768 MiB at 4096²).
pub const MAX_IMAGE_SIDE: u32 = 4096;

/// A perspective camera looking from `eye` at `target` with +y up.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    pub eye: Vec3,
    pub target: Vec3,
    pub fov_y_deg: f32,
}

impl Camera {
    /// The camera of an orbit description (see [`OrbitCamera`]).
    pub fn orbit(orbit: &OrbitCamera) -> Self {
        Self {
            eye: glam::DVec3::from(orbit.eye()).as_vec3(),
            target: glam::DVec3::from(orbit.target).as_vec3(),
            fov_y_deg: orbit.fov_y_deg as f32,
        }
    }

    /// World to clip space for an image of `aspect` = width/height (wgpu's depth range
    /// [0, 1]); near and far planes at 1/100 and 100 times the distance to the target.
    pub fn view_proj(&self, aspect: f32) -> Mat4 {
        let distance = self.eye.distance(self.target).max(1e-6);
        let forward = (self.target - self.eye) / distance;
        // Up is +y unless the camera looks (almost) straight along it.
        let up = if forward.y.abs() > 0.999 {
            Vec3::Z
        } else {
            Vec3::Y
        };
        let view = glam::camera::rh::view::look_at_mat4(self.eye, self.target, up);
        // The DirectX convention (depth in [0, 1], y up) is WebGPU's.
        let proj = glam::camera::rh::proj::directx::perspective(
            self.fov_y_deg.to_radians(),
            aspect,
            0.01 * distance,
            100.0 * distance,
        );
        proj * view
    }
}

/// A light as the renderer uses it: colour already multiplied in.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LightSource {
    /// `direction`: unit, towards the light; `irradiance`: colour × perpendicular irradiance.
    Directional { direction: Vec3, irradiance: Vec3 },
    /// `intensity`: colour × radiant intensity; irradiance `intensity/d²` at distance d.
    Point { position: Vec3, intensity: Vec3 },
}

impl LightSource {
    /// The light of a scene file.
    pub fn from_scene(light: &Light) -> Self {
        let v = |a: [f64; 3]| glam::DVec3::from(a).as_vec3();
        match *light {
            Light::Directional {
                direction,
                color,
                irradiance,
            } => Self::Directional {
                direction: v(direction).normalize_or(Vec3::Y),
                irradiance: v(color) * irradiance as f32,
            },
            Light::Point {
                position,
                color,
                intensity,
            } => Self::Point {
                position: v(position),
                intensity: v(color) * intensity as f32,
            },
        }
    }

    /// Unit direction towards the light and the RGB irradiance `E` it gives at `point`.
    pub fn at(&self, point: glam::DVec3) -> (glam::DVec3, glam::DVec3) {
        match *self {
            Self::Directional {
                direction,
                irradiance,
            } => (direction.as_dvec3(), irradiance.as_dvec3()),
            Self::Point {
                position,
                intensity,
            } => {
                let d = position.as_dvec3() - point;
                let d2 = d.length_squared().max(1e-12);
                (d / d2.sqrt(), intensity.as_dvec3() / d2)
            }
        }
    }
}

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
}

/// The default background: dark grey.
pub const BACKGROUND: [f32; 3] = [0.06, 0.06, 0.07];

impl FrameSettings {
    /// The camera, lights and exposure of a scene.
    pub fn from_scene(scene: &Scene) -> Self {
        Self {
            camera: Camera::orbit(&scene.camera),
            lights: scene.lights.iter().map(LightSource::from_scene).collect(),
            exposure: scene.exposure as f32,
            background: BACKGROUND,
        }
    }
}

/// One light of [`FrameUniform`] (WGSL `RenderLight`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
struct LightUniform {
    vector: [f32; 4],
    power: [f32; 4],
}

/// The uniform block of shaders/render.wgsl (`RenderFrameUniform`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
struct FrameUniform {
    view_proj: [[f32; 4]; 4],
    eye: [f32; 4],
    params: [f32; 4],
    counts: [u32; 4],
    lights: [LightUniform; MAX_LIGHTS],
}

impl FrameUniform {
    fn new(settings: &FrameSettings, aspect: f32, encode_srgb: bool) -> Self {
        let mut lights = [LightUniform::default(); MAX_LIGHTS];
        let count = settings.lights.len().min(MAX_LIGHTS);
        for (slot, light) in lights.iter_mut().zip(&settings.lights) {
            *slot = match *light {
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
            };
        }
        Self {
            view_proj: settings.camera.view_proj(aspect).to_cols_array_2d(),
            eye: settings.camera.eye.extend(1.0).to_array(),
            params: [settings.exposure, encode_srgb as u32 as f32, 0.0, 0.0],
            counts: [count as u32, 0, 0, 0],
            lights,
        }
    }
}

/// The targets of one frame. `linear` may be given only when the renderer was made with a
/// linear output (of [`Renderer::linear_format`]); without it the frame is the display image
/// alone, as a real-time frame. `depth` is [`DEPTH_FORMAT`]; all of `size`.
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

/// The pipelines of one BRDF shader: the display image alone, and display plus linear
/// radiance (when the renderer has a linear output).
#[derive(Clone)]
struct Pipelines {
    display: wgpu::RenderPipeline,
    display_linear: Option<wgpu::RenderPipeline>,
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
    brdf_group: wgpu::BindGroup,
    brdf_label: String,
    /// The current BRDF's pipelines (set by `new`), kept out of the map so that a frame
    /// does not hash the shader source to find them.
    current: Option<Pipelines>,
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
            brdf_group: brdf.bind_group().clone(),
            brdf_label: String::new(),
            current: None,
            pipelines: HashMap::new(),
            gbuffer_pipeline: None,
        };
        renderer.set_brdf(context, brdf)?;
        Ok(renderer)
    }

    /// Shades with `brdf` from now on (builds its pipeline unless one for the same shader
    /// was built before).
    pub fn set_brdf(&mut self, context: &GpuContext, brdf: &dyn GpuBrdf) -> Result<(), GpuError> {
        let source = brdf.wgsl() + "\n" + RENDER_WGSL;
        if let Some(pipelines) = self.pipelines.get(&source) {
            self.current = Some(pipelines.clone());
        } else {
            let display = wgpu::ColorTargetState::from(self.color_format);
            let pipelines = context.checked(|| {
                let layout = Some(brdf.bind_group_layout());
                let module = shader_module(context, &source);
                Pipelines {
                    display: self.pipeline(
                        context,
                        &module,
                        layout,
                        "fs_display",
                        &[Some(display.clone())],
                    ),
                    display_linear: self.linear_format.map(|format| {
                        self.pipeline(
                            context,
                            &module,
                            layout,
                            "fs_display_linear",
                            &[Some(display.clone()), Some(format.into())],
                        )
                    }),
                }
            })?;
            self.current = Some(pipelines.clone());
            self.pipelines.insert(source, pipelines);
        }
        self.brdf_group = brdf.bind_group().clone();
        self.brdf_label = brdf.label();
        Ok(())
    }

    /// The label of the current BRDF ([`GpuBrdf::label`]).
    pub fn brdf_label(&self) -> &str {
        &self.brdf_label
    }

    /// The format its linear-radiance target must have (`None`: made without one).
    pub fn linear_format(&self) -> Option<wgpu::TextureFormat> {
        self.linear_format
    }

    /// The pipeline drawing the mesh with fragment entry point `fragment` of `module` (the
    /// render WGSL appended to a BRDF's) into `targets`.
    fn pipeline(
        &self,
        context: &GpuContext,
        module: &wgpu::ShaderModule,
        brdf_layout: Option<&wgpu::BindGroupLayout>,
        fragment: &str,
        targets: &[Option<wgpu::ColorTargetState>],
    ) -> wgpu::RenderPipeline {
        let device = &context.device;
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("render"),
            bind_group_layouts: &[brdf_layout, Some(&self.frame_layout)],
            immediate_size: 0,
        });
        let attributes = wgpu::vertex_attr_array![
            0 => Float32x3, 1 => Float32x3, 2 => Float32x3, 3 => Float32x2
        ];
        device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some(fragment),
            layout: Some(&layout),
            vertex: wgpu::VertexState {
                module,
                entry_point: Some("vs_main"),
                compilation_options: Default::default(),
                buffers: &[Some(wgpu::VertexBufferLayout {
                    array_stride: std::mem::size_of::<Vertex>() as u64,
                    step_mode: wgpu::VertexStepMode::Vertex,
                    attributes: &attributes,
                })],
            },
            // Cloth is two-sided: no culling (the shader flips the frame to the viewer).
            primitive: wgpu::PrimitiveState {
                topology: wgpu::PrimitiveTopology::TriangleList,
                cull_mode: None,
                ..Default::default()
            },
            depth_stencil: Some(wgpu::DepthStencilState {
                format: DEPTH_FORMAT,
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::Less),
                stencil: Default::default(),
                bias: Default::default(),
            }),
            multisample: Default::default(),
            fragment: Some(wgpu::FragmentState {
                module,
                entry_point: Some(fragment),
                compilation_options: Default::default(),
                targets,
            }),
            multiview_mask: None,
            cache: None,
        })
    }

    fn write_uniforms(&self, queue: &wgpu::Queue, settings: &FrameSettings, size: (u32, u32)) {
        let aspect = size.0.max(1) as f32 / size.1.max(1) as f32;
        let uniform = FrameUniform::new(settings, aspect, self.encode_srgb);
        queue.write_buffer(&self.frame_buffer, 0, bytemuck::bytes_of(&uniform));
    }

    /// Records one frame: clears the targets (colour to `settings.background`, linear
    /// radiance and coverage to 0, depth to 1) and draws the cloth. The frame's uniforms
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
        let pipelines = self.current.as_ref().expect("Renderer::new sets a BRDF");
        let pipeline = match targets.linear {
            Some(_) => pipelines
                .display_linear
                .as_ref()
                .expect("a linear target needs a renderer made with a linear output"),
            None => &pipelines.display,
        };
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, &self.brdf_group, &[]);
        pass.set_bind_group(1, &self.frame_group, &[]);
        pass.set_vertex_buffer(0, self.vertices.slice(..));
        pass.set_index_buffer(self.indices.slice(..), wgpu::IndexFormat::Uint32);
        pass.draw_indexed(0..self.index_count, 0, 0..1);
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
            let source = STUB_BRDF_WGSL.to_string() + RENDER_WGSL;
            let formats: [Option<wgpu::ColorTargetState>; 3] =
                std::array::from_fn(|_| Some(GBUFFER_FORMAT.into()));
            let pipeline = context.checked(|| {
                let module = shader_module(context, &source);
                self.pipeline(context, &module, None, "fs_gbuffer", &formats)
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

fn shader_module(context: &GpuContext, source: &str) -> wgpu::ShaderModule {
    context
        .device
        .create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("render.wgsl"),
            source: wgpu::ShaderSource::Wgsl(source.into()),
        })
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

/// How frame times were measured.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TimingSource {
    /// GPU timestamps written at the start and end of the render pass.
    GpuTimestamps,
    /// Wall clock from submitting the frame to the device reporting it done (includes
    /// submission overhead; used when the device has no timestamp queries).
    WallClock,
}

impl std::fmt::Display for TimingSource {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Self::GpuTimestamps => "GPU timestamps around the render pass",
            Self::WallClock => "wall clock from submit to completion (no timestamp queries)",
        })
    }
}

/// Per-frame times of a headless render.
#[derive(Clone, Debug, PartialEq)]
pub struct FrameTiming {
    pub source: TimingSource,
    /// Milliseconds per timed frame (after one untimed warm-up frame).
    pub frame_ms: Vec<f64>,
}

impl FrameTiming {
    /// The median of [`FrameTiming::frame_ms`] (mean of the middle two for an even count).
    pub fn median_ms(&self) -> f64 {
        median(&self.frame_ms).unwrap_or(f64::NAN)
    }
}

/// The median of `values` (mean of the middle two for an even count), `None` when empty:
/// the one statistic every timing of the runtime and the report quotes.
pub fn median(values: &[f64]) -> Option<f64> {
    if values.is_empty() {
        return None;
    }
    let mut sorted = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    let n = sorted.len();
    Some(if n % 2 == 1 {
        sorted[n / 2]
    } else {
        0.5 * (sorted[n / 2 - 1] + sorted[n / 2])
    })
}

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

fn target(
    context: &GpuContext,
    name: &str,
    format: wgpu::TextureFormat,
    width: u32,
    height: u32,
) -> wgpu::Texture {
    context.device.create_texture(&wgpu::TextureDescriptor {
        label: Some(name),
        size: wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    })
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
fn map_read(context: &GpuContext, buffer: &wgpu::Buffer) -> Result<Vec<u8>, GpuError> {
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
fn read_texture(
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

/// Timestamp queries at the start and end of one render pass, and the buffers that bring
/// them back: used by [`Headless::render`] (read at once) and the viewer (read when mapped).
pub(crate) struct PassTimestamps {
    queries: wgpu::QuerySet,
    resolved: wgpu::Buffer,
    /// `MAP_READ` copy of the two ticks, filled by [`PassTimestamps::resolve`].
    pub readback: wgpu::Buffer,
    /// Nanoseconds per tick.
    period_ns: f64,
}

impl PassTimestamps {
    pub fn new(context: &GpuContext, label: &str) -> Self {
        let device = &context.device;
        // Two u64 ticks: 16 bytes, a multiple of the 8-byte resolve alignment.
        let buffer = |usage| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: 16,
                usage,
                mapped_at_creation: false,
            })
        };
        Self {
            queries: device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some(label),
                ty: wgpu::QueryType::Timestamp,
                count: 2,
            }),
            resolved: buffer(wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC),
            readback: buffer(wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST),
            period_ns: context.timestamp_period() as f64,
        }
    }

    /// The pass's timestamp writes.
    pub fn writes(&self) -> wgpu::RenderPassTimestampWrites<'_> {
        wgpu::RenderPassTimestampWrites {
            query_set: &self.queries,
            beginning_of_pass_write_index: Some(0),
            end_of_pass_write_index: Some(1),
        }
    }

    /// Records the resolve of the queries into `readback` (after the pass).
    pub fn resolve(&self, encoder: &mut wgpu::CommandEncoder) {
        encoder.resolve_query_set(&self.queries, 0..2, &self.resolved, 0);
        encoder.copy_buffer_to_buffer(&self.resolved, 0, &self.readback, 0, 16);
    }

    /// The pass's duration in milliseconds from the mapped contents of `readback`.
    pub fn elapsed_ms(&self, readback: &[u8]) -> f64 {
        let tick = |k: usize| u64::from_le_bytes(std::array::from_fn(|i| readback[8 * k + i]));
        // A pass can straddle a counter wrap; end < start is read modulo 2^64.
        tick(1).wrapping_sub(tick(0)) as f64 * self.period_ns * 1e-6
    }

    /// Maps `readback`, waiting for the device, and returns the duration in milliseconds.
    fn read(&self, context: &GpuContext) -> Result<f64, GpuError> {
        Ok(self.elapsed_ms(&map_read(context, &self.readback)?))
    }
}
