//! Facts about the repository's source tree that the build and the test script rely on.
//!
//! One binary per part of the crate, each module a former test file: each integration-test
//! binary is another release link of the whole crate with wgpu, naga, exr and ash.

mod feature_split;
mod file_size;
mod import_cycles;
mod links;
mod manual_figures;
mod model_purity;
mod stated_defaults;
