//! A JSON of an engine's material inputs (Filament's cloth material, Unreal's Cloth shading
//! model), for engines whose materials are authored in their own editors:
//!
//! ```json
//! {"engine": "filament", "shading_model": "cloth",
//!  "parameters": {"baseColor": [r, g, b], "roughness": 0.6, ...},
//!  "clothbake": {"fabric": "...", "model": "...", "loss": {...}}}
//! ```

use super::{ExportDocument, loss_json, parameters_json};

/// The JSON text of `document`.
pub fn write(document: &ExportDocument) -> String {
    let value = serde_json::json!({
        "engine": document.engine,
        "shading_model": document.shading_model,
        "parameters": parameters_json(document.material),
        "clothbake": loss_json(document),
    });
    let mut text = serde_json::to_string_pretty(&value).expect("JSON of plain values");
    text.push('\n');
    text
}
