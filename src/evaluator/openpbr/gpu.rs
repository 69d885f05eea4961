//! The OpenPBR unit's WGSL file (its GPU form is the stock units' [`crate::evaluator::stock::gpu`]).

use crate::shader::ShaderFile;

/// `cloth_brdf` of open_pbr_surface over the stock block.
pub const FILE: ShaderFile = ShaderFile {
    name: "evaluator/openpbr",
    path: "src/evaluator/openpbr/openpbr.wgsl",
    source: include_str!("openpbr.wgsl"),
};
