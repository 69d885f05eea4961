//! The GPU form of every stock unit: the material's parameter values and derived constants
//! in one uniform block (`stock.wgsl`), read by the unit's own WGSL.

use super::{MAX_DERIVED, MAX_PARAMETERS, StockMaterial, StockModel};
use crate::gpu::{GpuBrdf, GpuContext, GpuError, brdf_entry};
use crate::shader::ShaderFile;
use bytemuck::{Pod, Zeroable};
use wgpu::util::DeviceExt;

/// The uniform block and its accessors, which every stock unit's WGSL requires.
pub const BLOCK_FILE: ShaderFile = ShaderFile {
    name: "evaluator/stock",
    path: "src/evaluator/stock/stock.wgsl",
    source: include_str!("stock.wgsl"),
};

/// The lobes the units share (`lobes.rs`'s twins).
pub const LOBES_FILE: ShaderFile = ShaderFile {
    name: "evaluator/stock_lobes",
    path: "src/evaluator/stock/lobes.wgsl",
    source: include_str!("lobes.wgsl"),
};

/// `ClothStockBlock` of stock.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct StockBlock {
    pub parameters: [f32; MAX_PARAMETERS],
    pub derived: [f32; MAX_DERIVED],
}

impl StockBlock {
    /// The block of `material`, its values rounded to f32.
    pub fn new(material: &StockMaterial) -> Result<Self, GpuError> {
        let too_many = |what: &str, count: usize, most: usize| GpuError::Invalid {
            name: format!("{} {what}", material.model.name),
            message: format!("{count} of them, the block holds {most}"),
        };
        if material.values.len() > MAX_PARAMETERS {
            return Err(too_many(
                "parameters",
                material.values.len(),
                MAX_PARAMETERS,
            ));
        }
        if material.derived.len() > MAX_DERIVED {
            return Err(too_many(
                "derived constants",
                material.derived.len(),
                MAX_DERIVED,
            ));
        }
        let mut block = Self::default();
        for (slot, v) in block.parameters.iter_mut().zip(&material.values) {
            *slot = *v as f32;
        }
        for (slot, v) in block.derived.iter_mut().zip(&material.derived) {
            *slot = *v as f32;
        }
        Ok(block)
    }
}

/// The composed WGSL of `model`'s GPU form.
pub fn stock_wgsl(model: &StockModel) -> String {
    crate::shader::Composer::new()
        .unit_file(&BLOCK_FILE)
        .unit_file(&LOBES_FILE)
        .unit_file(model.wgsl)
        .compose(&[model.wgsl.name])
        .expect("the stock shaders compose (validated in the tests)")
}

/// A stock material on the GPU.
pub struct GpuStock {
    model: &'static StockModel,
    bind_group_layout: wgpu::BindGroupLayout,
    bind_group: wgpu::BindGroup,
}

impl GpuStock {
    pub fn new(context: &GpuContext, material: &StockMaterial) -> Result<Self, GpuError> {
        let block = StockBlock::new(material)?;
        context.checked(|| {
            let device = &context.device;
            let buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("stock material"),
                contents: bytemuck::bytes_of(&block),
                usage: wgpu::BufferUsages::UNIFORM,
            });
            let bind_group_layout =
                device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                    label: Some("stock material"),
                    entries: &[brdf_entry(
                        0,
                        wgpu::BindingType::Buffer {
                            ty: wgpu::BufferBindingType::Uniform,
                            has_dynamic_offset: false,
                            min_binding_size: wgpu::BufferSize::new(
                                std::mem::size_of::<StockBlock>() as u64,
                            ),
                        },
                    )],
                });
            let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("stock material"),
                layout: &bind_group_layout,
                entries: &[wgpu::BindGroupEntry {
                    binding: 0,
                    resource: buffer.as_entire_binding(),
                }],
            });
            Self {
                model: material.model,
                bind_group_layout,
                bind_group,
            }
        })
    }
}

impl GpuBrdf for GpuStock {
    fn wgsl(&self) -> String {
        stock_wgsl(self.model)
    }

    fn bind_group_layout(&self) -> &wgpu::BindGroupLayout {
        &self.bind_group_layout
    }

    fn bind_group(&self) -> &wgpu::BindGroup {
        &self.bind_group
    }

    fn label(&self) -> String {
        format!("{} (stock model, fitted)", self.model.name)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_block_is_the_size_stock_wgsl_declares() {
        // 4 + 8 vec4s.
        assert_eq!(std::mem::size_of::<StockBlock>(), (4 + 8) * 16);
    }
}
