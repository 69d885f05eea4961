//! Tables as OpenEXR files: one image of f16 channels `reflection`, `transmission1`,
//! `transmission2` laid out as [`crate::table`] documents, plus one text attribute,
//! `clothbake`, recording everything that made the table as a TOML document:
//!
//! | key | content |
//! |---|---|
//! | `clothbake_version` | the clothbake version that baked it |
//! | `layout` | layout name (`grid4d`) |
//! | `resolution` | layout resolution N |
//! | `integration` | the integration rule of every texel |
//! | `[[fabric]]` | the fabric, in the fabric-file schema (options included) |
//! | `hash` | SHA-256 (hex) of this document's TOML without the `hash` line |
//!
//! One attribute rather than several because the exr crate writes custom attributes in hash
//! map order, which would make the bytes of two bakes differ.
//!
//! Files are untrusted when read: size, header, dimensions, channels and attributes are
//! checked before any texel is allocated, and texels must be finite and non-negative.
//! Writing is atomic: a temporary file beside the target, synced, then renamed over it.

use crate::model::Fabric;
use crate::table::{CHANNELS, Layout, Table};
use exr::prelude::*;
use half::f16;
use sha2::{Digest, Sha256};
use std::path::{Path, PathBuf};

/// Describes the direct evaluation every texel comes from.
pub const INTEGRATION: &str =
    "direct: per-segment midpoint rule, alpha spacing <= min(0.05 deg, sigma/16)";

/// Why a table file was rejected or could not be written.
#[derive(Debug, thiserror::Error)]
pub enum TableFileError {
    #[error("table {path}: {message}")]
    Invalid { path: PathBuf, message: String },
    #[error("table {path}: {source}")]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("table {path}: not a readable OpenEXR file: {source}")]
    Exr {
        path: PathBuf,
        source: exr::error::Error,
    },
}

/// A table with the provenance recorded in its file.
#[derive(Clone, Debug)]
pub struct TableFile {
    pub table: Table,
    pub fabric: Fabric,
    pub version: String,
    pub hash: String,
}

/// The name of the EXR text attribute holding the provenance.
pub const ATTRIBUTE: &str = "clothbake";

/// What made a table, as stored in its `clothbake` attribute.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct Provenance {
    #[serde(default, skip_serializing_if = "String::is_empty")]
    hash: String,
    clothbake_version: String,
    layout: String,
    resolution: u32,
    integration: String,
    fabric: Vec<Fabric>,
}

impl Provenance {
    fn new(fabric: &Fabric, layout: Layout, resolution: u32) -> Self {
        let mut provenance = Self {
            hash: String::new(),
            clothbake_version: env!("CARGO_PKG_VERSION").to_string(),
            layout: layout.name().to_string(),
            resolution,
            integration: INTEGRATION.to_string(),
            fabric: vec![fabric.clone()],
        };
        provenance.hash = provenance.content_hash();
        provenance
    }

    /// SHA-256 of the TOML of every field but `hash`.
    fn content_hash(&self) -> String {
        let unhashed = Self {
            hash: String::new(),
            ..self.clone()
        };
        let text = toml::to_string(&unhashed).expect("provenance serialises to TOML");
        Sha256::digest(text.as_bytes())
            .iter()
            .map(|b| format!("{b:02x}"))
            .collect()
    }
}

/// The hash a table of `fabric` at `layout`/`resolution` baked by this version carries:
/// what the bake manifest compares to skip unchanged fabrics.
pub fn expected_hash(fabric: &Fabric, layout: Layout, resolution: u32) -> String {
    Provenance::new(fabric, layout, resolution).hash
}

/// Writes `table`, baked from `fabric`, to `path` atomically.
pub fn write_table(
    path: &Path,
    table: &Table,
    fabric: &Fabric,
) -> std::result::Result<String, TableFileError> {
    let io = |source| TableFileError::Io {
        path: path.to_path_buf(),
        source,
    };
    let provenance = Provenance::new(fabric, table.layout, table.resolution);
    let provenance_toml = toml::to_string(&provenance).expect("provenance serialises to TOML");
    let (width, height) = table.image_size();
    let channels: Vec<AnyChannel<FlatSamples>> = CHANNELS
        .iter()
        .enumerate()
        .map(|(c, name)| {
            let samples = table.texels().iter().map(|t| f16::from_f32(t[c])).collect();
            AnyChannel::new(*name, FlatSamples::F16(samples))
        })
        .collect();
    let mut layer_attributes = LayerAttributes::named("clothbake");
    layer_attributes.other.insert(
        Text::from(ATTRIBUTE),
        AttributeValue::Text(Text::from(provenance_toml.as_str())),
    );
    let layer = Layer::new(
        (width, height),
        layer_attributes,
        Encoding::SMALL_LOSSLESS,
        AnyChannels::sort(channels.into()),
    );
    let image = Image::from_layer(layer);

    let directory = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let file_name = path.file_name().ok_or_else(|| TableFileError::Invalid {
        path: path.to_path_buf(),
        message: "is not a file path".into(),
    })?;
    let temporary = directory.join(format!(
        ".{}.{}.tmp",
        file_name.to_string_lossy(),
        std::process::id()
    ));
    let result = image
        .write()
        .to_file(&temporary)
        .map_err(|source| TableFileError::Exr {
            path: temporary.clone(),
            source,
        })
        .and_then(|()| {
            std::fs::File::open(&temporary)
                .and_then(|f| f.sync_all())
                .map_err(io)
        })
        .and_then(|()| std::fs::rename(&temporary, path).map_err(io));
    if result.is_err() {
        let _ = std::fs::remove_file(&temporary);
    }
    result.map(|()| provenance.hash)
}

fn text_attribute(header: &exr::meta::header::Header, key: &str) -> Option<String> {
    match header.own_attributes.other.get(&Text::from(key)) {
        Some(AttributeValue::Text(text)) => Some(text.to_string()),
        _ => None,
    }
}

/// Reads and validates a table file.
pub fn read_table(path: &Path) -> std::result::Result<TableFile, TableFileError> {
    let invalid = |message: String| TableFileError::Invalid {
        path: path.to_path_buf(),
        message,
    };
    let exr_error = |source| TableFileError::Exr {
        path: path.to_path_buf(),
        source,
    };
    let size = std::fs::metadata(path)
        .map_err(|source| TableFileError::Io {
            path: path.to_path_buf(),
            source,
        })?
        .len();
    // Largest legitimate table, uncompressed, plus headers.
    let max_bytes = Layout::ALL
        .iter()
        .map(|l| {
            let (w, h) = l.image_size(l.max_resolution());
            (w * h * CHANNELS.len() * 2) as u64
        })
        .max()
        .unwrap_or(0)
        + (1 << 20);
    if size > max_bytes {
        return Err(invalid(format!(
            "is {size} bytes, larger than any table ({max_bytes})"
        )));
    }

    // The header alone first: nothing sized by the file is allocated until it checks out.
    let meta = exr::meta::MetaData::read_from_file(path, false).map_err(exr_error)?;
    let [header] = meta.headers.as_slice() else {
        return Err(invalid(format!(
            "has {} layers, expected 1",
            meta.headers.len()
        )));
    };
    let text = text_attribute(header, ATTRIBUTE)
        .ok_or_else(|| invalid(format!("lacks the text attribute '{ATTRIBUTE}'")))?;
    let provenance: Provenance = toml::from_str(&text)
        .map_err(|e| invalid(format!("attribute '{ATTRIBUTE}' is not valid: {e}")))?;
    let hash = provenance.content_hash();
    if hash != provenance.hash {
        return Err(invalid(format!(
            "recorded hash {} does not match its attribute ({hash})",
            provenance.hash
        )));
    }
    let layout = Layout::from_name(&provenance.layout)
        .ok_or_else(|| invalid(format!("unknown layout '{}'", provenance.layout)))?;
    let resolution = provenance.resolution;
    if !(2..=layout.max_resolution()).contains(&resolution) {
        return Err(invalid(format!(
            "resolution {resolution} is outside 2..={} for {layout}",
            layout.max_resolution()
        )));
    }
    let [fabric] = provenance.fabric.as_slice() else {
        return Err(invalid(format!(
            "records {} fabrics, expected 1",
            provenance.fabric.len()
        )));
    };
    fabric.validate().map_err(|e| invalid(e.to_string()))?;
    let (width, height) = layout.image_size(resolution);
    let stored = (header.layer_size.x(), header.layer_size.y());
    if stored != (width, height) || header.deep {
        return Err(invalid(format!(
            "image is {}x{}{}, but {layout} at resolution {resolution} needs {width}x{height}",
            stored.0,
            stored.1,
            if header.deep { " (deep)" } else { "" }
        )));
    }
    let channels: Vec<(String, SampleType)> = header
        .channels
        .list
        .iter()
        .map(|c| (c.name.to_string(), c.sample_type))
        .collect();
    let expected: Vec<(String, SampleType)> = CHANNELS
        .iter()
        .map(|c| (c.to_string(), SampleType::F16))
        .collect();
    if channels != expected {
        return Err(invalid(format!(
            "channels are {channels:?}, expected {expected:?}"
        )));
    }
    let image = read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .first_valid_layer()
        .all_attributes()
        .from_file(path)
        .map_err(exr_error)?;
    let list = &image.layer_data.channel_data.list;
    if list.len() != CHANNELS.len() || list.iter().any(|c| c.sample_data.len() != width * height) {
        return Err(invalid("channel data does not match the header".into()));
    }
    let mut texels = vec![[0.0f32; 3]; width * height];
    for (c, channel) in list.iter().enumerate() {
        for (texel, value) in texels.iter_mut().zip(channel.sample_data.values_as_f32()) {
            texel[c] = value;
        }
    }
    if let Some(i) = texels
        .iter()
        .position(|t| t.iter().any(|v| !v.is_finite() || *v < 0.0))
    {
        return Err(invalid(format!(
            "texel ({}, {}) holds {:?}: tables hold finite, non-negative values",
            i % width,
            i / width,
            texels[i]
        )));
    }
    let albedo = fabric.threads().map(|t| t.albedo_rgb().map(|c| c as f32));
    Ok(TableFile {
        table: Table::new(layout, resolution, albedo, texels),
        fabric: fabric.clone(),
        version: provenance.clothbake_version.clone(),
        hash,
    })
}
