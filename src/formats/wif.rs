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

use crate::weave::draft::{MAX_CELLS, MAX_THREADS};
use crate::weave::{Draft, Yarns};
use std::collections::BTreeMap;
use std::io::Read;
use std::path::{Path, PathBuf};

/// Largest WIF file read: a Jacquard draft of 2,000 ends and 2,000 picks written as a lift
/// plan with half its shafts lifted is about 9 MiB, so 32 MiB holds any real draft while
/// bounding what parsing allocates.
pub const MAX_WIF_BYTES: u64 = 32 << 20;

/// Largest colour palette: WIF palettes hold 256 entries or fewer in practice.
const MAX_PALETTE_ENTRIES: usize = 65_536;

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

/// The sections that are read; any other is skipped unread.
const READ_SECTIONS: [&str; 15] = [
    "WEAVING",
    "WARP",
    "WEFT",
    "THREADING",
    "TIEUP",
    "TREADLING",
    "LIFTPLAN",
    "COLOR PALETTE",
    "COLOR TABLE",
    "WARP COLORS",
    "WEFT COLORS",
    "WARP SPACING",
    "WEFT SPACING",
    "WARP THICKNESS",
    "WEFT THICKNESS",
];

/// One `key=value` line: the key as written (for errors) and the value with its comment cut.
struct Entry {
    key: String,
    value: String,
    line: usize,
}

/// A read section: its entries in file order, each key once.
#[derive(Default)]
struct Section {
    entries: Vec<Entry>,
    /// The normalised key (lower case, single spaces) of each entry, to its index.
    index: BTreeMap<String, usize>,
}

/// The read sections of a file, by normalised name (upper case, single spaces).
struct Ini {
    sections: BTreeMap<String, Section>,
}

/// Lower- or upper-cased with runs of white space made one space: ` Rising  Shed ` and
/// `rising shed` are the same key.
fn normalise(text: &str, upper: bool) -> String {
    let joined = text.split_whitespace().collect::<Vec<_>>().join(" ");
    if upper {
        joined.to_ascii_uppercase()
    } else {
        joined.to_ascii_lowercase()
    }
}

/// The lines of `text`, ended by LF, CRLF or CR.
fn split_lines(text: &str) -> Vec<&str> {
    let bytes = text.as_bytes();
    let mut lines = Vec::new();
    let (mut start, mut i) = (0, 0);
    while i < bytes.len() {
        match bytes[i] {
            b'\n' => {
                lines.push(&text[start..i]);
                i += 1;
                start = i;
            }
            b'\r' => {
                lines.push(&text[start..i]);
                i += if bytes.get(i + 1) == Some(&b'\n') {
                    2
                } else {
                    1
                };
                start = i;
            }
            _ => i += 1,
        }
    }
    if start < bytes.len() {
        lines.push(&text[start..]);
    }
    lines
}

/// `text` without a trailing `; comment`.
fn strip_comment(text: &str) -> &str {
    text.split(';').next().unwrap_or_default()
}

impl Ini {
    fn parse(text: &str, origin: &str) -> Result<Self, WifError> {
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        let line_error = |line: usize, message: String| WifError::Line {
            origin: origin.to_string(),
            line,
            message,
        };
        let mut sections: BTreeMap<String, Section> = BTreeMap::new();
        // The section the lines belong to: `None` before the first header, `Some(None)` in a
        // skipped section, `Some(Some(name))` in a read one.
        let mut current: Option<Option<String>> = None;
        for (number, raw) in split_lines(text).into_iter().enumerate() {
            let line = number + 1;
            let trimmed = raw.trim();
            if trimmed.is_empty() || trimmed.starts_with(';') {
                continue;
            }
            if trimmed.starts_with('[') {
                let header = strip_comment(trimmed).trim();
                let name = header
                    .strip_prefix('[')
                    .and_then(|h| h.strip_suffix(']'))
                    .map(|h| normalise(h, true));
                match name {
                    Some(name) if !name.is_empty() => {
                        if READ_SECTIONS.contains(&name.as_str()) {
                            // A section written twice continues the first: its keys must
                            // still be new.
                            sections.entry(name.clone()).or_default();
                            current = Some(Some(name));
                        } else {
                            current = Some(None);
                        }
                        continue;
                    }
                    // Free text of a skipped section may start with '['.
                    _ if current == Some(None) => continue,
                    _ => {
                        return Err(line_error(
                            line,
                            format!("'{trimmed}' is not a section header like [WEAVING]"),
                        ));
                    }
                }
            }
            let name = match &current {
                None => {
                    return Err(line_error(
                        line,
                        format!("'{trimmed}' comes before the first [SECTION] header"),
                    ));
                }
                Some(None) => continue,
                Some(Some(name)) => name,
            };
            let Some((key, value)) = trimmed.split_once('=') else {
                return Err(line_error(
                    line,
                    format!("'{trimmed}' in [{name}] is not a key=value line"),
                ));
            };
            let key = key.trim();
            let normalised = normalise(key, false);
            if normalised.is_empty() {
                return Err(line_error(line, format!("a line of [{name}] has no key")));
            }
            let section = sections.entry(name.clone()).or_default();
            // Duplicate keys are an error rather than "last wins": no weaving program writes
            // a key twice, so a repeated threading or treadling line is damage (a merge or a
            // hand edit gone wrong), and silently taking either line would weave another
            // cloth than the one drafted.
            if let Some(&first) = section.index.get(&normalised) {
                return Err(WifError::Value {
                    origin: origin.to_string(),
                    section: name.clone(),
                    key: key.to_string(),
                    line,
                    message: format!(
                        "the key is given twice (first on line {})",
                        section.entries[first].line
                    ),
                });
            }
            section.index.insert(normalised, section.entries.len());
            section.entries.push(Entry {
                key: key.to_string(),
                value: strip_comment(value).trim().to_string(),
                line,
            });
        }
        Ok(Self { sections })
    }
}

/// The warp or the weft, as the reader names their sections.
#[derive(Clone, Copy)]
enum Side {
    Warp,
    Weft,
}

impl Side {
    fn name(self) -> &'static str {
        match self {
            Side::Warp => "WARP",
            Side::Weft => "WEFT",
        }
    }

    fn thread(self) -> &'static str {
        match self {
            Side::Warp => "end",
            Side::Weft => "pick",
        }
    }
}

/// A colour as a file gives it: a palette index, or components in the palette's range.
#[derive(Clone, Copy)]
enum ColourRef {
    Index(usize),
    Rgb([f64; 3]),
}

/// The `[WARP]` or `[WEFT]` section.
struct FamilyHeader {
    threads: Option<usize>,
    colour: Option<(ColourRef, usize)>,
    spacing: Option<f64>,
    thickness: Option<f64>,
}

/// A numbered section's entries, by number: the parsed value and its entry.
type Numbered<'a, T> = BTreeMap<usize, (T, &'a Entry)>;

struct Reader<'a> {
    ini: &'a Ini,
    origin: &'a str,
}

impl<'a> Reader<'a> {
    fn value_error(&self, section: &str, entry: &Entry, message: String) -> WifError {
        WifError::Value {
            origin: self.origin.to_string(),
            section: section.to_string(),
            key: entry.key.clone(),
            line: entry.line,
            message,
        }
    }

    fn draft_error(&self, message: String) -> WifError {
        WifError::Draft {
            origin: self.origin.to_string(),
            message,
        }
    }

    fn section(&self, name: &str) -> Option<&'a Section> {
        self.ini.sections.get(name)
    }

    fn entry(&self, section: &str, key: &str) -> Option<&'a Entry> {
        let section = self.section(section)?;
        section.index.get(key).map(|&i| &section.entries[i])
    }

    /// A whole number within `least..=most`.
    fn count(
        &self,
        section: &str,
        entry: &Entry,
        text: &str,
        least: usize,
        most: usize,
    ) -> Result<usize, WifError> {
        let n = text.trim().parse::<u64>().map_err(|_| {
            self.value_error(
                section,
                entry,
                format!("'{text}' is not a whole number from {least} to {most}"),
            )
        })?;
        match usize::try_from(n) {
            Ok(n) if (least..=most).contains(&n) => Ok(n),
            _ => Err(self.value_error(
                section,
                entry,
                format!("{n} is not within {least}..={most}"),
            )),
        }
    }

    /// A finite number.
    fn number(&self, section: &str, entry: &Entry, text: &str) -> Result<f64, WifError> {
        match text.trim().parse::<f64>() {
            Ok(x) if x.is_finite() => Ok(x),
            _ => Err(self.value_error(
                section,
                entry,
                format!("'{}' is not a finite number", text.trim()),
            )),
        }
    }

    /// A length (spacing or thickness): finite and positive.
    fn length(&self, section: &str, entry: &Entry) -> Result<f64, WifError> {
        let x = self.number(section, entry, &entry.value)?;
        if x > 0.0 {
            Ok(x)
        } else {
            Err(self.value_error(section, entry, format!("{x} is not a positive length")))
        }
    }

    /// A comma-separated list of whole numbers within `1..=most` (empty items skipped: some
    /// programs end a list with a comma). A 0 is skipped too: WIF 1.1 gives every shaft and
    /// treadle the initial value 0, "unused", and programs write it (`3=0,2` for a pick on
    /// treadle 2 alone, or `4=0` for an end threaded on no shaft).
    fn list(
        &self,
        section: &str,
        entry: &Entry,
        most: usize,
        what: &str,
    ) -> Result<Vec<usize>, WifError> {
        let mut items = Vec::new();
        for item in entry.value.split(',').map(str::trim) {
            if item.is_empty() {
                continue;
            }
            let n = item
                .parse::<u64>()
                .ok()
                .and_then(|n| usize::try_from(n).ok());
            match n {
                Some(0) => {}
                Some(n) if (1..=most).contains(&n) => items.push(n),
                _ => {
                    return Err(self.value_error(
                        section,
                        entry,
                        format!("{what} '{item}' is not a number from 1 to {most} (or 0, unused)"),
                    ));
                }
            }
        }
        items.sort_unstable();
        items.dedup();
        Ok(items)
    }

    /// The entries of a numbered section (`N=value`, N from 1 to `most`), each value parsed.
    fn numbered<T>(
        &self,
        name: &str,
        what: &str,
        most: usize,
        mut parse: impl FnMut(&Entry) -> Result<T, WifError>,
    ) -> Result<Numbered<'a, T>, WifError> {
        let mut out = BTreeMap::new();
        let Some(section) = self.section(name) else {
            return Ok(out);
        };
        for entry in &section.entries {
            let n = self.count(name, entry, &entry.key, 1, most).map_err(|_| {
                self.value_error(
                    name,
                    entry,
                    format!("{what} numbers run from 1 to {most}; the key is not one"),
                )
            })?;
            let value = parse(entry)?;
            // The string keys are unique, but "01" and "1" are the same number.
            if let Some((_, first)) = out.insert(n, (value, entry)) {
                return Err(self.value_error(
                    name,
                    entry,
                    format!("{what} {n} is given twice (first on line {})", first.line),
                ));
            }
        }
        Ok(out)
    }

    /// Checks that every number of a numbered section is at most `count`.
    fn within<T>(
        &self,
        name: &str,
        map: &Numbered<'_, T>,
        count: usize,
        counted_by: &str,
    ) -> Result<(), WifError> {
        match map.last_key_value() {
            Some((&n, (_, entry))) if n > count => Err(self.value_error(
                name,
                entry,
                format!("{n} is beyond the {count} of {counted_by}"),
            )),
            _ => Ok(()),
        }
    }

    fn boolean(&self, section: &str, entry: &Entry) -> Result<bool, WifError> {
        match entry.value.to_ascii_lowercase().as_str() {
            "yes" | "true" | "1" | "on" => Ok(true),
            "no" | "false" | "0" | "off" => Ok(false),
            other => Err(self.value_error(
                section,
                entry,
                format!("'{other}' is not yes/no, true/false, 1/0 or on/off"),
            )),
        }
    }

    /// A colour: a palette index, or `r,g,b` in the palette's range.
    fn colour_ref(
        &self,
        section: &str,
        entry: &Entry,
        range: (f64, f64),
    ) -> Result<ColourRef, WifError> {
        if entry.value.contains(',') {
            self.rgb(section, entry, range).map(ColourRef::Rgb)
        } else {
            self.count(section, entry, &entry.value, 1, MAX_PALETTE_ENTRIES)
                .map(ColourRef::Index)
        }
    }

    /// `r,g,b` within `range`, as sRGB components in [0, 1].
    fn rgb(&self, section: &str, entry: &Entry, range: (f64, f64)) -> Result<[f64; 3], WifError> {
        let parts: Vec<&str> = entry.value.split(',').collect();
        if parts.len() != 3 {
            return Err(self.value_error(
                section,
                entry,
                format!("'{}' is not a colour r,g,b", entry.value),
            ));
        }
        let (min, max) = range;
        let mut rgb = [0.0; 3];
        for (out, part) in rgb.iter_mut().zip(parts) {
            let v = self.number(section, entry, part)?;
            if !(min..=max).contains(&v) {
                return Err(self.value_error(
                    section,
                    entry,
                    format!(
                        "{v} is outside the palette's range {min},{max} ([COLOR PALETTE] Range)"
                    ),
                ));
            }
            *out = (v - min) / (max - min);
        }
        Ok(rgb)
    }

    fn family_header(&self, side: Side, range: (f64, f64)) -> Result<FamilyHeader, WifError> {
        let name = side.name();
        let threads = match self.entry(name, "threads") {
            Some(e) => Some(self.count(name, e, &e.value, 1, MAX_THREADS)?),
            None => None,
        };
        let colour = match self.entry(name, "color") {
            Some(e) => Some((self.colour_ref(name, e, range)?, e.line)),
            None => None,
        };
        let spacing = match self.entry(name, "spacing") {
            Some(e) => Some(self.length(name, e)?),
            None => None,
        };
        let thickness = match self.entry(name, "thickness") {
            Some(e) => Some(self.length(name, e)?),
            None => None,
        };
        Ok(FamilyHeader {
            threads,
            colour,
            spacing,
            thickness,
        })
    }

    /// The palette's range, `[COLOR PALETTE] Range=min,max`, 0..255 if not given.
    fn palette_range(&self) -> Result<(f64, f64), WifError> {
        const NAME: &str = "COLOR PALETTE";
        let Some(entry) = self.entry(NAME, "range") else {
            return Ok((0.0, 255.0));
        };
        let Some((min, max)) = entry.value.split_once(',') else {
            return Err(self.value_error(
                NAME,
                entry,
                format!("'{}' is not a range min,max", entry.value),
            ));
        };
        let (min, max) = (
            self.number(NAME, entry, min)?,
            self.number(NAME, entry, max)?,
        );
        if max <= min || !(max - min).is_finite() {
            return Err(self.value_error(NAME, entry, format!("the range {min},{max} is empty")));
        }
        Ok((min, max))
    }

    /// The colour table, by index. `[COLOR PALETTE] Entries` is checked as a number but does
    /// not bound the indices: programs write it as the count of the table's lines, whose
    /// numbers may skip (colours 1, 2 and 7 are `Entries=3`), so a colour is refused only
    /// when a thread names one the table lacks.
    fn colour_table(&self, range: (f64, f64)) -> Result<Numbered<'a, [f64; 3]>, WifError> {
        const NAME: &str = "COLOR PALETTE";
        if let Some(e) = self.entry(NAME, "entries") {
            self.count(NAME, e, &e.value, 0, MAX_PALETTE_ENTRIES)?;
        }
        self.numbered("COLOR TABLE", "colour", MAX_PALETTE_ENTRIES, |e| {
            self.rgb("COLOR TABLE", e, range)
        })
    }

    /// The yarns of one family: colours, mean spacing and mean thickness.
    fn yarns(
        &self,
        side: Side,
        header: &FamilyHeader,
        count: usize,
        range: (f64, f64),
        table: &Numbered<'a, [f64; 3]>,
    ) -> Result<Yarns, WifError> {
        let family = side.name();
        let counted_by = format!("[{family}] Threads or the draft's {}s", side.thread());
        let resolve = |colour: ColourRef, section: &str, key: &str, line: usize| match colour {
            ColourRef::Rgb(rgb) => Ok(rgb),
            ColourRef::Index(i) => match table.get(&i) {
                Some((rgb, _)) => Ok(*rgb),
                None => Err(WifError::Value {
                    origin: self.origin.to_string(),
                    section: section.to_string(),
                    key: key.to_string(),
                    line,
                    message: format!("colour {i} is not in the [COLOR TABLE]"),
                }),
            },
        };
        let default = match header.colour {
            Some((colour, line)) => Some(resolve(colour, family, "Color", line)?),
            None => None,
        };
        let colours_name = format!("{family} COLORS");
        let colours = self.numbered(&colours_name, "thread", MAX_THREADS, |e| {
            self.colour_ref(&colours_name, e, range)
        })?;
        self.within(&colours_name, &colours, count, &counted_by)?;
        let mut per_thread = vec![default; count];
        for (&n, &(colour, entry)) in &colours {
            per_thread[n - 1] = Some(resolve(colour, &colours_name, &entry.key, entry.line)?);
        }

        let mean = |what: &str, default: Option<f64>| -> Result<Option<f64>, WifError> {
            let name = format!("{family} {what}");
            let values = self.numbered(&name, "thread", MAX_THREADS, |e| self.length(&name, e))?;
            self.within(&name, &values, count, &counted_by)?;
            let listed: f64 = values.values().map(|(x, _)| x).sum();
            Ok(match default {
                Some(d) => Some((listed + d * (count - values.len()) as f64) / count as f64),
                None if values.is_empty() => None,
                None => Some(listed / values.len() as f64),
            })
        };
        Ok(Yarns {
            colours: per_thread,
            spacing: mean("SPACING", header.spacing)?,
            thickness: mean("THICKNESS", header.thickness)?,
        })
    }

    fn draft(&self) -> Result<Draft, WifError> {
        const WEAVING: &str = "WEAVING";
        let limit = |key: &str| -> Result<Option<usize>, WifError> {
            match self.entry(WEAVING, key) {
                Some(e) => Ok(Some(self.count(WEAVING, e, &e.value, 0, MAX_THREADS)?)),
                None => Ok(None),
            }
        };
        let shafts = limit("shafts")?;
        let treadles = limit("treadles")?;
        let rising = match self.entry(WEAVING, "rising shed") {
            Some(e) => self.boolean(WEAVING, e)?,
            None => true,
        };
        let shaft_most = shafts.unwrap_or(MAX_THREADS);
        let treadle_most = treadles.unwrap_or(MAX_THREADS);

        let range = self.palette_range()?;
        let table = self.colour_table(range)?;
        let warp = self.family_header(Side::Warp, range)?;
        let weft = self.family_header(Side::Weft, range)?;

        let threading = self.numbered("THREADING", "end", MAX_THREADS, |e| {
            self.list("THREADING", e, shaft_most, "shaft")
        })?;
        // The tie-up may hold treadles past `Treadles` (Fiberworks PCW counts the treadles the
        // treadling presses and still writes the tie-up of the tabby treadles past them); the
        // treadling is what is held to `Treadles`.
        let tieup = self.numbered("TIEUP", "treadle", MAX_THREADS, |e| {
            self.list("TIEUP", e, shaft_most, "shaft")
        })?;
        let treadling = self.numbered("TREADLING", "pick", MAX_THREADS, |e| {
            self.list("TREADLING", e, treadle_most, "treadle")
        })?;
        let liftplan = self.numbered("LIFTPLAN", "pick", MAX_THREADS, |e| {
            self.list("LIFTPLAN", e, shaft_most, "shaft")
        })?;

        let has = |name: &str| self.section(name).is_some();
        if !has("THREADING") {
            return Err(self.draft_error(
                "there is no [THREADING] section: the draft says on which shafts the ends lie"
                    .to_string(),
            ));
        }
        // The lift plan rules where there is one, unless it is an empty section written
        // beside a treadling and tie-up.
        let treadled = has("TREADLING") && has("TIEUP");
        let use_liftplan = has("LIFTPLAN") && (!liftplan.is_empty() || !treadled);
        if !use_liftplan && !treadled {
            let missing = match (has("TREADLING"), has("TIEUP")) {
                (true, false) => "a [TREADLING] but no [TIEUP]",
                (false, true) => "a [TIEUP] but no [TREADLING]",
                _ => "neither",
            };
            return Err(self.draft_error(format!(
                "the draft needs a [LIFTPLAN], or a [TREADLING] and a [TIEUP], to say which \
                 shafts rise on each pick; it has {missing}"
            )));
        }
        let (pick_section, picks_listed) = if use_liftplan {
            ("LIFTPLAN", liftplan.last_key_value().map(|(&n, _)| n))
        } else {
            ("TREADLING", treadling.last_key_value().map(|(&n, _)| n))
        };

        let ends = match warp.threads {
            Some(n) => n,
            None => threading.last_key_value().map_or(0, |(&n, _)| n),
        };
        let picks = match weft.threads {
            Some(n) => n,
            None => picks_listed.unwrap_or(0),
        };
        if ends == 0 {
            return Err(self.draft_error(
                "no ends: [WARP] Threads is not given and [THREADING] is empty".to_string(),
            ));
        }
        if picks == 0 {
            return Err(self.draft_error(format!(
                "no picks: [WEFT] Threads is not given and [{pick_section}] is empty"
            )));
        }
        let ends_by = "[WARP] Threads";
        let picks_by = "[WEFT] Threads";
        self.within("THREADING", &threading, ends, ends_by)?;
        // Only the section that says which shafts rise is read; the other may be longer.
        if use_liftplan {
            self.within("LIFTPLAN", &liftplan, picks, picks_by)?;
        } else {
            self.within("TREADLING", &treadling, picks, picks_by)?;
        }
        if ends * picks > MAX_CELLS {
            return Err(self.draft_error(format!(
                "{ends} ends ([WARP] Threads or [THREADING]) × {picks} picks ([WEFT] Threads or \
                 [{pick_section}]) is more than {MAX_CELLS} crossings"
            )));
        }

        // Every number is checked: now allocate by the counts.
        let mut end_shafts: Vec<&[usize]> = vec![&[]; ends];
        for (&end, (shafts, _)) in &threading {
            end_shafts[end - 1] = shafts;
        }
        let mut pick_shafts: Vec<Vec<usize>> = vec![Vec::new(); picks];
        if use_liftplan {
            for (&pick, (shafts, _)) in &liftplan {
                pick_shafts[pick - 1].clone_from(shafts);
            }
        } else {
            for (&pick, (pedals, _)) in &treadling {
                let lifted = &mut pick_shafts[pick - 1];
                for treadle in pedals {
                    if let Some((shafts, _)) = tieup.get(treadle) {
                        lifted.extend_from_slice(shafts);
                    }
                }
                lifted.sort_unstable();
                lifted.dedup();
            }
        }
        let mut draft = Draft::from_fn(ends, picks, |end, pick| {
            let named = end_shafts[end]
                .iter()
                .any(|s| pick_shafts[pick].binary_search(s).is_ok());
            // Rising: the end rises with any of its shafts. Sinking: the listed shafts sink,
            // and the end stays up only where none of its shafts does.
            named == rising
        })
        .map_err(|e| self.draft_error(e.0))?;
        draft.warp = self.yarns(Side::Warp, &warp, ends, range, &table)?;
        draft.weft = self.yarns(Side::Weft, &weft, picks, range, &table)?;
        Ok(draft)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::weave::NamedWeave;
    use rand::{Rng, SeedableRng};
    use rand_pcg::Pcg64;

    const FIXTURES: [&str; 8] = [
        "twill_fiberworks_crlf.wif",
        "twill_liftplan_sinking.wif",
        "multi_treadle_multi_shaft.wif",
        "palette_65535.wif",
        "satin_private_cr_latin1.wif",
        "zero_unused.wif",
        "tieup_past_treadles.wif",
        "colour_table_sparse.wif",
    ];

    fn fixture_path(name: &str) -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tests/data/wif")
            .join(name)
    }

    fn fixture_text(name: &str) -> String {
        let bytes = std::fs::read(fixture_path(name)).unwrap();
        String::from_utf8_lossy(&bytes).into_owned()
    }

    fn load(name: &str) -> Draft {
        load_wif(&fixture_path(name)).unwrap_or_else(|e| panic!("{e}"))
    }

    fn error(text: &str) -> String {
        parse_wif(text, "test.wif").unwrap_err().to_string()
    }

    const TWILL_2_2: &str = "##..##..\n.##..##.\n..##..##\n#..##..#\n";

    #[test]
    fn treadled_twill_with_crlf() {
        let text = std::fs::read(fixture_path(FIXTURES[0])).unwrap();
        assert!(text.windows(2).any(|w| w == b"\r\n"));
        let draft = load(FIXTURES[0]);
        assert_eq!(draft.drawdown(), TWILL_2_2);
        // The 2/2 twill of the named weaves, repeated twice along the warp.
        let twill: NamedWeave = "twill:2/2".parse().unwrap();
        let twill = twill.draft();
        for end in 0..8 {
            for pick in 0..4 {
                assert_eq!(draft.warp_up(end, pick), twill.warp_up(end % 4, pick));
            }
        }
        // One colour for each family from [WARP] and [WEFT] Color.
        assert_eq!(draft.warp.colours, vec![Some([1.0, 1.0, 1.0]); 8]);
        assert_eq!(draft.weft.colours, vec![Some([0.0, 0.0, 0.0]); 4]);
        assert_eq!(draft.warp.spacing, Some(0.1));
        assert_eq!(draft.weft.thickness, Some(0.08));
    }

    #[test]
    fn sinking_lift_plan_equals_the_treadled_file() {
        let draft = load(FIXTURES[1]);
        assert_eq!(draft.drawdown(), TWILL_2_2);
        assert_eq!(draft.drawdown(), load(FIXTURES[0]).drawdown());
        assert_eq!(draft.warp.colours, vec![None; 8]);
        assert_eq!(draft.warp.spacing, None);
        // The same file with a rising shed weaves the complement.
        let text = fixture_text(FIXTURES[1]);
        assert!(text.contains("Rising Shed=no"));
        let rising = parse_wif(&text.replace("Rising Shed=no", "Rising Shed=yes"), "r.wif");
        let complement: String = TWILL_2_2
            .chars()
            .map(|c| match c {
                '#' => '.',
                '.' => '#',
                c => c,
            })
            .collect();
        assert_eq!(rising.unwrap().drawdown(), complement);
    }

    #[test]
    fn several_treadles_per_pick_and_shafts_per_end() {
        let draft = load(FIXTURES[2]);
        // Ends 5 and 6 rise with either of their shafts (1 or 3, 2 or 4); end 7 is not
        // threaded and pick 5 has no treadle, so neither ever shows warp.
        assert_eq!(
            draft.drawdown(),
            "##..##.\n.##.##.\n..####.\n#..###.\n.......\n"
        );
        assert_eq!(draft.warp.colours, vec![None; 7]);
        assert_eq!(draft.weft.colours, vec![None; 5]);
    }

    #[test]
    fn palette_range_and_per_thread_yarns() {
        let draft = load(FIXTURES[3]);
        assert_eq!(draft.drawdown(), "#.#.\n.#.#\n#.#.\n.#.#\n");
        let red = Some([1.0, 0.0, 0.0]);
        let blue = Some([0.0, 0.2, 1.0]);
        let white = Some([1.0, 1.0, 1.0]);
        assert_eq!(draft.warp.colours, vec![red, blue, red, white]);
        assert_eq!(draft.weft.colours, vec![blue, None, None, None]);
        // One end listed at 0.5, the three others at the default 0.25.
        assert_eq!(draft.warp.spacing, Some(0.3125));
        assert_eq!(draft.warp.thickness, Some(0.2));
        // No default: the mean of the threads listed.
        assert_eq!(draft.weft.spacing, None);
        assert_eq!(draft.weft.thickness, Some(0.3));
    }

    #[test]
    fn private_sections_comments_cr_bom_and_latin1() {
        let bytes = std::fs::read(fixture_path(FIXTURES[4])).unwrap();
        assert!(bytes.starts_with(b"\xef\xbb\xbf"));
        assert!(!bytes.contains(&b'\n'));
        assert!(std::str::from_utf8(&bytes).is_err());
        let draft = load(FIXTURES[4]);
        let satin: NamedWeave = "satin:5".parse().unwrap();
        assert_eq!(draft.drawdown(), ".####\n##.##\n####.\n#.###\n###.#\n");
        assert_eq!(draft.drawdown(), satin.draft().drawdown());
        // Default range 0..255.
        assert_eq!(draft.warp.colours, vec![Some([1.0, 0.2, 0.0]); 5]);
        assert_eq!(draft.weft.colours, vec![None; 5]);
    }

    #[test]
    fn zero_is_an_unused_shaft_or_treadle() {
        let draft = load(FIXTURES[5]);
        // End 4 (threaded on 0) never rises; end 5 (0,2) rises with shaft 2; treadle 3 (tied
        // to 0) and pick 4 (treadle 0) lift nothing.
        assert_eq!(draft.drawdown(), "#.....\n.#..#.\n......\n......\n##..#.\n");
        // A 0 in a lift plan lifts nothing either, and the sinking shed still sinks the rest.
        let lifted = format!("{PLAIN}[LIFTPLAN]\n1=0\n2=2,0\n");
        assert_eq!(parse_wif(&lifted, "p.wif").unwrap().drawdown(), "..\n.#\n");
        let sinking = lifted.replace("Treadles=2\n", "Treadles=2\nRising Shed=no\n");
        assert_eq!(parse_wif(&sinking, "p.wif").unwrap().drawdown(), "##\n#.\n");
        // Numbers past the count are still refused, and say that 0 is allowed.
        let past = PLAIN.replacen("[THREADING]\n1=1", "[THREADING]\n1=0,3", 1);
        assert!(error(&past).contains(
            "[THREADING] 1 (line 9): shaft '3' is not a number from 1 to 2 (or 0, unused)"
        ));
    }

    #[test]
    fn the_tieup_may_tie_treadles_past_the_count() {
        let draft = load(FIXTURES[6]);
        assert_eq!(draft.drawdown(), "..#..#\n.#..#.\n#..#..\n");
        // Treadles 4 and 5 are tied but not counted; pressing one is still refused.
        let pressed = fixture_text(FIXTURES[6]).replace("[TREADLING]\n1=3", "[TREADLING]\n1=5");
        let message = parse_wif(&pressed, "t.wif").unwrap_err().to_string();
        assert!(message.contains("[TREADLING] 1 (line "), "{message}");
        assert!(
            message.contains("treadle '5' is not a number from 1 to 3"),
            "{message}"
        );
        // The tie-up's shafts are still held to Shafts.
        let shaft = fixture_text(FIXTURES[6]).replace("5=2,3", "5=2,4");
        assert!(
            parse_wif(&shaft, "t.wif")
                .unwrap_err()
                .to_string()
                .contains("shaft '4'")
        );
    }

    #[test]
    fn colour_numbers_may_skip_past_the_entries() {
        let draft = load(FIXTURES[7]);
        assert_eq!(draft.drawdown(), "#.#.\n.#.#\n");
        let blue = Some([0.0, 0.2, 1.0]);
        let white = Some([1.0, 1.0, 1.0]);
        assert_eq!(draft.warp.colours, vec![blue, white, blue, blue]);
        assert_eq!(draft.weft.colours, vec![Some([0.0, 0.0, 0.0]); 2]);
        // A colour the table lacks is still refused, and so is an Entries that is no number.
        let missing = fixture_text(FIXTURES[7]).replace("Color=7", "Color=5");
        let message = parse_wif(&missing, "c.wif").unwrap_err().to_string();
        assert!(message.contains("[WARP] Color (line "), "{message}");
        assert!(
            message.contains("colour 5 is not in the [COLOR TABLE]"),
            "{message}"
        );
        let entries = fixture_text(FIXTURES[7]).replace("Entries=3", "Entries=three");
        assert!(
            parse_wif(&entries, "c.wif")
                .unwrap_err()
                .to_string()
                .contains("[COLOR PALETTE] Entries")
        );
    }

    /// A small treadled plain weave, for the error tests to damage one line of.
    const PLAIN: &str = "[WEAVING]\nShafts=2\nTreadles=2\n[WARP]\nThreads=2\n[WEFT]\nThreads=2\n\
        [THREADING]\n1=1\n2=2\n[TIEUP]\n1=1\n2=2\n[TREADLING]\n1=1\n2=2\n";

    #[test]
    fn the_lift_plan_rules_over_the_treadling() {
        assert_eq!(parse_wif(PLAIN, "p.wif").unwrap().drawdown(), "#.\n.#\n");
        let lifted = format!("{PLAIN}[LIFTPLAN]\n1=1,2\n");
        assert_eq!(parse_wif(&lifted, "p.wif").unwrap().drawdown(), "##\n..\n");
        // An empty lift plan beside a treadling is ignored.
        let empty = format!("{PLAIN}[LIFTPLAN]\n");
        assert_eq!(parse_wif(&empty, "p.wif").unwrap().drawdown(), "#.\n.#\n");
    }

    #[test]
    fn errors_name_the_file_and_the_place() {
        for (from, to, needle) in [
            (
                "2=2\n[TIEUP]",
                "2=2\n2=1\n[TIEUP]",
                "[THREADING] 2 (line 11): the key is given twice (first on line 10)",
            ),
            (
                "2=2\n[TIEUP]",
                "2=2\n02=2\n[TIEUP]",
                "[THREADING] 02 (line 11): end 2 is given twice (first on line 10)",
            ),
            (
                "[THREADING]\n1=1",
                "[THREADING]\n1=3",
                "[THREADING] 1 (line 9): shaft '3' is not a number from 1 to 2",
            ),
            ("[THREADING]\n1=1", "[THREADING]\n1=-1", "shaft '-1'"),
            (
                "[THREADING]\n1=1",
                "[THREADING]\n3=1",
                "[THREADING] 3 (line 9): 3 is beyond the 2 of [WARP] Threads",
            ),
            (
                "[THREADING]\n1=1",
                "[THREADING]\n0=1",
                "[THREADING] 0 (line 9): end numbers run from 1 to 16384",
            ),
            (
                "[TREADLING]\n1=1",
                "[TREADLING]\n1=7",
                "[TREADLING] 1 (line 15): treadle '7'",
            ),
            (
                "[WARP]\nThreads=2",
                "[WARP]\nThreads=99999999999999999999",
                "[WARP] Threads (line 5)",
            ),
            (
                "[WARP]\nThreads=2\n[WEFT]\nThreads=2",
                "[WARP]\nThreads=16384\n[WEFT]\nThreads=16384",
                "16384 ends ([WARP] Threads or [THREADING]) × 16384 picks ([WEFT] Threads or \
                 [TREADLING]) is more than 16777216 crossings",
            ),
            (
                "[WARP]\nThreads=2",
                "[WARP]\nThreads=16385",
                "[WARP] Threads (line 5): 16385 is not within 1..=16384",
            ),
            (
                "[WARP]\nThreads=2",
                "[WARP]\nThreads=2\nSpacing=-1",
                "[WARP] Spacing (line 6): -1 is not a positive length",
            ),
            (
                "[WARP]\nThreads=2",
                "[WARP]\nThreads=2\nColor=4",
                "[WARP] Color (line 6): colour 4 is not in the [COLOR TABLE]",
            ),
            (
                "[WARP]\nThreads=2",
                "[WARP]\nThreads=2\nColor=1,2,300",
                "outside the palette's range 0,255",
            ),
            (
                "Treadles=2\n",
                "Treadles=2\nRising Shed=maybe\n",
                "[WEAVING] Rising Shed (line 4)",
            ),
            (
                "[WEAVING]\n",
                "Shafts=2\n[WEAVING]\n",
                "line 1: 'Shafts=2' comes before the first [SECTION]",
            ),
            (
                "[WEAVING]\n",
                "[WEAVING\n",
                "line 1: '[WEAVING' is not a section header",
            ),
            (
                "Treadles=2\n",
                "Treadles 2\n",
                "line 3: 'Treadles 2' in [WEAVING] is not a key=value line",
            ),
            ("[TIEUP]\n", "[TIE]\n", "a [TREADLING] but no [TIEUP]"),
            (
                "[THREADING]\n",
                "[THREAD]\n",
                "there is no [THREADING] section",
            ),
        ] {
            assert!(PLAIN.contains(from), "{from}");
            let damaged = PLAIN.replacen(from, to, 1);
            let Err(e) = parse_wif(&damaged, "test.wif") else {
                panic!("{damaged} loads");
            };
            let message = e.to_string();
            assert!(message.starts_with("WIF file test.wif"), "{message}");
            assert!(message.contains(needle), "{needle}\n{message}");
        }
        let bare = "[WEAVING]\nShafts=2\n[THREADING]\n1=1\n";
        assert!(error(bare).contains("it has neither"));
        let range = "[COLOR PALETTE]\nRange=255,0\n";
        assert!(error(range).contains("[COLOR PALETTE] Range (line 2): the range 255,0 is empty"));
    }

    #[test]
    fn load_checks_the_size_first() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("huge.wif");
        let file = std::fs::File::create(&path).unwrap();
        file.set_len(MAX_WIF_BYTES + 1).unwrap();
        let message = load_wif(&path).unwrap_err().to_string();
        assert!(
            message.contains("huge.wif") && message.contains("limit"),
            "{message}"
        );
        let missing = load_wif(&dir.path().join("missing.wif")).unwrap_err();
        assert!(matches!(missing, WifError::Io { .. }));
        assert!(missing.to_string().contains("missing.wif"));
    }

    /// Numbers a damaged file may hold.
    const BAD_NUMBERS: [&str; 12] = [
        "99999999999999999999",
        "18446744073709551616",
        "4294967296",
        "16385",
        "4096",
        "-1",
        "0",
        "abc",
        "1e308",
        "NaN",
        "",
        ",,,",
    ];

    /// `original` with one to three random kinds of damage.
    fn damage(original: &[u8], rng: &mut Pcg64) -> Vec<u8> {
        let text = String::from_utf8_lossy(original);
        let ending = if text.contains("\r\n") {
            "\r\n"
        } else if text.contains('\r') {
            "\r"
        } else {
            "\n"
        };
        let mut lines: Vec<String> = split_lines(&text).into_iter().map(String::from).collect();
        let mut bytes = None;
        for _ in 0..rng.random_range(1..=3) {
            let n = lines.len().max(1);
            let at = rng.random_range(0..n).min(lines.len().saturating_sub(1));
            match rng.random_range(0..8) {
                0 if !lines.is_empty() => {
                    lines.remove(at);
                }
                1 if !lines.is_empty() => {
                    let copy = lines[at].clone();
                    let to = rng.random_range(0..=lines.len());
                    lines.insert(to, copy);
                }
                2 if !lines.is_empty() => {
                    let other = rng.random_range(0..lines.len());
                    lines.swap(at, other);
                }
                3 | 4 => {
                    // Byte damage ends the line edits: truncate or flip bytes.
                    let mut b = lines.join(ending).into_bytes();
                    if b.is_empty() {
                        continue;
                    }
                    if rng.random_range(0..2) == 0 {
                        b.truncate(rng.random_range(0..b.len()));
                    } else {
                        for _ in 0..rng.random_range(1..=4) {
                            let i = rng.random_range(0..b.len());
                            b[i] ^= rng.random_range(1..=255u8);
                        }
                    }
                    bytes = Some(b);
                    break;
                }
                5 | 6 => {
                    // Replace the value of a key=value line.
                    let keyed: Vec<usize> = (0..lines.len())
                        .filter(|&i| lines[i].contains('=') && !lines[i].starts_with(';'))
                        .collect();
                    if keyed.is_empty() {
                        continue;
                    }
                    let i = keyed[rng.random_range(0..keyed.len())];
                    let key = lines[i].split('=').next().unwrap_or_default().to_string();
                    let bad = BAD_NUMBERS[rng.random_range(0..BAD_NUMBERS.len())];
                    lines[i] = if rng.random_range(0..2) == 0 {
                        format!("{key}={bad}")
                    } else {
                        format!("{bad}={}", lines[i].split_once('=').map_or("", |kv| kv.1))
                    };
                }
                _ => {
                    // Drop a section header.
                    let headers: Vec<usize> = (0..lines.len())
                        .filter(|&i| lines[i].trim_start().starts_with('['))
                        .collect();
                    if !headers.is_empty() {
                        lines.remove(headers[rng.random_range(0..headers.len())]);
                    }
                }
            }
        }
        bytes.unwrap_or_else(|| lines.join(ending).into_bytes())
    }

    #[test]
    fn damaged_drafts_load_or_say_where() {
        let originals: Vec<Vec<u8>> = FIXTURES
            .iter()
            .map(|name| std::fs::read(fixture_path(name)).unwrap())
            .collect();
        let mut rng = Pcg64::seed_from_u64(0x0057_4946);
        let (mut loaded, mut rejected, mut panics) = (0, 0, Vec::new());
        for i in 0..1000 {
            let text = String::from_utf8_lossy(&damage(&originals[i % originals.len()], &mut rng))
                .into_owned();
            let origin = format!("damaged-{i}.wif");
            match std::panic::catch_unwind(|| parse_wif(&text, &origin)) {
                Err(_) => panics.push(i),
                Ok(Ok(_)) => loaded += 1,
                Ok(Err(e)) => {
                    rejected += 1;
                    let message = e.to_string();
                    let located = match &e {
                        WifError::Line { line, .. } => *line > 0,
                        WifError::Value { section, key, .. } => {
                            message.contains(&format!("[{section}] {key} (line "))
                        }
                        WifError::Draft { message, .. } => message.contains('['),
                        _ => false,
                    };
                    assert!(
                        message.contains(&origin) && located,
                        "variant {i}: {message}\n{text}"
                    );
                }
            }
        }
        assert!(panics.is_empty(), "variants that panicked: {panics:?}");
        // Both outcomes are exercised.
        assert!(
            loaded >= 100 && rejected >= 100,
            "{loaded} loaded, {rejected} rejected"
        );
    }
}
