//! The `render` command: each fabric of a scene rendered headless with the GPU form of an
//! evaluator (a table's lookup, paper mode, the resonant quadrature; [`crate::evaluator`]),
//! written as PNG with its median GPU time per frame; optionally the CPU reference of the
//! same view, an error heat map and the image error.

use super::image::{
    HEATMAP_LOG10_RANGE, ImageError, ImageFileError, error_heatmap, image_error, write_linear_exr,
    write_png,
};
use super::reference::ReferenceEnvironment;
use super::{FrameSettings, GpuEnvironment, Headless, RenderOutput, reference};
use crate::bake::taps::table_taps;
use crate::evaluator::{EvaluationContext, Evaluator, FabricEvaluator};
use crate::formats::fabric_toml::FabricSet;
use crate::formats::table_exr::fabric_table_file;
use crate::gpu::{GpuBrdf, GpuContext, GpuSampleTaps};
use crate::model::{Fabric, Integration, Patch, ResonantNodes};
use crate::scene::Scene;
use crate::scene::mesh::Mesh;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

/// One `render` run.
#[derive(Clone, Debug)]
pub struct RenderJob {
    pub scene: Scene,
    /// Render only this fabric (default: every fabric of the scene).
    pub fabric: Option<String>,
    /// Directory of the baked tables (the `table` evaluator's default).
    pub tables: PathBuf,
    /// Output PNG; with several fabrics, `STEM-FABRIC.png` beside it.
    pub out: PathBuf,
    pub width: u32,
    pub height: u32,
    /// Timed frames (after one warm-up frame).
    pub frames: u32,
    /// How the shader evaluates F: an evaluator with a GPU form.
    pub evaluator: Arc<dyn Evaluator>,
    /// Also render the CPU reference and compare.
    pub reference: bool,
    /// Monte Carlo samples per pixel of the reference's environment term.
    pub reference_samples: u32,
    /// Also write the linear radiance beside each PNG as `STEM.exr` (f16 RGBA).
    pub linear: bool,
    /// An OBJ mesh to render instead of the scene's; the camera is re-aimed at it.
    pub mesh: Option<PathBuf>,
}

/// What `render` produced for one fabric.
#[derive(Clone, Debug)]
pub struct FabricRender {
    pub fabric: String,
    pub png: PathBuf,
    pub output: RenderOutput,
    /// With `reference`: the reference and heat map files, the error, the CPU time.
    pub comparison: Option<Comparison>,
}

/// A render against its CPU reference.
#[derive(Clone, Debug)]
pub struct Comparison {
    pub reference_png: PathBuf,
    pub error_png: PathBuf,
    pub error: ImageError,
    pub reference_seconds: f64,
}

/// `out` for a single fabric, else `STEM-FABRIC.EXT` beside it.
pub fn output_path(out: &Path, fabric: &str, several: bool) -> PathBuf {
    if !several {
        return out.to_path_buf();
    }
    with_suffix(out, &format!("-{fabric}"))
}

/// `STEMsuffix.EXT` beside `path` (extension png if it has none).
pub fn with_suffix(path: &Path, suffix: &str) -> PathBuf {
    let stem = path
        .file_stem()
        .map_or_else(|| "frame".to_string(), |s| s.to_string_lossy().into_owned());
    let ext = path
        .extension()
        .map_or_else(|| "png".to_string(), |e| e.to_string_lossy().into_owned());
    path.with_file_name(format!("{stem}{suffix}.{ext}"))
}

/// Runs the job; `say` receives each line of the report as it happens.
/// Why a render job failed: the library error of the step that failed.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    #[error(transparent)]
    Fabrics(#[from] crate::formats::fabric_toml::FabricFileError),
    #[error(transparent)]
    Environment(#[from] crate::lighting::EnvironmentError),
    #[error(transparent)]
    Evaluator(#[from] crate::evaluator::EvaluatorError),
    #[error(transparent)]
    Mesh(#[from] crate::scene::mesh::MeshError),
    #[error(transparent)]
    Gpu(#[from] crate::gpu::GpuError),
    #[error(transparent)]
    Image(#[from] ImageFileError),
    #[error(transparent)]
    Table(#[from] crate::formats::table_exr::TableFileError),
    #[error("cannot create {path}: {source}", path = .path.display())]
    CreateDirectory {
        path: PathBuf,
        source: std::io::Error,
    },
}

pub fn run(job: &RenderJob, say: &mut dyn FnMut(&str)) -> Result<Vec<FabricRender>, RenderError> {
    let set = FabricSet::load_or_builtin(job.scene.fabric_file.as_deref())?;
    let names = match &job.fabric {
        Some(name) => vec![name.clone()],
        None => job.scene.fabrics.clone(),
    };
    let fabrics: Vec<Fabric> = names
        .iter()
        .map(|name| set.require(name).cloned())
        .collect::<Result<_, _>>()?;
    // The environment, then the tables: a bad file or a missing table is an error before
    // any GPU work.
    let environment = job.scene.environment.source.load()?;
    let evaluation_context = EvaluationContext {
        tables: job.tables.clone(),
    };
    let evaluations: Vec<Box<dyn FabricEvaluator>> = fabrics
        .iter()
        .map(|f| job.evaluator.prepare(f, &evaluation_context))
        .collect::<Result<_, _>>()?;
    let mut settings = FrameSettings::from_scene(&job.scene);
    let mesh = match &job.mesh {
        Some(path) => {
            let mesh = Mesh::load_obj(path)?;
            // Frame the user's mesh: aim at its bounding sphere, keep the view direction.
            let (centre, radius) = mesh.bounding_sphere();
            let fov = settings.camera.fov_y_deg.to_radians();
            let direction = (settings.camera.eye - settings.camera.target).normalize();
            settings.camera.target = centre;
            settings.camera.eye = centre + direction * (1.1 * radius / (0.5 * fov).sin());
            say(&format!(
                "mesh {}: {} vertices, {} triangles; camera aimed at its bounding sphere",
                path.display(),
                mesh.vertices.len(),
                mesh.triangle_count()
            ));
            mesh
        }
        None => Mesh::from_spec(&job.scene.mesh)?,
    };
    let context = GpuContext::new()?;
    say(&format!("adapter: {}", context.adapter));
    let gpu_environment = match &environment {
        Some(map) => {
            let start = Instant::now();
            let split = map.split_bright_sources(job.scene.environment.sources);
            let split_seconds = start.elapsed().as_secs_f64();
            say(&format!(
                "environment {} ({}×{}, {} mip levels): {}; then {} filtered importance samples \
                 per pixel of the rest (split in {:.2} s)",
                job.scene.environment.source,
                map.width(),
                map.height(),
                map.levels().len(),
                split,
                settings.environment_samples,
                split_seconds
            ));
            if let Some(clamped) = map.clamped_negatives() {
                say(&format!(
                    "environment {}: {clamped}",
                    job.scene.environment.source
                ));
            }
            Some(GpuEnvironment::split(&context, &split)?)
        }
        None => None,
    };
    let several = fabrics.len() > 1;
    let mut headless: Option<Headless> = None;
    let mut results = Vec::new();
    for (fabric, evaluation) in fabrics.iter().zip(&evaluations) {
        let brdf: Box<dyn GpuBrdf> = evaluation.gpu(&context)?;
        let renderer = match &mut headless {
            Some(h) => {
                h.renderer.set_brdf(&context, brdf.as_ref())?;
                h
            }
            None => headless.insert(Headless::new(
                &context,
                &mesh,
                brdf.as_ref(),
                job.width,
                job.height,
            )?),
        };
        // The importance sampler that fits the evaluation (a table's from its texels, else
        // the fabric's from the resonant quadrature) and the sample taps drawn from it: a
        // table's taps are read from beside it (built and stored there once), any other
        // evaluation's built on the CPU once per fabric; the taps are uploaded. The sampler
        // is built where the taps or the reference need it.
        let table = table_file(job, fabric);
        let mut sampler = gpu_environment
            .as_ref()
            .filter(|_| job.reference)
            .map(|_| evaluation.sampler());
        if let Some(map) = &gpu_environment {
            let start = Instant::now();
            let samples = settings.environment_samples;
            let (taps, origin) = match &table {
                Some(path) => {
                    let (taps, origin) = table_taps(path, samples)?;
                    (taps, origin.to_string())
                }
                None => {
                    let sampler = sampler.get_or_insert_with(|| evaluation.sampler());
                    (evaluation.sample_taps(sampler, samples), "built".into())
                }
            };
            say(&format!(
                "{}: sample taps ({} per wo node, {} nodes) in {:.2} s: {origin}",
                fabric.name,
                taps.samples(),
                crate::sampling::taps::TAP_NODES,
                start.elapsed().as_secs_f64()
            ));
            let gpu_taps = GpuSampleTaps::new(&context, &taps)?;
            renderer
                .renderer
                .set_environment(&context, map, &gpu_taps)?;
        }
        let output = renderer.render(&context, &settings, job.frames)?;
        let png = output_path(&job.out, &fabric.name, several);
        create_parent(&png)?;
        write_png(&png, &output.display)?;
        if job.linear {
            write_linear_exr(&png.with_extension("exr"), &output.linear)?;
        }
        let coverage = output.linear.coverage();
        say(&format!(
            "{}: {} ({}×{}, {:.1}% covered): {}: median {:.3} ms per frame over {} frames ({})",
            fabric.name,
            png.display(),
            job.width,
            job.height,
            100.0 * coverage as f64 / output.linear.pixels.len() as f64,
            brdf.label(),
            output.timing.median_ms(),
            output.timing.frame_ms.len(),
            output.timing.source
        ));
        let comparison = if job.reference {
            let gbuffer = renderer.gbuffer(&context, &settings)?;
            let start = Instant::now();
            // Under an environment light the reference evaluates F at hundreds of directions
            // per pixel: the resonant quadrature (its error against the direct rule is in
            // report/REPORT.md) keeps that to seconds.
            let (patch, evaluation) = match &environment {
                None => (Patch::new(fabric, Integration::Direct), "direct evaluation"),
                Some(_) => (
                    Patch::new(fabric, Integration::Resonant(ResonantNodes::DEFAULT)),
                    "resonant quadrature",
                ),
            };
            let reference_environment =
                environment
                    .as_ref()
                    .zip(sampler.as_ref())
                    .map(|(map, sampler)| ReferenceEnvironment {
                        map,
                        sampler,
                        samples: job.reference_samples,
                    });
            let reference =
                reference::shade(&gbuffer, &settings, &patch, reference_environment.as_ref());
            let reference_seconds = start.elapsed().as_secs_f64();
            let error = image_error(&output.linear, &reference, settings.exposure)?;
            let reference_png = with_suffix(&png, "-reference");
            let error_png = with_suffix(&png, "-error");
            write_png(
                &reference_png,
                &reference.tonemapped(settings.exposure, settings.background),
            )?;
            write_png(&error_png, &error_heatmap(&output.linear, &reference)?)?;
            let (lo, hi) = HEATMAP_LOG10_RANGE;
            say(&format!(
                "{}: CPU reference ({evaluation}{}, {} pixels) in {:.1} s: {}; error map {} \
                 (|render − reference|/|reference|, log scale: black 1e{lo} … blue, green, yellow, \
                 red … white ≥ 1e{hi}; bar below with ticks per decade)",
                fabric.name,
                if environment.is_some() {
                    format!(
                        "; environment by {} importance samples per pixel",
                        job.reference_samples
                    )
                } else {
                    String::new()
                },
                error.covered,
                reference_seconds,
                reference_png.display(),
                error_png.display(),
            ));
            say(&format!(
                "{}: image error against the reference: relative L2 {:.3}% (linear radiance), \
                 PSNR {:.2} dB (tone mapped){}",
                fabric.name,
                100.0 * error.relative_l2,
                error.psnr_db,
                if error.coverage_mismatch > 0 {
                    format!("; {} pixels differ in coverage", error.coverage_mismatch)
                } else {
                    String::new()
                }
            ));
            Some(Comparison {
                reference_png,
                error_png,
                error,
                reference_seconds,
            })
        } else {
            None
        };
        results.push(FabricRender {
            fabric: fabric.name.clone(),
            png,
            output,
            comparison,
        });
    }
    Ok(results)
}

/// The table file that `job`'s evaluator reads for `fabric`, when it is the `table` unit
/// (`table:PATH`, else the fabric's table in the tables directory); `None` for any other.
fn table_file(job: &RenderJob, fabric: &Fabric) -> Option<PathBuf> {
    let spelling = job.evaluator.spelling();
    let (unit, path) = crate::evaluator::split(&spelling);
    (unit == crate::evaluator::table::UNIT.name).then(|| match path {
        Some(path) => PathBuf::from(path),
        None => job.tables.join(fabric_table_file(&fabric.name)),
    })
}

fn create_parent(path: &Path) -> Result<(), RenderError> {
    match path.parent() {
        Some(dir) if !dir.as_os_str().is_empty() => {
            std::fs::create_dir_all(dir).map_err(|source| RenderError::CreateDirectory {
                path: dir.to_path_buf(),
                source,
            })
        }
        _ => Ok(()),
    }
}
