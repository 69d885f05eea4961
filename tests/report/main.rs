//! The report (`clothbake::report`, `clothbake report`).
//!
//! One binary per part of the crate, each module a former test file: each integration-test
//! binary is another release link of the whole crate with wgpu, naga, exr and ash.
#![cfg(feature = "runtime")] // the wgpu runtime: not in `--no-default-features` builds

mod render;
mod run;
mod stock;
