//! A constant F for cost measurements: the frame with no BRDF work in it.

use crate::gpu::{GpuBrdf, GpuContext};
use crate::shader::ShaderFile;

/// The constant shader's file (`cloth_brdf` = 1/π).
pub const FILE: ShaderFile = ShaderFile {
    name: "evaluator/constant",
    path: "src/evaluator/constant/constant.wgsl",
    source: include_str!("constant.wgsl"),
};

/// F(wi, wo) = 1/π (RGB, every pair above the horizon): not a cloth model, but the cost
/// floor of a frame. A render with it costs what every render costs besides evaluating F
/// (rasterisation, the shading frame, tone mapping), so a BRDF's own cost per frame is its
/// frame time minus this one's, and no BRDF can make a frame cheaper. Used by
/// `clothbake render --evaluator constant` and `scripts/runtime-figures.sh`.
pub struct GpuConstant {
    bind_group_layout: wgpu::BindGroupLayout,
    bind_group: wgpu::BindGroup,
}

/// The WGSL of [`GpuConstant`] ([`FILE`]).
pub fn constant_wgsl() -> String {
    crate::shader::Composer::new()
        .unit_file(&FILE)
        .compose(&[FILE.name])
        .expect("the constant shader composes (validated in the tests)")
}

impl GpuConstant {
    /// The constant BRDF, with an empty group 0.
    pub fn new(context: &GpuContext) -> Self {
        let (bind_group_layout, bind_group) = crate::gpu::empty_bind_group(context, "constant");
        Self {
            bind_group_layout,
            bind_group,
        }
    }
}

impl GpuBrdf for GpuConstant {
    fn wgsl(&self) -> String {
        constant_wgsl()
    }

    fn bind_group_layout(&self) -> &wgpu::BindGroupLayout {
        &self.bind_group_layout
    }

    fn bind_group(&self) -> &wgpu::BindGroup {
        &self.bind_group
    }

    fn label(&self) -> String {
        "constant F = 1/π (frame cost floor)".into()
    }
}
