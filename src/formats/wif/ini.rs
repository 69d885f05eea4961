//! A WIF file as INI text: its read sections, their `key=value` entries with their lines, and
//! the line that is wrong where the text is not INI.

use super::WifError;
use std::collections::BTreeMap;

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
pub(super) struct Entry {
    pub(super) key: String,
    pub(super) value: String,
    pub(super) line: usize,
}

/// A read section: its entries in file order, each key once.
#[derive(Default)]
pub(super) struct Section {
    pub(super) entries: Vec<Entry>,
    /// The normalised key (lower case, single spaces) of each entry, to its index.
    pub(super) index: BTreeMap<String, usize>,
}

/// The read sections of a file, by normalised name (upper case, single spaces).
pub(super) struct Ini {
    pub(super) sections: BTreeMap<String, Section>,
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
pub(super) fn split_lines(text: &str) -> Vec<&str> {
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
    pub(super) fn parse(text: &str, origin: &str) -> Result<Self, WifError> {
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
