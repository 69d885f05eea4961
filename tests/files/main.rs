//! File formats read as untrusted input: fabric files (`clothbake::formats::fabric_toml`),
//! environment maps with the traits of real HDR photographs (`Environment::load`) and the
//! measured samples a fit reads (`clothbake::fit::samples`).
//!
//! One binary per part of the crate, each module a former test file: each integration-test
//! binary is another release link of the whole crate with wgpu, naga, exr and ash.

#[path = "../common/mod.rs"]
mod common;

mod fabric_file;
mod hdr_photographs;
mod sample_file;
