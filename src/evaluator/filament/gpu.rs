//! The Filament unit's WGSL file (its GPU form is the stock units' [`crate::evaluator::stock::gpu`]).

use crate::shader::ShaderFile;

/// `cloth_brdf` of Filament's cloth model over the stock block.
pub const FILE: ShaderFile = ShaderFile {
    name: "evaluator/filament",
    path: "src/evaluator/filament/filament.wgsl",
    source: include_str!("filament.wgsl"),
};
