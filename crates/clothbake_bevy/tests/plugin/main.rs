//! The plugin in Bevy: table files through Bevy's asset loader, a headless app's render
//! against `clothbake render`, and the `drape` example under Xvfb.
//!
//! One binary, each module a former test file: every integration-test binary is another
//! release link of Bevy and the core.

#[path = "../common/mod.rs"]
mod common;

mod bindings;
mod example;
mod headless;
mod loader;
