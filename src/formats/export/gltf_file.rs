//! A glTF 2.0 asset (`.gltf`, JSON with its buffer as a base64 data URI): the scene's cloth
//! mesh with its normals, tangents (`TANGENT.xyz` along thread 1, `w = +1`: the bitangent
//! n × t runs along thread 2) and UVs, the fitted material (core metallic-roughness with
//! `KHR_materials_sheen` and `KHR_materials_anisotropy`), the scene's camera and its lights
//! (`KHR_lights_punctual`: a directional light's illuminance in lux is clothbake's
//! perpendicular irradiance, a point light's intensity in candela its `intensity`, both of
//! the renderer's `L = E·F` convention). The loss is in the material's `extras.clothbake`.

use super::{ExportDocument, loss_json};
use crate::scene::Light;
use crate::scene::mesh::Mesh;
use base64::Engine;
use glam::{DVec3, Quat, Vec3};
use serde_json::{Value, json};

/// glTF's component types and buffer targets.
const FLOAT: u32 = 5126;
const UNSIGNED_INT: u32 = 5125;
const ARRAY_BUFFER: u32 = 34962;
const ELEMENT_ARRAY_BUFFER: u32 = 34963;

/// The buffer, its views and accessors as they are appended.
#[derive(Default)]
struct Buffer {
    bytes: Vec<u8>,
    views: Vec<Value>,
    accessors: Vec<Value>,
}

impl Buffer {
    /// Appends `data` (little-endian 4-byte components) as one view and its accessor; returns
    /// the accessor's index.
    fn push(
        &mut self,
        data: &[u8],
        count: usize,
        kind: &str,
        component: u32,
        extra: Value,
    ) -> usize {
        let offset = self.bytes.len();
        self.bytes.extend_from_slice(data);
        let target = if component == UNSIGNED_INT {
            ELEMENT_ARRAY_BUFFER
        } else {
            ARRAY_BUFFER
        };
        self.views.push(json!({
            "buffer": 0, "byteOffset": offset, "byteLength": data.len(), "target": target,
        }));
        let mut accessor = json!({
            "bufferView": self.views.len() - 1, "componentType": component,
            "count": count, "type": kind,
        });
        if let (Value::Object(a), Value::Object(e)) = (&mut accessor, extra) {
            a.extend(e);
        }
        self.accessors.push(accessor);
        self.accessors.len() - 1
    }
}

fn floats(values: impl Iterator<Item = f32>) -> Vec<u8> {
    values.flat_map(f32::to_le_bytes).collect()
}

/// The rotation that turns −z (where a glTF camera looks and a light shines) to `forward`
/// with +y as near to `up` as it can be: the inverse of the view matrix looking that way.
fn looking(forward: Vec3, up: Vec3) -> Quat {
    let view = glam::camera::rh::view::look_to_mat3(forward.normalize(), up.normalize());
    Quat::from_mat3(&view.transpose()).normalize()
}

/// The mesh's buffers and primitive.
fn primitive(mesh: &Mesh, buffer: &mut Buffer) -> Value {
    let v = &mesh.vertices;
    let (mut min, mut max) = (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN));
    for vertex in v {
        min = min.min(Vec3::from(vertex.position));
        max = max.max(Vec3::from(vertex.position));
    }
    let position = buffer.push(
        &floats(v.iter().flat_map(|x| x.position)),
        v.len(),
        "VEC3",
        FLOAT,
        json!({"min": min.to_array(), "max": max.to_array()}),
    );
    // Renormalised: the validator checks unit length to a tolerance f32 rounding can reach.
    let unit = |a: [f32; 3]| Vec3::from(a).normalize_or_zero().to_array();
    let normal = buffer.push(
        &floats(v.iter().flat_map(|x| unit(x.normal))),
        v.len(),
        "VEC3",
        FLOAT,
        json!({}),
    );
    let tangent = buffer.push(
        &floats(v.iter().flat_map(|x| {
            let [a, b, c] = unit(x.tangent);
            [a, b, c, 1.0]
        })),
        v.len(),
        "VEC4",
        FLOAT,
        json!({}),
    );
    let uv = buffer.push(
        &floats(v.iter().flat_map(|x| x.uv)),
        v.len(),
        "VEC2",
        FLOAT,
        json!({}),
    );
    let indices: Vec<u8> = mesh.indices.iter().flat_map(|i| i.to_le_bytes()).collect();
    let index = buffer.push(
        &indices,
        mesh.indices.len(),
        "SCALAR",
        UNSIGNED_INT,
        json!({}),
    );
    json!({
        "attributes": {"POSITION": position, "NORMAL": normal, "TANGENT": tangent, "TEXCOORD_0": uv},
        "indices": index,
        "material": 0,
    })
}

/// The asset's text for `document`.
pub fn write(document: &ExportDocument) -> String {
    let mesh = document.mesh;
    let m = document.material;
    let value = |name: &str| m.value(name).expect("a glTF material parameter");
    let colour = |name: &str| m.colour(name).expect("a glTF material colour");
    let [r, g, b] = colour("baseColorFactor");
    let mut extras = loss_json(document);
    extras["tangent"] = json!("TANGENT runs along thread 1 of the fabric");
    // Double-sided, as clothbake shades a sheet seen from behind (its normal turned to the
    // eye); a one-sided material would leave holes where the drape shows its back.
    let material = json!({
        "name": document.fabric.name,
        "doubleSided": true,
        "pbrMetallicRoughness": {
            "baseColorFactor": [r, g, b, 1.0],
            "metallicFactor": value("metallicFactor"),
            "roughnessFactor": value("roughnessFactor"),
        },
        "extensions": {
            "KHR_materials_sheen": {
                "sheenColorFactor": colour("sheenColorFactor"),
                "sheenRoughnessFactor": value("sheenRoughnessFactor"),
            },
            "KHR_materials_anisotropy": {
                "anisotropyStrength": value("anisotropyStrength"),
                "anisotropyRotation": value("anisotropyRotation"),
            },
        },
        "extras": {"clothbake": extras},
    });

    let mut buffer = Buffer::default();
    let primitive = primitive(mesh, &mut buffer);
    let scene = document.scene;
    let camera = &scene.camera;
    let (eye, target) = (DVec3::from(camera.eye()), DVec3::from(camera.target));
    let distance = eye.distance(target);
    let mut nodes = vec![
        json!({"name": "cloth", "mesh": 0}),
        json!({
            "name": "camera",
            "camera": 0,
            "translation": eye.as_vec3().to_array(),
            "rotation": looking((target - eye).as_vec3(), Vec3::Y).to_array(),
        }),
    ];
    let mut lights = Vec::new();
    for light in &scene.lights {
        let index = lights.len();
        match *light {
            Light::Directional {
                direction,
                color,
                irradiance,
            } => {
                lights
                    .push(json!({"type": "directional", "color": color, "intensity": irradiance}));
                let towards = DVec3::from(direction).normalize().as_vec3();
                let up = if towards.y.abs() > 0.99 {
                    Vec3::Z
                } else {
                    Vec3::Y
                };
                nodes.push(json!({
                    "name": format!("light {index}"),
                    "rotation": looking(-towards, up).to_array(),
                    "extensions": {"KHR_lights_punctual": {"light": index}},
                }));
            }
            Light::Point {
                position,
                color,
                intensity,
            } => {
                lights.push(json!({"type": "point", "color": color, "intensity": intensity}));
                nodes.push(json!({
                    "name": format!("light {index}"),
                    "translation": DVec3::from(position).as_vec3().to_array(),
                    "extensions": {"KHR_lights_punctual": {"light": index}},
                }));
            }
        }
    }
    let uri = format!(
        "data:application/octet-stream;base64,{}",
        base64::engine::general_purpose::STANDARD.encode(&buffer.bytes)
    );
    let asset = json!({
        "asset": {"version": "2.0", "generator": concat!("clothbake ", env!("CARGO_PKG_VERSION"))},
        "extensionsUsed": ["KHR_materials_sheen", "KHR_materials_anisotropy", "KHR_lights_punctual"],
        "extensions": {"KHR_lights_punctual": {"lights": lights}},
        "scene": 0,
        "scenes": [{"nodes": (0..nodes.len()).collect::<Vec<_>>()}],
        "nodes": nodes,
        "cameras": [{
            "type": "perspective",
            "perspective": {
                "yfov": camera.fov_y_deg.to_radians(),
                "znear": 0.01 * distance,
                "zfar": 100.0 * distance,
            },
        }],
        "meshes": [{"name": document.fabric.name, "primitives": [primitive]}],
        "materials": [material],
        "buffers": [{"byteLength": buffer.bytes.len(), "uri": uri}],
        "bufferViews": buffer.views,
        "accessors": buffer.accessors,
    });
    let mut text = serde_json::to_string(&asset).expect("JSON of plain values");
    text.push('\n');
    text
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_camera_looking_down_minus_z_is_not_turned_and_one_looking_along_x_is_turned_a_quarter() {
        let q = looking(-Vec3::Z, Vec3::Y);
        assert!(q.angle_between(Quat::IDENTITY) < 1e-6);
        let q = looking(Vec3::X, Vec3::Y);
        assert!((q * -Vec3::Z - Vec3::X).length() < 1e-6);
        assert!((q * Vec3::Y - Vec3::Y).length() < 1e-6);
        // Directions of any length, as the camera's target − eye.
        let q = looking(Vec3::new(3.0, -2.0, 0.0), Vec3::Y);
        assert!((q * -Vec3::Z - Vec3::new(3.0, -2.0, 0.0).normalize()).length() < 1e-6);
    }
}
