//! The environment light on the GPU: an [`Environment`]'s mip chain as a filterable
//! shared-exponent texture, the compact bright sources taken out of it as directional lights
//! ([`crate::lighting::bright_sources`]), and the render pass's lighting group (@group(2) of
//! shaders/render/renderer.wgsl): that texture, its trilinear sampler and the fabric's
//! sample taps ([`crate::gpu::GpuSampleTaps`]) that filtered importance sampling reads.

use crate::gpu::sampler::sampler_entry;
use crate::gpu::{GpuContext, GpuError, GpuSampleTaps};
use crate::lighting::{Environment, SplitEnvironment};
use glam::Vec3;

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
    /// Uploads every mip level of `environment` as `Rgb9e5Ufloat` (packed by `rgb9e5` below):
    /// filterable on every backend, unlike 32-bit float, and 4 bytes a texel against
    /// Rgba16Float's 8, which makes the environment light's fetches, most of its cost, cheaper
    /// (docs/notebook/2026-12-07-performance.md#environment-light-on-lavapipe).
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
                format: wgpu::TextureFormat::Rgb9e5Ufloat,
                usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
                view_formats: &[],
            });
            for (mip, level) in levels.iter().enumerate() {
                let packed: Vec<u32> = level.texels().iter().map(|&t| rgb9e5(t)).collect();
                context.queue.write_texture(
                    wgpu::TexelCopyTextureInfo {
                        texture: &texture,
                        mip_level: mip as u32,
                        origin: wgpu::Origin3d::ZERO,
                        aspect: wgpu::TextureAspect::All,
                    },
                    bytemuck::cast_slice(&packed),
                    wgpu::TexelCopyBufferLayout {
                        offset: 0,
                        bytes_per_row: Some(level.width() * 4),
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

/// Largest value RGB9E5 holds, (1 − 2⁻⁹)·2¹⁶: brighter texels (a sun left in the map) are
/// clamped to it.
const RGB9E5_MAX: f32 = 511.0 / 512.0 * 65536.0;

/// `rgb` in the shared-exponent format of `Rgb9e5Ufloat` (bits 0–8 red, 9–17 green, 18–26
/// blue, 27–31 the exponent): a channel reads m·2^(e − 15 − 9) for its 9-bit mantissa m and
/// the shared exponent e. The exponent is the smallest that holds the largest channel, so that
/// channel keeps 9 bits (an error of at most 2⁻⁹ of it, rounded to nearest) and every other
/// channel the same absolute step. Values are clamped to [0, [`RGB9E5_MAX`]]; NaN reads 0.
fn rgb9e5(rgb: [f32; 3]) -> u32 {
    const MANTISSA_BITS: i32 = 9;
    const BIAS: i32 = 15;
    let c = rgb.map(|v| if v > 0.0 { v.min(RGB9E5_MAX) } else { 0.0 });
    let largest = c[0].max(c[1]).max(c[2]);
    if largest == 0.0 {
        return 0;
    }
    // largest < 2^(floor(log2 largest) + 1) = 2^(e − 15): it fits 9 bits of steps 2^(e − 24),
    // unless rounding carries it to 2^9 steps, one exponent up. The format's smallest
    // exponent, 0, flushes what is below its step to 0.
    let step = |e: i32| ((e - BIAS - MANTISSA_BITS) as f32).exp2();
    let mut exponent = (largest.log2().floor() as i32 + 1 + BIAS).max(0);
    if (largest / step(exponent)).round() >= (1 << MANTISSA_BITS) as f32 {
        exponent += 1;
    }
    let mantissas = c.map(|v| (v / step(exponent)).round() as u32);
    mantissas[0] | mantissas[1] << 9 | mantissas[2] << 18 | (exponent as u32) << 27
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

#[cfg(test)]
mod tests {
    use super::*;

    /// What the GPU reads of a packed texel.
    fn decode(bits: u32) -> [f32; 3] {
        let step = ((bits >> 27) as f32 - 24.0).exp2();
        [0, 9, 18].map(|shift| ((bits >> shift) & 0x1ff) as f32 * step)
    }

    /// Every channel reads back within half a step of the shared exponent, at most 2⁻⁹ of
    /// the largest channel, from 10⁻⁴ (above the smallest exponent's range, 2⁻¹⁵) to the
    /// largest value and for channel ratios down to 1/1000; below that range within half the
    /// smallest step.
    #[test]
    fn rgb9e5_keeps_nine_bits_of_the_largest_channel() {
        let smallest_step = 0.5f32.powi(24);
        for largest in [1e-9, 1e-6, 2e-5] {
            let back = decode(rgb9e5([largest, 0.3 * largest, 0.0]));
            assert!(
                (back[0] - largest).abs() <= 0.5 * smallest_step,
                "{largest}: {back:?}"
            );
        }
        let mut worst = 0.0f32;
        for decade in -4..=4 {
            for i in 0..200 {
                let largest = 10f32.powf(decade as f32 + i as f32 / 200.0).min(RGB9E5_MAX);
                for ratios in [[1.0, 0.5, 0.25], [0.001, 1.0, 0.3], [0.7, 0.9, 1.0]] {
                    let rgb = ratios.map(|r| r * largest);
                    let back = decode(rgb9e5(rgb));
                    for (v, b) in rgb.iter().zip(back) {
                        worst = worst.max((v - b).abs() / largest);
                    }
                }
            }
        }
        println!("worst error relative to the largest channel: {worst:.3e}");
        assert!(worst <= 0.5f32.powi(9), "{worst}");
    }

    #[test]
    fn rgb9e5_edges() {
        assert_eq!(decode(rgb9e5([1.0, 0.5, 0.0])), [1.0, 0.5, 0.0]);
        assert_eq!(rgb9e5([0.0; 3]), 0);
        assert_eq!(rgb9e5([f32::NAN, -1.0, 0.0]), 0);
        assert_eq!(decode(rgb9e5([1e6, 0.0, 0.0]))[0], RGB9E5_MAX);
        // Just below a power of two rounds up into the next exponent.
        assert_eq!(decode(rgb9e5([2.0 - 1e-4, 0.0, 0.0]))[0], 2.0);
    }
}
