//! The `clothbake` binary as users and scripts run it: `fabrics`, `eval`, `sample`,
//! `albedo`, `bake`, `check`, `wgsl`, `weave`, `fit`, `export`; the editor's plots against `eval` and
//! `albedo`.
//!
//! Builds without the `runtime` feature: scripts/test.sh runs this binary a second time with
//! `--no-default-features`, against the `clothbake` binary without `render`, `view` and
//! `report` (its one test of `render`'s arguments is compiled with the runtime only). The
//! renderer and the viewer are tested in the `gpu` binary, the report in `report`.
//!
//! One binary per part of the crate, each module a former test file: each integration-test
//! binary is another release link of the whole crate with wgpu, naga, exr and ash.

#[path = "../common/mod.rs"]
mod common;

mod background;
mod bake;
mod eval;
mod export;
mod fit;
mod plots;
mod taps;
mod weave;
