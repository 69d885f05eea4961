//! The files `clothbake export` writes, one module per engine format: a glTF 2.0 asset
//! ([`gltf_file`]), a MaterialX document ([`materialx`]) and a JSON of an engine's material
//! inputs ([`engine_json`]). Each states the fabric it approximates and what the
//! approximation loses.

pub mod engine_json;
pub mod gltf_file;
pub mod materialx;

use crate::evaluator::stock::StockMaterial;
use crate::export::loss::Loss;
use crate::model::Fabric;
use crate::scene::Scene;
use crate::scene::mesh::Mesh;

/// What a writer is given.
pub struct ExportDocument<'a> {
    /// The target's name (`--to`) and its engine's name of the material model.
    pub engine: &'a str,
    pub shading_model: &'a str,
    pub fabric: &'a Fabric,
    pub material: &'a StockMaterial,
    pub loss: &'a Loss,
    /// The scene whose camera and lights a glTF carries, and its cloth mesh.
    pub scene: &'a Scene,
    pub mesh: &'a Mesh,
}

/// The loss as JSON, for the files that carry it (`extras` of a glTF, a JSON's `clothbake`).
pub fn loss_json(document: &ExportDocument) -> serde_json::Value {
    serde_json::json!({
        "generator": concat!("clothbake ", env!("CARGO_PKG_VERSION")),
        "fabric": document.fabric.name,
        "model": document.material.model.title,
        "loss": document.loss,
    })
}

/// The parameters of `material` as JSON by their engine names, a colour's three channels
/// (`NAME.r`, `.g`, `.b`) as one array.
pub fn parameters_json(material: &StockMaterial) -> serde_json::Map<String, serde_json::Value> {
    let mut map = serde_json::Map::new();
    for (p, &value) in material.model.parameters.iter().zip(&material.values) {
        match p.name.rsplit_once('.') {
            Some((colour, "r" | "g" | "b")) => {
                if !map.contains_key(colour) {
                    let rgb = material
                        .colour(colour)
                        .expect("a colour has all three channels");
                    map.insert(colour.to_string(), serde_json::json!(rgb));
                }
            }
            _ => {
                map.insert(p.name.to_string(), serde_json::json!(value));
            }
        }
    }
    map
}
