//! The fabric sampler on the GPU: [`crate::sampling::Sampler`]'s data in a read-only storage
//! buffer and its WGSL (`shaders/sampling/fabric_sampler.wgsl`), plus compute runs of its two
//! functions for tests and measurements (`shaders/gpu/sampler_pairs.wgsl`).

use super::{GpuContext, GpuError, brdf_entry, run_pairs};
use crate::sampling::Sampler;
use glam::Vec3;
use wgpu::util::DeviceExt;

/// A fabric's sampler uploaded to the GPU.
pub struct GpuSampler {
    pub buffer: wgpu::Buffer,
    layout: wgpu::BindGroupLayout,
    group: wgpu::BindGroup,
}

/// The storage binding layout entry of the sampler's data.
pub fn sampler_entry(binding: u32) -> wgpu::BindGroupLayoutEntry {
    brdf_entry(
        binding,
        wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only: true },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
    )
}

/// The compute entry points over the sampler (`shaders/gpu/sampler_pairs.wgsl`, which
/// requires `shaders/sampling/fabric_sampler.wgsl` and declares `sampling_data`), for
/// [`GpuSampler::draw`] and [`GpuSampler::pdf`].
pub fn sampler_pairs_wgsl() -> String {
    crate::shader::Composer::new()
        .module(crate::shader::SAMPLER_CONSTANTS, Sampler::wgsl_constants())
        .compose(&["gpu/sampler_pairs"])
        .expect("the sampler kernels compose (validated in the tests)")
}

impl GpuSampler {
    /// Uploads `sampler`'s data.
    pub fn new(context: &GpuContext, sampler: &Sampler) -> Result<Self, GpuError> {
        Self::from_data(context, sampler.data())
    }

    /// A one-value stand-in, for a pipeline's sampler binding that is never read (the render
    /// pass without an environment light).
    pub fn placeholder(context: &GpuContext) -> Result<Self, GpuError> {
        Self::from_data(context, &[0.0])
    }

    fn from_data(context: &GpuContext, data: &[f32]) -> Result<Self, GpuError> {
        let device = &context.device;
        context.checked(|| {
            let buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("fabric sampler"),
                contents: bytemuck::cast_slice(data),
                usage: wgpu::BufferUsages::STORAGE,
            });
            let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("fabric sampler"),
                entries: &[sampler_entry(0)],
            });
            let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("fabric sampler"),
                layout: &layout,
                entries: &[wgpu::BindGroupEntry {
                    binding: 0,
                    resource: buffer.as_entire_binding(),
                }],
            });
            Self {
                buffer,
                layout,
                group,
            }
        })
    }

    fn run(
        &self,
        context: &GpuContext,
        entry: &str,
        pairs: &[(Vec3, Vec3)],
    ) -> Result<Vec<[f32; 4]>, GpuError> {
        let source = sampler_pairs_wgsl();
        run_pairs(context, (&self.layout, &self.group), &source, entry, pairs)
    }

    /// `sampling_sample(wo, u)` for each `(wo, u)`: (wi, pdf), all zero when rejected.
    pub fn draw(
        &self,
        context: &GpuContext,
        requests: &[(Vec3, Vec3)],
    ) -> Result<Vec<[f32; 4]>, GpuError> {
        self.run(context, "sample_draws_main", requests)
    }

    /// `sampling_pdf(wo, wi)` for each `(wo, wi)`.
    pub fn pdf(&self, context: &GpuContext, pairs: &[(Vec3, Vec3)]) -> Result<Vec<f32>, GpuError> {
        Ok(self
            .run(context, "sample_pdf_main", pairs)?
            .into_iter()
            .map(|v| v[0])
            .collect())
    }
}
