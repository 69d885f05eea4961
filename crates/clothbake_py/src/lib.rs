//! `clothbake._clothbake`: clothbake's fabrics, evaluators, sampler and tables for Python.
//!
//! A thin layer over the `clothbake` crate: every evaluator of its registry
//! (`clothbake::evaluator::EVALUATORS`) by the spelling the commands share, batch evaluation
//! and sampling over NumPy arrays of directions in the cloth frame (x thread 1, y thread 2, z
//! the normal), with the GIL released while the Rust batch runs on rayon's threads. Errors
//! are `ClothbakeError` (a `ValueError`) carrying the library's message, which names the
//! field, file or row that is wrong. The Python package (`python/clothbake`) re-exports this
//! module and adds the Mitsuba 3 BSDF.

use clothbake::evaluator::{self, EvaluationContext, FabricEvaluator};
use clothbake::formats::fabric_toml::FabricSet;
use clothbake::formats::json_lines::unit_direction;
use clothbake::formats::table_exr::{read_table, write_table};
use clothbake::lighting::EnvironmentSource;
use clothbake::measure::accuracy::{SetError, measure};
use clothbake::sampling::Sampler;
use clothbake::scene::mesh::Mesh;
use clothbake::scene::{Light, Scene};
use clothbake::table::Layout;
use glam::DVec3;
use numpy::ndarray::{Array1, Array2, Array3};
use numpy::{
    AllowTypeChange, IntoPyArray, PyArray1, PyArray2, PyArray3, PyArrayLike2, PyUntypedArrayMethods,
};
use pyo3::create_exception;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rayon::prelude::*;
use std::path::PathBuf;
use std::sync::OnceLock;

create_exception!(
    _clothbake,
    ClothbakeError,
    PyValueError,
    "A fabric, evaluator, table, file or array that clothbake refuses; the message names what is wrong."
);

fn error(message: impl std::fmt::Display) -> PyErr {
    ClothbakeError::new_err(message.to_string())
}

/// One fabric of the model: two thread families with their tangent curves
/// (docs/model.md#the-six-built-in-fabrics).
#[pyclass(frozen, module = "clothbake._clothbake")]
struct Fabric {
    inner: clothbake::model::Fabric,
}

#[pymethods]
impl Fabric {
    /// The built-in fabric `name` (one of `fabric_names()`).
    #[staticmethod]
    fn builtin(name: &str) -> PyResult<Self> {
        let set = FabricSet::builtin();
        let inner = set.require(name).map_err(error)?.clone();
        Ok(Self { inner })
    }

    /// The fabric's name.
    #[getter]
    fn name(&self) -> &str {
        &self.inner.name
    }

    fn __repr__(&self) -> String {
        format!("Fabric('{}')", self.inner.name)
    }
}

/// The names of the built-in fabrics, in the fabric file's order.
#[pyfunction]
fn fabric_names() -> Vec<String> {
    FabricSet::builtin()
        .fabrics()
        .iter()
        .map(|f| f.name.clone())
        .collect()
}

/// Every fabric of a fabric file (TOML, docs/file-formats.md#fabric-files), validated.
#[pyfunction]
fn load_fabrics(path: PathBuf) -> PyResult<Vec<Fabric>> {
    let set = FabricSet::load(&path).map_err(error)?;
    Ok(set
        .fabrics()
        .iter()
        .map(|f| Fabric { inner: f.clone() })
        .collect())
}

/// The registered evaluators' spellings (`direct`, `paper[:N]`, `resonant[:S/V/B]`,
/// `table[:PATH]`, `constant`).
#[pyfunction]
fn evaluator_syntaxes() -> Vec<&'static str> {
    evaluator::EVALUATORS.iter().map(|u| u.syntax()).collect()
}

/// Refuses an array `name` whose shape is not (N, 3).
fn three_columns(name: &str, shape: &[usize]) -> PyResult<()> {
    if shape.len() == 2 && shape[1] == 3 {
        Ok(())
    } else {
        Err(error(format!(
            "{name}: expected an array of shape (N, 3), got {shape:?}"
        )))
    }
}

/// A checked (N, 3) array of directions, read lazily row by row.
struct Directions<'a> {
    name: &'static str,
    /// The rows one after the other: the array's own memory when it is C-contiguous (the
    /// usual case, read in place), else a copy.
    flat: std::borrow::Cow<'a, [f64]>,
}

impl<'a> Directions<'a> {
    fn new(
        name: &'static str,
        array: &'a PyArrayLike2<'_, f64, AllowTypeChange>,
    ) -> PyResult<Self> {
        three_columns(name, array.shape())?;
        let view = array.as_array();
        let flat = match view.to_slice() {
            Some(flat) => std::borrow::Cow::Borrowed(flat),
            None => std::borrow::Cow::Owned(view.iter().copied().collect()),
        };
        Ok(Self { name, flat })
    }

    fn len(&self) -> usize {
        self.flat.len() / 3
    }

    /// Row `row` normalised as every clothbake command reads a direction
    /// (`unit_direction`: finite, not zero, any length).
    fn read(&self, row: usize) -> Result<DVec3, String> {
        let w = &self.flat[3 * row..3 * row + 3];
        unit_direction([w[0], w[1], w[2]], self.name)
    }

    /// Row `row`, or NaN where it is refused (which `unit_direction` never returns).
    fn read_or_nan(&self, row: usize) -> DVec3 {
        self.read(row).unwrap_or(DVec3::NAN)
    }

    /// The error of the first refused row among `refused` (a refused row reads as NaN).
    fn refusal(&self, refused: Option<usize>) -> PyResult<()> {
        match refused {
            Some(row) => Err(error(format!(
                "row {row}: {}",
                self.read(row).err().unwrap_or_default()
            ))),
            None => Ok(()),
        }
    }

    /// Every row, on rayon's threads (read on one thread, a million rows would cost a
    /// third of a table lookup batch).
    fn all(&self) -> PyResult<Vec<DVec3>> {
        let rows: Vec<DVec3> = (0..self.len())
            .into_par_iter()
            .map(|row| self.read_or_nan(row))
            .collect();
        self.refusal(rows.par_iter().position_first(|w| w.is_nan()))?;
        Ok(rows)
    }
}

/// The pairs (a, b) of two arrays of directions of equal length, read together.
fn direction_pairs(a: &Directions, b: &Directions) -> PyResult<Vec<(DVec3, DVec3)>> {
    same_length([a.name, b.name], a.len(), b.len())?;
    let pairs: Vec<(DVec3, DVec3)> = (0..a.len())
        .into_par_iter()
        .map(|row| (a.read_or_nan(row), b.read_or_nan(row)))
        .collect();
    if let Some(row) = pairs
        .par_iter()
        .position_first(|(a, b)| a.is_nan() || b.is_nan())
    {
        a.refusal(pairs[row].0.is_nan().then_some(row))?;
        b.refusal(Some(row))?;
    }
    Ok(pairs)
}

/// `batch` of the pairs of rows of two arrays of directions, read by [`direction_pairs`],
/// with the GIL released.
fn over_pairs<T: Send>(
    py: Python<'_>,
    (a_name, a): (&'static str, &PyArrayLike2<'_, f64, AllowTypeChange>),
    (b_name, b): (&'static str, &PyArrayLike2<'_, f64, AllowTypeChange>),
    batch: impl FnOnce(&[(DVec3, DVec3)]) -> T + Send,
) -> PyResult<T> {
    let (a, b) = (Directions::new(a_name, a)?, Directions::new(b_name, b)?);
    py.detach(|| Ok(batch(&direction_pairs(&a, &b)?)))
}

fn same_length(names: [&str; 2], a: usize, b: usize) -> PyResult<()> {
    if a == b {
        Ok(())
    } else {
        Err(error(format!(
            "{} has {a} rows and {} has {b}: they must match",
            names[0], names[1]
        )))
    }
}

/// Vectors (RGB values, directions) as the rows of an (N, 3) array.
fn rows_array(values: Vec<DVec3>) -> Array2<f64> {
    let n = values.len();
    let rows: Vec<[f64; 3]> = values.par_iter().map(|v| v.to_array()).collect();
    let flat = rows.into_flattened();
    Array2::from_shape_vec((n, 3), flat).expect("n rows of 3")
}

/// Sampled directions (N, 3) and their densities (N,).
type Draws<'py> = (Bound<'py, PyArray2<f64>>, Bound<'py, PyArray1<f64>>);

/// F(wi, wo) of one fabric by one evaluator of the registry, with the importance sampler
/// that fits it.
///
/// `Evaluator(fabric, evaluator="direct", tables="tables")`: `evaluator` is spelled as on
/// every clothbake command (`direct`, `paper:32`, `resonant:6/5/2`, `table`, `table:PATH`,
/// `PATH.exr`, `constant`); `table` without a path reads `TABLES/NAME.exr`.
#[pyclass(frozen, module = "clothbake._clothbake")]
struct Evaluator {
    inner: Box<dyn FabricEvaluator>,
    spelling: String,
    sampler: OnceLock<Sampler>,
}

impl Evaluator {
    fn sampler(&self) -> &Sampler {
        self.sampler.get_or_init(|| self.inner.sampler())
    }
}

#[pymethods]
impl Evaluator {
    #[new]
    #[pyo3(signature = (fabric, evaluator = "direct", tables = PathBuf::from("tables")))]
    fn new(py: Python<'_>, fabric: &Fabric, evaluator: &str, tables: PathBuf) -> PyResult<Self> {
        let configured = evaluator::parse(evaluator).map_err(error)?;
        let context = EvaluationContext { tables };
        let inner = py
            .detach(|| configured.prepare(&fabric.inner, &context))
            .map_err(error)?;
        Ok(Self {
            inner,
            spelling: configured.spelling(),
            sampler: OnceLock::new(),
        })
    }

    /// The evaluator's spelling, as it parses back (`paper:32`).
    #[getter]
    fn spelling(&self) -> &str {
        &self.spelling
    }

    /// A short description (`table split_frame R=31`).
    #[getter]
    fn label(&self) -> String {
        self.inner.label()
    }

    /// F(wi, wo) (RGB, cosines included, shape (N, 3)) for each row of `wi` (towards the
    /// light) and `wo` (towards the viewer), directions in the cloth frame, normalised as
    /// read; 0 where either is on or below the horizon.
    fn eval<'py>(
        &self,
        py: Python<'py>,
        wi: PyArrayLike2<'py, f64, AllowTypeChange>,
        wo: PyArrayLike2<'py, f64, AllowTypeChange>,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let values = over_pairs(py, ("wi", &wi), ("wo", &wo), |pairs| {
            self.inner.eval_batch(pairs)
        })?;
        Ok(rows_array(values).into_pyarray(py))
    }

    /// Directions drawn for each row of `wo` from three uniform numbers in [0, 1) per row
    /// of `u`: `(wi, pdf)` with wi of shape (N, 3) and pdf(wi | wo) per unit solid angle of
    /// shape (N,). A rejected draw (wo or the draw on or below the horizon) has wi = 0 and
    /// pdf = 0.
    fn sample<'py>(
        &self,
        py: Python<'py>,
        wo: PyArrayLike2<'py, f64, AllowTypeChange>,
        u: PyArrayLike2<'py, f64, AllowTypeChange>,
    ) -> PyResult<Draws<'py>> {
        let wo = Directions::new("wo", &wo)?;
        let wo = py.detach(|| wo.all())?;
        three_columns("u", u.shape())?;
        let u: Vec<[f64; 3]> = u
            .as_array()
            .rows()
            .into_iter()
            .map(|r| [r[0], r[1], r[2]])
            .collect();
        if let Some(row) = u
            .iter()
            .position(|r| r.iter().any(|x| !(0.0..1.0).contains(x)))
        {
            return Err(error(format!(
                "row {row}: u = {:?} is not in [0, 1)",
                u[row]
            )));
        }
        same_length(["wo", "u"], wo.len(), u.len())?;
        let draws: Vec<(DVec3, f64)> = py.detach(|| {
            let sampler = self.sampler();
            wo.par_iter()
                .zip(&u)
                .map(|(&wo, &u)| {
                    sampler
                        .sample(wo, u)
                        .map_or((DVec3::ZERO, 0.0), |s| (s.wi, s.pdf))
                })
                .collect()
        });
        let wi = rows_array(draws.iter().map(|d| d.0).collect());
        let pdf = Array1::from_iter(draws.iter().map(|d| d.1));
        Ok((wi.into_pyarray(py), pdf.into_pyarray(py)))
    }

    /// pdf(wi | wo) per unit solid angle of the sampler, shape (N,); 0 unless both are
    /// above the horizon.
    fn pdf<'py>(
        &self,
        py: Python<'py>,
        wo: PyArrayLike2<'py, f64, AllowTypeChange>,
        wi: PyArrayLike2<'py, f64, AllowTypeChange>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let pdf = over_pairs(py, ("wo", &wo), ("wi", &wi), |pairs| {
            let sampler = self.sampler();
            pairs
                .par_iter()
                .map(|&(wo, wi)| sampler.pdf(wo, wi))
                .collect::<Vec<f64>>()
        })?;
        Ok(Array1::from_vec(pdf).into_pyarray(py))
    }

    /// Seconds the Rust batch of this evaluator takes over the pairs (wi, wo), already in
    /// Rust's form: the floor that `eval` is compared with (bench/batch.py).
    fn _rust_batch_seconds<'py>(
        &self,
        py: Python<'py>,
        wi: PyArrayLike2<'py, f64, AllowTypeChange>,
        wo: PyArrayLike2<'py, f64, AllowTypeChange>,
    ) -> PyResult<f64> {
        over_pairs(py, ("wi", &wi), ("wo", &wo), |pairs| {
            let start = std::time::Instant::now();
            std::hint::black_box(self.inner.eval_batch(std::hint::black_box(pairs)));
            start.elapsed().as_secs_f64()
        })
    }

    fn __repr__(&self) -> String {
        format!("Evaluator('{}')", self.inner.label())
    }
}

/// A baked table read from its EXR file, with the provenance it records.
#[pyclass(frozen, module = "clothbake._clothbake")]
struct Table {
    file: clothbake::formats::table_exr::TableFile,
    path: PathBuf,
}

fn set_error_dict<'py>(py: Python<'py>, e: &SetError) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("relative_rms", e.relative_rms)?;
    d.set_item("max_abs", e.max_abs)?;
    d.set_item("max_abs_at_value", e.max_abs_at_value)?;
    Ok(d)
}

#[pymethods]
impl Table {
    /// Reads and checks a table file (`clothbake check`'s reading: layout, planes, fabric,
    /// hash).
    #[staticmethod]
    fn load(py: Python<'_>, path: PathBuf) -> PyResult<Self> {
        let file = py.detach(|| read_table(&path)).map_err(error)?;
        Ok(Self { file, path })
    }

    /// The table's layout (`thread_frame`, `split_frame`, `grid4d`).
    #[getter]
    fn layout(&self) -> &'static str {
        self.file.table.layout.name()
    }

    #[getter]
    fn resolution(&self) -> u32 {
        self.file.table.resolution
    }

    /// The fabric it was baked from.
    #[getter]
    fn fabric(&self) -> Fabric {
        Fabric {
            inner: self.file.table.fabric.clone(),
        }
    }

    /// Bytes of f16 texels.
    #[getter]
    fn byte_size(&self) -> usize {
        self.file.table.byte_size()
    }

    /// SHA-256 of what made the table (fabric, layout, resolution, baker revision).
    #[getter]
    fn hash(&self) -> &str {
        &self.file.hash
    }

    /// The table's error against the direct evaluation of its fabric, as `clothbake check`
    /// measures it: `pairs` uniform and `pairs` highlight pairs; a dict per set
    /// (`uniform`, `highlight`, and the same above 1° and 3° elevation) of relative RMS,
    /// largest |error| and F where it occurs.
    #[pyo3(signature = (pairs = 20000))]
    fn check<'py>(&self, py: Python<'py>, pairs: usize) -> PyResult<Bound<'py, PyDict>> {
        if !(1..=1_000_000).contains(&pairs) {
            return Err(error(format!("pairs: {pairs} is not in 1..=1000000")));
        }
        let table = &self.file.table;
        let e = py.detach(|| measure(table, &table.fabric, pairs));
        let d = PyDict::new(py);
        for (key, set) in [
            ("uniform", &e.uniform),
            ("uniform_above_1deg", &e.uniform_above_1deg),
            ("uniform_above_3deg", &e.uniform_above_3deg),
            ("highlight", &e.highlight),
            ("highlight_above_1deg", &e.highlight_above_1deg),
            ("highlight_above_3deg", &e.highlight_above_3deg),
        ] {
            d.set_item(key, set_error_dict(py, set)?)?;
        }
        Ok(d)
    }

    /// The evaluator of this table (`Evaluator(fabric, "table:PATH")`).
    fn evaluator(&self, py: Python<'_>) -> PyResult<Evaluator> {
        let spelling = format!("table:{}", self.path.display());
        Evaluator::new(py, &self.fabric(), &spelling, PathBuf::from("tables"))
    }

    fn __repr__(&self) -> String {
        format!(
            "Table('{}': {} {} at resolution {})",
            self.path.display(),
            self.file.table.fabric.name,
            self.layout(),
            self.resolution()
        )
    }
}

/// Bakes `fabric` into a table of `layout` (default `split_frame`) at `resolution`
/// (default: the layout's) and writes it to `path` atomically (a temporary file, then a
/// rename); returns the table as read back.
#[pyfunction]
#[pyo3(signature = (fabric, path, layout = None, resolution = None))]
fn bake(
    py: Python<'_>,
    fabric: &Fabric,
    path: PathBuf,
    layout: Option<&str>,
    resolution: Option<u32>,
) -> PyResult<Table> {
    let layout = match layout {
        None => Layout::DEFAULT,
        Some(name) => Layout::from_name(name).ok_or_else(|| {
            error(format!(
                "layout: unknown '{name}'; layouts: {}",
                Layout::ALL
                    .iter()
                    .map(|l| l.name())
                    .collect::<Vec<_>>()
                    .join(", ")
            ))
        })?,
    };
    let resolution = resolution.unwrap_or(layout.default_resolution());
    py.detach(|| -> Result<(), String> {
        let table = clothbake::bake::bake(&fabric.inner, layout, resolution, &|| {})
            .map_err(|e| e.to_string())?;
        write_table(&path, &table).map_err(|e| e.to_string())?;
        Ok(())
    })
    .map_err(error)?;
    Table::load(py, path)
}

/// An (n, k) array of `rows`.
fn matrix<const K: usize, T: Copy + Into<f64>>(rows: impl Iterator<Item = [T; K]>) -> Array2<f64> {
    let flat: Vec<f64> = rows.flat_map(|r| r.map(Into::into)).collect();
    let n = flat.len() / K;
    Array2::from_shape_vec((n, K), flat).expect("n rows of K")
}

/// The scene `clothbake render` draws, for another renderer to draw the same view: the
/// built-in scene, or the scene file at `path`. A dict of `fabrics`, `exposure`, `camera`
/// (`eye`, `target`, `fov_y_deg`; +y up), `lights` (dicts: `kind` "directional" with
/// `direction` towards the light and `irradiance`, or "point" with `position` and
/// `intensity`; `color`), and `mesh`: `positions`, `normals`, `tangents` (thread 1) of shape
/// (N, 3), `uvs` (N, 2) and `faces` (M, 3) of vertex indices.
#[pyfunction]
#[pyo3(signature = (path = None))]
fn load_scene(py: Python<'_>, path: Option<PathBuf>) -> PyResult<Bound<'_, PyDict>> {
    let scene = match path {
        Some(path) => Scene::load(&path).map_err(error)?,
        None => Scene::builtin(),
    };
    let mesh = py.detach(|| Mesh::from_spec(&scene.mesh)).map_err(error)?;
    let d = PyDict::new(py);
    d.set_item("fabrics", scene.fabrics.clone())?;
    d.set_item("exposure", scene.exposure)?;
    let camera = PyDict::new(py);
    camera.set_item("eye", scene.camera.eye())?;
    camera.set_item("target", scene.camera.target)?;
    camera.set_item("fov_y_deg", scene.camera.fov_y_deg)?;
    d.set_item("camera", camera)?;
    let mut lights = Vec::new();
    for light in &scene.lights {
        let l = PyDict::new(py);
        match *light {
            Light::Directional {
                direction,
                color,
                irradiance,
            } => {
                l.set_item("kind", "directional")?;
                l.set_item("direction", DVec3::from(direction).normalize().to_array())?;
                l.set_item("color", color)?;
                l.set_item("irradiance", irradiance)?;
            }
            Light::Point {
                position,
                color,
                intensity,
            } => {
                l.set_item("kind", "point")?;
                l.set_item("position", position)?;
                l.set_item("color", color)?;
                l.set_item("intensity", intensity)?;
            }
        }
        lights.push(l);
    }
    d.set_item("lights", lights)?;
    let m = PyDict::new(py);
    let v = &mesh.vertices;
    m.set_item(
        "positions",
        matrix(v.iter().map(|v| v.position)).into_pyarray(py),
    )?;
    m.set_item(
        "normals",
        matrix(v.iter().map(|v| v.normal)).into_pyarray(py),
    )?;
    m.set_item(
        "tangents",
        matrix(v.iter().map(|v| v.tangent)).into_pyarray(py),
    )?;
    m.set_item("uvs", matrix(v.iter().map(|v| v.uv)).into_pyarray(py))?;
    let faces: Vec<u32> = mesh.indices.clone();
    let faces = Array2::from_shape_vec((faces.len() / 3, 3), faces).expect("triangles");
    m.set_item("faces", faces.into_pyarray(py))?;
    d.set_item("mesh", m)?;
    Ok(d)
}

/// The environment map that `--env SOURCE` names (`studio`, `sky`, `overcast`, `interior`,
/// `uniform`, or an equirectangular `.hdr`/`.exr` file, read and checked as the renderer reads
/// it) as an (H, W, 3) array of linear radiance: row 0 looks up (+y), and the texel at
/// (u, v) looks along d with u = 1/2 + atan2(d.x, −d.z)/2π, v = acos(d.y)/π
/// (docs/file-formats.md#environment-maps).
#[pyfunction]
#[pyo3(signature = (source = "studio"))]
fn environment_map<'py>(py: Python<'py>, source: &str) -> PyResult<Bound<'py, PyArray3<f32>>> {
    let parsed: EnvironmentSource = source.parse().map_err(error)?;
    let environment = py
        .detach(|| parsed.load())
        .map_err(error)?
        .ok_or_else(|| error(format!("source: '{source}' is no environment")))?;
    let level = &environment.levels()[0];
    let flat: Vec<f32> = level.texels().iter().flatten().copied().collect();
    let shape = (level.height() as usize, level.width() as usize, 3);
    Ok(Array3::from_shape_vec(shape, flat)
        .expect("height rows of width texels")
        .into_pyarray(py))
}

/// clothbake's version.
const VERSION: &str = env!("CARGO_PKG_VERSION");

#[pymodule]
fn _clothbake(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", VERSION)?;
    m.add("ClothbakeError", m.py().get_type::<ClothbakeError>())?;
    m.add_class::<Fabric>()?;
    m.add_class::<Evaluator>()?;
    m.add_class::<Table>()?;
    m.add_function(wrap_pyfunction!(fabric_names, m)?)?;
    m.add_function(wrap_pyfunction!(load_fabrics, m)?)?;
    m.add_function(wrap_pyfunction!(evaluator_syntaxes, m)?)?;
    m.add_function(wrap_pyfunction!(bake, m)?)?;
    m.add_function(wrap_pyfunction!(load_scene, m)?)?;
    m.add_function(wrap_pyfunction!(environment_map, m)?)?;
    Ok(())
}
