//! Measured samples of F to fit: JSON lines, one sample a line, in the patch frame of
//! docs/model.md#frames-and-directions (as `clothbake eval` writes them):
//!
//! ```text
//! {"wi":[x,y,z],"wo":[x,y,z],"f":[r,g,b]}
//! {"wi":[x,y,z],"wo":[x,y,z],"f":[r,g,b],"weight":2.0}
//! ```
//!
//! Directions are normalised here and must lie strictly above the horizon (z > 0 after
//! normalising: F is 0 below it, so a sample there constrains nothing). `f` is the
//! cosine-weighted transfer F (each component finite, ≥ 0, at most [`MAX_VALUE`]); `weight`
//! (default 1) multiplies the sample's squared residual and must be finite and > 0. Blank
//! lines and lines whose first non-blank character is `#` are skipped, so a file can carry
//! its own provenance. Unknown keys are errors.
//!
//! The file is untrusted: its size is checked before it is read ([`MAX_SAMPLE_FILE_BYTES`]),
//! each line's length too ([`MAX_LINE_BYTES`]), and every error names the line (1-based, as
//! an editor counts) and the field. Nothing in it can make the parser panic.

use crate::formats::table_exr::hex;
use glam::DVec3;
use serde::Deserialize;
use sha2::{Digest, Sha256};
use std::path::{Path, PathBuf};

pub use crate::formats::json_lines::MAX_LINE_BYTES;
use crate::formats::json_lines::{DirectionError, DirectionProblem, unit_direction};

/// Largest sample file read: 64 MiB is about a million samples, far more than a fit needs.
pub const MAX_SAMPLE_FILE_BYTES: u64 = 64 << 20;

/// Largest accepted component of `f` and largest weight. F of the built-in fabrics peaks
/// near 10 (the narrowest highlights); 1e6 leaves room for any unit convention while
/// keeping every sum of squares of a million samples far from overflow.
pub const MAX_VALUE: f64 = 1e6;

/// One measured sample: unit directions in the patch frame, F (RGB) and a weight.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample {
    pub wi: DVec3,
    pub wo: DVec3,
    pub f: DVec3,
    pub weight: f64,
}

/// The samples of one file, in file order, with where they came from.
#[derive(Clone, Debug, PartialEq)]
pub struct Samples {
    pub samples: Vec<Sample>,
    /// The file's path, or what the caller named the text.
    pub origin: String,
    /// SHA-256 of the bytes read, lower-case hex: the provenance a fitted fabric records.
    pub sha256: String,
}

/// Why a sample file was rejected.
#[derive(Debug, thiserror::Error)]
pub enum SampleError {
    #[error("cannot read sample file {path}: {source}")]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error(
        "sample file {path} is {size} bytes, larger than the {MAX_SAMPLE_FILE_BYTES}-byte limit"
    )]
    TooLarge { path: PathBuf, size: u64 },
    #[error("sample file {origin}, line {line}, field '{field}': {message}")]
    Line {
        origin: String,
        line: usize,
        field: String,
        message: String,
    },
    #[error("sample file {origin} holds no samples")]
    Empty { origin: String },
    #[error(
        "sample file {origin}: {count} samples are fewer than the {needed} a fit of {parameters} \
         free parameters needs ({what})"
    )]
    TooFew {
        origin: String,
        count: usize,
        needed: usize,
        parameters: usize,
        what: String,
    },
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SampleLine {
    wi: [f64; 3],
    wo: [f64; 3],
    f: [f64; 3],
    #[serde(default)]
    weight: Option<f64>,
}

/// The field a serde_json message is about, when it names one.
fn field_of(message: &str) -> String {
    if let Some(rest) = message.strip_prefix("unknown field `")
        && let Some(end) = rest.find('`')
    {
        return rest[..end].to_string();
    }
    for key in ["wi", "wo", "f", "weight"] {
        if message.contains(&format!("`{key}`")) {
            return key.into();
        }
    }
    "(line)".into()
}

/// A direction read as every command reads one ([`unit_direction`]), and above the horizon.
fn direction(v: [f64; 3], field: &str) -> Result<DVec3, DirectionError> {
    let unit = unit_direction(v, field)?;
    if unit.z <= 0.0 {
        return Err(DirectionError {
            field: field.to_string(),
            problem: DirectionProblem::BelowHorizon,
        });
    }
    Ok(unit)
}

/// Parses one line (already known not to be blank or a comment).
fn parse_line(text: &str) -> Result<Sample, (String, String)> {
    let line: SampleLine = serde_json::from_str(text).map_err(|e| {
        let message = e.to_string();
        (
            field_of(&message),
            format!(
                "expected {{\"wi\":[x,y,z],\"wo\":[x,y,z],\"f\":[r,g,b]}} with an optional \
                 \"weight\": {message}"
            ),
        )
    })?;
    checked_sample(line.wi, line.wo, line.f, line.weight)
}

/// One sample checked as a file line is: directions finite, non-zero and above the horizon
/// (normalised), `f` finite, ≥ 0 and at most [`MAX_VALUE`], the weight (1 when absent)
/// finite, > 0 and at most [`MAX_VALUE`]. The error names the field.
fn checked_sample(
    wi: [f64; 3],
    wo: [f64; 3],
    f: [f64; 3],
    weight: Option<f64>,
) -> Result<Sample, (String, String)> {
    let refuse = |e: DirectionError, v: [f64; 3]| {
        let [x, y, z] = v;
        (e.field, format!("[{x}, {y}, {z}] {}", e.problem))
    };
    let wi = direction(wi, "wi").map_err(|e| refuse(e, wi))?;
    let wo = direction(wo, "wo").map_err(|e| refuse(e, wo))?;
    for (c, &v) in f.iter().enumerate() {
        let fail = |m: String| ("f".to_string(), format!("component {c}: {m}"));
        if !v.is_finite() {
            return Err(fail(format!("{v} is not finite")));
        }
        if v < 0.0 {
            return Err(fail(format!("{v} is negative: F is never below 0")));
        }
        if v > MAX_VALUE {
            return Err(fail(format!("{v} is larger than {MAX_VALUE}")));
        }
    }
    let weight = weight.unwrap_or(1.0);
    if !weight.is_finite() || weight <= 0.0 || weight > MAX_VALUE {
        return Err((
            "weight".into(),
            format!("{weight} must be finite, > 0 and at most {MAX_VALUE}"),
        ));
    }
    Ok(Sample {
        wi,
        wo,
        f: DVec3::from_array(f),
        weight,
    })
}

/// One row of samples given as arrays (Python's NumPy arrays): `wi`, `wo`, `f` and an
/// optional weight.
pub type SampleRow = ([f64; 3], [f64; 3], [f64; 3], Option<f64>);

impl Samples {
    /// Samples from rows, each checked as a file line is; an error names the row (1-based,
    /// as `line`) and the field. `origin` names the source; the SHA-256 is of the rows'
    /// numbers as little-endian f64 (a weight of 1 where none is given), in row order.
    pub fn from_rows(rows: &[SampleRow], origin: &str) -> Result<Samples, SampleError> {
        let mut hasher = Sha256::new();
        let mut samples = Vec::with_capacity(rows.len());
        for (i, &(wi, wo, f, weight)) in rows.iter().enumerate() {
            let sample = checked_sample(wi, wo, f, weight).map_err(|(field, message)| {
                SampleError::Line {
                    origin: origin.to_string(),
                    line: i + 1,
                    field,
                    message,
                }
            })?;
            for v in wi
                .iter()
                .chain(&wo)
                .chain(&f)
                .chain([&weight.unwrap_or(1.0)])
            {
                hasher.update(v.to_le_bytes());
            }
            samples.push(sample);
        }
        Samples::new(samples, origin, hex(&hasher.finalize()))
    }

    /// The samples of `origin`, an error when there are none.
    fn new(samples: Vec<Sample>, origin: &str, sha256: String) -> Result<Samples, SampleError> {
        if samples.is_empty() {
            return Err(SampleError::Empty {
                origin: origin.to_string(),
            });
        }
        Ok(Samples {
            samples,
            origin: origin.to_string(),
            sha256,
        })
    }
}

/// Parses sample lines from `bytes`; `origin` names the source in errors. Never panics.
pub fn parse_samples(bytes: &[u8], origin: &str) -> Result<Samples, SampleError> {
    let sha256 = hex(&Sha256::digest(bytes));
    let mut samples = Vec::new();
    let fail = |line: usize, field: &str, message: String| SampleError::Line {
        origin: origin.to_string(),
        line,
        field: field.to_string(),
        message,
    };
    for (index, raw) in bytes.split(|&b| b == b'\n').enumerate() {
        let line = index + 1;
        if raw.len() > MAX_LINE_BYTES + 1 {
            return Err(fail(
                line,
                "(line)",
                format!("longer than {MAX_LINE_BYTES} bytes"),
            ));
        }
        let text =
            std::str::from_utf8(raw).map_err(|_| fail(line, "(line)", "is not UTF-8".into()))?;
        let text = text.trim();
        if text.is_empty() || text.starts_with('#') {
            continue;
        }
        let sample = parse_line(text).map_err(|(field, message)| fail(line, &field, message))?;
        samples.push(sample);
    }
    Samples::new(samples, origin, sha256)
}

/// Reads and parses a sample file, its size checked before anything is read.
pub fn load_samples(path: &Path) -> Result<Samples, SampleError> {
    let io = |source| SampleError::Io {
        path: path.to_path_buf(),
        source,
    };
    let size = std::fs::metadata(path).map_err(io)?.len();
    if size > MAX_SAMPLE_FILE_BYTES {
        return Err(SampleError::TooLarge {
            path: path.to_path_buf(),
            size,
        });
    }
    let mut bytes = Vec::with_capacity(size as usize);
    use std::io::Read;
    std::fs::File::open(path)
        .map_err(io)?
        // The file may grow between the check and the read: read at most one byte past the limit.
        .take(MAX_SAMPLE_FILE_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(io)?;
    if bytes.len() as u64 > MAX_SAMPLE_FILE_BYTES {
        return Err(SampleError::TooLarge {
            path: path.to_path_buf(),
            size: bytes.len() as u64,
        });
    }
    parse_samples(&bytes, &path.display().to_string())
}

/// Writes `samples` as JSON lines in the format [`parse_samples`] reads (what a test or a
/// measurement script feeds the fit).
pub fn write_samples(samples: &[Sample], out: &mut impl std::io::Write) -> std::io::Result<()> {
    for s in samples {
        let mut line = serde_json::json!({
            "wi": s.wi.to_array(),
            "wo": s.wo.to_array(),
            "f": s.f.to_array(),
        });
        if s.weight != 1.0 {
            line["weight"] = serde_json::json!(s.weight);
        }
        serde_json::to_writer(&mut *out, &line).map_err(std::io::Error::other)?;
        out.write_all(b"\n")?;
    }
    Ok(())
}

/// Synthetic measurements: `fabric`'s converged direct F at `pairs`, each channel multiplied
/// by `1 + noise · N(0, 1)` (seeded; clamped at 0): what the round-trip tests, the bench and
/// examples/fit_round_trips.rs fit.
pub fn synthetic_samples(
    fabric: &crate::model::Fabric,
    pairs: &[(DVec3, DVec3)],
    noise: f64,
    seed: u64,
) -> Vec<Sample> {
    use crate::model::{Integration, Patch};
    use rand::{Rng, SeedableRng};
    use rayon::prelude::*;
    let patch = Patch::new(fabric, Integration::Direct);
    let values: Vec<DVec3> = pairs
        .par_iter()
        .map(|&(wi, wo)| patch.eval(wi, wo))
        .collect();
    let mut rng = rand_pcg::Pcg64::seed_from_u64(seed);
    let mut normal = move || {
        // Box–Muller: platform independent, unlike a library's ziggurat tables.
        let u1 = 1.0 - rng.random::<f64>();
        let u2 = rng.random::<f64>();
        (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
    };
    pairs
        .iter()
        .zip(values)
        .map(|(&(wi, wo), f)| {
            let noisy = DVec3::new(
                f.x * (1.0 + noise * normal()),
                f.y * (1.0 + noise * normal()),
                f.z * (1.0 + noise * normal()),
            );
            Sample {
                wi,
                wo,
                f: noisy.max(DVec3::ZERO),
                weight: 1.0,
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn error(text: &str) -> String {
        parse_samples(text.as_bytes(), "t.jsonl")
            .unwrap_err()
            .to_string()
    }

    const GOOD: &str = r#"{"wi":[0,0,1],"wo":[0.3,0.2,0.9],"f":[0.1,0.2,0.3]}"#;

    #[test]
    fn parses_normalises_and_skips_comments_and_blank_lines() {
        let text = format!(
            "# made by hand\n\n{GOOD}\r\n  \n{{\"wi\":[0,0,2],\"wo\":[0,1,1],\"f\":[0,0,0],\"weight\":2.5}}\n"
        );
        let s = parse_samples(text.as_bytes(), "t").unwrap();
        assert_eq!(s.samples.len(), 2);
        assert!((s.samples[1].wo.length() - 1.0).abs() < 1e-15);
        assert_eq!(s.samples[1].weight, 2.5);
        assert_eq!(s.samples[0].weight, 1.0);
        assert_eq!(s.sha256.len(), 64);
    }

    #[test]
    fn errors_name_the_line_and_the_field() {
        let cases = [
            (r#"{"wi":[0,0,1],"wo":[0,0,1],"f":[NaN,0,0]}"#, "(line)"),
            (r#"{"wi":[0,0,1],"wo":[0,0,1],"f":[1e999,0,0]}"#, "(line)"),
            (r#"{"wi":[0,0,1],"wo":[0,0,1],"f":[2e6,0,0]}"#, "'f'"),
            (r#"{"wi":[0,0,1],"wo":[0,0,1],"f":[0.1,-0.2,0]}"#, "'f'"),
            (r#"{"wi":[0,0,0],"wo":[0,0,1],"f":[0,0,0]}"#, "'wi'"),
            (r#"{"wi":[0,0,1],"wo":[1,0,0],"f":[0,0,0]}"#, "'wo'"),
            (r#"{"wi":[0,0,1],"wo":[1,0,-1],"f":[0,0,0]}"#, "'wo'"),
            (
                r#"{"wi":[0,0,1],"wo":[0,0,1],"f":[0,0,0],"weight":0}"#,
                "'weight'",
            ),
            (
                r#"{"wi":[0,0,1],"wo":[0,0,1],"f":[0,0,0],"weight":-1}"#,
                "'weight'",
            ),
            (
                r#"{"wi":[0,0,1],"wo":[0,0,1],"f":[0,0,0],"colour":1}"#,
                "'colour'",
            ),
            (r#"{"wi":[0,0,1],"wo":[0,0,1]}"#, "'f'"),
            (r#"{"wi":[0,0,1],"wo":[0,0,1],"f":[0,0]}"#, "(line)"),
            ("not json", "(line)"),
        ];
        for (bad, field) in cases {
            let message = error(&format!("{GOOD}\n# comment\n{bad}\n{GOOD}\n"));
            assert!(message.contains("line 3"), "{bad}: {message}");
            assert!(message.contains(field), "{bad}: {message}");
        }
    }

    #[test]
    fn rejects_long_lines_non_utf8_and_empty_files() {
        let long = format!("{GOOD}\n{}\n", " ".repeat(MAX_LINE_BYTES + 10));
        assert!(error(&long).contains("line 2"));
        let mut bytes = format!("{GOOD}\n").into_bytes();
        bytes.extend_from_slice(&[0xff, 0xfe, b'\n']);
        let message = parse_samples(&bytes, "t").unwrap_err().to_string();
        assert!(
            message.contains("line 2") && message.contains("UTF-8"),
            "{message}"
        );
        assert!(error("# nothing\n\n").contains("no samples"));
    }

    #[test]
    fn write_then_parse_round_trips() {
        let s = parse_samples(GOOD.as_bytes(), "t").unwrap().samples;
        let mut out = Vec::new();
        write_samples(&s, &mut out).unwrap();
        assert_eq!(parse_samples(&out, "t").unwrap().samples, s);
    }
}
