//! The environment light on the GPU: an [`Environment`]'s mip chain as a filterable f16
//! texture, the compact bright sources taken out of it as directional lights
//! ([`crate::lighting::bright_sources`]), and the render pass's lighting group (@group(2) of
//! shaders/render/renderer.wgsl): that texture, its trilinear sampler and the fabric's
//! sample taps ([`crate::gpu::GpuSampleTaps`]) that filtered importance sampling reads.

use crate::gpu::sampler::sampler_entry;
use crate::gpu::{GpuContext, GpuError, GpuSampleTaps};
use crate::lighting::{Environment, SplitEnvironment};
use glam::Vec3;
use half::f16;

/// Largest f16 value: brighter texels (the sun of a captured sky) are clamped to it.
const F16_MAX: f32 = 65504.0;

/// What the frame uniform says of the environment map: level-0 width and height, and the
/// number of mip levels.
pub type EnvironmentDimensions = [u32; 3];

/// What a frame's uniform takes of the environment: the map's sizes, and the sources taken
/// out of it, lit as directional lights beside the scene's.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct EnvironmentFrame {
    pub dimensions: EnvironmentDimensions,
    pub sources: Vec<SourceLight>,
}

/// A bright source of the environment as the frame lights it: a directional light that the
/// horizon sets over its disk ([`crate::lighting::disk_above_horizon`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SourceLight {
    /// Unit direction towards its centre, in the map's frame (before the frame's turn).
    pub direction: Vec3,
    /// RGB perpendicular irradiance.
    pub irradiance: Vec3,
    /// sin of its disk's angular radius ([`crate::lighting::DistantSource::disk_radius`]).
    pub sin_radius: f32,
}

/// An environment map uploaded for rendering: its mip chain, and the sources taken out of it.
pub struct GpuEnvironment {
    view: wgpu::TextureView,
    sampler: wgpu::Sampler,
    frame: EnvironmentFrame,
}

impl GpuEnvironment {
    /// Uploads every mip level of `environment` as Rgba16Float (filterable everywhere, unlike
    /// 32-bit float), values clamped to the f16 range.
    pub fn new(context: &GpuContext, environment: &Environment) -> Result<Self, GpuError> {
        let levels = environment.levels();
        let (width, height) = (levels[0].width(), levels[0].height());
        let limit = context.device.limits().max_texture_dimension_2d;
        if width.max(height) > limit {
            return Err(GpuError::Limits(format!(
                "environment map of {width}×{height} texels; the device allows {limit}"
            )));
        }
        let (view, sampler) = context.checked(|| {
            let texture = context.device.create_texture(&wgpu::TextureDescriptor {
                label: Some("environment"),
                size: wgpu::Extent3d {
                    width,
                    height,
                    depth_or_array_layers: 1,
                },
                mip_level_count: levels.len() as u32,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: wgpu::TextureFormat::Rgba16Float,
                usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
                view_formats: &[],
            });
            for (mip, level) in levels.iter().enumerate() {
                let bits: Vec<u16> = level
                    .texels()
                    .iter()
                    .flat_map(|t| [t[0], t[1], t[2], 1.0])
                    .map(|v| f16::from_f32(v.min(F16_MAX)).to_bits())
                    .collect();
                context.queue.write_texture(
                    wgpu::TexelCopyTextureInfo {
                        texture: &texture,
                        mip_level: mip as u32,
                        origin: wgpu::Origin3d::ZERO,
                        aspect: wgpu::TextureAspect::All,
                    },
                    bytemuck::cast_slice(&bits),
                    wgpu::TexelCopyBufferLayout {
                        offset: 0,
                        bytes_per_row: Some(level.width() * 8),
                        rows_per_image: Some(level.height()),
                    },
                    wgpu::Extent3d {
                        width: level.width(),
                        height: level.height(),
                        depth_or_array_layers: 1,
                    },
                );
            }
            let view = texture.create_view(&wgpu::TextureViewDescriptor::default());
            // Azimuth wraps around the seam; the poles clamp. Trilinear: the shader picks
            // the level of each sample.
            let sampler = context.device.create_sampler(&wgpu::SamplerDescriptor {
                label: Some("environment"),
                address_mode_u: wgpu::AddressMode::Repeat,
                address_mode_v: wgpu::AddressMode::ClampToEdge,
                mag_filter: wgpu::FilterMode::Linear,
                min_filter: wgpu::FilterMode::Linear,
                mipmap_filter: wgpu::MipmapFilterMode::Linear,
                ..Default::default()
            });
            (view, sampler)
        })?;
        Ok(Self {
            view,
            sampler,
            frame: EnvironmentFrame {
                dimensions: [width, height, levels.len() as u32],
                sources: Vec::new(),
            },
        })
    }

    /// Uploads the residual of a split map, and keeps its sources as directional lights.
    pub fn split(context: &GpuContext, split: &SplitEnvironment) -> Result<Self, GpuError> {
        let mut environment = Self::new(context, &split.residual)?;
        environment.frame.sources = split
            .sources
            .iter()
            .map(|source| SourceLight {
                direction: source.direction.as_vec3(),
                irradiance: source.irradiance.as_vec3(),
                sin_radius: source.disk_radius.sin() as f32,
            })
            .collect();
        Ok(environment)
    }

    /// A black 1×1 map: the lighting group's content when there is no environment.
    pub fn black(context: &GpuContext) -> Result<Self, GpuError> {
        let black = Environment::from_texels(1, 1, vec![[0.0; 3]])
            .map_err(|e| GpuError::Wgpu(e.to_string()))?;
        Self::new(context, &black)
    }

    /// What the frame uniform passes to the shader.
    pub fn frame(&self) -> &EnvironmentFrame {
        &self.frame
    }
}

/// The layout of the render pass's lighting group: environment texture (0), its sampler
/// (1), the fabric sampler's data (2).
pub(super) fn lighting_layout(context: &GpuContext) -> wgpu::BindGroupLayout {
    let fragment = wgpu::ShaderStages::FRAGMENT;
    context
        .device
        .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("render lighting"),
            entries: &[
                wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    visibility: fragment,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Float { filterable: true },
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: false,
                    },
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 1,
                    visibility: fragment,
                    ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                    count: None,
                },
                sampler_entry(2),
            ],
        })
}

/// The lighting group for `environment` and the fabric's sample `taps`.
pub(super) fn lighting_group(
    context: &GpuContext,
    layout: &wgpu::BindGroupLayout,
    environment: &GpuEnvironment,
    taps: &GpuSampleTaps,
) -> wgpu::BindGroup {
    context
        .device
        .create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("render lighting"),
            layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::TextureView(&environment.view),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::Sampler(&environment.sampler),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: taps.buffer().as_entire_binding(),
                },
            ],
        })
}
