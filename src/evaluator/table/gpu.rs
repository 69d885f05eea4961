//! [`GpuTable`]: a baked table on the GPU, a [`GpuBrdf`] whose `cloth_brdf` is the table
//! lookup of `shaders/table/lookup.wgsl` and the layout's WGSL file (mirroring [`Table::lookup`]).
//!
//! The WGSL is specialised for each table ([`lookup_wgsl`]): a generated block holds the
//! table's axes (warps, knots, texel counts), thread frames and fabric constants as
//! literals, so that the shader reads no uniforms and branches on no table parameter (a
//! shader compiler folds literals it cannot fold from a uniform block). To use a table in another
//! engine, take [`GpuBrdf::wgsl`] of its `GpuTable`, or [`lookup_wgsl`] of the [`Table`]
//! (no device needed), and bind the textures of its layout
//! ([`crate::table::TableLookup::textures`]). Two tables share a shader only when their
//! geometry and albedos agree, so a renderer switching between fabrics compiles one
//! pipeline per fabric.

use crate::gpu::{GpuBrdf, GpuContext, GpuError, brdf_entry};
use crate::table::bindings::SAMPLER_BINDING;
use crate::table::wgsl::lookup_wgsl;
use crate::table::{Table, TextureData};

/// A table on the GPU: its textures, bound in one bind group, and its specialised lookup.
///
/// Bindings (group 0, declared in [`crate::table::bindings`]): a linear clamp-to-edge
/// sampler at `SAMPLER_BINDING`; the layout's textures at the slots its
/// [`crate::table::TableLookup::textures`] give.
pub struct GpuTable {
    label: String,
    /// [`lookup_wgsl`] of the table.
    wgsl: String,
    bind_group_layout: wgpu::BindGroupLayout,
    bind_group: wgpu::BindGroup,
}

impl GpuTable {
    /// Uploads `table` (its layout's `TableLookup::textures`) and builds its bind group; the
    /// lookup is the same on every adapter.
    pub fn new(context: &GpuContext, table: &Table) -> Result<Self, GpuError> {
        context.checked(|| Self::create(context, table))?
    }

    fn create(context: &GpuContext, table: &Table) -> Result<Self, GpuError> {
        let device = &context.device;
        let limits = device.limits();
        let mut views = Vec::new();
        for data in table.geometry().textures(table.planes()) {
            check_size(&data, &limits)?;
            views.push((data.binding, data.three_d, upload(context, &data)));
        }
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("table sampler"),
            address_mode_u: wgpu::AddressMode::ClampToEdge,
            address_mode_v: wgpu::AddressMode::ClampToEdge,
            address_mode_w: wgpu::AddressMode::ClampToEdge,
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            mipmap_filter: wgpu::MipmapFilterMode::Nearest,
            ..Default::default()
        });

        let mut layout_entries = vec![brdf_entry(
            SAMPLER_BINDING,
            wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
        )];
        layout_entries.extend(views.iter().map(|&(binding, three_d, _)| {
            let view_dimension = if three_d {
                wgpu::TextureViewDimension::D3
            } else {
                wgpu::TextureViewDimension::D2Array
            };
            brdf_entry(
                binding,
                wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Float { filterable: true },
                    view_dimension,
                    multisampled: false,
                },
            )
        }));
        let bind_group_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("lookup"),
            entries: &layout_entries,
        });
        let mut entries = vec![wgpu::BindGroupEntry {
            binding: SAMPLER_BINDING,
            resource: wgpu::BindingResource::Sampler(&sampler),
        }];
        entries.extend(views.iter().map(|(binding, _, view)| wgpu::BindGroupEntry {
            binding: *binding,
            resource: wgpu::BindingResource::TextureView(view),
        }));
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("lookup"),
            layout: &bind_group_layout,
            entries: &entries,
        });
        Ok(Self {
            label: format!("lookup {} R={}", table.layout, table.resolution),
            wgsl: lookup_wgsl(table),
            bind_group_layout,
            bind_group,
        })
    }
}

impl GpuBrdf for GpuTable {
    /// The lookup specialised for this table ([`lookup_wgsl`]): only the bindings of its
    /// layout are used.
    fn wgsl(&self) -> String {
        self.wgsl.clone()
    }

    fn bind_group_layout(&self) -> &wgpu::BindGroupLayout {
        &self.bind_group_layout
    }

    fn bind_group(&self) -> &wgpu::BindGroup {
        &self.bind_group
    }

    fn label(&self) -> String {
        self.label.clone()
    }
}

/// Fails with [`GpuError::Limits`] when the texture exceeds the device's limits.
fn check_size(data: &TextureData, limits: &wgpu::Limits) -> Result<(), GpuError> {
    let [w, h, d] = data.size;
    let fits = if data.three_d {
        w.max(h).max(d) <= limits.max_texture_dimension_3d
    } else {
        w.max(h) <= limits.max_texture_dimension_2d && d <= limits.max_texture_array_layers
    };
    if fits {
        Ok(())
    } else {
        Err(GpuError::Limits(format!(
            "{} texture '{}' of {w}×{h}×{d} texels; the device allows {} (3D), {} (2D), \
             {} array layers",
            if data.three_d { "3D" } else { "2D array" },
            data.name,
            limits.max_texture_dimension_3d,
            limits.max_texture_dimension_2d,
            limits.max_texture_array_layers
        )))
    }
}

/// Creates a filterable f16 texture (R16Float, Rg16Float or Rgba16Float by channel count)
/// holding `data`, and its view (3D, or 2D array over the depth).
fn upload(context: &GpuContext, data: &TextureData) -> wgpu::TextureView {
    let name = data.name.as_str();
    let dimension = if data.three_d {
        wgpu::TextureDimension::D3
    } else {
        wgpu::TextureDimension::D2
    };
    let format = match data.channels {
        1 => wgpu::TextureFormat::R16Float,
        2 => wgpu::TextureFormat::Rg16Float,
        _ => wgpu::TextureFormat::Rgba16Float,
    };
    let [width, height, depth] = data.size;
    let size = wgpu::Extent3d {
        width,
        height,
        depth_or_array_layers: depth,
    };
    let texture = context.device.create_texture(&wgpu::TextureDescriptor {
        label: Some(name),
        size,
        mip_level_count: 1,
        sample_count: 1,
        dimension,
        format,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    });
    let bits: Vec<u16> = data.texels.iter().map(|t| t.to_bits()).collect();
    context.queue.write_texture(
        wgpu::TexelCopyTextureInfo {
            texture: &texture,
            mip_level: 0,
            origin: wgpu::Origin3d::ZERO,
            aspect: wgpu::TextureAspect::All,
        },
        bytemuck::cast_slice(&bits),
        wgpu::TexelCopyBufferLayout {
            offset: 0,
            bytes_per_row: Some(width * data.channels * 2),
            rows_per_image: Some(height),
        },
        size,
    );
    texture.create_view(&wgpu::TextureViewDescriptor {
        label: Some(name),
        dimension: Some(match dimension {
            wgpu::TextureDimension::D3 => wgpu::TextureViewDimension::D3,
            _ => wgpu::TextureViewDimension::D2Array,
        }),
        ..Default::default()
    })
}
