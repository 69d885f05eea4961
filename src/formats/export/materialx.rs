//! A MaterialX 1.39 document: one `open_pbr_surface` holding the fitted inputs (the others
//! at the node's defaults) and the `surfacematerial` that uses it. The anisotropy follows
//! the node's `geometry_tangent`, the mesh's tangent: lay it along thread 1.

use super::ExportDocument;

/// A MaterialX element name from a fabric name: letters, digits and underscores.
fn element_name(prefix: &str, fabric: &str) -> String {
    let body: String = fabric
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
        .collect();
    format!("{prefix}_{body}")
}

/// The document's text.
pub fn write(document: &ExportDocument) -> String {
    let material = document.material;
    let shader = element_name("SR", &document.fabric.name);
    let mut inputs = String::new();
    let mut seen = Vec::new();
    for (p, &value) in material.model.parameters.iter().zip(&material.values) {
        let (name, kind, text) = match p.name.rsplit_once('.') {
            Some((colour, _)) => {
                if seen.contains(&colour) {
                    continue;
                }
                seen.push(colour);
                let [r, g, b] = material
                    .colour(colour)
                    .expect("a colour has all three channels");
                (colour, "color3", format!("{r:.6}, {g:.6}, {b:.6}"))
            }
            None => (p.name, "float", format!("{value:.6}")),
        };
        inputs.push_str(&format!(
            "    <input name=\"{name}\" type=\"{kind}\" value=\"{text}\" />\n"
        ));
    }
    let loss = document.loss;
    let comment = format!(
        "clothbake {}: OpenPBR fitted to fabric '{}'. Relative RMS of F against the fabric: {:.4} \
         (uniform pairs), {:.4} (highlight pairs); directional albedo off by up to {:.4} (relative).",
        env!("CARGO_PKG_VERSION"),
        document.fabric.name.replace("--", "- -"),
        loss.uniform.relative_rms,
        loss.highlight.relative_rms,
        loss.albedo.largest_relative,
    );
    format!(
        "<?xml version=\"1.0\"?>\n\
         <materialx version=\"1.39\">\n  \
         <!-- {comment} -->\n  \
         <open_pbr_surface name=\"{shader}\" type=\"surfaceshader\">\n\
         {inputs}  \
         </open_pbr_surface>\n  \
         <surfacematerial name=\"{material_name}\" type=\"material\">\n    \
         <input name=\"surfaceshader\" type=\"surfaceshader\" nodename=\"{shader}\" />\n  \
         </surfacematerial>\n\
         </materialx>\n",
        material_name = element_name("M", &document.fabric.name),
    )
}
