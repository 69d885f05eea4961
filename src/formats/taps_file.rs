//! Sample taps as files: `NAME.taps` beside the table `NAME.exr` they were built from
//! ([`crate::sampling::taps`]), so that `render` and `view` read a fabric's taps instead of
//! building them again. Little-endian throughout:
//!
//! | offset | bytes | field |
//! |---|---|---|
//! | 0 | 8 | magic, `CLOTHTAP` |
//! | 8 | 4 | [`FORMAT_VERSION`] of this layout |
//! | 12 | 4 | [`TAPS_REVISION`] of the code that built the taps |
//! | 16 | 4 | samples per pixel K, 1 to [`MAX_ENVIRONMENT_SAMPLES`] |
//! | 20 | 4 | nodes over wo, [`TAP_NODES`] |
//! | 24 | 32 | SHA-256 of the table file's bytes |
//! | 56 | 32 | SHA-256 of the words that follow, as stored |
//! | 88 | 4·W | the taps' words ([`SampleTaps::words`]), W = 4·(1 + nodes·K) |
//!
//! The header names everything the taps depend on: the table (its file's bytes, so any
//! change to the table makes them stale), the sample count, and the code that built them.
//! Taps that do not match what the reader wants are [`TapsFileError::Stale`]; a file that
//! is not taps at all, or damaged, is [`TapsFileError::Invalid`]. Files are untrusted: the
//! header is checked and the file's size compared with what it announces before the words
//! are read, so a hostile header allocates nothing.
//!
//! Beside the table rather than inside its EXR: the EXR is the table, read by the Bevy
//! plugin, Python and other engines, and its bytes are what bakes compare; the taps are
//! derived from it for one renderer setting (the sample count), larger than the table, and
//! an EXR cannot hold a digest of its own bytes.

use crate::formats::atomic::write_atomically;
use crate::formats::table_exr::hex;
use crate::sampling::taps::stored::{TAPS_REVISION, TapsWordsError};
use crate::sampling::taps::{SampleTaps, TAP_NODES};
use crate::scene::MAX_ENVIRONMENT_SAMPLES;
use sha2::{Digest, Sha256};
use std::fmt;
use std::io::Read;
use std::path::{Path, PathBuf};

/// The file's first eight bytes.
pub const MAGIC: [u8; 8] = *b"CLOTHTAP";
/// Version of the layout above: raised when the header or the words' encoding changes.
pub const FORMAT_VERSION: u32 = 1;
/// Bytes before the words.
pub const HEADER_BYTES: usize = 88;
/// The extension of a taps file, which otherwise has its table's name.
pub const EXTENSION: &str = "taps";

/// The taps file of the table at `table_path`: `NAME.taps` beside `NAME.exr`.
pub fn taps_path(table_path: &Path) -> PathBuf {
    table_path.with_extension(EXTENSION)
}

/// SHA-256 of a table file's bytes: what a taps file names as its table.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TableDigest(pub [u8; 32]);

impl TableDigest {
    /// The digest of a table file's `bytes`.
    pub fn of(bytes: &[u8]) -> Self {
        Self(Sha256::digest(bytes).into())
    }
}

impl fmt::Display for TableDigest {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&hex(&self.0))
    }
}

/// What a reader wants taps built from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TapsKey {
    /// The table file's digest.
    pub table: TableDigest,
    /// Samples per pixel.
    pub samples: u32,
}

/// Why a taps file was not read or not written.
#[derive(Debug, thiserror::Error)]
pub enum TapsFileError {
    #[error("taps {path}: {source}", path = .path.display())]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("taps {path}: {message}", path = .path.display())]
    Invalid { path: PathBuf, message: String },
    #[error("taps {path}: built for {what}", path = .path.display())]
    Stale { path: PathBuf, what: String },
}

impl TapsFileError {
    /// Whether the file is sound but built from something else than what was asked for.
    pub fn is_stale(&self) -> bool {
        matches!(self, Self::Stale { .. })
    }
}

/// The bytes of a taps file holding `taps`, built from the table file whose digest is
/// `table`.
pub fn taps_bytes(table: &TableDigest, taps: &SampleTaps) -> Vec<u8> {
    let words: Vec<u8> = taps.words().iter().flat_map(|w| w.to_le_bytes()).collect();
    let mut bytes = Vec::with_capacity(HEADER_BYTES + words.len());
    bytes.extend_from_slice(&MAGIC);
    for field in [
        FORMAT_VERSION,
        TAPS_REVISION,
        taps.samples(),
        TAP_NODES as u32,
    ] {
        bytes.extend_from_slice(&field.to_le_bytes());
    }
    bytes.extend_from_slice(&table.0);
    bytes.extend_from_slice(&Sha256::digest(&words));
    bytes.extend_from_slice(&words);
    bytes
}

/// Writes `taps`, built from the table file whose digest is `table`, to `path` atomically.
pub fn write_taps(
    path: &Path,
    table: &TableDigest,
    taps: &SampleTaps,
) -> Result<(), TapsFileError> {
    write_atomically(path, &taps_bytes(table, taps)).map_err(|source| TapsFileError::Io {
        path: path.to_path_buf(),
        source,
    })
}

/// Reads the taps at `path` if they were built as `key` asks, by this version of the
/// builder: [`TapsFileError::Stale`] if they were built from another table, for another
/// sample count or by other code; [`TapsFileError::Invalid`] if the file is not a sound
/// taps file.
pub fn read_taps(path: &Path, key: &TapsKey) -> Result<SampleTaps, TapsFileError> {
    let io = |source| TapsFileError::Io {
        path: path.to_path_buf(),
        source,
    };
    let mut file = std::fs::File::open(path).map_err(io)?;
    let size = file.metadata().map_err(io)?.len();
    if size < HEADER_BYTES as u64 {
        return Err(invalid(
            path,
            format!("is {size} bytes, shorter than the {HEADER_BYTES}-byte header"),
        ));
    }
    let mut header = [0u8; HEADER_BYTES];
    file.read_exact(&mut header).map_err(io)?;
    let words = check_header(path, &header, key)?;
    let expected = HEADER_BYTES as u64 + 4 * words as u64;
    if size != expected {
        return Err(invalid(
            path,
            format!("is {size} bytes, its header announces {expected} (truncated or extended)"),
        ));
    }
    // The size matches the header, whose sample count is bounded: no more than the taps
    // of the most samples are allocated.
    let mut body = Vec::with_capacity(4 * words);
    file.take(4 * words as u64)
        .read_to_end(&mut body)
        .map_err(io)?;
    if body.len() != 4 * words {
        return Err(invalid(path, "changed while it was read".into()));
    }
    let checksum: [u8; 32] = Sha256::digest(&body).into();
    if checksum[..] != header[56..88] {
        return Err(invalid(
            path,
            "the words' checksum does not match the header's: the words are damaged".into(),
        ));
    }
    let words = body
        .chunks_exact(4)
        .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        .collect();
    SampleTaps::from_words(key.samples, words)
        .map_err(|e: TapsWordsError| invalid(path, format!("words: {e}")))
}

fn invalid(path: &Path, message: String) -> TapsFileError {
    TapsFileError::Invalid {
        path: path.to_path_buf(),
        message,
    }
}

fn field(header: &[u8; HEADER_BYTES], offset: usize) -> u32 {
    u32::from_le_bytes([
        header[offset],
        header[offset + 1],
        header[offset + 2],
        header[offset + 3],
    ])
}

/// The number of words the file must hold, once its header is sound and matches `key`.
fn check_header(
    path: &Path,
    header: &[u8; HEADER_BYTES],
    key: &TapsKey,
) -> Result<usize, TapsFileError> {
    if header[..8] != MAGIC {
        return Err(invalid(path, "is not a taps file (wrong magic)".into()));
    }
    let (version, revision, samples, nodes) = (
        field(header, 8),
        field(header, 12),
        field(header, 16),
        field(header, 20),
    );
    if !(1..=MAX_ENVIRONMENT_SAMPLES).contains(&samples) {
        return Err(invalid(
            path,
            format!("field samples is {samples}, outside 1..={MAX_ENVIRONMENT_SAMPLES}"),
        ));
    }
    let stale = |what: String| TapsFileError::Stale {
        path: path.to_path_buf(),
        what,
    };
    if version != FORMAT_VERSION {
        return Err(stale(format!(
            "file format {version} (this version reads {FORMAT_VERSION})"
        )));
    }
    if revision != TAPS_REVISION || nodes != TAP_NODES as u32 {
        return Err(stale(format!(
            "taps revision {revision} with {nodes} nodes (this version builds revision \
             {TAPS_REVISION} with {TAP_NODES})"
        )));
    }
    if header[24..56] != key.table.0 {
        return Err(stale(format!(
            "another table (its file's SHA-256 {}, this table's {})",
            hex(&header[24..56]),
            key.table
        )));
    }
    if samples != key.samples {
        return Err(stale(format!(
            "{samples} samples per pixel, not {}",
            key.samples
        )));
    }
    SampleTaps::word_count(samples)
        .ok_or_else(|| invalid(path, format!("field samples {samples} is too large")))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Taps for one sample per pixel whose words are a pattern, not built (the format does
    /// not care what the words mean).
    fn synthetic_taps(samples: u32) -> SampleTaps {
        let count = SampleTaps::word_count(samples).unwrap();
        let mut words: Vec<u32> = (0..count as u32)
            .map(|i| i.wrapping_mul(2_654_435_761))
            .collect();
        words[0] = samples;
        words[1] = 0.75f32.to_bits();
        SampleTaps::from_words(samples, words).unwrap()
    }

    fn key(samples: u32) -> TapsKey {
        TapsKey {
            table: TableDigest::of(b"a table file"),
            samples,
        }
    }

    fn scratch(name: &str) -> (tempfile::TempDir, PathBuf) {
        let dir = tempfile::Builder::new()
            .prefix("clothbake-taps-file-")
            .tempdir()
            .unwrap();
        let path = dir.path().join(name);
        (dir, path)
    }

    #[test]
    fn taps_read_back_bit_identical_and_only_for_their_table_and_sample_count() {
        let (_dir, path) = scratch("velvet.taps");
        let taps = synthetic_taps(2);
        write_taps(&path, &key(2).table, &taps).unwrap();
        assert_eq!(
            std::fs::metadata(&path).unwrap().len(),
            (HEADER_BYTES + 4 * taps.words().len()) as u64
        );
        assert_eq!(read_taps(&path, &key(2)).unwrap(), taps);

        let other_table = TapsKey {
            table: TableDigest::of(b"another table file"),
            ..key(2)
        };
        let error = read_taps(&path, &other_table).unwrap_err();
        assert!(
            error.is_stale() && error.to_string().contains("another table"),
            "{error}"
        );
        let error = read_taps(&path, &key(3)).unwrap_err();
        assert!(
            error.is_stale() && error.to_string().contains("2 samples per pixel, not 3"),
            "{error}"
        );
        // Taps of an earlier builder, or of another layout of the file, are stale too.
        let bytes = std::fs::read(&path).unwrap();
        for (offset, what) in [(8, "file format"), (12, "taps revision")] {
            let mut other = bytes.clone();
            other[offset..offset + 4].copy_from_slice(&999u32.to_le_bytes());
            std::fs::write(&path, &other).unwrap();
            let error = read_taps(&path, &key(2)).unwrap_err();
            assert!(
                error.is_stale() && error.to_string().contains(what),
                "{error}"
            );
        }
    }

    /// Damaged and hostile files are refused with what is wrong, before anything sized by
    /// the file is allocated, and never taken for taps.
    #[test]
    fn damaged_and_hostile_files_are_refused_by_name() {
        let (_dir, path) = scratch("linen.taps");
        let good = taps_bytes(&key(1).table, &synthetic_taps(1));
        let patched = |offset: usize, value: u32| {
            let mut bytes = good.clone();
            bytes[offset..offset + 4].copy_from_slice(&value.to_le_bytes());
            bytes
        };
        let mut flipped = good.clone();
        flipped[HEADER_BYTES + 1000] ^= 0x10;
        let mut wrong_magic = good.clone();
        wrong_magic[0] = b'X';
        let mut extended = good.clone();
        extended.extend_from_slice(&[0; 16]);
        let mut bad_scale = good.clone();
        bad_scale[HEADER_BYTES + 4..HEADER_BYTES + 8]
            .copy_from_slice(&f32::NAN.to_bits().to_le_bytes());
        let checksum: [u8; 32] = Sha256::digest(&bad_scale[HEADER_BYTES..]).into();
        bad_scale[56..88].copy_from_slice(&checksum);
        let cases: Vec<(&str, Vec<u8>, &str)> = vec![
            ("empty", Vec::new(), "shorter than"),
            ("header only, cut", good[..40].to_vec(), "shorter than"),
            (
                "words truncated",
                good[..good.len() - 3].to_vec(),
                "truncated",
            ),
            ("extended", extended, "truncated or extended"),
            ("wrong magic", wrong_magic, "wrong magic"),
            ("no samples", patched(16, 0), "field samples is 0"),
            ("absurd samples", patched(16, u32::MAX), "field samples"),
            ("flipped word", flipped, "damaged"),
            ("scale not finite", bad_scale, "weight scale"),
        ];
        for (label, bytes, needle) in cases {
            std::fs::write(&path, &bytes).unwrap();
            let error = read_taps(&path, &key(1)).unwrap_err();
            let text = error.to_string();
            assert!(
                !error.is_stale() && text.contains(needle) && text.contains("linen.taps"),
                "{label}: {text}"
            );
        }
        let error = read_taps(&path.with_file_name("absent.taps"), &key(1)).unwrap_err();
        assert!(matches!(error, TapsFileError::Io { .. }), "{error}");
    }

    #[test]
    fn a_tables_taps_file_is_beside_it_with_its_name() {
        assert_eq!(
            taps_path(Path::new("tables/velvet.exr")),
            Path::new("tables/velvet.taps")
        );
    }
}
