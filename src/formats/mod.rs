//! File formats: everything clothbake reads from or writes to disk besides images, each read
//! as untrusted input (sizes checked before allocating, the wrong field named).
//!
//! - [`table_exr`]: baked tables as OpenEXR files, written atomically, with a texel hash.
//! - [`taps_file`]: a table's sample taps for environment light, beside its EXR.
//! - [`fabric_toml`]: fabric files and the built-in measured fabrics.
//! - [`environment_map`]: equirectangular environment maps, Radiance `.hdr` and OpenEXR.
//! - [`wif`] and [`draft_source`]: weave drafts, WIF 1.1 files and named weaves.
//! - [`json_lines`]: the JSON-lines streams of `clothbake eval` and `clothbake sample`.
//! - [`atomic`]: every file written whole or not at all.

pub mod atomic;
pub mod draft_source;
pub mod environment_map;
pub mod export;
pub mod fabric_toml;
pub mod json_lines;
pub mod table_exr;
pub mod taps_file;
pub mod wif;
