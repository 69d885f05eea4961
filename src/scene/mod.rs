//! Scene files (TOML): the fabrics a scene uses and its error or memory budget, so that
//! `bake --scene` bakes only what the scene needs, and what `render` draws them on: camera,
//! lights, exposure and mesh. Everything but `fabrics` is optional; the defaults are those of
//! the built-in scene, `tables/scene.toml`. World space is right-handed with +y up.
//!
//! ```toml
//! fabrics = ["polyester_satin_charmeuse", "velvet"]  # names in the fabric file
//! fabric_file = "my_fabrics.toml"   # optional; relative to the scene file; default built-in
//! layout = "grid4d"                 # optional; default the default layout
//! exposure = 1.0                    # optional; radiance scale before tone mapping, > 0
//! [budget]                          # optional; at most one of the two
//! max_error = 0.05                  # relative RMS on uniform and highlight pairs
//! max_bytes_per_fabric = 16777216   # texel bytes per table
//! [camera]                          # optional: an orbit camera, every key optional
//! target = [0.0, -0.1, 0.0]         # the point it looks at
//! distance = 3.6                    # from the target, > 0
//! yaw_deg = 30.0                    # about +y, 0 = looking along -z from +z
//! pitch_deg = 28.0                  # elevation above the target, in (-90, 90)
//! fov_y_deg = 40.0                  # vertical field of view, in [1, 150]
//! [[lights]]                        # optional: 1 to 8 lights (default: the two below)
//! kind = "directional"
//! direction = [0.4, 1.0, 0.6]       # towards the light (wi), normalised on reading
//! color = [1.0, 1.0, 1.0]           # each in [0, 1e6]
//! irradiance = 2.0                  # perpendicular irradiance E: radiance = E·F(wi, wo)
//! [[lights]]
//! kind = "point"
//! position = [-1.5, 0.8, 1.2]
//! color = [1.0, 0.85, 0.7]
//! intensity = 3.0                   # I: irradiance E = I/d² at distance d
//! [environment]                     # optional: distant light from everywhere
//! source = "default"                # default (studio) | sky | overcast | interior | uniform | none | FILE.hdr/.exr
//! samples = 96                      # filtered importance samples per pixel, 1 to 256
//! sources = 8                       # bright sources lit as lights, 0 to 8 (0: all sampled)
//! [mesh]                            # optional: the cloth (default: draped over a sphere)
//! kind = "drape"                    # "drape" | "curtain" | "plane" | "obj"
//! resolution = 160                  # grid quads per side (procedural kinds), [2, 1024]
//! folds = 9                         # folds around the drape / across the curtain, [0, 64]
//! fold_depth = 0.1                  # their depth, in [0, 1] (scene units, sheet ≈ 3 wide)
//! path = "cloth.obj"                # kind = "obj" only; relative to the scene file
//! ```

pub mod mesh;
mod validate;

pub use validate::{SceneError, SceneParseError};
use validate::{check_color, check_range, check_vector, field_error};

use crate::lighting::EnvironmentSource;
use crate::lighting::bright_sources::MAX_SOURCES;
use crate::table::Layout;
use serde::Deserialize;
use std::path::{Path, PathBuf};

/// Largest scene file read.
pub const MAX_SCENE_FILE_BYTES: u64 = 1 << 20;

/// The built-in scene, `tables/scene.toml`.
pub const BUILTIN_SCENE_TOML: &str = include_str!("../../tables/scene.toml");

/// What a scene asks of the baker.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    pub fabrics: Vec<String>,
    #[serde(default)]
    pub fabric_file: Option<PathBuf>,
    #[serde(default)]
    pub layout: Option<String>,
    #[serde(default)]
    pub budget: Budget,
    /// Radiance scale applied before tone mapping.
    #[serde(default = "default_exposure")]
    pub exposure: f64,
    #[serde(default)]
    pub camera: OrbitCamera,
    #[serde(default = "default_lights")]
    pub lights: Vec<Light>,
    #[serde(default)]
    pub mesh: MeshSpec,
    #[serde(default)]
    pub environment: EnvironmentSpec,
}

/// Most lights a scene may have (the shader's fixed light array).
pub const MAX_LIGHTS: usize = 8;

fn default_exposure() -> f64 {
    1.0
}

/// An orbit camera: at `distance` from `target`, turned by `yaw_deg` about +y and raised by
/// `pitch_deg`, looking at the target with a vertical field of view `fov_y_deg`.
#[derive(Clone, Copy, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct OrbitCamera {
    pub target: [f64; 3],
    pub distance: f64,
    pub yaw_deg: f64,
    pub pitch_deg: f64,
    pub fov_y_deg: f64,
}

impl Default for OrbitCamera {
    fn default() -> Self {
        Self {
            target: [0.0, -0.1, 0.0],
            distance: 3.6,
            yaw_deg: 30.0,
            pitch_deg: 28.0,
            fov_y_deg: 40.0,
        }
    }
}

impl OrbitCamera {
    /// The eye position: `target + distance·(cos p·sin y, sin p, cos p·cos y)`.
    pub fn eye(&self) -> [f64; 3] {
        let (yaw, pitch) = (self.yaw_deg.to_radians(), self.pitch_deg.to_radians());
        let t = self.target;
        [
            t[0] + self.distance * pitch.cos() * yaw.sin(),
            t[1] + self.distance * pitch.sin(),
            t[2] + self.distance * pitch.cos() * yaw.cos(),
        ]
    }
}

/// A light. Radiance leaving the cloth is `Σ E·color·F(wi, wo)` over the lights
/// (docs/model.md#the-patch-transfer-f: a distant light of perpendicular irradiance E gives
/// `L_o = E·F`); there are no shadows.
#[derive(Clone, Copy, Debug, PartialEq, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum Light {
    /// A distant light: `direction` points from the scene towards the light (it is `wi`).
    Directional {
        direction: [f64; 3],
        #[serde(default = "white")]
        color: [f64; 3],
        irradiance: f64,
    },
    /// A point light of radiant intensity `intensity`: irradiance `intensity/d²` at distance d.
    Point {
        position: [f64; 3],
        #[serde(default = "white")]
        color: [f64; 3],
        intensity: f64,
    },
}

fn white() -> [f64; 3] {
    [1.0; 3]
}

/// The default lights: a directional key light and a warm point light.
pub fn default_lights() -> Vec<Light> {
    vec![
        Light::Directional {
            direction: [0.4, 1.0, 0.6],
            color: [1.0, 1.0, 1.0],
            irradiance: 2.0,
        },
        Light::Point {
            position: [-1.5, 0.8, 1.2],
            color: [1.0, 0.85, 0.7],
            intensity: 3.0,
        },
    ]
}

/// Which cloth mesh to render (see [`crate::scene::mesh`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum MeshKind {
    /// A square sheet draped over a sphere, hanging in folds.
    #[default]
    Drape,
    /// A hanging curtain with vertical folds.
    Curtain,
    /// A flat square facing +y.
    Plane,
    /// A user's OBJ file with UVs (`path`).
    Obj,
}

/// Environment samples (sample taps) per pixel of the default scene: about the fewest that
/// keep every fabric within the environment light's goal, at about what 16 samples drawn per
/// pixel cost before the taps (docs/notebook/2026-12-07-sampling.md#the-goal-and-its-margin).
pub const DEFAULT_ENVIRONMENT_SAMPLES: u32 = 96;
/// Most environment samples per pixel: the fabric's sample taps take 16 bytes per sample and
/// wo node (8,320 nodes), 33 MiB at 256, within the 128 MiB that wgpu's default limits allow
/// a storage binding.
pub const MAX_ENVIRONMENT_SAMPLES: u32 = 256;

/// The environment light of a scene.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct EnvironmentSpec {
    /// `default`, a built-in environment's name, `uniform`, `none` or a file (comes back from [`Scene::load`] resolved
    /// against the scene's directory).
    #[serde(deserialize_with = "environment_source")]
    pub source: EnvironmentSource,
    /// Filtered importance samples per pixel, 1 to [`MAX_ENVIRONMENT_SAMPLES`].
    pub samples: u32,
    /// Most compact bright sources (sun, lamps) taken out of the map and lit as directional
    /// lights, 0 to [`MAX_SOURCES`] (0: the whole map is sampled).
    pub sources: usize,
}

impl Default for EnvironmentSpec {
    fn default() -> Self {
        Self {
            source: EnvironmentSource::Default,
            samples: DEFAULT_ENVIRONMENT_SAMPLES,
            sources: MAX_SOURCES,
        }
    }
}

fn environment_source<'de, D: serde::Deserializer<'de>>(
    deserializer: D,
) -> Result<EnvironmentSource, D::Error> {
    let word = String::deserialize(deserializer)?;
    word.parse().map_err(serde::de::Error::custom)
}

/// The cloth mesh of a scene.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct MeshSpec {
    pub kind: MeshKind,
    /// Grid quads per side of the procedural sheets.
    pub resolution: u32,
    /// Folds around the drape, or across the curtain.
    pub folds: u32,
    /// Depth of the folds in scene units.
    pub fold_depth: f64,
    /// The OBJ file (kind `obj`); comes back from [`Scene::load`] resolved against the
    /// scene's directory.
    pub path: Option<PathBuf>,
}

impl Default for MeshSpec {
    fn default() -> Self {
        Self {
            kind: MeshKind::Drape,
            resolution: 160,
            folds: 9,
            fold_depth: 0.1,
            path: None,
        }
    }
}

/// Largest `mesh.resolution`: 1025² vertices, 2 M triangles.
pub const MAX_MESH_RESOLUTION: u32 = 1024;
/// Most folds a procedural mesh may have.
pub const MAX_FOLDS: u32 = 64;

/// A scene's accuracy or memory budget.
#[derive(Clone, Copy, Debug, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Budget {
    pub max_error: Option<f64>,
    pub max_bytes_per_fabric: Option<u64>,
}

impl Scene {
    /// Reads and validates a scene file; `fabric_file` comes back resolved against the
    /// scene's directory.
    pub fn load(path: &Path) -> Result<Self, SceneError> {
        let read = |source| SceneError::Read {
            path: path.to_path_buf(),
            source,
        };
        let size = std::fs::metadata(path).map_err(read)?.len();
        if size > MAX_SCENE_FILE_BYTES {
            return Err(SceneError::TooLarge {
                path: path.to_path_buf(),
                size,
            });
        }
        let text = std::fs::read_to_string(path).map_err(read)?;
        let mut scene = Self::parse(&text).map_err(|source| SceneError::Invalid {
            path: path.to_path_buf(),
            source,
        })?;
        let base = path.parent().unwrap_or(Path::new(""));
        if let Some(file) = &scene.fabric_file {
            scene.fabric_file = Some(base.join(file));
        }
        if let Some(file) = &scene.mesh.path {
            scene.mesh.path = Some(base.join(file));
        }
        if let EnvironmentSource::File(file) = &scene.environment.source {
            scene.environment.source = EnvironmentSource::File(base.join(file));
        }
        Ok(scene)
    }

    /// Parses and validates a scene from TOML text; relative paths stay as written.
    pub fn parse(text: &str) -> Result<Self, SceneParseError> {
        let scene: Scene = toml::from_str(text)?;
        scene.validate()?;
        Ok(scene)
    }

    /// The built-in default scene (`tables/scene.toml`): the six fabrics, a directional and
    /// a point light, an orbit camera, cloth draped over a sphere.
    pub fn builtin() -> Self {
        Self::parse(BUILTIN_SCENE_TOML).expect("the built-in scene is valid")
    }

    fn validate(&self) -> Result<(), SceneParseError> {
        if self.fabrics.is_empty() {
            return Err(field_error("fabrics", "names no fabric"));
        }
        if let Some(name) = &self.layout {
            Layout::from_name(name)
                .ok_or_else(|| field_error("layout", format!("unknown layout '{name}'")))?;
        }
        match (self.budget.max_error, self.budget.max_bytes_per_fabric) {
            (Some(_), Some(_)) => Err(field_error(
                "budget",
                "give max_error or max_bytes_per_fabric, not both",
            )),
            (Some(e), None) if !(e.is_finite() && e > 0.0) => Err(field_error(
                "budget.max_error",
                format!("must be a positive number, got {e}"),
            )),
            (None, Some(0)) => Err(field_error(
                "budget.max_bytes_per_fabric",
                "must be positive",
            )),
            _ => Ok(()),
        }?;
        self.validate_render()
    }

    /// Checks the fields that only `render` uses.
    fn validate_render(&self) -> Result<(), SceneParseError> {
        check_range("exposure", self.exposure, 1e-6, 1e6)?;
        let c = &self.camera;
        check_vector("camera.target", c.target, 1e6)?;
        check_range("camera.distance", c.distance, 1e-3, 1e6)?;
        check_range("camera.yaw_deg", c.yaw_deg, -3600.0, 3600.0)?;
        // Strictly inside (-90, 90): at the poles the orbit's up vector is undefined.
        check_range("camera.pitch_deg", c.pitch_deg, -89.9, 89.9)?;
        check_range("camera.fov_y_deg", c.fov_y_deg, 1.0, 150.0)?;
        if !(1..=MAX_ENVIRONMENT_SAMPLES).contains(&self.environment.samples) {
            return Err(field_error(
                "environment.samples",
                format!(
                    "must be in 1..={MAX_ENVIRONMENT_SAMPLES}, got {}",
                    self.environment.samples
                ),
            ));
        }
        if self.environment.sources > MAX_SOURCES {
            return Err(field_error(
                "environment.sources",
                format!(
                    "must be in 0..={MAX_SOURCES}, got {}",
                    self.environment.sources
                ),
            ));
        }
        if self.lights.is_empty() {
            return Err(field_error(
                "lights",
                "names no light (leave [[lights]] out for the default lights)",
            ));
        }
        if self.lights.len() > MAX_LIGHTS {
            return Err(field_error(
                "lights",
                format!(
                    "{} lights, at most {MAX_LIGHTS} are supported",
                    self.lights.len()
                ),
            ));
        }
        for (i, light) in self.lights.iter().enumerate() {
            let field = |name: &str| format!("lights[{i}].{name}");
            match *light {
                Light::Directional {
                    direction,
                    color,
                    irradiance,
                } => {
                    check_vector(&field("direction"), direction, 1e6)?;
                    let length = direction.iter().map(|v| v * v).sum::<f64>().sqrt();
                    if length < 1e-9 {
                        return Err(field_error(
                            field("direction"),
                            "must not be the zero vector",
                        ));
                    }
                    check_color(&field("color"), color)?;
                    check_range(&field("irradiance"), irradiance, 0.0, 1e6)?;
                }
                Light::Point {
                    position,
                    color,
                    intensity,
                } => {
                    check_vector(&field("position"), position, 1e6)?;
                    check_color(&field("color"), color)?;
                    check_range(&field("intensity"), intensity, 0.0, 1e6)?;
                }
            }
        }
        let m = &self.mesh;
        if !(2..=MAX_MESH_RESOLUTION).contains(&m.resolution) {
            return Err(field_error(
                "mesh.resolution",
                format!(
                    "must be in [2, {MAX_MESH_RESOLUTION}], got {}",
                    m.resolution
                ),
            ));
        }
        if m.folds > MAX_FOLDS {
            return Err(field_error(
                "mesh.folds",
                format!("must be at most {MAX_FOLDS}, got {}", m.folds),
            ));
        }
        check_range("mesh.fold_depth", m.fold_depth, 0.0, 1.0)?;
        match (m.kind, &m.path) {
            (MeshKind::Obj, None) => Err(field_error(
                "mesh.path",
                "kind \"obj\" needs the path of an OBJ file",
            )),
            (MeshKind::Obj, Some(_)) | (_, None) => Ok(()),
            (_, Some(_)) => Err(field_error(
                "mesh.path",
                "only meshes of kind \"obj\" read a file (add kind = \"obj\")",
            )),
        }
    }

    /// The scene's layout, or `default` when it names none.
    pub fn layout_or(&self, default: Layout) -> Layout {
        self.layout
            .as_deref()
            .and_then(Layout::from_name)
            .unwrap_or(default)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn builtin_scene_has_six_fabrics_two_lights_and_a_drape() {
        let scene = Scene::builtin();
        assert_eq!(scene.fabrics.len(), 6);
        assert_eq!(scene.lights.len(), 2);
        assert!(matches!(scene.lights[0], Light::Directional { .. }));
        assert!(matches!(scene.lights[1], Light::Point { .. }));
        assert_eq!(scene.mesh.kind, MeshKind::Drape);
        // Every fabric of the scene exists in the built-in fabric file.
        let set = crate::formats::fabric_toml::FabricSet::builtin();
        for name in &scene.fabrics {
            assert!(set.get(name).is_some(), "{name}");
        }
    }

    #[test]
    fn render_fields_are_optional_and_default() {
        let scene = Scene::parse("fabrics = [\"velvet\"]\n").unwrap();
        assert_eq!(scene.camera, OrbitCamera::default());
        assert_eq!(scene.lights, default_lights());
        assert_eq!(scene.mesh, MeshSpec::default());
        assert_eq!(scene.exposure, 1.0);
    }

    #[test]
    fn bad_render_fields_are_named() {
        let base = "fabrics = [\"velvet\"]\n";
        let cases = [
            ("exposure = 0.0\n", "exposure"),
            ("exposure = nan\n", "exposure"),
            ("[camera]\ndistance = -1.0\n", "camera.distance"),
            ("[camera]\npitch_deg = 90.0\n", "camera.pitch_deg"),
            ("[camera]\nfov_y_deg = 179.0\n", "camera.fov_y_deg"),
            ("[camera]\ntarget = [0.0, inf, 0.0]\n", "camera.target"),
            ("[camera]\nzoom = 2.0\n", "zoom"),
            ("lights = []\n", "lights"),
            (
                "[[lights]]\nkind = \"directional\"\ndirection = [0.0, 0.0, 0.0]\nirradiance = 1.0\n",
                "lights[0].direction",
            ),
            (
                "[[lights]]\nkind = \"point\"\nposition = [0.0, 1.0, 0.0]\nintensity = -1.0\n",
                "lights[0].intensity",
            ),
            (
                "[[lights]]\nkind = \"point\"\nposition = [0.0, 1.0, 0.0]\nintensity = 1.0\ncolor = [1.0, -1.0, 0.0]\n",
                "lights[0].color",
            ),
            ("[[lights]]\nkind = \"spot\"\n", "spot"),
            (
                "[[lights]]\nkind = \"point\"\nposition = [0.0, 1.0, 0.0]\nintensity = 1.0\nradius = 2.0\n",
                "radius",
            ),
            ("[mesh]\nresolution = 1\n", "mesh.resolution"),
            ("[mesh]\nfolds = 1000\n", "mesh.folds"),
            ("[mesh]\nfold_depth = 2.0\n", "mesh.fold_depth"),
            ("[mesh]\nkind = \"obj\"\n", "mesh.path"),
            ("[mesh]\npath = \"a.obj\"\n", "mesh.path"),
            ("[mesh]\nkind = \"teapot\"\n", "teapot"),
            ("[environment]\nsources = 9\n", "environment.sources"),
            ("[environment]\nsamples = 0\n", "environment.samples"),
        ];
        for (extra, field) in cases {
            let error = Scene::parse(&format!("{base}{extra}"))
                .expect_err(extra)
                .to_string();
            assert!(error.contains(field), "{extra}: {error}");
        }
        let nine =
            "[[lights]]\nkind = \"directional\"\ndirection = [0.0, 1.0, 0.0]\nirradiance = 1.0\n"
                .repeat(MAX_LIGHTS + 1);
        let error = Scene::parse(&format!("{base}{nine}"))
            .unwrap_err()
            .to_string();
        assert!(error.contains("at most 8"), "{error}");
    }

    #[test]
    fn mesh_path_is_resolved_against_the_scene_directory() {
        let scratch = tempfile::tempdir().unwrap();
        let dir = scratch.path();
        let path = dir.join("scene.toml");
        std::fs::write(
            &path,
            "fabrics = [\"velvet\"]\n[mesh]\nkind = \"obj\"\npath = \"cloth.obj\"\n",
        )
        .unwrap();
        let scene = Scene::load(&path).unwrap();
        assert_eq!(scene.mesh.path, Some(dir.join("cloth.obj")));
    }

    #[test]
    fn orbit_eye_is_at_distance_from_target() {
        let camera = OrbitCamera {
            target: [1.0, 2.0, 3.0],
            distance: 2.0,
            yaw_deg: 0.0,
            pitch_deg: 0.0,
            fov_y_deg: 40.0,
        };
        assert_eq!(camera.eye(), [1.0, 2.0, 5.0]);
    }
}
