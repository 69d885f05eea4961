//! Sampling and environment light on the CPU: the fabric sampler (`clothbake::sampling`)
//! and environment maps (`clothbake::lighting`).
//!
//! One binary per part of the crate, each module a former test file: each integration-test
//! binary is another release link of the whole crate with wgpu, naga, exr and ash.

#[path = "../common/chi2.rs"]
mod chi2;
#[path = "../common/mod.rs"]
mod common;

mod bright_sources;
mod environment;
mod sampler;
