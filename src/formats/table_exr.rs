//! Tables as OpenEXR files: one EXR layer (part) per plane of the layout, named as the plane,
//! with the plane's f16 channels, laid out as [`crate::table`] documents; the first layer
//! carries one text attribute, `clothbake`, recording everything that made the table as a
//! TOML document:
//!
//! | key | content |
//! |---|---|
//! | `clothbake_version` | the clothbake version that baked it |
//! | `baker_revision` | [`BAKER_REVISION`] of the baker (absent: 1) |
//! | `layout` | a registered layout's name (`thread_frame`, `split_frame`, `grid4d`) |
//! | `resolution` | layout resolution |
//! | `integration` | the integration rule of every texel |
//! | `[[fabric]]` | the fabric, in the fabric-file schema (options included) |
//! | `texels` | SHA-256 (hex) of the texel data: every plane in layout order, each texel's f16 channels in plane order, as little-endian bit patterns (absent before baker revision 3) |
//! | `hash` | SHA-256 (hex) of this document's TOML without the `hash` and `texels` lines |
//!
//! `hash` identifies what the table was baked from (the bake manifest predicts it without
//! baking); `texels` checks what was baked: a file whose texels were damaged in a way that
//! still decodes (a flipped bit inside compressed data) is rejected by it.
//!
//! One attribute rather than several because the exr crate writes custom attributes in hash
//! map order, which would make the bytes of two bakes differ.
//!
//! Files are untrusted when read: size, header, dimensions, channels and attributes are
//! checked before any texel is allocated, and texels must be finite and non-negative.
//! Writing is atomic: a temporary file beside the target, synced, then renamed over it.

use crate::model::Fabric;
use crate::table::{Layout, Plane, Table};
use exr::prelude::*;
use half::f16;
use sha2::{Digest, Sha256};
use std::path::{Path, PathBuf};

/// Revision of the baking code, recorded in every table and part of its hash: raised
/// whenever a change makes the same inputs bake different texels, so that `bake` does not
/// keep the tables of an earlier baker as up to date (a version number alone does not move
/// between releases). Files without the field are revision 1.
/// 2: thread_frame masking planes by the baking rule; filled texels symmetric across the
/// u = 0 fold.
/// 3: the `texels` checksum.
/// 4: thread_frame and split_frame texels where ⟨P⟩ ≤ 1e-5 hold 0 (were: ⟨P⟩ < 1e-3 filled
/// from their neighbours).
/// 5: thread_frame and split_frame 4D texels hold the least-squares quadrilinear fit
/// instead of point samples ([`crate::table::prefilter`]); odd v counts.
/// 6: the model's θh and cos θd from one atan2 of the summed half-plane directions
/// (`model::sample::half_angle_and_difference`) instead of two atan2 and a cos: equal up
/// to rounding, which flips a few f16 texels.
/// 7: the βH axis of a thread whose curve jumps (velvet's thread 2) puts its texels on the
/// bands of its segments' ridges, and fewer on the gap between them.
/// 8: split_frame: the βH axis of a thread whose one ridge band reaches an end of the axis
/// (velvet's thread 1) is 1.5 times denser on the zone around the band's other edge.
pub const BAKER_REVISION: u32 = 8;

/// The first revision that records the `texels` checksum: from it on the checksum is required.
const TEXEL_CHECKSUM_REVISION: u32 = 3;

/// The revision of files that do not record one.
const FIRST_REVISION: u32 = 1;

/// The name of the EXR text attribute holding the provenance.
pub const ATTRIBUTE: &str = "clothbake";

/// Largest table file read: the largest legitimate table uncompressed, plus headers.
pub const MAX_TABLE_FILE_BYTES: u64 = 128 << 20;

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
    pub version: String,
    /// The [`BAKER_REVISION`] that baked it.
    pub baker_revision: u32,
    pub hash: String,
}

/// What made a table, as stored in its `clothbake` attribute.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct Provenance {
    #[serde(default, skip_serializing_if = "String::is_empty")]
    hash: String,
    #[serde(default, skip_serializing_if = "String::is_empty")]
    texels: String,
    clothbake_version: String,
    // Not written for revision 1, so that the hashes of files from before the field existed
    // still check out.
    #[serde(default = "first_revision", skip_serializing_if = "is_first_revision")]
    baker_revision: u32,
    layout: String,
    resolution: u32,
    integration: String,
    fabric: Vec<Fabric>,
}

impl Provenance {
    fn new(fabric: &Fabric, layout: Layout, resolution: u32) -> Self {
        let mut provenance = Self {
            hash: String::new(),
            texels: String::new(),
            clothbake_version: env!("CARGO_PKG_VERSION").to_string(),
            baker_revision: BAKER_REVISION,
            layout: layout.name().to_string(),
            resolution,
            integration: layout.unit().integration().to_string(),
            fabric: vec![fabric.clone()],
        };
        provenance.hash = provenance.content_hash();
        provenance
    }

    /// SHA-256 of the TOML of every field but `hash` and `texels`.
    fn content_hash(&self) -> String {
        let unhashed = Self {
            hash: String::new(),
            texels: String::new(),
            ..self.clone()
        };
        let text = toml::to_string(&unhashed).expect("provenance serialises to TOML");
        hex(&Sha256::digest(text.as_bytes()))
    }
}

/// Lower-case hexadecimal of `digest`.
pub fn hex(digest: &[u8]) -> String {
    digest.iter().map(|b| format!("{b:02x}")).collect()
}

/// SHA-256 of the texels of `planes` as the `texels` field defines it.
fn texel_checksum(planes: &[Plane]) -> String {
    let mut hasher = Sha256::new();
    for plane in planes {
        let bytes: Vec<u8> = plane
            .data
            .iter()
            .flat_map(|&v| f16::from_f32(v).to_bits().to_le_bytes())
            .collect();
        hasher.update(&bytes);
    }
    hex(&hasher.finalize())
}

fn first_revision() -> u32 {
    FIRST_REVISION
}

fn is_first_revision(revision: &u32) -> bool {
    *revision == FIRST_REVISION
}

/// The hash a table of `fabric` at `layout`/`resolution` baked by this version carries:
/// what the bake manifest compares to skip unchanged fabrics.
pub fn expected_hash(fabric: &Fabric, layout: Layout, resolution: u32) -> String {
    Provenance::new(fabric, layout, resolution).hash
}

/// The file name of a fabric's table in a tables directory, `NAME.exr`: where `bake` writes
/// it and `render`, `view` and the `table` evaluator look for it.
pub fn fabric_table_file(fabric_name: &str) -> String {
    format!("{fabric_name}.exr")
}

/// Writes `table` to `path` atomically; returns its provenance hash.
pub fn write_table(path: &Path, table: &Table) -> std::result::Result<String, TableFileError> {
    let (bytes, hash) = table_bytes(table, path)?;
    crate::formats::atomic::write_atomically(path, &bytes).map_err(|source| {
        TableFileError::Io {
            path: path.to_path_buf(),
            source,
        }
    })?;
    Ok(hash)
}

/// The bytes of `table`'s file, exactly as [`write_table`] writes them, and its provenance
/// hash; `path` names the file in errors.
pub fn table_bytes(
    table: &Table,
    path: &Path,
) -> std::result::Result<(Vec<u8>, String), TableFileError> {
    let provenance = Provenance {
        texels: texel_checksum(table.planes()),
        ..Provenance::new(&table.fabric, table.layout, table.resolution)
    };
    let provenance_toml = toml::to_string(&provenance).expect("provenance serialises to TOML");
    let layers: Vec<Layer<AnyChannels<FlatSamples>>> = table
        .planes()
        .iter()
        .enumerate()
        .map(|(index, plane)| {
            let count = plane.spec.channels.len();
            let channels: Vec<AnyChannel<FlatSamples>> = plane
                .spec
                .channels
                .iter()
                .enumerate()
                .map(|(c, name)| {
                    let samples = plane
                        .data
                        .iter()
                        .skip(c)
                        .step_by(count)
                        .map(|&v| f16::from_f32(v))
                        .collect();
                    AnyChannel::new(*name, FlatSamples::F16(samples))
                })
                .collect();
            let mut attributes = LayerAttributes::named(plane.spec.name.as_str());
            if index == 0 {
                attributes.other.insert(
                    Text::from(ATTRIBUTE),
                    AttributeValue::Text(Text::from(provenance_toml.as_str())),
                );
            }
            Layer::new(
                (plane.spec.width, plane.spec.height),
                attributes,
                Encoding::SMALL_LOSSLESS,
                AnyChannels::sort(channels.into()),
            )
        })
        .collect();
    let image = Image::from_layers(
        ImageAttributes::new(IntegerBounds::from_dimensions((1, 1))),
        layers,
    );
    let mut bytes = std::io::Cursor::new(Vec::new());
    image
        .write()
        .to_buffered(&mut bytes)
        .map_err(|source| TableFileError::Exr {
            path: path.to_path_buf(),
            source,
        })?;
    Ok((bytes.into_inner(), provenance.hash))
}

fn text_attribute(header: &exr::meta::header::Header, key: &str) -> Option<String> {
    match header.own_attributes.other.get(&Text::from(key)) {
        Some(AttributeValue::Text(text)) => Some(text.to_string()),
        _ => None,
    }
}

/// Reads and validates a table file.
pub fn read_table(path: &Path) -> std::result::Result<TableFile, TableFileError> {
    read_table_bytes(&table_file_bytes(path)?, path)
}

/// The bytes of the file at `path`, unread if it is larger than any table.
pub fn table_file_bytes(path: &Path) -> std::result::Result<Vec<u8>, TableFileError> {
    let io_error = |source| TableFileError::Io {
        path: path.to_path_buf(),
        source,
    };
    // Checked before reading, so that a huge file is never read into memory.
    let size = std::fs::metadata(path).map_err(io_error)?.len();
    if size > MAX_TABLE_FILE_BYTES {
        return Err(TableFileError::Invalid {
            path: path.to_path_buf(),
            message: too_large(size),
        });
    }
    std::fs::read(path).map_err(io_error)
}

fn too_large(size: u64) -> String {
    format!("is {size} bytes, larger than any table ({MAX_TABLE_FILE_BYTES})")
}

/// Reads and validates a table from the bytes of its file (for asset systems that hand
/// over bytes, such as Bevy's); `path` names it in errors. A caller reading from a stream
/// should stop after [`MAX_TABLE_FILE_BYTES`] + 1 bytes: more is refused here anyway.
pub fn read_table_bytes(
    bytes: &[u8],
    path: &Path,
) -> std::result::Result<TableFile, TableFileError> {
    let invalid = |message: String| TableFileError::Invalid {
        path: path.to_path_buf(),
        message,
    };
    let exr_error = |source| TableFileError::Exr {
        path: path.to_path_buf(),
        source,
    };
    if bytes.len() as u64 > MAX_TABLE_FILE_BYTES {
        return Err(invalid(too_large(bytes.len() as u64)));
    }

    // The headers alone first: nothing sized by the file is allocated until they check out.
    let meta = exr::meta::MetaData::read_from_buffered(bytes, false).map_err(exr_error)?;
    let first = meta
        .headers
        .first()
        .ok_or_else(|| invalid("has no layers".into()))?;
    let text = text_attribute(first, ATTRIBUTE)
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
    let specs = layout.plane_specs(fabric, resolution);
    if meta.headers.len() != specs.len() {
        return Err(invalid(format!(
            "has {} layers, {layout} needs {}",
            meta.headers.len(),
            specs.len()
        )));
    }
    for (header, spec) in meta.headers.iter().zip(&specs) {
        let name = header
            .own_attributes
            .layer_name
            .as_ref()
            .map(|n| n.to_string())
            .unwrap_or_default();
        let stored = (header.layer_size.x(), header.layer_size.y());
        if name != spec.name || stored != (spec.width, spec.height) || header.deep {
            return Err(invalid(format!(
                "layer '{name}' is {}x{}{}, but {layout} at resolution {resolution} needs layer '{}' of {}x{}",
                stored.0,
                stored.1,
                if header.deep { " (deep)" } else { "" },
                spec.name,
                spec.width,
                spec.height
            )));
        }
        let channels: Vec<(String, SampleType)> = header
            .channels
            .list
            .iter()
            .map(|c| (c.name.to_string(), c.sample_type))
            .collect();
        let expected: Vec<(String, SampleType)> = spec
            .channels
            .iter()
            .map(|c| (c.to_string(), SampleType::F16))
            .collect();
        if channels != expected {
            return Err(invalid(format!(
                "layer '{name}' has channels {channels:?}, expected {expected:?}"
            )));
        }
    }

    let image = read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .all_layers()
        .all_attributes()
        .from_buffered(std::io::Cursor::new(bytes))
        .map_err(exr_error)?;
    let mut planes = Vec::with_capacity(specs.len());
    for spec in specs {
        let layer = image
            .layer_data
            .iter()
            .find(|l| {
                l.attributes
                    .layer_name
                    .as_ref()
                    .is_some_and(|n| n.to_string() == spec.name)
            })
            .ok_or_else(|| invalid(format!("layer '{}' is missing", spec.name)))?;
        let list = &layer.channel_data.list;
        if list.len() != spec.channels.len()
            || list
                .iter()
                .any(|c| c.sample_data.len() != spec.texel_count())
        {
            return Err(invalid(format!(
                "layer '{}' data does not match its header",
                spec.name
            )));
        }
        let count = spec.channels.len();
        let mut data = vec![0.0f32; spec.texel_count() * count];
        for (c, channel) in list.iter().enumerate() {
            for (slot, value) in data
                .iter_mut()
                .skip(c)
                .step_by(count)
                .zip(channel.sample_data.values_as_f32())
            {
                *slot = value;
            }
        }
        if let Some(i) = data.iter().position(|v| !v.is_finite() || *v < 0.0) {
            let texel = i / count;
            return Err(invalid(format!(
                "layer '{}' texel ({}, {}) holds {:?}: tables hold finite, non-negative values",
                spec.name,
                texel % spec.width,
                texel / spec.width,
                &data[texel * count..texel * count + count]
            )));
        }
        planes.push(Plane { spec, data });
    }
    if provenance.baker_revision >= TEXEL_CHECKSUM_REVISION || !provenance.texels.is_empty() {
        let checksum = texel_checksum(&planes);
        if checksum != provenance.texels {
            return Err(invalid(format!(
                "texel checksum {checksum} does not match the recorded '{}': the texels are damaged",
                provenance.texels
            )));
        }
    }
    let table =
        Table::new(layout, resolution, fabric, planes).map_err(|e| invalid(e.to_string()))?;
    Ok(TableFile {
        table,
        version: provenance.clothbake_version.clone(),
        baker_revision: provenance.baker_revision,
        hash,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::formats::fabric_toml::FabricSet;

    /// Tables of an earlier baker stay readable (their recorded hash still checks out) but
    /// no longer match what this baker would write, so `bake` bakes them again.
    #[test]
    fn earlier_baker_revisions_read_back_and_count_as_stale() {
        let fabric = FabricSet::builtin().fabrics()[0].clone();
        let current = Provenance::new(&fabric, Layout::DEFAULT, 16);
        let text = toml::to_string(&current).unwrap();
        assert!(text.contains(&format!("baker_revision = {BAKER_REVISION}")));

        let mut earlier = Provenance {
            baker_revision: FIRST_REVISION,
            ..current.clone()
        };
        earlier.hash = earlier.content_hash();
        let earlier_text = toml::to_string(&earlier).unwrap();
        assert!(!earlier_text.contains("baker_revision"), "{earlier_text}");
        let read: Provenance = toml::from_str(&earlier_text).unwrap();
        assert_eq!(read.baker_revision, FIRST_REVISION);
        assert_eq!(read.content_hash(), read.hash);
        assert_ne!(read.hash, expected_hash(&fabric, Layout::DEFAULT, 16));
    }
}
