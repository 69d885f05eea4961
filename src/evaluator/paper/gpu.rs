//! [`GpuPaper`]: the model of docs/model.md evaluated in the shader (`paper.wgsl`) in f32,
//! in paper mode: N stratified tangent samples per thread, the same nodes and weights as the
//! CPU's `Patch::new(fabric, Integration::Paper(N))`.

use super::MAX_SHADER_SAMPLES;
use crate::gpu::{GpuBrdf, GpuContext, GpuError, brdf_entry};
use crate::model::curve::{Integration, curve_pieces};
use crate::model::{Fabric, Thread};
use crate::shader::ShaderFile;
use bytemuck::{Pod, Zeroable};
use wgpu::util::DeviceExt;

/// The paper-mode shader's own file (defines `cloth_brdf`).
pub const FILE: ShaderFile = ShaderFile {
    name: "evaluator/paper",
    path: "src/evaluator/paper/paper.wgsl",
    source: include_str!("paper.wgsl"),
};

/// The complete WGSL module of [`GpuPaper`]: `paper.wgsl` after the tangent sample it
/// requires, its bindings in group 0.
pub fn paper_wgsl() -> String {
    crate::shader::Composer::new()
        .unit_file(&FILE)
        .compose(&[FILE.name])
        .expect("the paper-mode shader composes (validated in the tests)")
}

/// One thread family as `ClothPaperThread` of paper.wgsl reads it.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct PaperThread {
    pub t0: [f32; 4],
    pub b: [f32; 4],
    pub albedo: [f32; 4],
    /// Surface −1/(2σs²), 1/(σs√(2π)); volume −1/(2σv²), 1/(σv√(2π)) (σ in radians).
    pub lobes: [f32; 4],
    /// η, kd, coverage, 1 if η == 1 else 0.
    pub material: [f32; 4],
    /// First node, node count.
    pub nodes: [u32; 4],
}

/// The uniform block of paper.wgsl (`ClothPaperParams`): both threads and `misc` =
/// (−1/(2σu²), gap, degenerate-projection threshold, 0).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct PaperParams {
    pub threads: [PaperThread; 2],
    pub misc: [f32; 4],
}

use crate::table::wgsl::{degenerate_threshold, unit_area_gaussian};

/// Paper-mode nodes of `thread` as (cos α, sin α, weight, 0), cos and sin computed in f64
/// like the CPU's, then rounded.
fn thread_nodes(fabric: &Fabric, thread: &Thread, samples: u32) -> Result<Vec<[f32; 4]>, GpuError> {
    curve_pieces(thread, &fabric.options, Integration::Paper(samples))
        .iter()
        .map(|p| {
            // Paper mode and the control-point option only make single-point pieces; an
            // interval would need the clipping of the direct rule, which the shader lacks.
            if p.start != p.end || p.count != 1 {
                return Err(GpuError::Invalid {
                    name: "tangent nodes".into(),
                    message: format!("paper mode made an interval piece {p:?}"),
                });
            }
            Ok([
                p.start.cos() as f32,
                p.start.sin() as f32,
                p.weight as f32,
                0.0,
            ])
        })
        .collect()
}

/// The model evaluated in the shader with N tangent samples per thread (paper mode), a
/// [`GpuBrdf`]. Bindings (group 0): 0 the uniform block [`PaperParams`], 1 a read-only
/// storage buffer of the tangent nodes of both threads.
pub struct GpuPaper {
    samples: u32,
    bind_group_layout: wgpu::BindGroupLayout,
    bind_group: wgpu::BindGroup,
}

impl GpuPaper {
    /// Prepares `fabric` for paper mode with `samples` = N tangent samples per thread
    /// (`Integration::Paper(N)`), N in 1..=[`MAX_SHADER_SAMPLES`]. Fails with
    /// [`GpuError::Invalid`] for another N or an invalid fabric (see [`Fabric::validate`]).
    pub fn new(context: &GpuContext, fabric: &Fabric, samples: u32) -> Result<Self, GpuError> {
        if !(1..=MAX_SHADER_SAMPLES).contains(&samples) {
            return Err(GpuError::Invalid {
                name: "tangent samples per thread".into(),
                message: format!("must be within 1..={MAX_SHADER_SAMPLES}, got {samples}"),
            });
        }
        fabric.validate().map_err(|e| GpuError::Invalid {
            name: "fabric".into(),
            message: e.to_string(),
        })?;
        let (params, nodes) = Self::prepare(fabric, samples)?;
        context.checked(|| Self::create(context, samples, &params, &nodes))
    }

    /// The uniform block and the node buffer contents for `fabric`, mirroring
    /// `ThreadModel::new` and `Patch::new`.
    pub fn prepare(
        fabric: &Fabric,
        samples: u32,
    ) -> Result<(PaperParams, Vec<[f32; 4]>), GpuError> {
        let options = fabric.options;
        let mut nodes = Vec::new();
        let mut threads = [PaperThread::default(); 2];
        for (j, thread) in fabric.threads().into_iter().enumerate() {
            let (t0, b) = if j == 0 {
                ([1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0])
            } else {
                ([0.0, 1.0, 0.0, 0.0], [1.0, 0.0, 0.0, 0.0])
            };
            let sigma_s = options.lobe_sigma_deg(thread.gamma_s_deg).to_radians();
            let sigma_v = options.lobe_sigma_deg(thread.gamma_v_deg).to_radians();
            let [ks, ps] = unit_area_gaussian(sigma_s);
            let [kv, pv] = unit_area_gaussian(sigma_v);
            let [r, g, bl] = thread.albedo_rgb().map(|c| c as f32);
            let thread_nodes = thread_nodes(fabric, thread, samples)?;
            threads[j] = PaperThread {
                t0,
                b,
                albedo: [r, g, bl, 0.0],
                lobes: [ks, ps, kv, pv],
                material: [
                    thread.eta as f32,
                    thread.kd as f32,
                    thread.coverage as f32,
                    if thread.eta == 1.0 { 1.0 } else { 0.0 },
                ],
                nodes: [nodes.len() as u32, thread_nodes.len() as u32, 0, 0],
            };
            nodes.extend(thread_nodes);
        }
        let sigma_u = options.sigma_u_deg.to_radians();
        let gap = (1.0 - fabric.thread1.coverage - fabric.thread2.coverage).max(0.0);
        let params = PaperParams {
            threads,
            misc: [
                (-0.5 / (sigma_u * sigma_u)) as f32,
                gap as f32,
                degenerate_threshold(),
                0.0,
            ],
        };
        Ok((params, nodes))
    }

    fn create(
        context: &GpuContext,
        samples: u32,
        params: &PaperParams,
        nodes: &[[f32; 4]],
    ) -> Self {
        let device = &context.device;
        let uniforms = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("paper params"),
            contents: bytemuck::bytes_of(params),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let node_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("paper nodes"),
            contents: bytemuck::cast_slice(nodes),
            usage: wgpu::BufferUsages::STORAGE,
        });
        let bind_group_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("paper"),
            entries: &[
                brdf_entry(
                    0,
                    wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Uniform,
                        has_dynamic_offset: false,
                        min_binding_size: wgpu::BufferSize::new(
                            std::mem::size_of::<PaperParams>() as u64
                        ),
                    },
                ),
                brdf_entry(
                    1,
                    wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Storage { read_only: true },
                        has_dynamic_offset: false,
                        min_binding_size: wgpu::BufferSize::new(16),
                    },
                ),
            ],
        });
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("paper"),
            layout: &bind_group_layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: uniforms.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: node_buffer.as_entire_binding(),
                },
            ],
        });
        Self {
            samples,
            bind_group_layout,
            bind_group,
        }
    }
}

impl GpuBrdf for GpuPaper {
    fn wgsl(&self) -> String {
        paper_wgsl()
    }

    fn bind_group_layout(&self) -> &wgpu::BindGroupLayout {
        &self.bind_group_layout
    }

    fn bind_group(&self) -> &wgpu::BindGroup {
        &self.bind_group
    }

    fn label(&self) -> String {
        format!("paper N={}", self.samples)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::formats::fabric_toml::FabricSet;

    #[test]
    fn uniform_sizes_match_wgsl() {
        assert_eq!(std::mem::size_of::<PaperThread>(), 6 * 16);
        assert_eq!(std::mem::size_of::<PaperParams>(), 2 * 6 * 16 + 16);
    }

    #[test]
    fn nodes_are_the_paper_mode_nodes_with_unit_weight_per_thread() {
        for fabric in FabricSet::builtin().fabrics() {
            for n in [1, 8, 32] {
                let (params, nodes) = GpuPaper::prepare(fabric, n).unwrap();
                for thread in params.threads {
                    let [first, count, _, _] = thread.nodes.map(|v| v as usize);
                    assert!((1..=n as usize).contains(&count));
                    let total: f32 = nodes[first..first + count].iter().map(|v| v[2]).sum();
                    assert!((total - 1.0).abs() < 1e-6, "{}: {total}", fabric.name);
                }
            }
        }
    }
}
