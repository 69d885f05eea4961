//! The glTF unit's WGSL file (its GPU form is the stock units' [`crate::evaluator::stock::gpu`]).

use crate::shader::ShaderFile;

/// `cloth_brdf` of the glTF material over the stock block.
pub const FILE: ShaderFile = ShaderFile {
    name: "evaluator/gltf",
    path: "src/evaluator/gltf/gltf.wgsl",
    source: include_str!("gltf.wgsl"),
};
