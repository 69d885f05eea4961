//! Tables (`clothbake::table`, `clothbake::formats::table_exr`, `clothbake::bake`): the CPU lookup
//! of every layout, bakes, the EXR files, the default tables' accuracy against the direct
//! evaluation, and the lookup's translations to other shading languages.
//!
//! One binary per part of the crate, each module a former test file: each integration-test
//! binary is another release link of the whole crate with wgpu, naga, exr and ash.

#[path = "../common/mod.rs"]
mod common;

mod accuracy;
mod shader_language;
mod table;
