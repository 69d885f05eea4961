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
/// Bindings in the material's group: the table's sampler (3), its textures (4–7), the
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
    /// The table; holding it keeps the file's load alive for the sub-assets above.
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

    /// The material of the table at `path` (an asset path, e.g. `"tables/velvet.exr"`), by
    /// its labeled sub-assets: usable at once, drawn when the table has loaded.
    pub fn load(asset_server: &AssetServer, path: &str) -> Self {
        let label = |name: &str| format!("{path}#{name}");
        // Loading the table as a `ClothTable` first picks clothbake's loader for the file
        // (Bevy's EXR image loader may claim the extension too); the labeled loads below
        // share that load.
        let table: Handle<ClothTable> = asset_server.load(path.to_string());
        Self {
            binding4: asset_server.load(label("binding4")),
            binding5: asset_server.load(label("binding5")),
            binding6: asset_server.load(label("binding6")),
            binding7: asset_server.load(label("binding7")),
            albedo: asset_server.load(label("albedo")),
            sampling: asset_server.load(label("sampling")),
            shader: asset_server.load(label("shader")),
            table,
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
