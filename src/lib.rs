//! clothbake: the Sadeghi et al. 2013 microcylinder cloth model, evaluated directly and
//! baked into lookup tables for real-time shading. `docs/architecture.md` is the map.
//!
//! [`gpu`], [`render`], [`report`] and [`viewer`] (and wgpu) come with the default cargo
//! feature `runtime`; without it the crate is the core, for an engine with its own wgpu.
//!
//! - [`model`]: the physics of `docs/model.md`, pure maths, no I/O.
//! - [`table`]: table layouts and the lookup that GPU shaders mirror.
//! - [`bake`]: integrates the model into a table (rayon); [`bake::job`]: the `bake`
//!   command's choice of layout and resolution, its manifest and files.
//! - [`formats`]: files read and written (table EXR, fabric TOML, environment maps, JSON
//!   lines), all read as untrusted input.
//! - [`evaluator`]: the ways F is evaluated (direct, paper, resonant, a table), one unit each
//!   behind one interface and registry, with one spelling on every command.
//! - [`measure`]: a table's error against the direct evaluation, on seeded direction pairs.
//! - [`scene`]: what a scene shows and needs baked (fabrics, camera, lights, mesh, budget).
//! - [`lighting`]: distant environment light: maps, their mip chain, the built-in studio.
//! - [`sampling`]: importance sampling of a fabric (CPU;
//!   `shaders/sampling/fabric_sampler.wgsl` mirrors it) and of an environment map.
//! - [`shader`]: the one WGSL composer: the registry of `shaders/` and the modules every
//!   shader is composed of, each file declaring what it requires.
//! - [`gpu`]: the wgpu runtime core: a device, and tables and the model as GPU BRDFs.
//! - [`render`]: cloth rendered with a GPU BRDF, headless or into a window; the CPU
//!   reference of the same view and image error metrics.
//! - [`report`]: `clothbake report`, speed against error for every fabric.
//! - [`viewer`]: `clothbake view`, the interactive window (winit).
//! - [`weave`]: a fabric from a weave draft (named weaves and WIF files) and yarn knobs.

pub mod bake;
pub mod editor;
pub mod evaluator;
pub mod export;
pub mod fit;
pub mod formats;
#[cfg(feature = "runtime")]
pub mod gpu;
pub mod lighting;
pub mod measure;
pub mod model;
#[cfg(feature = "runtime")]
pub mod render;
#[cfg(feature = "runtime")]
pub mod report;
pub mod sampling;
pub mod scene;
pub mod shader;
pub mod table;
#[cfg(feature = "runtime")]
pub mod viewer;
pub mod weave;
