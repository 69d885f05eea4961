//! [`ClothMaterial`]: a Bevy [`Material`] that shades cloth by a clothbake table.
//!
//! Every table gets its own fragment shader (the lookup is specialised: the table's constants
//! are literals), so the material's pipeline key carries the table's shader and
//! [`Material::specialize`] swaps it in for the forward pass. Prepass and shadow passes keep
//! Bevy's own shaders: cloth is opaque, and its depth is the mesh's.

use crate::table_asset::ClothTable;
use bevy::asset::uuid_handle;
use bevy::mesh::MeshVertexBufferLayoutRef;
use bevy::pbr::{MaterialPipeline, MaterialPipelineKey};
use bevy::prelude::*;
use bevy::render::render_resource::{
    AsBindGroup, RenderPipelineDescriptor, SpecializedMeshPipelineError,
};
use bevy::render::storage::ShaderBuffer;
use bevy::shader::{Shader, ShaderRef};

/// What [`ClothMaterial::fragment_shader`] names: a stand-in that `specialize` always replaces
/// by the table's shader (the pipeline cache waits for that shader to load). It draws magenta,
/// should a pipeline ever be built with it.
pub(crate) const PLACEHOLDER_SHADER: Handle<Shader> =
    uuid_handle!("5d1c3a4e-8f0b-4c6e-9a7d-2b3e4f5a6c7d");

pub(crate) const PLACEHOLDER_SOURCE: &str = "#import bevy_pbr::forward_io::VertexOutput
@fragment
fn fragment(in: VertexOutput) -> @location(0) vec4<f32> {
    return vec4<f32>(1.0, 0.0, 1.0, 1.0);
}
";

/// Importance samples per fragment of an environment map light, as `clothbake render`'s
/// default: 1.8–2.8% from a converged reference on the studio map
/// (docs/sampling.md#measured). The loader builds each table's sample taps for this many.
pub const DEFAULT_ENVIRONMENT_SAMPLES: u32 = 96;

/// Cloth shaded by a clothbake table: F(wi, wo) of the table's fabric under Bevy's
/// directional and point lights (with their shadows), its ambient light and the view's
/// environment map light, in the thread frame of the mesh's UV tangents (thread 1 along u;
/// meshes need `Mesh::ATTRIBUTE_TANGENT`).
///
/// Bindings in the material's group: the table's sampler and texture slots as clothbake
/// declares them (`clothbake::table::bindings`: the sampler at 3, the slots at 4–7; the
/// attributes below must be literals, and the plugin's tests pin them to that list), the
/// directional albedo map (8) and the fabric's sample taps (9), all sub-assets of one
/// [`ClothTable`].
#[derive(Asset, TypePath, AsBindGroup, Clone, Debug)]
#[bind_group_data(ClothMaterialKey)]
pub struct ClothMaterial {
    #[texture(4, dimension = "3d")]
    pub binding4: Handle<Image>,
    #[texture(5, dimension = "3d")]
    pub binding5: Handle<Image>,
    #[texture(6, dimension = "2d_array")]
    pub binding6: Handle<Image>,
    #[texture(7, dimension = "2d_array")]
    pub binding7: Handle<Image>,
    /// The albedo map; its sampler (linear, clamp to edge) is the table's too.
    #[texture(8)]
    #[sampler(3)]
    pub albedo: Handle<Image>,
    /// The fabric's sample taps, for environment map light.
    #[storage(9, read_only)]
    pub sampling: Handle<ShaderBuffer>,
    /// The fragment shader with the table's lookup.
    pub shader: Handle<Shader>,
    /// The table, whose sub-assets the fields above are.
    pub table: Handle<ClothTable>,
}

/// The part of the pipeline key a material sets: its table's shader.
#[derive(Clone, PartialEq, Eq, Hash)]
pub struct ClothMaterialKey {
    shader: Handle<Shader>,
}

impl From<&ClothMaterial> for ClothMaterialKey {
    fn from(material: &ClothMaterial) -> Self {
        Self {
            shader: material.shader.clone(),
        }
    }
}

impl ClothMaterial {
    /// The material of a loaded table (`handle` is `table`'s).
    pub fn from_table(handle: Handle<ClothTable>, table: &ClothTable) -> Self {
        // One handle per core slot, in slot order: a slot added to the core fails to compile
        // here until the material binds it.
        let [binding4, binding5, binding6, binding7] = table.textures.clone();
        Self {
            binding4,
            binding5,
            binding6,
            binding7,
            albedo: table.albedo.clone(),
            sampling: table.sampling.clone(),
            shader: table.shader.clone(),
            table: handle,
        }
    }

    /// The material of the table at `path` (an asset path, e.g. `"tables/velvet.exr"`): usable
    /// at once, drawn once the table has loaded and [`crate::ClothPlugin`] has bound its
    /// sub-assets.
    pub fn load(asset_server: &AssetServer, path: &str) -> Self {
        // Only the table is loaded: Bevy loads the whole file again for every labeled
        // sub-asset asked for by path before the file has loaded (bevyengine/bevy#10549), and
        // each load builds the sample taps and the albedo map.
        Self {
            binding4: PENDING_IMAGE,
            binding5: PENDING_IMAGE,
            binding6: PENDING_IMAGE,
            binding7: PENDING_IMAGE,
            albedo: PENDING_IMAGE,
            sampling: PENDING_BUFFER,
            shader: PENDING_SHADER,
            table: asset_server.load(path.to_string()),
        }
    }

    /// Whether the table's sub-assets are still to be bound (the material was made by
    /// [`ClothMaterial::load`] and its table has not loaded yet).
    pub fn is_pending(&self) -> bool {
        self.shader == PENDING_SHADER
    }
}

/// What a pending material binds: handles of assets that never exist, so that Bevy retries
/// its bind group (and builds no pipeline) until [`bind_loaded_tables`] replaces them.
const PENDING_IMAGE: Handle<Image> = uuid_handle!("0b6f2d4e-3c1a-4e8b-9f7d-6a5c4b3e2d1f");
const PENDING_BUFFER: Handle<ShaderBuffer> = uuid_handle!("1c7a3e5f-4d2b-4f9c-8e6a-7b6d5c4f3e2a");
const PENDING_SHADER: Handle<Shader> = uuid_handle!("2d8b4f6a-5e3c-4a0d-9f7b-8c7e6d5a4f3b");

/// Binds the sub-assets of every pending material whose table has loaded (a system of
/// [`crate::ClothPlugin`]). Only those materials are touched: a mutable access marks a
/// material changed and Bevy then rebuilds its bind group.
pub(crate) fn bind_loaded_tables(
    tables: Res<Assets<ClothTable>>,
    mut materials: ResMut<Assets<ClothMaterial>>,
) {
    let ready: Vec<AssetId<ClothMaterial>> = materials
        .iter()
        .filter(|(_, m)| m.is_pending() && tables.contains(&m.table))
        .map(|(id, _)| id)
        .collect();
    for id in ready {
        if let Some(mut material) = materials.get_mut(id)
            && let Some(table) = tables.get(&material.table)
        {
            *material = ClothMaterial::from_table(material.table.clone(), table);
        }
    }
}

impl Material for ClothMaterial {
    fn fragment_shader() -> ShaderRef {
        PLACEHOLDER_SHADER.into()
    }

    fn specialize(
        _pipeline: &MaterialPipeline,
        descriptor: &mut RenderPipelineDescriptor,
        _layout: &MeshVertexBufferLayoutRef,
        key: MaterialPipelineKey<Self>,
    ) -> Result<(), SpecializedMeshPipelineError> {
        // Cloth is two-sided: the shader shades the side facing the viewer, and both sides
        // cast shadows.
        descriptor.primitive.cull_mode = None;
        if let Some(fragment) = descriptor.fragment.as_mut()
            && fragment.shader == PLACEHOLDER_SHADER
        {
            fragment.shader = key.bind_group_data.shader.clone();
        }
        Ok(())
    }
}
