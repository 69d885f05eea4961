//! Where a session comes from and where it goes: built-in fabrics, fabric files, weaves
//! (named or WIF), and saving.

use super::{EditSession, FILE_FIELD};
use crate::formats::draft_source::{DraftSourceError, load_draft};
use crate::formats::fabric_toml::{FabricFileError, FabricSet, write_fabric_file};
use crate::model::FabricError;
use crate::weave::{DraftError, NamedWeave, Weave};
use std::fmt;
use std::path::{Path, PathBuf};

/// Where a session's fabric came from.
#[derive(Clone, Debug, PartialEq)]
pub enum Source {
    /// A built-in fabric, by name.
    Builtin(String),
    /// A fabric of a fabric file.
    File { path: PathBuf, fabric: String },
    /// A weave: a named weave or a WIF file, as `clothbake weave` spells it, and whether its
    /// back is woven (`--back`) and warp and weft exchanged (`--swap`).
    Weave {
        spelling: String,
        back: bool,
        swap: bool,
    },
}

impl fmt::Display for Source {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Source::Builtin(name) => write!(f, "the built-in fabric '{name}'"),
            Source::File { path, fabric } => {
                write!(f, "fabric '{fabric}' of {}", path.display())
            }
            Source::Weave {
                spelling,
                back,
                swap,
            } => {
                write!(f, "the weave {spelling}")?;
                if *back {
                    f.write_str(", its back")?;
                }
                if *swap {
                    f.write_str(", warp and weft swapped")?;
                }
                Ok(())
            }
        }
    }
}

/// Why a session could not be opened or saved; an open that fails leaves the session as it
/// was.
#[derive(Debug, thiserror::Error)]
pub enum SessionError {
    #[error(transparent)]
    FabricFile(#[from] FabricFileError),
    #[error(transparent)]
    Draft(#[from] DraftSourceError),
    #[error("weave {spelling}: {source}")]
    Weave {
        spelling: String,
        source: FabricError,
    },
    #[error(
        "'{target}' is no file, built-in fabric ({builtin}) or weave ({}): {weave}",
        NamedWeave::SYNTAX
    )]
    UnknownTarget {
        target: String,
        builtin: String,
        weave: DraftError,
    },
    #[error("'{target}' is a built-in fabric: a fabric name chooses among a file's fabrics")]
    NameOfBuiltin { target: String },
    #[error("cannot save {path}: {source}")]
    Save {
        path: PathBuf,
        source: std::io::Error,
    },
}

impl EditSession {
    /// A session of the built-in fabric `name`.
    pub fn builtin(name: &str) -> Result<Self, SessionError> {
        let fabric = FabricSet::builtin().require(name)?.clone();
        Ok(Self::new(fabric, Source::Builtin(name.to_string()), None))
    }

    /// A session of the fabric called `fabric` in the fabric file `path` (TOML), or of its
    /// first fabric.
    pub fn from_file(path: &Path, fabric: Option<&str>) -> Result<Self, SessionError> {
        let set = FabricSet::load(path)?;
        let chosen = match fabric {
            Some(name) => set.require(name)?,
            None => &set.fabrics()[0],
        };
        let source = Source::File {
            path: path.to_path_buf(),
            fabric: chosen.name.clone(),
        };
        Ok(Self::new(chosen.clone(), source, None))
    }

    /// A session of a weave: `spelling` a named weave or a WIF file as `clothbake weave`
    /// takes it, with default yarn knobs; `back` and `swap` as its `--back` and `--swap`;
    /// the fabric called `name`, else named from the spelling.
    pub fn from_weave(
        spelling: &str,
        back: bool,
        swap: bool,
        name: Option<&str>,
    ) -> Result<Self, SessionError> {
        let (draft, default_name) = load_draft(spelling)?;
        let weave = Weave::new(draft.oriented(back, swap));
        let fabric = weave
            .fabric(name.unwrap_or(&default_name))
            .map_err(|source| SessionError::Weave {
                spelling: spelling.to_string(),
                source,
            })?;
        let source = Source::Weave {
            spelling: spelling.to_string(),
            back,
            swap,
        };
        Ok(Self::new(fabric, source, Some(weave)))
    }

    /// A session of the file at `path`: a WIF draft when it ends in `.wif`, else a fabric
    /// file's first fabric.
    pub fn from_path(path: &Path) -> Result<Self, SessionError> {
        if is_wif(path) {
            Self::from_weave(&path.to_string_lossy(), false, false, None)
        } else {
            Self::from_file(path, None)
        }
    }

    /// A session of whatever `target` names, tried in this order: a WIF file (`.wif`), a
    /// fabric file (`.toml`, or any other existing file), a built-in fabric, a named weave.
    /// `name` chooses a fabric file's fabric or names a weave's fabric.
    pub fn from_target(target: &str, name: Option<&str>) -> Result<Self, SessionError> {
        let path = Path::new(target);
        let toml = path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("toml"));
        if is_wif(path) {
            return Self::from_weave(target, false, false, name);
        }
        if toml || path.is_file() {
            return Self::from_file(path, name);
        }
        let builtin = FabricSet::builtin();
        if builtin.get(target).is_some() {
            return match name {
                Some(_) => Err(SessionError::NameOfBuiltin {
                    target: target.to_string(),
                }),
                None => Self::builtin(target),
            };
        }
        match target.parse::<NamedWeave>() {
            Ok(_) => Self::from_weave(target, false, false, name),
            Err(weave) => Err(SessionError::UnknownTarget {
                target: target.to_string(),
                builtin: builtin
                    .fabrics()
                    .iter()
                    .map(|f| f.name.as_str())
                    .collect::<Vec<_>>()
                    .join(", "),
                weave,
            }),
        }
    }

    /// Opens the file at `path` in place of this session ([`EditSession::from_path`]); on
    /// an error the session is unchanged but for the error shown beside the file
    /// ([`FILE_FIELD`]).
    pub fn open(&mut self, path: &Path) -> Result<(), SessionError> {
        let opened = Self::from_path(path);
        self.replace(opened)
    }

    /// Opens what `target` names in place of this session ([`EditSession::from_target`]);
    /// on an error the session is unchanged but for the error beside the file.
    pub fn open_target(&mut self, target: &str, name: Option<&str>) -> Result<(), SessionError> {
        let opened = Self::from_target(target, name);
        self.replace(opened)
    }

    fn replace(&mut self, opened: Result<Self, SessionError>) -> Result<(), SessionError> {
        match opened {
            Ok(mut session) => {
                session.revision = self.revision + 1;
                *self = session;
                Ok(())
            }
            Err(error) => {
                self.errors
                    .insert(FILE_FIELD.to_string(), error.to_string());
                Err(error)
            }
        }
    }

    /// Writes the fabric to `path` as a fabric file of one fabric, atomically (the crate's
    /// fabric writer: a temporary file renamed over it, the text read back first), and makes
    /// it the saved fabric. On an error nothing is written and the error shows beside the
    /// file.
    pub fn save(&mut self, path: &Path) -> Result<(), SessionError> {
        let header = format!("Edited with clothbake view --edit from {}.", self.source);
        self.gesture = None;
        match write_fabric_file(path, std::slice::from_ref(&self.fabric), &header) {
            Ok(()) => {
                self.saved = self.fabric.clone();
                self.saved_path = Some(path.to_path_buf());
                self.errors.remove(FILE_FIELD);
                Ok(())
            }
            Err(source) => {
                let error = SessionError::Save {
                    path: path.to_path_buf(),
                    source,
                };
                self.errors
                    .insert(FILE_FIELD.to_string(), error.to_string());
                Err(error)
            }
        }
    }
}

fn is_wif(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("wif"))
}
