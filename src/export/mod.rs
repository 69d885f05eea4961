//! `clothbake export`: a fabric's best approximation by an engine's stock material, written
//! in that engine's own file, with what it loses measured (docs/export.md).
//!
//! A target ([`ExportTarget`], one entry each in [`TARGETS`]) pairs a stock model (a
//! registered evaluator, [`crate::evaluator::stock`]) with the writer of its file
//! ([`crate::formats::export`]). An export fits the model to the fabric's F, measures the
//! fit against the fabric ([`loss`]) and writes the file atomically, the figures in it.

pub mod loss;

use crate::evaluator::stock::fit::{StockFit, fit};
use crate::evaluator::stock::{StockMaterial, StockModel};
use crate::evaluator::{filament, gltf, openpbr, unreal};
use crate::formats::atomic::write_atomically;
use crate::formats::export::{ExportDocument, engine_json, gltf_file, materialx};
use crate::model::Fabric;
use crate::scene::Scene;
use crate::scene::mesh::Mesh;
use loss::Loss;
use std::path::{Path, PathBuf};

/// One export target: an engine's file and the stock model it holds.
#[derive(Clone, Copy, Debug)]
pub struct ExportTarget {
    /// The word of `--to` (`gltf`, `materialx`).
    pub name: &'static str,
    pub model: &'static StockModel,
    /// The file's usual extension.
    pub extension: &'static str,
    /// The engine's name for the material model the file holds (an engine JSON's
    /// `shading_model`).
    pub shading_model: &'static str,
    /// The file's text for a document.
    pub write: fn(&ExportDocument) -> String,
}

/// The registry: every target of `--to`.
pub const TARGETS: &[ExportTarget] = &[
    ExportTarget {
        name: "gltf",
        shading_model: "pbrMetallicRoughness",
        model: &gltf::MODEL,
        extension: "gltf",
        write: gltf_file::write,
    },
    ExportTarget {
        name: "materialx",
        shading_model: "open_pbr_surface",
        model: &openpbr::MODEL,
        extension: "mtlx",
        write: materialx::write,
    },
    ExportTarget {
        name: "filament",
        shading_model: "cloth",
        model: &filament::MODEL,
        extension: "json",
        write: engine_json::write,
    },
    ExportTarget {
        name: "unreal",
        shading_model: "MSM_Cloth",
        model: &unreal::MODEL,
        extension: "json",
        write: engine_json::write,
    },
];

/// The target named `name`, or the list of known ones.
pub fn target(name: &str) -> Result<&'static ExportTarget, ExportError> {
    TARGETS
        .iter()
        .find(|t| t.name == name)
        .ok_or_else(|| ExportError::UnknownTarget {
            name: name.to_string(),
            known: TARGETS
                .iter()
                .map(|t| t.name)
                .collect::<Vec<_>>()
                .join(", "),
        })
}

/// Why an export failed.
#[derive(Debug, thiserror::Error)]
pub enum ExportError {
    #[error("unknown export target '{name}'; targets: {known}")]
    UnknownTarget { name: String, known: String },
    #[error(transparent)]
    Mesh(#[from] crate::scene::mesh::MeshError),
    #[error("cannot write {path}: {source}", path = .path.display())]
    Write {
        path: PathBuf,
        source: std::io::Error,
    },
}

/// What an export made.
pub struct Export {
    pub fit: StockFit,
    pub loss: Loss,
    pub path: PathBuf,
    pub bytes: usize,
}

/// Fits `target`'s model to `fabric`, measures it with `measure` and writes the file to
/// `out` (atomically: a failed write leaves no file).
pub fn export(
    target: &ExportTarget,
    fabric: &Fabric,
    scene: &Scene,
    out: &Path,
    measure: &dyn Fn(&StockMaterial) -> Loss,
) -> Result<Export, ExportError> {
    let mesh = Mesh::from_spec(&scene.mesh)?;
    let fit = fit(target.model, fabric);
    let loss = measure(&fit.material);
    let text = (target.write)(&ExportDocument {
        engine: target.name,
        shading_model: target.shading_model,
        fabric,
        material: &fit.material,
        loss: &loss,
        scene,
        mesh: &mesh,
    });
    write_atomically(out, text.as_bytes()).map_err(|source| ExportError::Write {
        path: out.to_path_buf(),
        source,
    })?;
    Ok(Export {
        fit,
        loss,
        path: out.to_path_buf(),
        bytes: text.len(),
    })
}
