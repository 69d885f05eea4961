//! Cloth meshes with a thread frame per vertex: position, normal and tangent, where the
//! tangent is the direction of thread 1 (the model's x, docs/model.md#frames-and-directions; the
//! mesh's u direction) and thread 2 runs along y = n × t. Procedural sheets (`drape`, `curtain`,
//! `plane`) or a user's OBJ file with UVs.
//!
//! Procedural sheets are parametric surfaces P(u, v): the tangent is ∂P/∂u and the normal
//! (∂P/∂u × ∂P/∂v)/|…|, both from central differences of P at a step far below a grid cell,
//! so the frames do not depend on the grid resolution. OBJ meshes take the tangent of each
//! triangle from its UVs (the ∂P/∂u that maps the triangle's UV edges onto its position
//! edges), accumulated per vertex weighted by area, then orthonormalised against the
//! vertex normal.

use crate::scene::{MeshKind, MeshSpec};
use bytemuck::{Pod, Zeroable};
use glam::{DVec2, DVec3, Vec3};
use std::path::Path;

/// Most vertices a mesh may have (after OBJ vertices are unified per position/UV/normal).
pub const MAX_MESH_VERTICES: usize = 1 << 22;
/// Most triangles a mesh may have.
pub const MAX_MESH_TRIANGLES: usize = 1 << 23;
/// Largest OBJ file read.
pub const MAX_OBJ_FILE_BYTES: u64 = 512 << 20;

/// One vertex as the render shader reads it (`shaders/render/renderer.wgsl`, `VertexIn`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct Vertex {
    pub position: [f32; 3],
    /// Unit surface normal (the model's z).
    pub normal: [f32; 3],
    /// Unit tangent orthogonal to the normal: thread 1, the mesh's u direction (x).
    pub tangent: [f32; 3],
    pub uv: [f32; 2],
}

/// A triangle mesh of cloth.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    pub vertices: Vec<Vertex>,
    /// Three vertex indices per triangle.
    pub indices: Vec<u32>,
}

/// Why a mesh was rejected.
#[derive(Debug, thiserror::Error)]
#[error("mesh {origin}: {message}")]
pub struct MeshError {
    pub origin: String,
    pub message: String,
}

impl Mesh {
    /// The mesh a scene describes: a procedural sheet, or the OBJ file at `spec.path`.
    pub fn from_spec(spec: &MeshSpec) -> Result<Self, MeshError> {
        match spec.kind {
            MeshKind::Drape => Ok(Self::drape(spec.resolution, spec.folds, spec.fold_depth)),
            MeshKind::Curtain => Ok(Self::curtain(spec.resolution, spec.folds, spec.fold_depth)),
            MeshKind::Plane => Ok(Self::plane(spec.resolution)),
            MeshKind::Obj => match &spec.path {
                Some(path) => Self::load_obj(path),
                None => Err(MeshError {
                    origin: "scene".into(),
                    message: "kind \"obj\" needs a path".into(),
                }),
            },
        }
    }

    /// A square sheet 3 units wide draped over a sphere of radius 0.6 at the origin: it
    /// follows the sphere down to 65° from the top, then bends over towards the vertical
    /// and hangs, buckling into `folds` radial folds of depth `fold_depth` that grow from
    /// where the cloth leaves the sphere. Thread 1 runs along world x on the top.
    pub fn drape(resolution: u32, folds: u32, fold_depth: f64) -> Self {
        let profile = DrapeProfile::new();
        let folds = folds as f64;
        grid_surface(resolution, |u, v| {
            // Sheet coordinates (a, b) in [-H, H]²; s the distance from the centre along the
            // sheet, measured along the profile; the sheet's b axis maps onto world -z so that
            // ∂P/∂u × ∂P/∂v points up on the top.
            let a = (2.0 * u - 1.0) * DRAPE_HALF_SIZE;
            let b = (2.0 * v - 1.0) * DRAPE_HALF_SIZE;
            let s = a.hypot(b);
            let (radius, height) = profile.at(s);
            // Horizontal unit direction of the point; radius/s → 1 as s → 0 (no singularity).
            let scale = if s > 1e-12 { radius / s } else { 1.0 };
            let mut p = DVec3::new(a * scale, height, -b * scale);
            let beyond = s - profile.contact;
            if beyond > 0.0 && folds > 0.0 {
                // Fold amplitude: zero and flat where the cloth leaves the sphere
                // (smoothstep over 0.5 units), then growing with the hanging length.
                let x = (beyond / 0.5).min(1.0);
                let grow = x * x * (3.0 - 2.0 * x) * (1.0 + beyond);
                let phi = b.atan2(a);
                let offset = fold_depth * grow * (folds * phi).cos();
                p += DVec3::new(a / s, 0.0, -b / s) * offset;
            }
            p
        })
    }

    /// A curtain 2.4 units square in the xy plane facing +z, with `folds` vertical folds of
    /// depth `fold_depth` at the top growing to 1.6 times that at the bottom. Thread 1 runs
    /// horizontally (x), thread 2 vertically.
    pub fn curtain(resolution: u32, folds: u32, fold_depth: f64) -> Self {
        let folds = folds as f64;
        grid_surface(resolution, |u, v| {
            let depth = fold_depth * (1.0 + 0.6 * (1.0 - v));
            DVec3::new(
                2.4 * (u - 0.5),
                2.4 * (v - 0.5),
                depth * (std::f64::consts::TAU * folds * u).sin(),
            )
        })
    }

    /// A flat square 2 units wide at y = 0 facing +y; thread 1 along +x, thread 2 along -z.
    pub fn plane(resolution: u32) -> Self {
        grid_surface(resolution, |u, v| {
            DVec3::new(2.0 * u - 1.0, 0.0, -(2.0 * v - 1.0))
        })
    }

    /// Loads a triangulated OBJ file with texture coordinates (polygons are triangulated,
    /// every object is merged into one mesh; normals are the file's or, without them,
    /// area-weighted face normals). Rejects files without UVs, with non-finite values, over
    /// [`MAX_MESH_VERTICES`]/[`MAX_MESH_TRIANGLES`], or with vertices whose UVs give no u
    /// direction.
    pub fn load_obj(path: &Path) -> Result<Self, MeshError> {
        let fail = |message: String| MeshError {
            origin: path.display().to_string(),
            message,
        };
        let size = std::fs::metadata(path)
            .map_err(|e| fail(e.to_string()))?
            .len();
        if size > MAX_OBJ_FILE_BYTES {
            return Err(fail(format!(
                "is {size} bytes, over the {MAX_OBJ_FILE_BYTES}-byte limit"
            )));
        }
        let options = tobj::LoadOptions {
            single_index: true,
            triangulate: true,
            ignore_points: true,
            ignore_lines: true,
        };
        // Materials are not used: a missing or bad .mtl file is no error.
        let (models, _materials) = tobj::load_obj(path, &options)
            .map_err(|e| fail(format!("not a readable OBJ file: {e}")))?;
        let mut positions = Vec::new();
        let mut normals = Vec::new();
        let mut uvs = Vec::new();
        let mut indices = Vec::new();
        let mut all_normals = true;
        for model in &models {
            let m = &model.mesh;
            let count = m.positions.len() / 3;
            if m.texcoords.len() != 2 * count {
                return Err(fail(format!(
                    "object '{}' has no texture coordinates (vt) on every vertex; the UVs \
                     give the thread directions, so clothbake needs them",
                    model.name
                )));
            }
            if positions.len() + count > MAX_MESH_VERTICES {
                return Err(fail(format!(
                    "has over {MAX_MESH_VERTICES} vertices, the most clothbake renders"
                )));
            }
            if (indices.len() + m.indices.len()) / 3 > MAX_MESH_TRIANGLES {
                return Err(fail(format!(
                    "has over {MAX_MESH_TRIANGLES} triangles, the most clothbake renders"
                )));
            }
            let base = positions.len() as u32;
            for i in 0..count {
                let p = DVec3::new(
                    m.positions[3 * i] as f64,
                    m.positions[3 * i + 1] as f64,
                    m.positions[3 * i + 2] as f64,
                );
                let uv = DVec2::new(m.texcoords[2 * i] as f64, m.texcoords[2 * i + 1] as f64);
                if !p.is_finite() || !uv.is_finite() {
                    return Err(fail(format!(
                        "object '{}', vertex {i}: non-finite position or texture coordinate",
                        model.name
                    )));
                }
                positions.push(p);
                uvs.push(uv);
            }
            if m.normals.len() == 3 * count {
                for i in 0..count {
                    normals.push(DVec3::new(
                        m.normals[3 * i] as f64,
                        m.normals[3 * i + 1] as f64,
                        m.normals[3 * i + 2] as f64,
                    ));
                }
            } else {
                all_normals = false;
                normals.resize(positions.len(), DVec3::ZERO);
            }
            for &index in &m.indices {
                if index as usize >= count {
                    return Err(fail(format!(
                        "object '{}': face index {index} beyond its {count} vertices",
                        model.name
                    )));
                }
                indices.push(base + index);
            }
        }
        if indices.is_empty() {
            return Err(fail("has no triangles".into()));
        }
        let normals = if all_normals {
            normals
        } else {
            face_normals(&positions, &indices)
        };
        frames_from_uvs(&positions, &normals, &uvs, indices).map_err(|e| fail(e.to_string()))
    }

    /// The centre and radius of a sphere holding every vertex.
    pub fn bounding_sphere(&self) -> (Vec3, f32) {
        let (lo, hi) = self.vertices.iter().fold(
            (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
            |(lo, hi), v| {
                let p = Vec3::from(v.position);
                (lo.min(p), hi.max(p))
            },
        );
        if self.vertices.is_empty() {
            return (Vec3::ZERO, 1.0);
        }
        let centre = 0.5 * (lo + hi);
        let radius = self
            .vertices
            .iter()
            .map(|v| Vec3::from(v.position).distance(centre))
            .fold(0.0f32, f32::max);
        (centre, radius.max(1e-6))
    }

    /// Triangles in the mesh.
    pub fn triangle_count(&self) -> usize {
        self.indices.len() / 3
    }
}

/// Half the side of the draped sheet.
const DRAPE_HALF_SIZE: f64 = 1.5;
/// Radius of the sphere under the drape.
const DRAPE_SPHERE: f64 = 0.6;

/// The drape's profile in a vertical half-plane: (horizontal radius, height) as functions of
/// the arc length s from the top of the sphere.
struct DrapeProfile {
    /// Arc length where the cloth leaves the sphere.
    contact: f64,
    step: f64,
    /// (radius, height) at s = contact + k·step.
    table: Vec<(f64, f64)>,
}

impl DrapeProfile {
    /// Polar angle at which the cloth leaves the sphere.
    const CONTACT_DEG: f64 = 65.0;
    /// The angle below the horizontal that the hanging cloth approaches.
    const HANG_DEG: f64 = 88.0;
    /// Arc length over which it bends towards that angle (1/e).
    const BEND: f64 = 0.25;

    fn new() -> Self {
        let theta_c = Self::CONTACT_DEG.to_radians();
        let hang = Self::HANG_DEG.to_radians();
        let contact = DRAPE_SPHERE * theta_c;
        let length = DRAPE_HALF_SIZE * std::f64::consts::SQRT_2 - contact;
        let steps = 8192;
        let step = length / steps as f64;
        // Beyond the sphere the tangent's angle below the horizontal relaxes from θc to the
        // hanging angle: β(s) = β∞ − (β∞ − θc)·exp(−(s − s_c)/λ); the profile is its
        // integral (cos β, −sin β), by the midpoint rule on a fine table.
        let mut table = Vec::with_capacity(steps + 1);
        let (mut r, mut y) = (DRAPE_SPHERE * theta_c.sin(), DRAPE_SPHERE * theta_c.cos());
        table.push((r, y));
        for k in 0..steps {
            let s = (k as f64 + 0.5) * step;
            let beta = hang - (hang - theta_c) * (-s / Self::BEND).exp();
            r += beta.cos() * step;
            y -= beta.sin() * step;
            table.push((r, y));
        }
        Self {
            contact,
            step,
            table,
        }
    }

    fn at(&self, s: f64) -> (f64, f64) {
        if s <= self.contact {
            let theta = s / DRAPE_SPHERE;
            return (DRAPE_SPHERE * theta.sin(), DRAPE_SPHERE * theta.cos());
        }
        let x = ((s - self.contact) / self.step).min((self.table.len() - 1) as f64);
        let k = (x.floor() as usize).min(self.table.len() - 2);
        let f = x - k as f64;
        let (r0, y0) = self.table[k];
        let (r1, y1) = self.table[k + 1];
        (r0 + f * (r1 - r0), y0 + f * (y1 - y0))
    }
}

/// A (resolution + 1)² grid over the unit square of P(u, v), two triangles per cell, with
/// the thread frame from central differences of P.
fn grid_surface(resolution: u32, surface: impl Fn(f64, f64) -> DVec3) -> Mesh {
    let n = resolution.max(1) as usize;
    // Finite-difference step: small against a cell of the finest grid (1/1024) and large
    // against f64 rounding of positions of order 1 (ε/h ≈ 1e-10).
    const H: f64 = 1e-6;
    let mut vertices = Vec::with_capacity((n + 1) * (n + 1));
    for j in 0..=n {
        for i in 0..=n {
            let (u, v) = (i as f64 / n as f64, j as f64 / n as f64);
            let p = surface(u, v);
            let du = (surface(u + H, v) - surface(u - H, v)) / (2.0 * H);
            let dv = (surface(u, v + H) - surface(u, v - H)) / (2.0 * H);
            let normal = du.cross(dv).normalize_or_zero();
            let tangent = (du - normal * normal.dot(du)).normalize_or_zero();
            vertices.push(Vertex {
                position: p.as_vec3().to_array(),
                normal: normal.as_vec3().to_array(),
                tangent: tangent.as_vec3().to_array(),
                uv: [u as f32, v as f32],
            });
        }
    }
    let mut indices = Vec::with_capacity(6 * n * n);
    let at = |i: usize, j: usize| (j * (n + 1) + i) as u32;
    for j in 0..n {
        for i in 0..n {
            // Counter-clockwise seen from the side the normal points to.
            indices.extend([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
            indices.extend([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
        }
    }
    Mesh { vertices, indices }
}

/// Area-weighted face normals summed per vertex (the cross product's length is twice the
/// area), for meshes whose file gives none.
fn face_normals(positions: &[DVec3], indices: &[u32]) -> Vec<DVec3> {
    let mut normals = vec![DVec3::ZERO; positions.len()];
    for tri in indices.chunks_exact(3) {
        let [a, b, c] = [0, 1, 2].map(|k| tri[k] as usize);
        let n = (positions[b] - positions[a]).cross(positions[c] - positions[a]);
        for k in [a, b, c] {
            normals[k] += n;
        }
    }
    normals
}

/// Why a mesh's vertices get no shading frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
pub enum FrameProblem {
    #[error("every triangle is degenerate in position or in UV")]
    AllDegenerate,
    #[error("vertex {0}: no normal (zero or non-finite normal, or only degenerate triangles)")]
    NoNormal(usize),
    #[error(
        "vertex {0}: its UVs give no u direction (every triangle around it is degenerate in \
         UV, or u runs along the normal)"
    )]
    NoUDirection(usize),
}

/// Builds the vertices: normals normalised, tangents from the UVs.
///
/// Per triangle with edges e1 = p1 − p0, e2 = p2 − p0 and UV edges (du1, dv1), (du2, dv2),
/// the linear map with e_k = T·du_k + B·dv_k gives T = ∂P/∂u = (e1·dv2 − e2·dv1)/det,
/// det = du1·dv2 − du2·dv1. Each triangle adds its unit T weighted by its area (so that the
/// UV scale does not weight triangles); triangles with zero area or det = 0 add nothing.
fn frames_from_uvs(
    positions: &[DVec3],
    normals: &[DVec3],
    uvs: &[DVec2],
    indices: Vec<u32>,
) -> Result<Mesh, FrameProblem> {
    let mut tangents = vec![DVec3::ZERO; positions.len()];
    let mut used = 0usize;
    for tri in indices.chunks_exact(3) {
        let [a, b, c] = [0, 1, 2].map(|k| tri[k] as usize);
        let (e1, e2) = (positions[b] - positions[a], positions[c] - positions[a]);
        let (d1, d2) = (uvs[b] - uvs[a], uvs[c] - uvs[a]);
        let area = 0.5 * e1.cross(e2).length();
        let det = d1.x * d2.y - d2.x * d1.y;
        let scale = e1.length().max(e2.length());
        if area <= 1e-12 * scale * scale || det.abs() <= 1e-14 {
            continue;
        }
        let t = ((e1 * d2.y - e2 * d1.y) / det).normalize_or_zero();
        for k in [a, b, c] {
            tangents[k] += t * area;
        }
        used += 1;
    }
    if used == 0 {
        return Err(FrameProblem::AllDegenerate);
    }
    let mut vertices = Vec::with_capacity(positions.len());
    let referenced = {
        let mut r = vec![false; positions.len()];
        for &i in &indices {
            r[i as usize] = true;
        }
        r
    };
    for (i, p) in positions.iter().enumerate() {
        let n = normals[i].normalize_or_zero();
        let t = (tangents[i] - n * n.dot(tangents[i])).normalize_or_zero();
        if referenced[i] && n == DVec3::ZERO {
            return Err(FrameProblem::NoNormal(i));
        }
        if referenced[i] && t == DVec3::ZERO {
            return Err(FrameProblem::NoUDirection(i));
        }
        vertices.push(Vertex {
            position: p.as_vec3().to_array(),
            normal: n.as_vec3().to_array(),
            tangent: t.as_vec3().to_array(),
            uv: uvs[i].as_vec2().to_array(),
        });
    }
    Ok(Mesh { vertices, indices })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check_frames(mesh: &Mesh) {
        for v in &mesh.vertices {
            let (n, t) = (Vec3::from(v.normal), Vec3::from(v.tangent));
            assert!((n.length() - 1.0).abs() < 1e-5, "{v:?}");
            assert!((t.length() - 1.0).abs() < 1e-5, "{v:?}");
            assert!(n.dot(t).abs() < 1e-5, "{v:?}");
        }
        assert!(
            mesh.indices
                .iter()
                .all(|&i| (i as usize) < mesh.vertices.len())
        );
    }

    #[test]
    fn procedural_sheets_have_orthonormal_frames_along_u() {
        for mesh in [
            Mesh::drape(32, 9, 0.1),
            Mesh::curtain(32, 5, 0.1),
            Mesh::plane(32),
        ] {
            check_frames(&mesh);
            // The tangent follows u: it is parallel to the position difference between
            // neighbouring vertices along u (to first order), away from the drape's centre.
            let n = 33;
            let (i, j) = (20, 7);
            let p0 = Vec3::from(mesh.vertices[j * n + i].position);
            let p1 = Vec3::from(mesh.vertices[j * n + i + 1].position);
            let t = Vec3::from(mesh.vertices[j * n + i].tangent);
            let nrm = Vec3::from(mesh.vertices[j * n + i].normal);
            let step = (p1 - p0) - nrm * nrm.dot(p1 - p0);
            assert!(step.normalize().dot(t) > 0.98, "{step} vs {t}");
        }
    }

    #[test]
    fn drape_faces_up_on_top_and_covers_many_orientations() {
        let mesh = Mesh::drape(64, 9, 0.1);
        let top = &mesh.vertices[32 * 65 + 32];
        assert!(Vec3::from(top.normal).dot(Vec3::Y) > 0.999);
        assert!(Vec3::from(top.tangent).dot(Vec3::X) > 0.999);
        // Normals spread over the upper hemisphere and around the sides.
        let sideways = mesh
            .vertices
            .iter()
            .filter(|v| v.normal[1].abs() < 0.3)
            .count();
        assert!(sideways > mesh.vertices.len() / 4, "{sideways}");
    }

    fn write(dir: &Path, name: &str, text: &str) -> std::path::PathBuf {
        let path = dir.join(name);
        std::fs::write(&path, text).unwrap();
        path
    }

    #[test]
    fn obj_with_uvs_gets_tangents_along_u() {
        let scratch = tempfile::tempdir().unwrap();
        let dir = scratch.path();
        // A unit quad in the xz plane, u along -z, v along +x: the tangent must be -z.
        let quad = "v 0 0 0\nv 1 0 0\nv 1 0 -1\nv 0 0 -1\n\
                    vt 0 0\nvt 0 1\nvt 1 1\nvt 1 0\n\
                    f 1/1 2/2 3/3 4/4\n";
        let mesh = Mesh::load_obj(&write(dir, "quad.obj", quad)).unwrap();
        check_frames(&mesh);
        assert_eq!(mesh.triangle_count(), 2);
        for v in &mesh.vertices {
            assert!(Vec3::from(v.tangent).dot(-Vec3::Z) > 0.9999, "{v:?}");
            // Normal from the winding: (1,0,0) × (1,0,-1) = (0, 1, 0).
            assert!(Vec3::from(v.normal).dot(Vec3::Y) > 0.9999, "{v:?}");
        }
    }

    #[test]
    fn bad_obj_files_are_rejected_with_a_reason() {
        let scratch = tempfile::tempdir().unwrap();
        let dir = scratch.path();
        let cases = [
            (
                "nouv.obj",
                "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
                "texture coordinates",
            ),
            (
                "nan.obj",
                "v 0 0 0\nv nan 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/3\n",
                "non-finite",
            ),
            (
                "degenerate.obj",
                "v 0 0 0\nv 1 0 0\nv 2 0 0\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/3\n",
                "degenerate",
            ),
            (
                "flatuv.obj",
                "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 0 0\nvt 0 0\nf 1/1 2/2 3/3\n",
                "degenerate",
            ),
            ("empty.obj", "# nothing\n", "no triangles"),
        ];
        for (name, text, reason) in cases {
            let error = Mesh::load_obj(&write(dir, name, text))
                .expect_err(name)
                .to_string();
            assert!(error.contains(name) && error.contains(reason), "{error}");
        }
        let missing = Mesh::load_obj(&dir.join("missing.obj")).expect_err("missing");
        assert!(missing.to_string().contains("missing.obj"));
    }
}
