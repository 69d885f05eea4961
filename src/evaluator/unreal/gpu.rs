//! The Unreal unit's WGSL file (its GPU form is the stock units' [`crate::evaluator::stock::gpu`]).

use crate::shader::ShaderFile;

/// `cloth_brdf` of Unreal's cloth shading model over the stock block.
pub const FILE: ShaderFile = ShaderFile {
    name: "evaluator/unreal",
    path: "src/evaluator/unreal/unreal.wgsl",
    source: include_str!("unreal.wgsl"),
};
