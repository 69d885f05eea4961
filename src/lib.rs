//! clothbake: the Sadeghi et al. 2013 microcylinder cloth model, evaluated directly and
//! baked into lookup tables for real-time shading.
//!
//! [`gpu`], [`render`], [`report`] and [`viewer`] (and wgpu) come with the default cargo
//! feature `runtime`; without it the crate is the core, for an engine with its own wgpu.
//!
//! - [`model`]: the physics of MODEL.md, pure maths.
//! - [`table`]: table layouts and the lookup that GPU shaders mirror.
//! - [`bake`]: integrates the model into a table (rayon); [`bake_job`]: the `bake` command's
//!   choice of resolution, manifest and files.
//! - [`table_file`]: tables as EXR files, written atomically, read as untrusted input.
//! - [`accuracy`]: a table's error against the direct evaluation.
//! - [`scene`], [`manifest`]: what a scene needs baked, and what was baked from what.
//! - [`gpu`]: the wgpu runtime core: a device, and tables and the direct model as GPU BRDFs.
//! - [`render`]: cloth rendered with a GPU BRDF (table lookup or direct), headless or into a
//!   window; the CPU reference of the same view and image error metrics.
//! - [`fabric_file`]: reading fabric files (TOML), the built-in measured fabrics.
//! - [`sampling`]: importance sampling of a fabric: directions with a density close to F,
//!   and that density (CPU; `shaders/sampling.wgsl` mirrors it).
//! - [`environment`]: distant environment lighting: equirectangular `.hdr`/`.exr` maps read as
//!   untrusted input, the built-in studio and white furnace, a prefiltered mip chain and the
//!   CPU mirror of its GPU sampling.
//! - [`direction_sets`]: the seeded direction pairs on which errors are measured.
//! - [`eval_stream`]: the JSON-lines evaluation interface of `clothbake eval`.
//! - [`report`]: `clothbake report`, speed against error for every fabric (Markdown, JSON,
//!   plots).
//! - [`viewer`]: `clothbake view`, the interactive window (winit): lookup or direct shading.

pub mod accuracy;
pub mod bake;
pub mod bake_job;
pub mod direction_sets;
pub mod environment;
pub mod eval_stream;
pub mod fabric_file;
#[cfg(feature = "runtime")]
pub mod gpu;
pub mod manifest;
pub mod mesh;
pub mod model;
#[cfg(feature = "runtime")]
pub mod render;
#[cfg(feature = "runtime")]
pub mod report;
pub mod sampling;
pub mod scene;
pub mod table;
pub mod table_file;
#[cfg(feature = "runtime")]
pub mod viewer;
