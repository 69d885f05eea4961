//! The bake manifest, `manifest.bin` beside the tables (bincode): for each table, the hash
//! of what it was baked from (see [`crate::formats::table_exr::expected_hash`]), how long it took
//! and its measured error, so that an unchanged fabric is not baked again and `check` can
//! report the bake time.

use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// File name of the manifest inside a table directory.
pub const FILE_NAME: &str = "manifest.bin";
/// Largest manifest read: entries are ~200 bytes, so this holds tens of thousands.
pub const MAX_MANIFEST_BYTES: u64 = 8 << 20;

/// What one table was baked from and what it cost.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Entry {
    pub hash: String,
    pub layout: String,
    pub resolution: u32,
    pub bake_seconds: f64,
    pub threads: usize,
    /// Relative RMS on uniform and on highlight pairs, when the bake measured it.
    pub error: Option<(f64, f64)>,
}

/// Table file name → entry, sorted so the file's bytes are deterministic.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Manifest {
    pub tables: BTreeMap<String, Entry>,
}

fn path_in(directory: &Path) -> PathBuf {
    directory.join(FILE_NAME)
}

impl Manifest {
    /// The manifest of `directory`; empty if there is none or it cannot be read (a damaged
    /// manifest only costs a re-bake, so it is not an error).
    pub fn load(directory: &Path) -> Self {
        let path = path_in(directory);
        let small = std::fs::metadata(&path).is_ok_and(|m| m.len() <= MAX_MANIFEST_BYTES);
        let bytes = if small {
            std::fs::read(&path).ok()
        } else {
            None
        };
        bytes
            .and_then(|b| bincode::serde::decode_from_slice(&b, bincode::config::standard()).ok())
            .map(|(manifest, _)| manifest)
            .unwrap_or_default()
    }

    /// Writes the manifest atomically (temporary file, then rename).
    pub fn save(&self, directory: &Path) -> std::io::Result<()> {
        let bytes = bincode::serde::encode_to_vec(self, bincode::config::standard())
            .map_err(std::io::Error::other)?;
        crate::formats::atomic::write_atomically(&path_in(directory), &bytes)
    }
}

/// The manifest entry recorded for the table at `table_path`, if it matches `hash` (a
/// table replaced by hand has no entry of its own).
pub fn entry_for(table_path: &Path, hash: &str) -> Option<Entry> {
    let directory = table_path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let name = table_path.file_name()?.to_string_lossy().into_owned();
    Manifest::load(directory)
        .tables
        .remove(&name)
        .filter(|entry| entry.hash == hash)
}
