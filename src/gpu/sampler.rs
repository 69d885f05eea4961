//! The fabric sampler on the GPU: [`crate::sampling::Sampler`]'s data in a read-only storage
//! buffer and its WGSL (`shaders/sampling/fabric_sampler.wgsl`), plus compute runs of its two
//! functions for tests and measurements (`shaders/gpu/sampler_pairs.wgsl`); and the
//! environment light's sample taps ([`crate::sampling::SampleTaps`],
//! `shaders/sampling/sample_taps.wgsl`), with a compute run of their pick
//! (`shaders/gpu/tap_pairs.wgsl`).

use super::{GpuContext, GpuError, brdf_entry, run_pairs};
use crate::sampling::{SampleTaps, Sampler};
use glam::Vec3;
use wgpu::util::DeviceExt;

/// A fabric's sampler uploaded to the GPU.
pub struct GpuSampler {
    storage: Storage,
}

/// A fabric's sample taps uploaded to the GPU.
pub struct GpuSampleTaps {
    storage: Storage,
    samples: u32,
}

/// A read-only storage buffer alone in a bind group (binding 0).
struct Storage {
    buffer: wgpu::Buffer,
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
        let storage = Storage::new(
            context,
            "fabric sampler",
            bytemuck::cast_slice(sampler.data()),
        )?;
        Ok(Self { storage })
    }

    fn run(
        &self,
        context: &GpuContext,
        entry: &str,
        pairs: &[(Vec3, Vec3)],
    ) -> Result<Vec<[f32; 4]>, GpuError> {
        let source = sampler_pairs_wgsl();
        self.storage.run(context, &source, entry, pairs)
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

/// The compute entry points over the taps (`shaders/gpu/tap_pairs.wgsl`), for
/// [`GpuSampleTaps::pick`].
pub fn tap_pairs_wgsl() -> String {
    crate::shader::Composer::new()
        .module(crate::shader::SAMPLER_CONSTANTS, Sampler::wgsl_constants())
        .compose(&["gpu/tap_pairs"])
        .expect("the tap kernels compose (validated in the tests)")
}

impl GpuSampleTaps {
    /// Uploads `taps`.
    pub fn new(context: &GpuContext, taps: &SampleTaps) -> Result<Self, GpuError> {
        let storage = Storage::new(context, "sample taps", bytemuck::cast_slice(taps.words()))?;
        Ok(Self {
            storage,
            samples: taps.samples(),
        })
    }

    /// A stand-in for no samples, for a pipeline's taps binding that is never read (the
    /// render pass without an environment light).
    pub fn placeholder(context: &GpuContext) -> Result<Self, GpuError> {
        let storage = Storage::new(context, "sample taps", &[0; 16])?;
        Ok(Self {
            storage,
            samples: 0,
        })
    }

    /// The samples per pixel the taps serve.
    pub fn samples(&self) -> u32 {
        self.samples
    }

    /// The storage buffer of the taps (`sampling_taps`).
    pub fn buffer(&self) -> &wgpu::Buffer {
        &self.storage.buffer
    }

    /// `sampling_tap` for each `(wo, k)` (wo above the horizon, k below the samples): the
    /// tap's (wi, log2 of its solid angle) and (weight, 0).
    pub fn pick(
        &self,
        context: &GpuContext,
        requests: &[(Vec3, u32)],
    ) -> Result<Vec<[[f32; 4]; 2]>, GpuError> {
        let pairs: Vec<(Vec3, Vec3)> = requests
            .iter()
            .map(|&(wo, k)| (wo, Vec3::new(k as f32, self.samples as f32, 0.0)))
            .collect();
        let source = tap_pairs_wgsl();
        let draws = self
            .storage
            .run(context, &source, "tap_draws_main", &pairs)?;
        let weights = self
            .storage
            .run(context, &source, "tap_weights_main", &pairs)?;
        Ok(draws
            .into_iter()
            .zip(weights)
            .map(|(d, w)| [d, w])
            .collect())
    }
}

impl Storage {
    fn new(context: &GpuContext, label: &str, contents: &[u8]) -> Result<Self, GpuError> {
        let device = &context.device;
        context.checked(|| {
            let buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents,
                usage: wgpu::BufferUsages::STORAGE,
            });
            let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some(label),
                entries: &[sampler_entry(0)],
            });
            let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some(label),
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
        source: &str,
        entry: &str,
        pairs: &[(Vec3, Vec3)],
    ) -> Result<Vec<[f32; 4]>, GpuError> {
        run_pairs(context, (&self.layout, &self.group), source, entry, pairs)
    }
}
