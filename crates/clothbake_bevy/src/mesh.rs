//! Clothbake meshes as Bevy meshes.

use bevy::asset::RenderAssetUsages;
use bevy::mesh::{Indices, PrimitiveTopology};
use bevy::prelude::*;

/// A Bevy triangle mesh of `mesh` with positions, normals, UVs and tangents: the tangent
/// (w = +1) is thread 1, so Bevy's bitangent sign·(n × t) is thread 2, as in docs/model.md's
/// frame (x = thread 1, y = n × x).
pub fn cloth_mesh(mesh: &clothbake::scene::mesh::Mesh) -> Mesh {
    let vertices = &mesh.vertices;
    Mesh::new(
        PrimitiveTopology::TriangleList,
        RenderAssetUsages::RENDER_WORLD,
    )
    .with_inserted_attribute(
        Mesh::ATTRIBUTE_POSITION,
        vertices.iter().map(|v| v.position).collect::<Vec<_>>(),
    )
    .with_inserted_attribute(
        Mesh::ATTRIBUTE_NORMAL,
        vertices.iter().map(|v| v.normal).collect::<Vec<_>>(),
    )
    .with_inserted_attribute(
        Mesh::ATTRIBUTE_UV_0,
        vertices.iter().map(|v| v.uv).collect::<Vec<_>>(),
    )
    .with_inserted_attribute(
        Mesh::ATTRIBUTE_TANGENT,
        vertices
            .iter()
            .map(|v| [v.tangent[0], v.tangent[1], v.tangent[2], 1.0])
            .collect::<Vec<_>>(),
    )
    .with_inserted_indices(Indices::U32(mesh.indices.clone()))
}
