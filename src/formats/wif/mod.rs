//! WIF 1.1 weave drafts (the Weaving Information File every weaving program exchanges): an
//! INI-like text of `[SECTION]`s holding `key=value` lines, read into a [`Draft`].
//!
//! What is read: `[WEAVING]` (`Shafts`, `Treadles`, `Rising Shed`), `[WARP]` and `[WEFT]`
//! (`Threads`, `Color`, `Spacing`, `Thickness`), `[THREADING]`, `[TIEUP]`, `[TREADLING]`,
//! `[LIFTPLAN]`, `[COLOR PALETTE]` (`Entries`, `Range`), `[COLOR TABLE]`, `[WARP COLORS]`,
//! `[WEFT COLORS]` and the per-thread `[WARP SPACING]`, `[WEFT SPACING]`, `[WARP THICKNESS]`
//! and `[WEFT THICKNESS]`. `[WIF]`, `[CONTENTS]`, `[TEXT]`, `[NOTES]`, `[PRIVATE …]` and any
//! other section are skipped unread, and so are unknown keys of the sections that are read.
//!
//! The text as weaving programs write it: section names and keys in any case and with spaces
//! around them, comments from a `;` (a whole line, or the rest of a value), blank lines, LF,
//! CRLF or CR line endings, a UTF-8 byte-order mark, spaces around the commas of a list, and
//! bytes that are not UTF-8 (Latin-1 from old Windows programs; [`load_wif`] converts them
//! lossily, and they only ever appear in text the reader skips).
//!
//! A crossing (end, pick) has the warp on top when a shaft the end is threaded on is lifted
//! on that pick; the lifted shafts are the pick's line of `[LIFTPLAN]` if the file has one,
//! else the union of the `[TIEUP]` lines of the pick's treadles in `[TREADLING]`. With
//! `Rising Shed=no` the tie-up or lift plan names the shafts that sink, and the end stays up
//! where none of its shafts sinks: the drawdown is the complement of the same file's with a
//! rising shed.
//!
//! What real files hold beyond the letter of the format is read too, as the spec reads it or
//! as the programs that write it mean it: a shaft or treadle number 0 in `[THREADING]`,
//! `[TIEUP]`, `[TREADLING]` or `[LIFTPLAN]` is "unused" (the spec's initial value) and is
//! dropped; `[TIEUP]` may tie treadles beyond `[WEAVING] Treadles` (Fiberworks PCW keeps the
//! tie-up of treadles the treadling never presses); and `[COLOR PALETTE] Entries` counts the
//! colours of a `[COLOR TABLE]` whose numbers may skip (1, 2 and 7 are 3 entries).
//!
//! Files are untrusted: the size is bounded before reading, every number is checked (shafts
//! within `Shafts`, the treadles of `[TREADLING]` within `Treadles`, thread numbers from 1 to
//! the count, the counts within [`MAX_THREADS`] and [`MAX_CELLS`]) before anything sized by it
//! is allocated, and an error names the file and the section and key, or the line, that is
//! wrong.

mod ini;
mod reader;
#[cfg(test)]
mod tests;

use crate::weave::Draft;
#[cfg(doc)]
use crate::weave::draft::{MAX_CELLS, MAX_THREADS};
use ini::Ini;
use reader::Reader;
use std::io::Read;
use std::path::{Path, PathBuf};

/// Largest WIF file read: a Jacquard draft of 2,000 ends and 2,000 picks written as a lift
/// plan with half its shafts lifted is about 9 MiB, so 32 MiB holds any real draft while
/// bounding what parsing allocates.
pub const MAX_WIF_BYTES: u64 = 32 << 20;

/// Largest colour palette: WIF palettes hold 256 entries or fewer in practice.
pub(crate) const MAX_PALETTE_ENTRIES: usize = 65_536;

/// Why a WIF file was rejected.
#[derive(Debug, thiserror::Error)]
pub enum WifError {
    #[error("cannot read WIF file {path}: {source}")]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("WIF file {path} is {size} bytes, larger than the {MAX_WIF_BYTES}-byte limit")]
    TooLarge { path: PathBuf, size: u64 },
    /// A line that is neither a section header, a `key=value`, a comment nor blank.
    #[error("WIF file {origin}, line {line}: {message}")]
    Line {
        origin: String,
        line: usize,
        message: String,
    },
    /// A value that is wrong where it stands.
    #[error("WIF file {origin}, [{section}] {key} (line {line}): {message}")]
    Value {
        origin: String,
        section: String,
        key: String,
        line: usize,
        message: String,
    },
    /// Something the draft needs is missing; the message names the sections and keys.
    #[error("WIF file {origin}: {message}")]
    Draft { origin: String, message: String },
}

/// Reads the WIF file at `path` (at most [`MAX_WIF_BYTES`]; bytes that are not UTF-8 are
/// replaced) and parses it with [`parse_wif`], the path naming it in errors.
pub fn load_wif(path: &Path) -> Result<Draft, WifError> {
    let io = |source| WifError::Io {
        path: path.to_path_buf(),
        source,
    };
    let too_large = |size| WifError::TooLarge {
        path: path.to_path_buf(),
        size,
    };
    let file = std::fs::File::open(path).map_err(io)?;
    let size = file.metadata().map_err(io)?.len();
    if size > MAX_WIF_BYTES {
        return Err(too_large(size));
    }
    // The file may grow between the check and the read: read one byte past the limit at most.
    let mut bytes = Vec::with_capacity(size as usize);
    file.take(MAX_WIF_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(io)?;
    if bytes.len() as u64 > MAX_WIF_BYTES {
        return Err(too_large(bytes.len() as u64));
    }
    parse_wif(
        &String::from_utf8_lossy(&bytes),
        &path.display().to_string(),
    )
}

/// Parses the text of a WIF file into its draft; `origin` names the file in errors.
pub fn parse_wif(text: &str, origin: &str) -> Result<Draft, WifError> {
    let ini = Ini::parse(text, origin)?;
    Reader { ini: &ini, origin }.draft()
}
