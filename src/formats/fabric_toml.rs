//! Fabric files: TOML holding `[[fabric]]` tables in the schema documented in
//! [`crate::model::fabric`]. Files are untrusted: their size is bounded before reading, unknown
//! keys are rejected and every fabric is validated before use.

use crate::model::{Fabric, FabricError};
use serde::Deserialize;
use std::path::{Path, PathBuf};

/// The six measured fabrics of docs/model.md#the-six-built-in-fabrics, as shipped in
/// `tables/fabrics.toml`.
pub const BUILTIN_FABRICS_TOML: &str = include_str!("../../tables/fabrics.toml");

/// Largest fabric file read: a fabric with two 256-point curves is about 10 KiB of TOML, so
/// 4 MiB holds hundreds of fabrics while bounding what parsing can allocate.
pub const MAX_FABRIC_FILE_BYTES: u64 = 4 << 20;

/// Why a fabric file was rejected.
#[derive(Debug, thiserror::Error)]
pub enum FabricFileError {
    #[error("cannot read fabric file {path}: {source}")]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error(
        "fabric file {path} is {size} bytes, larger than the {MAX_FABRIC_FILE_BYTES}-byte limit"
    )]
    TooLarge { path: PathBuf, size: u64 },
    #[error("fabric file {origin}: {source}")]
    Parse {
        origin: String,
        source: toml::de::Error,
    },
    #[error("fabric file {origin}: {source}")]
    Invalid { origin: String, source: FabricError },
    #[error("fabric file {origin}: fabric '{name}' is defined twice")]
    Duplicate { origin: String, name: String },
    #[error("fabric file {origin}: holds no [[fabric]] table")]
    Empty { origin: String },
    #[error("no fabric named '{name}'; known fabrics: {known}")]
    Unknown { name: String, known: String },
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct FabricFile {
    #[serde(default)]
    fabric: Vec<Fabric>,
}

/// A validated set of fabrics with unique names, in file order.
#[derive(Clone, Debug)]
pub struct FabricSet {
    fabrics: Vec<Fabric>,
}

impl FabricSet {
    /// The built-in measured fabrics.
    pub fn builtin() -> Self {
        Self::parse(BUILTIN_FABRICS_TOML, "tables/fabrics.toml (built in)")
            .expect("the built-in fabric file is valid; tests/files/fabric_file.rs checks it")
    }

    /// Parses and validates fabric TOML; `origin` names the source in errors.
    pub fn parse(text: &str, origin: &str) -> Result<Self, FabricFileError> {
        let origin = origin.to_string();
        let file: FabricFile = toml::from_str(text).map_err(|source| FabricFileError::Parse {
            origin: origin.clone(),
            source,
        })?;
        if file.fabric.is_empty() {
            return Err(FabricFileError::Empty { origin });
        }
        for (i, fabric) in file.fabric.iter().enumerate() {
            fabric
                .validate()
                .map_err(|source| FabricFileError::Invalid {
                    origin: origin.clone(),
                    source,
                })?;
            if file.fabric[..i].iter().any(|f| f.name == fabric.name) {
                return Err(FabricFileError::Duplicate {
                    origin,
                    name: fabric.name.clone(),
                });
            }
        }
        Ok(Self {
            fabrics: file.fabric,
        })
    }

    /// Reads, parses and validates a fabric file.
    pub fn load(path: &Path) -> Result<Self, FabricFileError> {
        let io = |source| FabricFileError::Io {
            path: path.to_path_buf(),
            source,
        };
        let size = std::fs::metadata(path).map_err(io)?.len();
        if size > MAX_FABRIC_FILE_BYTES {
            return Err(FabricFileError::TooLarge {
                path: path.to_path_buf(),
                size,
            });
        }
        let text = std::fs::read_to_string(path).map_err(io)?;
        Self::parse(&text, &path.display().to_string())
    }

    /// The fabrics of `path`, or the built-in ones when `path` is `None`.
    pub fn load_or_builtin(path: Option<&Path>) -> Result<Self, FabricFileError> {
        path.map_or_else(|| Ok(Self::builtin()), Self::load)
    }

    pub fn fabrics(&self) -> &[Fabric] {
        &self.fabrics
    }

    /// The fabric called `name`.
    pub fn get(&self, name: &str) -> Option<&Fabric> {
        self.fabrics.iter().find(|f| f.name == name)
    }

    /// The fabric called `name`, or an error listing the names there are.
    pub fn require(&self, name: &str) -> Result<&Fabric, FabricFileError> {
        self.get(name).ok_or_else(|| {
            let names: Vec<&str> = self.fabrics.iter().map(|f| f.name.as_str()).collect();
            FabricFileError::Unknown {
                name: name.to_string(),
                known: names.join(", "),
            }
        })
    }

    /// The fabrics called `names` in that order, or every fabric when `names` is empty.
    pub fn select(&self, names: &[String]) -> Result<Vec<Fabric>, FabricFileError> {
        if names.is_empty() {
            return Ok(self.fabrics.clone());
        }
        names
            .iter()
            .map(|name| self.require(name).cloned())
            .collect()
    }
}

#[derive(serde::Serialize)]
struct FabricFileOut<'a> {
    fabric: &'a [Fabric],
}

/// The fabric file of `fabrics` as TOML, each line of `header` a `#` comment above it (where
/// a fabric came from: the command, the draft, the fit's samples and error).
pub fn fabric_file_text(fabrics: &[Fabric], header: &str) -> String {
    let body = toml::to_string(&FabricFileOut { fabric: fabrics })
        .expect("a fabric of plain numbers, arrays and strings serialises to TOML");
    // A TOML comment may hold no control character but tab: others become U+FFFD.
    let comment = |line: &str| -> String {
        line.chars()
            .map(|c| {
                if c.is_control() && c != '\t' {
                    '\u{fffd}'
                } else {
                    c
                }
            })
            .collect()
    };
    let mut text: String = header
        .lines()
        .map(|line| format!("# {}\n", comment(line)))
        .collect();
    text.push_str(&body);
    text
}

/// Writes `fabrics` to `path` atomically (a temporary file beside it, synced, then renamed
/// over it), so that an error leaves no partial file and an existing one untouched. The text
/// is parsed back first, so what is written always loads.
pub fn write_fabric_file(path: &Path, fabrics: &[Fabric], header: &str) -> std::io::Result<()> {
    let text = fabric_file_text(fabrics, header);
    FabricSet::parse(&text, &path.display().to_string()).map_err(std::io::Error::other)?;
    crate::formats::atomic::write_atomically(path, text.as_bytes())
}

/// A human-readable summary of `set`: one block per fabric with its key parameters.
pub fn describe(set: &FabricSet) -> String {
    use std::fmt::Write;
    let mut out = String::new();
    for fabric in set.fabrics() {
        let o = &fabric.options;
        let _ = writeln!(
            out,
            "{}  (gaussian_width {:?}, sigma_u {}°, tangent_sampling {:?})",
            fabric.name, o.gaussian_width, o.sigma_u_deg, o.tangent_sampling
        );
        for (j, t) in fabric.threads().into_iter().enumerate() {
            let a = t.albedo_rgb();
            let _ = writeln!(
                out,
                "  thread {}: a={:<5} eta={:<6} A=({:.4}, {:.4}, {:.4}) kd={:<4} gamma_s={}° gamma_v={}° offsets={:?}° lengths={:?}",
                j + 1,
                t.coverage,
                t.eta,
                a[0],
                a[1],
                a[2],
                t.kd,
                t.gamma_s_deg,
                t.gamma_v_deg,
                t.offsets_deg,
                t.lengths
            );
        }
    }
    out
}
