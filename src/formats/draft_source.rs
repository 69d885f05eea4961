//! A weave draft from its spelling, the same on every command and in Python: a named weave
//! (`plain`, `basket:N`, `twill:N/M[:s|:z]`, `satin:N[/STEP]`, `sateen:N[/STEP]`) or a WIF
//! file (a path ending in `.wif`, or any existing file).

use super::wif::{WifError, load_wif};
use crate::weave::{Draft, DraftError, NamedWeave, fabric_name_from};
use std::path::Path;

/// Why a draft's spelling gave no draft.
#[derive(Debug, thiserror::Error)]
pub enum DraftSourceError {
    #[error("weave '{spelling}': {source}")]
    Named {
        spelling: String,
        source: DraftError,
    },
    #[error(transparent)]
    Wif(#[from] WifError),
}

/// The draft that `spelling` names and a fabric name made from it (the weave's spelling or
/// the WIF file's stem).
pub fn load_draft(spelling: &str) -> Result<(Draft, String), DraftSourceError> {
    let path = Path::new(spelling);
    let is_wif = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("wif"))
        || path.is_file();
    if is_wif {
        let stem = path.file_stem().map(|s| s.to_string_lossy().into_owned());
        let draft = load_wif(path)?;
        return Ok((draft, fabric_name_from(stem.as_deref().unwrap_or("weave"))));
    }
    let named: NamedWeave = spelling.parse().map_err(|source| DraftSourceError::Named {
        spelling: spelling.to_string(),
        source,
    })?;
    Ok((named.draft(), fabric_name_from(&named.to_string())))
}
