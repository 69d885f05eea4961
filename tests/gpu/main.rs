//! The wgpu runtime on a device: the WGSL evaluations (direct, resonant, lookup, sampler)
//! against the CPU's, the GLSL translation dispatched through Vulkan, the renderer, and
//! `clothbake view` under Xvfb.
//!
//! Needs a wgpu adapter; without a GPU, Mesa's lavapipe (`apt-get install -y
//! mesa-vulkan-drivers libvulkan1`). No adapter is a failure, not a skip. Each test makes its
//! own device; the harness runs as many tests at once as there are cores, as it did in each
//! of the former binaries.
//!
//! One binary per part of the crate, each module a former test file: each integration-test
//! binary is another release link of the whole crate with wgpu, naga, exr and ash.
#![cfg(feature = "runtime")] // the wgpu runtime: not in `--no-default-features` builds

#[path = "../common/chi2.rs"]
mod chi2;
#[path = "../common/mod.rs"]
mod common;

mod editor;
mod export_threejs;
mod glsl_vulkan;
mod lookup;
mod paper;
mod render;
mod render_environment;
mod resonant;
mod sampler;
mod view;
