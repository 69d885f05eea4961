//! The render pipelines of one BRDF shader: the cloth's and the environment's behind it,
//! each for the display target alone and for display plus linear radiance.

use super::targets::DEPTH_FORMAT;
use crate::gpu::GpuContext;
use crate::scene::mesh::Vertex;

/// The pipelines of one BRDF shader: the display image alone, and display plus linear
/// radiance (when the renderer has a linear output).
#[derive(Clone)]
pub(super) struct Pipelines {
    pub display: wgpu::RenderPipeline,
    pub display_linear: Option<wgpu::RenderPipeline>,
    /// The environment behind the cloth, into the display target alone (the linear target,
    /// where the pass has one, is declared with an empty write mask).
    pub background: wgpu::RenderPipeline,
    pub background_linear: Option<wgpu::RenderPipeline>,
}

impl Pipelines {
    /// The pipelines of the render WGSL `source` (a BRDF's shader with the render module)
    /// whose @group(0) is `brdf_layout`, drawing into `color_format` and, where given,
    /// `linear_format`.
    pub(super) fn build(
        context: &GpuContext,
        source: &str,
        brdf_layout: &wgpu::BindGroupLayout,
        [frame_layout, lighting_layout]: [&wgpu::BindGroupLayout; 2],
        color_format: wgpu::TextureFormat,
        linear_format: Option<wgpu::TextureFormat>,
    ) -> Self {
        let layout = Some(brdf_layout);
        let module = shader_module(context, source);
        let display = wgpu::ColorTargetState::from(color_format);
        let mesh = |fragment: &str, targets: &[Option<wgpu::ColorTargetState>]| {
            mesh_pipeline(
                context,
                frame_layout,
                &module,
                [layout, Some(lighting_layout)],
                fragment,
                targets,
            )
        };
        let background = |targets: &[Option<wgpu::ColorTargetState>]| {
            background_pipeline(
                context,
                frame_layout,
                lighting_layout,
                &module,
                layout,
                targets,
            )
        };
        Self {
            display: mesh("fs_display", &[Some(display.clone())]),
            display_linear: linear_format.map(|format| {
                mesh(
                    "fs_display_linear",
                    &[Some(display.clone()), Some(format.into())],
                )
            }),
            background: background(&[Some(display.clone())]),
            background_linear: linear_format.map(|format| {
                let untouched = wgpu::ColorTargetState {
                    format,
                    blend: None,
                    write_mask: wgpu::ColorWrites::empty(),
                };
                background(&[Some(display.clone()), Some(untouched)])
            }),
        }
    }
}

/// The pipeline drawing the mesh with fragment entry point `fragment` of `module` (the
/// render WGSL appended to a BRDF's) into `targets`; `groups` are the layouts of
/// @group(0) (the BRDF's) and @group(2) (lighting), `None` where the entry point reads
/// neither.
pub(super) fn mesh_pipeline(
    context: &GpuContext,
    frame_layout: &wgpu::BindGroupLayout,
    module: &wgpu::ShaderModule,
    groups: [Option<&wgpu::BindGroupLayout>; 2],
    fragment: &str,
    targets: &[Option<wgpu::ColorTargetState>],
) -> wgpu::RenderPipeline {
    let device = &context.device;
    let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("render"),
        bind_group_layouts: &[groups[0], Some(frame_layout), groups[1]],
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

/// The pipeline drawing the environment behind the cloth: one triangle over the screen,
/// no vertex buffer, depth neither tested nor written (it is drawn first).
fn background_pipeline(
    context: &GpuContext,
    frame_layout: &wgpu::BindGroupLayout,
    lighting_layout: &wgpu::BindGroupLayout,
    module: &wgpu::ShaderModule,
    brdf_layout: Option<&wgpu::BindGroupLayout>,
    targets: &[Option<wgpu::ColorTargetState>],
) -> wgpu::RenderPipeline {
    let device = &context.device;
    let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("background"),
        bind_group_layouts: &[brdf_layout, Some(frame_layout), Some(lighting_layout)],
        immediate_size: 0,
    });
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("fs_background"),
        layout: Some(&layout),
        vertex: wgpu::VertexState {
            module,
            entry_point: Some("vs_background"),
            compilation_options: Default::default(),
            buffers: &[],
        },
        primitive: Default::default(),
        depth_stencil: Some(wgpu::DepthStencilState {
            format: DEPTH_FORMAT,
            depth_write_enabled: Some(false),
            depth_compare: Some(wgpu::CompareFunction::Always),
            stencil: Default::default(),
            bias: Default::default(),
        }),
        multisample: Default::default(),
        fragment: Some(wgpu::FragmentState {
            module,
            entry_point: Some("fs_background"),
            compilation_options: Default::default(),
            targets,
        }),
        multiview_mask: None,
        cache: None,
    })
}

/// The render pass's WGSL as a shader module.
pub(super) fn shader_module(context: &GpuContext, source: &str) -> wgpu::ShaderModule {
    context
        .device
        .create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("render.wgsl"),
            source: wgpu::ShaderSource::Wgsl(source.into()),
        })
}
