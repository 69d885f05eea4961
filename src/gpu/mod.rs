//! The GPU runtime core: a wgpu device (headless or for a window surface) and the one
//! interface, [`GpuBrdf`], behind which every evaluator's GPU form evaluates the patch
//! transfer F(wi, wo) (docs/model.md#the-patch-transfer-f): a WGSL module defining
//! `cloth_brdf(wi, wo)` plus the bind group it reads. The GPU forms themselves live with their
//! evaluators (`src/evaluator/<name>/gpu.rs`, reached through [`crate::evaluator`]'s registry).
//!
//! - [`GpuContext`]: device and queue, the adapter's description, GPU timestamps if offered.
//! - [`GpuSampler`]: a fabric's importance sampler (`shaders/sampling/fabric_sampler.wgsl`,
//!   mirrors [`crate::sampling::Sampler`]).
//! - [`evaluate_pairs`]: F(wi, wo) for a list of direction pairs by any [`GpuBrdf`]
//!   (`shaders/gpu/eval_pairs.wgsl`), for tests and measurements.
//!
//! Every shader is composed by [`crate::shader::Composer`].

pub mod sampler;

pub use sampler::{GpuSampleTaps, GpuSampler};

use glam::Vec3;
use std::fmt;
use wgpu::util::DeviceExt;

/// The compute entry point `eval_pairs_main` (`shaders/gpu/eval_pairs.wgsl`) over a
/// [`GpuBrdf`]'s WGSL `brdf_wgsl` (the generated module [`crate::shader::BRDF`]): the shader
/// of [`evaluate_pairs`].
pub fn eval_pairs_wgsl(brdf_wgsl: String) -> String {
    crate::shader::Composer::new()
        .module(crate::shader::BRDF, brdf_wgsl)
        .compose(&["gpu/eval_pairs"])
        .expect("the pair kernel composes (validated in the tests)")
}

/// Pairs per dispatch: bounds the storage buffers (32 bytes in, 16 out per pair) well below
/// wgpu's default 128 MiB binding limit and the workgroup count below 65535.
const PAIRS_PER_DISPATCH: usize = 1 << 20;
/// `@workgroup_size` of `eval_pairs_main`.
const WORKGROUP_SIZE: usize = 64;

/// The shader stages a [`GpuBrdf`]'s bindings are visible to: `cloth_brdf` may be called from
/// fragment and compute shaders (not vertex shaders: some devices allow no storage buffers
/// there).
pub const BRDF_VISIBILITY: wgpu::ShaderStages =
    wgpu::ShaderStages::FRAGMENT.union(wgpu::ShaderStages::COMPUTE);

/// Why a GPU operation failed.
#[derive(Debug, thiserror::Error)]
pub enum GpuError {
    #[error(
        "no GPU adapter found ({0}); without a GPU install a software Vulkan driver \
         (Debian: apt-get install mesa-vulkan-drivers libvulkan1)"
    )]
    NoAdapter(String),
    #[error("cannot create a device on adapter {adapter}: {reason}")]
    Device { adapter: String, reason: String },
    #[error("table does not fit the device: {0}")]
    Limits(String),
    /// A parameter out of its documented range, named with its value.
    #[error("invalid {name}: {message}")]
    Invalid { name: String, message: String },
    #[error("GPU error: {0}")]
    Wgpu(String),
}

/// What wgpu says about the adapter in use.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct AdapterDescription {
    pub name: String,
    pub backend: String,
    pub device_type: String,
    pub driver: String,
}

impl AdapterDescription {
    fn new(info: &wgpu::AdapterInfo) -> Self {
        Self {
            name: info.name.clone(),
            backend: format!("{:?}", info.backend),
            device_type: format!("{:?}", info.device_type),
            driver: [info.driver.as_str(), info.driver_info.as_str()]
                .iter()
                .filter(|s| !s.is_empty())
                .copied()
                .collect::<Vec<_>>()
                .join(" "),
        }
    }
}

impl fmt::Display for AdapterDescription {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} (backend {}, device type {}",
            self.name, self.backend, self.device_type
        )?;
        if !self.driver.is_empty() {
            write!(f, ", driver {}", self.driver)?;
        }
        f.write_str(")")
    }
}

/// A device and its queue, headless ([`GpuContext::new`]) or able to present to a surface
/// ([`GpuContext::with_surface`]).
pub struct GpuContext {
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
    pub adapter: AdapterDescription,
}

/// Optional features requested when the adapter offers them: GPU timestamps, for timing
/// frames and passes.
const OPTIONAL_FEATURES: wgpu::Features =
    wgpu::Features::TIMESTAMP_QUERY.union(wgpu::Features::TIMESTAMP_QUERY_INSIDE_ENCODERS);

impl GpuContext {
    /// A headless device on any adapter wgpu finds (backends and adapter choice follow the
    /// `WGPU_BACKEND`, `WGPU_POWER_PREF` and `WGPU_ADAPTER_NAME` environment variables when
    /// set), with the adapter's own limits so that large tables fit where the adapter allows.
    pub fn new() -> Result<Self, GpuError> {
        pollster::block_on(Self::create(&Self::instance(), None))
    }

    /// The wgpu instance [`GpuContext::new`] uses: backends, flags and backend options from
    /// the environment (`WGPU_BACKEND`, `WGPU_DEBUG`, …), no display handle. A windowed
    /// viewer creates its surface from it and passes both to [`GpuContext::with_surface`].
    /// (The GL backend needs a display handle to present; Vulkan, Metal and DX12 do not.)
    pub fn instance() -> wgpu::Instance {
        wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env())
    }

    /// A device on an adapter of `instance` that can present to `surface` (adapter choice as
    /// in [`GpuContext::new`]).
    pub fn with_surface(
        instance: &wgpu::Instance,
        surface: &wgpu::Surface<'_>,
    ) -> Result<Self, GpuError> {
        pollster::block_on(Self::create(instance, Some(surface)))
    }

    async fn create(
        instance: &wgpu::Instance,
        surface: Option<&wgpu::Surface<'_>>,
    ) -> Result<Self, GpuError> {
        let adapter = wgpu::util::initialize_adapter_from_env_or_default(instance, surface)
            .await
            .map_err(|e| GpuError::NoAdapter(e.to_string()))?;
        let description = AdapterDescription::new(&adapter.get_info());
        let (device, queue) = adapter
            .request_device(&wgpu::DeviceDescriptor {
                label: Some("clothbake"),
                required_features: adapter.features() & OPTIONAL_FEATURES,
                required_limits: adapter.limits(),
                ..Default::default()
            })
            .await
            .map_err(|e| GpuError::Device {
                adapter: description.to_string(),
                reason: e.to_string(),
            })?;
        Ok(Self {
            device,
            queue,
            adapter: description,
        })
    }

    /// Whether the device has `wgpu::Features::TIMESTAMP_QUERY` (timestamp writes at the
    /// start and end of passes). [`GpuContext::timestamps_inside_encoders`] says whether
    /// `CommandEncoder::write_timestamp` is available too.
    pub fn timestamps(&self) -> bool {
        self.device
            .features()
            .contains(wgpu::Features::TIMESTAMP_QUERY)
    }

    /// Whether the device has `wgpu::Features::TIMESTAMP_QUERY_INSIDE_ENCODERS`.
    pub fn timestamps_inside_encoders(&self) -> bool {
        self.device.features().contains(OPTIONAL_FEATURES)
    }

    /// Nanoseconds per timestamp tick (`Queue::get_timestamp_period`).
    pub fn timestamp_period(&self) -> f32 {
        self.queue.get_timestamp_period()
    }

    /// Runs `f`, turning validation errors it raises into [`GpuError::Wgpu`].
    pub(crate) fn checked<T>(&self, f: impl FnOnce() -> T) -> Result<T, GpuError> {
        let scope = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let value = f();
        match pollster::block_on(scope.pop()) {
            Some(error) => Err(GpuError::Wgpu(error.to_string())),
            None => Ok(value),
        }
    }
}

/// A GPU evaluation of the patch transfer F(wi, wo) (docs/model.md#the-patch-transfer-f), as a
/// WGSL module plus its resources. A shader using it composes [`GpuBrdf::wgsl`], as the
/// generated module [`crate::shader::BRDF`], with its own modules (which require it) and binds
/// [`GpuBrdf::bind_group`] at group 0 (its own resources in other groups).
///
/// Naming contract: besides `cloth_brdf`, every top-level name the module declares (types,
/// functions, constants, bindings) starts with `cloth_`, `Cloth` or `CLOTH_`, so a caller's
/// own WGSL avoids those prefixes.
pub trait GpuBrdf {
    /// WGSL source that defines `fn cloth_brdf(wi: vec3<f32>, wo: vec3<f32>) -> vec3<f32>`:
    /// F(wi, wo) RGB in the local cloth frame (x = thread 1 tangent t0 direction / along u,
    /// z = normal), 0 when wi.z <= 0 or wo.z <= 0; all its bindings in @group(0), nothing in
    /// other groups, no entry points. Callable from fragment and compute shaders
    /// ([`BRDF_VISIBILITY`]).
    fn wgsl(&self) -> String;
    /// The layout of group 0 for pipelines using [`GpuBrdf::wgsl`].
    fn bind_group_layout(&self) -> &wgpu::BindGroupLayout;
    /// The group 0 resources.
    fn bind_group(&self) -> &wgpu::BindGroup;
    /// Short description for logs, e.g. "lookup LAYOUT R=31" or "paper N=32".
    fn label(&self) -> String;
    /// Makes this form shade `fabric` from the next submission on, if it can without a new
    /// shader: `Ok(true)` when it now shades `fabric` with the same WGSL, bind group layout
    /// and bind group (pipelines built for it stay valid; the resonant quadrature's form
    /// rewrites its fabric buffer); `Ok(false)` when the form bakes its fabric into its shader
    /// or table (paper mode, a table), so the caller builds a new form for `fabric`. An
    /// invalid fabric is refused with [`GpuError::Invalid`] and the form keeps shading its
    /// old one. The live editor of `view --edit` calls it on each edit.
    fn update_fabric(
        &self,
        _context: &GpuContext,
        _fabric: &crate::model::Fabric,
    ) -> Result<bool, GpuError> {
        Ok(false)
    }
}

/// F(wi, wo) for each pair (local frame, unit vectors) evaluated on the GPU by `brdf`: the
/// shader [`eval_pairs_wgsl`] of `brdf.wgsl()`, one invocation per pair, RGB per pair.
pub fn evaluate_pairs(
    context: &GpuContext,
    brdf: &dyn GpuBrdf,
    pairs: &[(Vec3, Vec3)],
) -> Result<Vec<[f32; 3]>, GpuError> {
    let source = eval_pairs_wgsl(brdf.wgsl());
    let results = run_pairs(
        context,
        (brdf.bind_group_layout(), brdf.bind_group()),
        &source,
        "eval_pairs_main",
        pairs,
    )?;
    Ok(results.into_iter().map(|v| [v[0], v[1], v[2]]).collect())
}

/// [`crate::lighting::bright_sources::disk_above_horizon`] on the device for each
/// `(wi, sin radius)`: WGSL's `source_disk_above_horizon` (shaders/lighting/source_disk.wgsl),
/// (centroid direction, visible fraction). For its twin test.
pub fn disks_above_horizon(
    context: &GpuContext,
    requests: &[(Vec3, f32)],
) -> Result<Vec<(Vec3, f32)>, GpuError> {
    let source = crate::shader::Composer::new()
        .compose(&["gpu/source_disk_pairs"])
        .expect("the source disk kernel composes (validated in the tests)");
    let pairs: Vec<(Vec3, Vec3)> = requests
        .iter()
        .map(|&(wi, sin_radius)| (wi, Vec3::new(sin_radius, 0.0, 0.0)))
        .collect();
    let (layout, group) = empty_bind_group(context, "source disk");
    let results = run_pairs(
        context,
        (&layout, &group),
        &source,
        "source_disk_main",
        &pairs,
    )?;
    Ok(results
        .into_iter()
        .map(|v| (Vec3::new(v[0], v[1], v[2]), v[3]))
        .collect())
}

/// Runs compute entry point `entry` of `source` once per pair of 3-vectors: the pairs are
/// `eval_pairs[2k]`, `eval_pairs[2k + 1]` and the results `eval_results[k]` (vec4) in
/// @group(1) as `shaders/gpu/eval_pairs.wgsl` declares them; `group0` is bound at @group(0).
pub(crate) fn run_pairs(
    context: &GpuContext,
    group0: (&wgpu::BindGroupLayout, &wgpu::BindGroup),
    source: &str,
    entry: &str,
    pairs: &[(Vec3, Vec3)],
) -> Result<Vec<[f32; 4]>, GpuError> {
    let evaluator = context.checked(|| PairEvaluator::new(context, group0.0, source, entry))?;
    let mut results = Vec::with_capacity(pairs.len());
    for chunk in pairs.chunks(PAIRS_PER_DISPATCH) {
        results.extend(context.checked(|| evaluator.dispatch(context, group0.1, chunk))??);
    }
    Ok(results)
}

/// The compute pipeline of [`run_pairs`] for one module and entry point.
struct PairEvaluator {
    pipeline: wgpu::ComputePipeline,
    buffers_layout: wgpu::BindGroupLayout,
}

impl PairEvaluator {
    fn new(
        context: &GpuContext,
        group0: &wgpu::BindGroupLayout,
        source: &str,
        entry: &str,
    ) -> Self {
        let device = &context.device;
        let storage = |binding, read_only| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Storage { read_only },
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        };
        let buffers_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("eval_pairs buffers"),
            entries: &[storage(0, true), storage(1, false)],
        });
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("eval_pairs"),
            bind_group_layouts: &[Some(group0), Some(&buffers_layout)],
            immediate_size: 0,
        });
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(entry),
            source: wgpu::ShaderSource::Wgsl(source.into()),
        });
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("eval_pairs"),
            layout: Some(&layout),
            module: &module,
            entry_point: Some(entry),
            compilation_options: Default::default(),
            cache: None,
        });
        Self {
            pipeline,
            buffers_layout,
        }
    }

    fn dispatch(
        &self,
        context: &GpuContext,
        group0: &wgpu::BindGroup,
        pairs: &[(Vec3, Vec3)],
    ) -> Result<Vec<[f32; 4]>, GpuError> {
        if pairs.is_empty() {
            return Ok(Vec::new());
        }
        let device = &context.device;
        let input: Vec<[f32; 4]> = pairs
            .iter()
            .flat_map(|(wi, wo)| [wi.extend(0.0).to_array(), wo.extend(0.0).to_array()])
            .collect();
        let pair_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("pairs"),
            contents: bytemuck::cast_slice(&input),
            usage: wgpu::BufferUsages::STORAGE,
        });
        // One vec4<f32> per pair: 16 bytes, a multiple of the 4-byte copy alignment.
        let result_bytes = (pairs.len() * 16) as u64;
        let result_buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("results"),
            size: result_bytes,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let readback = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("results readback"),
            size: result_bytes,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let buffers = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("eval_pairs buffers"),
            layout: &self.buffers_layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: pair_buffer.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: result_buffer.as_entire_binding(),
                },
            ],
        });
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("eval_pairs"),
        });
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("eval_pairs"),
                timestamp_writes: None,
            });
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, group0, &[]);
            pass.set_bind_group(1, &buffers, &[]);
            pass.dispatch_workgroups(pairs.len().div_ceil(WORKGROUP_SIZE) as u32, 1, 1);
        }
        encoder.copy_buffer_to_buffer(&result_buffer, 0, &readback, 0, result_bytes);
        context.queue.submit([encoder.finish()]);
        let slice = readback.slice(..);
        let (sender, receiver) = std::sync::mpsc::channel();
        slice.map_async(wgpu::MapMode::Read, move |r| {
            let _ = sender.send(r);
        });
        device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| GpuError::Wgpu(e.to_string()))?;
        receiver
            .recv()
            .map_err(|e| GpuError::Wgpu(e.to_string()))?
            .map_err(|e| GpuError::Wgpu(e.to_string()))?;
        let view = slice
            .get_mapped_range()
            .map_err(|e| GpuError::Wgpu(e.to_string()))?;
        let values: Vec<[f32; 4]> = bytemuck::cast_slice(&view).to_vec();
        drop(view);
        readback.unmap();
        Ok(values)
    }
}

/// An empty group 0 (layout and bind group), for a [`GpuBrdf`] whose WGSL holds everything
/// it reads as constants.
pub fn empty_bind_group(
    context: &GpuContext,
    label: &str,
) -> (wgpu::BindGroupLayout, wgpu::BindGroup) {
    let device = &context.device;
    let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some(label),
        entries: &[],
    });
    let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some(label),
        layout: &layout,
        entries: &[],
    });
    (layout, group)
}

/// A bind group layout entry of a [`GpuBrdf`] (visible to [`BRDF_VISIBILITY`]).
pub fn brdf_entry(binding: u32, ty: wgpu::BindingType) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: BRDF_VISIBILITY,
        ty,
        count: None,
    }
}
