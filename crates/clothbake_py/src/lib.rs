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
use clothbake::fit::samples::SampleRow;
use clothbake::fit::weave::WeaveParameters;
use clothbake::fit::{
    FitError, FitOptions, FitReport, LikeFabric, Parametrisation, SampleError, Samples,
    fit as fit_samples,
};
use clothbake::formats::draft_source::load_draft;
use clothbake::formats::fabric_toml::{FabricSet, fabric_file_text};
use clothbake::formats::json_lines::unit_direction;
use clothbake::formats::table_exr::{read_table, write_table};
use clothbake::lighting::EnvironmentSource;
use clothbake::measure::accuracy::{SetError, measure};
use clothbake::sampling::Sampler;
use clothbake::scene::mesh::Mesh;
use clothbake::scene::{Light, Scene};
use clothbake::table::Layout;
use clothbake::weave::{Fibre, Weave, Yarn};
use glam::DVec3;
use numpy::ndarray::{Array1, Array2, Array3};
use numpy::{
    AllowTypeChange, IntoPyArray, PyArray1, PyArray2, PyArray3, PyArrayLike1, PyArrayLike2,
    PyUntypedArrayMethods,
};
use pyo3::create_exception;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyString};
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

    /// The fabric as a fabric file (TOML, one `[[fabric]]`, as `clothbake weave --out` and
    /// `clothbake fit --out` write it), each line of `header` a `#` comment above it; the
    /// file reads back with `load_fabrics` and every command's `--fabrics`.
    #[pyo3(signature = (header = ""))]
    fn to_toml(&self, header: &str) -> String {
        fabric_file_text(std::slice::from_ref(&self.inner), header)
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
    evaluator::EVALUATORS.iter().map(|u| u.syntax).collect()
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
        unit_direction([w[0], w[1], w[2]], self.name).map_err(|e| e.to_string())
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

/// The text of a yarn knob's value as `Yarn::set` reads it: a string as it is, a number as
/// Python would print it, a sequence (a colour) as its items joined by `/`.
fn knob_text(option: &str, key: &str, value: &Bound<'_, PyAny>) -> PyResult<String> {
    if value.is_instance_of::<PyString>() {
        return value.extract();
    }
    if value.is_instance_of::<PyBool>() {
        return Err(error(format!(
            "{option}: yarn knob '{key}' takes a number or a string, got {value}"
        )));
    }
    if value.is_instance_of::<PyInt>() || value.is_instance_of::<PyFloat>() {
        return Ok(value.str()?.to_string());
    }
    if let Ok(items) = value.extract::<Vec<Bound<'_, PyAny>>>() {
        let parts = items
            .iter()
            .map(|item| knob_text(option, key, item))
            .collect::<PyResult<Vec<String>>>()?;
        return Ok(parts.join("/"));
    }
    Err(error(format!(
        "{option}: yarn knob '{key}' takes a number, a string or (for colour) three numbers, got {}",
        value.get_type().name()?
    )))
}

/// Sets the knobs of `spec` on `yarn`: a dict of knob to value, or the commands'
/// `key=value,...` text; errors are the library's, after the argument's name.
fn set_knobs(option: &str, spec: Option<&Bound<'_, PyAny>>, yarn: &mut Yarn) -> PyResult<()> {
    let Some(spec) = spec.filter(|s| !s.is_none()) else {
        return Ok(());
    };
    if let Ok(text) = spec.extract::<String>() {
        return yarn
            .set_all(&text)
            .map_err(|e| error(format!("{option}: {e}")));
    }
    let Ok(knobs) = spec.cast::<PyDict>() else {
        return Err(error(format!(
            "{option}: expected a dict of yarn knobs or a 'key=value,...' string, got {}",
            spec.get_type().name()?
        )));
    };
    for (key, value) in knobs.iter() {
        let key: String = key.extract().map_err(|_| {
            error(format!(
                "{option}: yarn knobs are named by strings, got the key {key}"
            ))
        })?;
        let text = knob_text(option, &key, &value)?;
        yarn.set(&key, &text)
            .map_err(|e| error(format!("{option}: {e}")))?;
    }
    Ok(())
}

/// The yarn knobs of `weave()` and `fit()`: `yarn` for both families, then each one's own.
type Knobs<'a, 'py> = [Option<&'a Bound<'py, PyAny>>; 3];

/// The weave that a draft's spelling and the yarn knobs make, with the draft's fabric name,
/// as `clothbake weave` makes it (src/cli/weave.rs, `weave_of`): the draft turned over
/// (`back`), then warp and weft exchanged (`swap`), then `yarn`'s knobs on both families and
/// each family's own.
fn woven(draft: &str, knobs: Knobs, back: bool, swap: bool) -> PyResult<(Weave, String)> {
    let (draft, name) = load_draft(draft).map_err(|e| error(format!("draft: {e}")))?;
    let draft = draft.oriented(back, swap);
    let [both, warp, weft] = knobs;
    let yarn = |own: Option<&Bound<'_, PyAny>>, option: &str| -> PyResult<Yarn> {
        let mut yarn = Yarn::default();
        set_knobs("yarn", both, &mut yarn)?;
        set_knobs(option, own, &mut yarn)?;
        Ok(yarn)
    };
    let weave = Weave {
        warp: yarn(warp, "warp")?,
        weft: yarn(weft, "weft")?,
        draft,
    };
    Ok((weave, name))
}

/// The fabric woven from `draft` (a named weave, `plain`, `basket:N`, `twill:N/M[:s|:z]`,
/// `satin:N[/STEP]`, `sateen:N[/STEP]`, or a WIF file) with yarn knobs (docs/weave.md), as
/// `clothbake weave` makes it: `yarn` for both families, then `warp` (thread 1, along x) and
/// `weft` (thread 2, along y), each a dict (`{"crimp": 30, "fibre": "silk"}`) or the
/// commands' text (`"crimp=30,fibre=silk"`); `back` weaves the back of the cloth, `swap`
/// exchanges warp and weft before the knobs apply; `name` defaults to the draft's.
#[pyfunction]
#[pyo3(signature = (draft, yarn = None, warp = None, weft = None, back = false, swap = false, name = None))]
#[allow(clippy::too_many_arguments)]
fn weave(
    draft: &str,
    yarn: Option<&Bound<'_, PyAny>>,
    warp: Option<&Bound<'_, PyAny>>,
    weft: Option<&Bound<'_, PyAny>>,
    back: bool,
    swap: bool,
    name: Option<&str>,
) -> PyResult<Fabric> {
    let (weave, default_name) = woven(draft, [yarn, warp, weft], back, swap)?;
    let inner = weave.fabric(name.unwrap_or(&default_name)).map_err(error)?;
    Ok(Fabric { inner })
}

/// The drawdown of `draft` (after `back` and `swap`, as in `weave()`), as `clothbake weave
/// --drawdown` prints it: one line per pick, pick 1 first; `#` where the warp is on top, `.`
/// where the weft is.
#[pyfunction]
#[pyo3(signature = (draft, back = false, swap = false))]
fn drawdown(draft: &str, back: bool, swap: bool) -> PyResult<String> {
    let (weave, _) = woven(draft, [None; 3], back, swap)?;
    Ok(weave.draft.drawdown())
}

/// The report of a fit as a dict (see `fit`).
fn fit_report_dict<'py>(py: Python<'py>, report: &FitReport) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("fit_relative_rms", report.fit_relative_rms)?;
    d.set_item("holdout_relative_rms", report.holdout_relative_rms)?;
    d.set_item("fit_count", report.fit_count)?;
    d.set_item("holdout_count", report.holdout_count)?;
    let names: Vec<&str> = report.parameters.iter().map(|p| p.name.as_str()).collect();
    d.set_item("parameters", names.clone())?;
    let values = PyDict::new(py);
    for (name, value) in names.iter().zip(&report.values) {
        values.set_item(name, value)?;
    }
    d.set_item("values", values)?;
    let bounds = PyDict::new(py);
    for p in &report.parameters {
        bounds.set_item(&p.name, (p.lower, p.upper))?;
    }
    d.set_item("bounds", bounds)?;
    d.set_item(
        "flat_directions",
        report
            .flat_directions
            .iter()
            .map(|f| f.to_string())
            .collect::<Vec<_>>(),
    )?;
    d.set_item("singular_values", report.singular_values.clone())?;
    d.set_item("start_objectives", report.start_objectives.clone())?;
    d.set_item("best_start", report.best_start)?;
    d.set_item("evaluations", report.evaluations)?;
    d.set_item("termination", &report.termination)?;
    Ok(d)
}

/// A sample error in the bindings' words: rows counted from 0 as NumPy counts them.
fn row_error(e: &SampleError) -> String {
    match e {
        SampleError::Line {
            line,
            field,
            message,
            ..
        } => format!("row {}: {field}: {message}", line - 1),
        SampleError::Empty { .. } => "wi, wo and f have no rows".into(),
        SampleError::TooFew {
            count,
            needed,
            parameters,
            what,
            ..
        } => format!(
            "{count} rows are fewer than the {needed} a fit of {parameters} free parameters \
             needs ({what})"
        ),
        e => e.to_string(),
    }
}

/// The rows of `f` (N, 3) or `weight` (N,) as numbers, refusing a wrong shape.
fn values_of(
    name: &str,
    array: &PyArrayLike2<'_, f64, AllowTypeChange>,
) -> PyResult<Vec<[f64; 3]>> {
    three_columns(name, array.shape())?;
    Ok(array
        .as_array()
        .rows()
        .into_iter()
        .map(|r| [r[0], r[1], r[2]])
        .collect())
}

/// A fabric fitted to measured samples of F (RGB, cosines included, as `Evaluator.eval`
/// gives it) at the directions `wi` (towards the light) and `wo` (towards the viewer) in the
/// patch frame, as `clothbake fit` fits a sample file: the rows are checked as its lines are
/// (directions above the horizon, F finite and ≥ 0, weights > 0); every `hold_out`-th row is
/// held out and measured after the fit. It starts from `like` (a `Fabric`, whose parameters
/// are fitted with its structure kept) or from `weave` (a draft's spelling, whose yarn knobs
/// are fitted, starting from `yarn`, `warp`, `weft`, `back`, `swap` as in `weave()`).
/// `fibre` fixes η of both threads to a fibre's; `starts` sets the number of starts (default 2
/// with `like`, the fabric's own values under two schedules of broadened lobes, 3 with
/// `weave`; more add seeded perturbations);
/// `name` names the fitted fabric. Returns the fabric and a report dict.
#[pyfunction]
#[pyo3(signature = (
    wi, wo, f, like = None, weave = None, yarn = None, warp = None, weft = None,
    back = false, swap = false, weight = None, fibre = None, name = None, starts = None,
    hold_out = 5
))]
#[allow(clippy::too_many_arguments)]
fn fit<'py>(
    py: Python<'py>,
    wi: PyArrayLike2<'py, f64, AllowTypeChange>,
    wo: PyArrayLike2<'py, f64, AllowTypeChange>,
    f: PyArrayLike2<'py, f64, AllowTypeChange>,
    like: Option<PyRef<'py, Fabric>>,
    weave: Option<&str>,
    yarn: Option<&Bound<'py, PyAny>>,
    warp: Option<&Bound<'py, PyAny>>,
    weft: Option<&Bound<'py, PyAny>>,
    back: bool,
    swap: bool,
    weight: Option<PyArrayLike1<'py, f64, AllowTypeChange>>,
    fibre: Option<&str>,
    name: Option<&str>,
    starts: Option<usize>,
    hold_out: usize,
) -> PyResult<(Fabric, Bound<'py, PyDict>)> {
    let eta = match fibre {
        None => None,
        Some(fibre) => Some(
            fibre
                .parse::<Fibre>()
                .map_err(|e| error(format!("fibre: {e}")))?
                .eta(),
        ),
    };
    if let Some(starts) = starts
        && !(1..=64).contains(&starts)
    {
        return Err(error(format!("starts: {starts} is not in 1..=64")));
    }
    let knobs_given = [yarn, warp, weft]
        .iter()
        .any(|k| k.is_some_and(|k| !k.is_none()));
    let parametrisation: Box<dyn Parametrisation> = match (like, weave) {
        (Some(like), None) => {
            if knobs_given || back || swap {
                return Err(error(
                    "yarn, warp, weft, back and swap go with weave=, not like=",
                ));
            }
            let mut parametrisation = LikeFabric::new(&like.inner, eta);
            if let Some(name) = name {
                let mut renamed = like.inner.clone();
                renamed.name = name.to_string();
                renamed.validate().map_err(error)?;
                parametrisation = parametrisation.with_name(name);
            }
            Box::new(parametrisation)
        }
        (None, Some(draft)) => {
            let (woven, default_name) = woven(draft, [yarn, warp, weft], back, swap)?;
            let name = name.unwrap_or(&default_name);
            // The start's fabric, validated (the name among it).
            woven.fabric(name).map_err(error)?;
            Box::new(WeaveParameters::new(&woven, name, eta))
        }
        _ => {
            return Err(error(
                "give exactly one of like= (a Fabric) and weave= (a draft's spelling)",
            ));
        }
    };
    let wi = values_of("wi", &wi)?;
    let wo = values_of("wo", &wo)?;
    let f = values_of("f", &f)?;
    same_length(["wi", "wo"], wi.len(), wo.len())?;
    same_length(["wi", "f"], wi.len(), f.len())?;
    let weight: Option<Vec<f64>> = match &weight {
        None => None,
        Some(w) => {
            let w: Vec<f64> = w.as_array().iter().copied().collect();
            same_length(["wi", "weight"], wi.len(), w.len())?;
            Some(w)
        }
    };
    let mut options = FitOptions {
        holdout_every: hold_out,
        ..FitOptions::default()
    };
    if let Some(starts) = starts {
        options.starts = Some(starts);
    }
    let report = py
        .detach(|| -> Result<FitReport, String> {
            let rows: Vec<SampleRow> = (0..f.len())
                .map(|row| (wi[row], wo[row], f[row], weight.as_ref().map(|w| w[row])))
                .collect();
            let samples = Samples::from_rows(&rows, "arrays").map_err(|e| row_error(&e))?;
            fit_samples(parametrisation.as_ref(), &samples, &options, &|_| {}).map_err(
                |e| match e {
                    FitError::Samples(e) => row_error(&e),
                    e => e.to_string(),
                },
            )
        })
        .map_err(error)?;
    let d = fit_report_dict(py, &report)?;
    Ok((
        Fabric {
            inner: report.fabric,
        },
        d,
    ))
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
    m.add_function(wrap_pyfunction!(weave, m)?)?;
    m.add_function(wrap_pyfunction!(drawdown, m)?)?;
    m.add_function(wrap_pyfunction!(fit, m)?)?;
    Ok(())
}
