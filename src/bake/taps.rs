//! A baked table's sample taps kept beside it (`NAME.taps`, [`crate::formats::taps_file`]):
//! `bake` stores them with each table, and `render` and `view` read them
//! ([`table_taps`]) instead of building them at every start. Taps that were built from
//! another table file, for another sample count or by other code are never used: they are
//! built again and stored over the old ones, and the caller is told why.

use crate::formats::table_exr::{
    TableFileError, expected_hash, fabric_table_file, read_table_bytes, table_file_bytes,
};
use crate::formats::taps_file::TapsFileError;
use crate::formats::taps_file::{TableDigest, TapsKey, read_taps, taps_path, write_taps};
use crate::measure::accuracy::lookup_batch_f64;
use crate::model::Fabric;
use crate::sampling::Sampler;
use crate::sampling::taps::SampleTaps;
use crate::table::Table;
use crate::table::progress::BakeProgress;
use std::fmt;
use std::path::{Path, PathBuf};

/// Where a table's taps came from.
#[derive(Clone, Debug, PartialEq)]
pub enum TapsOrigin {
    /// Read from the taps file at `path`.
    Loaded { path: PathBuf },
    /// Built from the table, because the file at `path` was absent (`reason` None) or not
    /// usable (`reason` says why), then written there (`stored` Ok) or not (why).
    Built {
        path: PathBuf,
        reason: Option<String>,
        stored: Result<(), String>,
    },
}

impl TapsOrigin {
    /// Whether the taps were read rather than built.
    pub fn loaded(&self) -> bool {
        matches!(self, Self::Loaded { .. })
    }
}

impl fmt::Display for TapsOrigin {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Loaded { path } => write!(f, "loaded from {}", path.display()),
            Self::Built {
                path,
                reason,
                stored,
            } => {
                match reason {
                    None => write!(f, "built (no {} yet)", path.display())?,
                    Some(reason) => write!(f, "built ({reason})")?,
                }
                match stored {
                    Ok(()) => write!(f, ", stored in {}", path.display()),
                    Err(why) => write!(f, ", not stored ({why})"),
                }
            }
        }
    }
}

/// The taps of `table` for `samples` per pixel, as the `table` evaluator's
/// `FabricEvaluator::sample_taps` builds them from its own sampler (F by the table's f64
/// batch lookup, strata of `Sampler::for_table`), telling `progress` of each node done;
/// `None` once `progress` says it is cancelled.
pub fn build_table_taps(
    table: &Table,
    samples: u32,
    progress: &dyn BakeProgress,
) -> Option<SampleTaps> {
    if progress.cancelled() {
        return None;
    }
    let sampler = Sampler::for_table(table);
    SampleTaps::build_cancellable(
        &sampler,
        samples,
        |pairs, out| lookup_batch_f64(table, pairs, out),
        progress,
    )
}

/// The sample taps for `samples` per pixel of the table file at `table_path`: read from
/// its taps file (`NAME.taps` beside `NAME.exr`) when that was built from exactly this
/// file's bytes, for this sample count, by this version's builder; else built from the
/// table (parsed from the same bytes that were digested) and written there atomically, or
/// only returned where the directory is not writable. A damaged, foreign or stale taps
/// file costs a rebuild, never an error; the error is the table's own.
pub fn table_taps(
    table_path: &Path,
    samples: u32,
) -> Result<(SampleTaps, TapsOrigin), TableFileError> {
    let bytes = table_file_bytes(table_path)?;
    let key = TapsKey {
        table: TableDigest::of(&bytes),
        samples,
    };
    let path = taps_path(table_path);
    let reason = match read_taps(&path, &key) {
        Ok(taps) => return Ok((taps, TapsOrigin::Loaded { path })),
        Err(TapsFileError::Io { source, .. }) if source.kind() == std::io::ErrorKind::NotFound => {
            None
        }
        Err(error) => Some(error.to_string()),
    };
    let table = read_table_bytes(&bytes, table_path)?.table;
    let taps = SampleTaps::for_table(&table, &Sampler::for_table(&table), samples);
    let stored = write_taps(&path, &key.table, &taps).map_err(|e| e.to_string());
    Ok((
        taps,
        TapsOrigin::Built {
            path,
            reason,
            stored,
        },
    ))
}

/// The taps stored beside `fabric`'s table in the tables directory `tables`, where both
/// are there and current: the table file's provenance is `fabric`'s (at the layout and
/// resolution it records) and the taps were built from exactly its bytes for `samples`.
/// Nothing is built or written: `None` costs the caller a build of its own.
pub fn stored_fabric_taps(tables: &Path, fabric: &Fabric, samples: u32) -> Option<SampleTaps> {
    let path = tables.join(fabric_table_file(&fabric.name));
    let bytes = table_file_bytes(&path).ok()?;
    let file = read_table_bytes(&bytes, &path).ok()?;
    let hash = expected_hash(fabric, file.table.layout, file.table.resolution);
    if file.hash != hash {
        return None;
    }
    let key = TapsKey {
        table: TableDigest::of(&bytes),
        samples,
    };
    read_taps(&taps_path(&path), &key).ok()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::evaluator::FabricEvaluator;
    use crate::evaluator::table::TableEvaluation;
    use crate::formats::fabric_toml::FabricSet;
    use crate::formats::table_exr::write_table;
    use crate::table::Layout;

    /// A small grid4d table of built-in fabric `index` (cheap to bake and to look up).
    fn small_table(index: usize) -> Table {
        let fabric = FabricSet::builtin().fabrics()[index].clone();
        crate::bake::bake(&fabric, Layout::GRID4D, 4, &|| {}).unwrap()
    }

    /// Taps are built and stored once, then read back bit-identical to what the table
    /// evaluator builds; a changed table, another sample count or a damaged file makes them
    /// built again (with the reason) and stored over the old ones.
    #[test]
    fn taps_are_stored_once_then_read_and_rebuilt_when_they_do_not_match() {
        let dir = tempfile::Builder::new()
            .prefix("clothbake-table-taps-")
            .tempdir()
            .unwrap();
        let table_path = dir.path().join("velvet.exr");
        let table = small_table(0);
        write_table(&table_path, &table).unwrap();
        let samples = 4;

        let (built, origin) = table_taps(&table_path, samples).unwrap();
        assert!(
            matches!(
                &origin,
                TapsOrigin::Built {
                    reason: None,
                    stored: Ok(()),
                    ..
                }
            ),
            "{origin}"
        );
        let (loaded, origin) = table_taps(&table_path, samples).unwrap();
        assert!(origin.loaded(), "{origin}");
        assert_eq!(loaded, built);
        let evaluation = TableEvaluation { table };
        assert_eq!(
            loaded.words(),
            evaluation
                .sample_taps(&evaluation.sampler(), samples)
                .words()
        );

        // Another sample count: built again and stored in place of the old ones.
        let (other, origin) = table_taps(&table_path, samples + 1).unwrap();
        assert!(
            !origin.loaded() && origin.to_string().contains("not 5"),
            "{origin}"
        );
        assert_eq!(other.samples(), samples + 1);
        assert!(table_taps(&table_path, samples + 1).unwrap().1.loaded());

        // Another table in the same file: the taps name the old file's bytes.
        write_table(&table_path, &small_table(1)).unwrap();
        let (_, origin) = table_taps(&table_path, samples + 1).unwrap();
        assert!(origin.to_string().contains("another table"), "{origin}");

        // A damaged file is built again, not an error.
        let taps_file = dir.path().join("velvet.taps");
        let bytes = std::fs::read(&taps_file).unwrap();
        std::fs::write(&taps_file, &bytes[..bytes.len() / 2]).unwrap();
        let (_, origin) = table_taps(&table_path, samples + 1).unwrap();
        assert!(origin.to_string().contains("truncated"), "{origin}");
        assert!(table_taps(&table_path, samples + 1).unwrap().1.loaded());
    }

    /// The table's own errors are errors: a missing or damaged table gives no taps.
    #[test]
    fn a_missing_or_damaged_table_is_an_error_naming_it() {
        let dir = tempfile::Builder::new()
            .prefix("clothbake-table-taps-bad-")
            .tempdir()
            .unwrap();
        let path = dir.path().join("silk.exr");
        let error = table_taps(&path, 4).unwrap_err();
        assert!(error.to_string().contains("silk.exr"), "{error}");
        std::fs::write(&path, b"not an EXR").unwrap();
        let error = table_taps(&path, 4).unwrap_err();
        assert!(error.to_string().contains("silk.exr"), "{error}");
        assert!(!dir.path().join("silk.taps").exists());
    }

    /// A cancelled build stops and gives nothing; one that is not gives the taps the table
    /// evaluator builds.
    #[test]
    fn a_cancelled_build_gives_no_taps() {
        struct Cancelled;
        impl BakeProgress for Cancelled {
            fn row_done(&self) {}
            fn cancelled(&self) -> bool {
                true
            }
        }
        let table = small_table(2);
        assert!(build_table_taps(&table, 2, &Cancelled).is_none());
        let rows = std::sync::atomic::AtomicU64::new(0);
        let counted = || {
            rows.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        };
        let taps = build_table_taps(&table, 2, &counted).unwrap();
        assert_eq!(
            rows.load(std::sync::atomic::Ordering::Relaxed),
            crate::sampling::taps::TAP_NODES as u64
        );
        assert_eq!(
            taps,
            SampleTaps::for_table(&table, &Sampler::for_table(&table), 2)
        );
    }

    /// The editor's start: a fabric's stored taps are found only for that fabric as its
    /// table was baked, and for the sample count they were built for.
    #[test]
    fn a_fabric_s_stored_taps_are_found_only_while_current() {
        let dir = tempfile::Builder::new()
            .prefix("clothbake-fabric-taps-")
            .tempdir()
            .unwrap();
        let fabric = FabricSet::builtin().fabrics()[0].clone();
        let table_path = dir.path().join(fabric_table_file(&fabric.name));
        write_table(&table_path, &small_table(0)).unwrap();
        let samples = 4;
        assert_eq!(stored_fabric_taps(dir.path(), &fabric, samples), None);
        let (built, _) = table_taps(&table_path, samples).unwrap();
        assert_eq!(
            stored_fabric_taps(dir.path(), &fabric, samples),
            Some(built)
        );
        assert_eq!(stored_fabric_taps(dir.path(), &fabric, samples + 1), None);
        let mut edited = fabric.clone();
        edited.thread1.coverage *= 0.5;
        assert_eq!(stored_fabric_taps(dir.path(), &edited, samples), None);
    }
}
