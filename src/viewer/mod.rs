//! `clothbake view`: an interactive window (winit + a wgpu surface) showing the scene's cloth
//! shaded by the GPU form of an evaluator ([`crate::evaluator`]): the table's lookup, paper
//! mode or the resonant quadrature in the shader, so that they can be compared live.
//! Radiance is `Σ E·F(wi, wo)` over the scene's lights (docs/model.md#the-patch-transfer-f),
//! tone mapped as `render` does.
//!
//! - [`controls`]: keys, mouse and frame statistics, without window or GPU.
//! - `app`: the winit application: event handling, the evaluators shown, drawing.
//! - `surface`: the window's surface, depth buffer and the window system's errors.
//! - `timer`: GPU time of the cloth pass from timestamp queries, read without stalling.
//!
//! Tables are read from a directory (`NAME.exr` per fabric, as `bake` writes them) and must
//! have been baked from the fabrics the scene's fabric file gives (as for `render`); the
//! first fabric's table is read before the window opens so that a missing table is an error
//! at once, the others when first selected. With [`ViewOptions::frames`] the viewer draws that
//! many frames and closes, for tests and scripts.

mod app;
pub mod controls;
pub mod edit;
mod shading;
mod surface;
mod timer;

pub use app::{EDIT_WINDOW_SIZE, EditSetup, EditTimings};
pub use controls::KEY_HELP;

use crate::evaluator::Evaluator;
use crate::evaluator::table::load_fabric_table;
use crate::formats::fabric_toml::FabricSet;
use crate::formats::table_exr::{TableFile, fabric_table_file};
use crate::model::Fabric;
use crate::scene::mesh::Mesh;
use crate::scene::{MeshKind, MeshSpec, OrbitCamera, Scene};
use std::path::PathBuf;
use std::sync::Arc;

/// What `clothbake view` was asked to show.
#[derive(Clone, Debug)]
pub struct ViewOptions {
    /// The scene: fabrics (the list Tab and 1–9 move through), camera, lights, exposure, mesh.
    pub scene: Scene,
    /// The fabric shown first (default: the scene's first); added to the list if the scene
    /// does not name it.
    pub fabric: Option<String>,
    /// Directory holding `NAME.exr` for each fabric.
    pub tables: PathBuf,
    /// An OBJ mesh with UVs to show instead of the scene's mesh.
    pub mesh: Option<PathBuf>,
    /// Draw this many frames, then close (`None`: until the user quits).
    pub frames: Option<u32>,
    /// The evaluators key V cycles through, the first shown at start (each through its GPU
    /// form; at least one).
    pub evaluators: Vec<Arc<dyn Evaluator>>,
    /// `view --edit`: edit this fabric with the panel instead of showing the scene's list.
    pub edit: Option<EditSetup>,
}

/// What a viewing session measured.
#[derive(Clone, Debug, PartialEq)]
pub struct ViewSummary {
    pub adapter: String,
    /// Frames drawn and presented.
    pub frames: u64,
    /// Median CPU-side interval between successive frames, milliseconds.
    pub median_frame_ms: Option<f64>,
    /// Median GPU time of the cloth pass from timestamps, milliseconds (when the adapter
    /// offers timestamps).
    pub median_gpu_ms: Option<f64>,
    /// What an editing session measured.
    pub edit: Option<EditSummary>,
}

/// The frame times of an editing session and the script steps that failed.
#[derive(Clone, Debug, PartialEq)]
pub struct EditSummary {
    pub timings: EditTimings,
    pub failed_steps: usize,
}

/// Why the viewer could not run.
#[derive(Debug, thiserror::Error)]
pub enum ViewError {
    #[error("{0}")]
    Setup(String),
    #[error(
        "cannot open a window: {0} (is a display available? set DISPLAY, or run under \
         xvfb-run on a machine without one)"
    )]
    Display(String),
    #[error(transparent)]
    Gpu(#[from] crate::gpu::GpuError),
    #[error("{0}")]
    Render(String),
}

/// The fabric list the viewer moves through and the index shown first.
fn fabric_list(scene: &Scene, first: Option<&str>) -> (Vec<String>, usize) {
    let mut names = scene.fabrics.clone();
    let index = match first {
        None => 0,
        Some(name) => match names.iter().position(|n| n == name) {
            Some(i) => i,
            None => {
                names.insert(0, name.to_string());
                0
            }
        },
    };
    (names, index)
}

/// Opens the viewer window and runs until the user quits (or `options.frames` frames are
/// drawn). Prints the adapter and the key list at start. Errors (no tables, no display, no
/// adapter, GPU validation errors) come back as [`ViewError`], never as a panic.
pub fn run(options: ViewOptions) -> Result<ViewSummary, ViewError> {
    let mut scene = options.scene.clone();
    if let Some(mesh) = &options.mesh {
        scene.mesh = MeshSpec {
            kind: MeshKind::Obj,
            path: Some(mesh.clone()),
            ..MeshSpec::default()
        };
    }
    if options.evaluators.is_empty() {
        return Err(ViewError::Setup("no evaluator to show".into()));
    }
    let (fabrics, first, table) = match &options.edit {
        // The editor bakes its own tables.
        Some(edit) => (vec![edit.session.fabric().clone()], 0, None),
        None => {
            let (fabrics, first, table) = fabric_list_and_table(&scene, &options)?;
            (fabrics, first, Some(table))
        }
    };
    let mesh = Mesh::from_spec(&scene.mesh).map_err(|e| ViewError::Setup(e.to_string()))?;
    if options.mesh.is_some() {
        // A user's mesh may be of any size and anywhere: aim the scene's camera at it.
        let (centre, radius) = mesh.bounding_sphere();
        scene.camera = framing_camera(&scene.camera, centre.as_dvec3().to_array(), radius as f64);
    }
    let environment = scene
        .environment
        .source
        .load()
        .map_err(|e| ViewError::Setup(e.to_string()))?;
    if let Some(clamped) = environment.as_ref().and_then(|e| e.clamped_negatives()) {
        eprintln!(
            "clothbake view: environment {}: {clamped}",
            scene.environment.source
        );
    }
    let environment = environment.map(|map| {
        let start = std::time::Instant::now();
        let split = map.split_bright_sources(scene.environment.sources);
        eprintln!(
            "clothbake view: environment {}: {split} (split in {:.2} s)",
            scene.environment.source,
            start.elapsed().as_secs_f64()
        );
        split
    });
    app::run(
        app::Setup {
            environment,
            scene,
            mesh,
            fabrics,
            first,
            tables: options.tables,
            frames: options.frames,
            evaluators: options.evaluators,
            edit: options.edit,
        },
        table,
    )
}

/// The fabrics the viewer moves through, the index of the first shown and its table (read
/// before any window, so that a missing or stale table is reported at once; the others'
/// when selected).
fn fabric_list_and_table(
    scene: &Scene,
    options: &ViewOptions,
) -> Result<(Vec<Fabric>, usize, TableFile), ViewError> {
    if !options.tables.is_dir() {
        return Err(ViewError::Setup(format!(
            "tables directory {} does not exist or is not a directory (bake tables into it \
             with `clothbake bake --out {}`)",
            options.tables.display(),
            options.tables.display()
        )));
    }
    let (names, first) = fabric_list(scene, options.fabric.as_deref());
    let set = FabricSet::load_or_builtin(scene.fabric_file.as_deref())
        .map_err(|e| ViewError::Setup(e.to_string()))?;
    let fabrics: Vec<Fabric> = names
        .iter()
        .map(|name| set.require(name).cloned())
        .collect::<Result<_, _>>()
        .map_err(|e| ViewError::Setup(e.to_string()))?;
    let table = load_fabric_table(&options.tables, &fabrics[first])
        .map_err(|e| ViewError::Setup(e.to_string()))?;
    let missing: Vec<&str> = names
        .iter()
        .filter(|n| !options.tables.join(fabric_table_file(n)).is_file())
        .map(String::as_str)
        .collect();
    if !missing.is_empty() {
        eprintln!(
            "clothbake view: note: no table in {} for {} (selecting them reports the missing table)",
            options.tables.display(),
            missing.join(", ")
        );
    }
    Ok((fabrics, first, table))
}

/// `camera` turned on a sphere of `radius` at `centre`: same angles, looking at the centre
/// from the distance at which the sphere fills the vertical field of view with a 10% margin
/// (the sphere subtends half-angle asin(r/d), so d = 1.1·r/sin(fov/2)).
pub fn framing_camera(camera: &OrbitCamera, centre: [f64; 3], radius: f64) -> OrbitCamera {
    let half_fov = (0.5 * camera.fov_y_deg).to_radians();
    OrbitCamera {
        target: centre,
        distance: (1.1 * radius / half_fov.sin()).max(1e-3),
        ..*camera
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fabric_list_starts_at_the_requested_fabric() {
        let scene = Scene::builtin();
        let (names, i) = fabric_list(&scene, None);
        assert_eq!((names.clone(), i), (scene.fabrics.clone(), 0));
        let (names2, i) = fabric_list(&scene, Some("velvet"));
        assert_eq!(names2, names);
        assert_eq!(names2[i], "velvet");
        let (names3, i) = fabric_list(&scene, Some("my_fabric"));
        assert_eq!((names3.len(), i), (names.len() + 1, 0));
        assert_eq!(names3[0], "my_fabric");
    }

    #[test]
    fn framing_fits_the_sphere_in_the_field_of_view() {
        let camera = OrbitCamera::default();
        let framed = framing_camera(&camera, [1.0, 2.0, 3.0], 5.0);
        assert_eq!(framed.target, [1.0, 2.0, 3.0]);
        assert_eq!(
            (framed.yaw_deg, framed.pitch_deg),
            (camera.yaw_deg, camera.pitch_deg)
        );
        // The sphere's angular radius seen from the eye is 1/1.1 of the half field of view's
        // sine.
        let ratio = 5.0 / framed.distance / (0.5 * camera.fov_y_deg).to_radians().sin();
        assert!((ratio - 1.0 / 1.1).abs() < 1e-12, "{ratio}");
    }

    #[test]
    fn missing_tables_say_how_to_bake_them() {
        let scratch = tempfile::tempdir().unwrap();
        let dir = scratch.path();
        let options = ViewOptions {
            scene: Scene::builtin(),
            fabric: Some("velvet".into()),
            tables: dir.to_path_buf(),
            mesh: None,
            frames: Some(1),
            evaluators: vec![crate::evaluator::parse("table").unwrap()],
            edit: None,
        };
        let e = run(options.clone()).unwrap_err().to_string();
        assert!(
            e.contains("velvet.exr") && e.contains("clothbake bake"),
            "{e}"
        );
        let e = run(ViewOptions {
            fabric: Some("burlap".into()),
            ..options.clone()
        })
        .unwrap_err()
        .to_string();
        assert!(e.contains("no fabric named 'burlap'"), "{e}");
        let e = run(ViewOptions {
            tables: dir.join("absent"),
            ..options
        })
        .unwrap_err()
        .to_string();
        assert!(e.contains("absent") && e.contains("does not exist"), "{e}");
    }
}
