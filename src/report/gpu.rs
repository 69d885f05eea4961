//! The report's GPU section: the standard scene (tables/scene.toml, [`Scene::builtin`])
//! rendered headless for each fabric, by the table lookup shader and by the GPU form of each
//! evaluator spelling of the configuration (every unit's [`crate::evaluator::ReportPlan`]),
//! with the GPU time per frame and the image error against the CPU reference render (direct
//! evaluation of the same G-buffer).
//!
//! Without an adapter the section says so and holds no figures; nothing is estimated in
//! its place. A software adapter (device type Cpu, e.g. llvmpipe) is measured like any
//! other and named as such, so its "GPU" times are read as what they are.

use super::{Evaluation, ReportConfig};
use crate::evaluator::table::TableEvaluation;
use crate::evaluator::{EvaluationContext, EvaluatorError, FabricEvaluator, direct};
use crate::gpu::{GpuContext, GpuError};
use crate::render::image::{ImageFileError, LinearImage, image_error};
use crate::render::{FrameSettings, Headless, reference};
use crate::scene::Scene;
use crate::scene::mesh::{Mesh, MeshError};
use crate::table::Table;
use serde::{Deserialize, Serialize};
use std::time::Instant;

/// One way of shading the scene: its GPU time per frame and its image error.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct GpuPoint {
    /// What the shader evaluates F by: the table's lookup, or an evaluator's GPU form.
    pub evaluation: Evaluation,
    /// Median milliseconds per frame.
    pub ms_per_frame: f64,
    /// Milliseconds of each timed frame (after one untimed warm-up frame).
    pub samples_ms: Vec<f64>,
    /// ‖render − reference‖₂ / ‖reference‖₂ over the linear RGB radiance of the covered
    /// pixels (`render::image::ImageError::relative_l2`).
    pub image_relative_l2: f64,
    /// PSNR of the tone-mapped images, dB.
    pub image_psnr_db: f64,
}

/// GPU figures of one fabric.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct GpuFabric {
    pub name: String,
    /// Pixels the reference covers.
    pub covered_pixels: usize,
    /// Seconds the CPU reference render took (all cores).
    pub reference_seconds: f64,
    pub points: Vec<GpuPoint>,
}

impl GpuFabric {
    /// The lookup shader's point, if it was measured.
    pub fn lookup(&self) -> Option<&GpuPoint> {
        self.points.iter().find(|p| !p.evaluation.is_model())
    }
}

/// The GPU section of the report.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct GpuSection {
    /// The adapter wgpu found (name, backend, device type, driver), if any.
    pub adapter: Option<String>,
    /// wgpu's device type of the adapter ("Cpu" for a software rasteriser).
    pub device_type: Option<String>,
    /// Whether frames were rendered and timed.
    pub measured: bool,
    /// Why figures are missing, or what was measured.
    pub status: String,
    /// Frame size (width, height).
    pub frame: Option<[u32; 2]>,
    /// Timed frames per measurement.
    pub frames: usize,
    /// How frame times were taken (GPU timestamps or wall clock).
    pub timing_source: Option<String>,
    pub fabrics: Vec<GpuFabric>,
    /// Wall-clock seconds the section took, device creation included.
    pub seconds: f64,
}

impl GpuSection {
    fn empty(adapter: Option<String>, device_type: Option<String>, status: String) -> Self {
        Self {
            adapter,
            device_type,
            measured: false,
            status,
            frame: None,
            frames: 0,
            timing_source: None,
            fabrics: Vec::new(),
            seconds: 0.0,
        }
    }

    /// The section of a run configured without the GPU.
    pub fn not_requested() -> Self {
        Self::empty(None, None, "GPU not requested for this run".into())
    }
}

/// Looks for an adapter and, when there is one, measures every fabric of `tables` (the
/// table the lookup shader samples, one per fabric of `config`).
pub fn measure(
    config: &ReportConfig,
    tables: &[Table],
    progress: &mut dyn FnMut(&str),
) -> GpuSection {
    let context = match GpuContext::new() {
        Ok(context) => context,
        Err(e) => {
            progress(&format!("GPU: {e}; GPU section skipped"));
            return GpuSection::empty(None, None, format!("GPU section skipped: {e}"));
        }
    };
    let adapter = context.adapter.to_string();
    let device_type = context.adapter.device_type.clone();
    progress(&format!("GPU: adapter {adapter}"));
    if tables.is_empty() {
        return GpuSection::empty(
            Some(adapter),
            Some(device_type),
            "Nothing to render: no table of the default layout was measured".into(),
        );
    }
    match measure_on(config, tables, &context, progress) {
        Ok((fabrics, source)) => GpuSection {
            adapter: Some(adapter),
            status: if device_type == "Cpu" {
                "Measured on a software rasteriser (device type Cpu): its frame times are \
                 CPU times, not a GPU's"
                    .into()
            } else {
                "Measured".into()
            },
            device_type: Some(device_type),
            measured: true,
            frame: Some(config.gpu_frame),
            frames: config.gpu_frames,
            timing_source: Some(source),
            fabrics,
            seconds: 0.0,
        },
        Err(e) => {
            progress(&format!("GPU: {e}; GPU section skipped"));
            GpuSection::empty(
                Some(adapter),
                Some(device_type),
                format!("GPU section skipped: {e}"),
            )
        }
    }
}

/// Why the GPU section could not be measured (it is then skipped, saying why).
#[derive(Debug, thiserror::Error)]
enum GpuSectionError {
    #[error(transparent)]
    Gpu(#[from] GpuError),
    #[error(transparent)]
    Evaluator(#[from] EvaluatorError),
    #[error(transparent)]
    Mesh(#[from] MeshError),
    #[error(transparent)]
    Image(#[from] ImageFileError),
}

/// Renders and times every shader of every fabric; returns the figures and the timing
/// source.
fn measure_on(
    config: &ReportConfig,
    tables: &[Table],
    context: &GpuContext,
    progress: &mut dyn FnMut(&str),
) -> Result<(Vec<GpuFabric>, String), GpuSectionError> {
    let context_files = EvaluationContext::default();
    let scene = Scene::builtin();
    // The shaders are compared on the scene's lights alone: an environment light multiplies
    // every shader's BRDF work by its sample count (docs/sampling.md#measured).
    let settings = FrameSettings {
        environment_samples: 0,
        ..FrameSettings::from_scene(&scene)
    };
    let mesh = Mesh::from_spec(&scene.mesh)?;
    let [width, height] = config.gpu_frame;
    let frames = config.gpu_frames.max(1) as u32;
    let mut headless: Option<Headless> = None;
    let mut gbuffer = None;
    let mut source = String::new();
    let mut fabrics = Vec::new();
    for table in tables {
        let fabric = &table.fabric;
        let name = &fabric.name;
        // The table measured above and the model's evaluations, each through its unit of
        // the evaluator registry, as `render` builds them.
        let lookup = Evaluation::Table {
            layout: table.layout,
            resolution: table.resolution,
        };
        let lookup_evaluator: Box<dyn FabricEvaluator> = Box::new(TableEvaluation {
            table: table.clone(),
        });
        let mut prepared = vec![(lookup, lookup_evaluator)];
        for spelling in &config.gpu_evaluators {
            let evaluator = crate::evaluator::parse(spelling)
                .and_then(|e| e.prepare(fabric, &context_files))?;
            prepared.push((Evaluation::evaluator(spelling.clone()), evaluator));
        }
        let direct = (direct::UNIT.parse)(None).and_then(|e| e.prepare(fabric, &context_files))?;
        let mut brdfs = Vec::new();
        for (evaluation, evaluator) in prepared {
            let brdf = evaluator.gpu(context)?;
            brdfs.push((evaluation, brdf));
        }
        let mut reference: Option<(LinearImage, f64)> = None;
        let mut points = Vec::new();
        for (evaluation, brdf) in &brdfs {
            let renderer = match &mut headless {
                Some(h) => {
                    h.renderer.set_brdf(context, brdf.as_ref())?;
                    h
                }
                None => {
                    headless.insert(Headless::new(context, &mesh, brdf.as_ref(), width, height)?)
                }
            };
            // The G-buffer depends on the mesh and the view only: one for all fabrics.
            let gbuffer = match &gbuffer {
                Some(g) => g,
                None => gbuffer.insert(renderer.gbuffer(context, &settings)?),
            };
            let (reference, _) = reference.get_or_insert_with(|| {
                let started = Instant::now();
                let brdf = |wi, wo| direct.eval(wi, wo);
                let image = reference::shade_with(gbuffer, &settings, brdf, None);
                (image, started.elapsed().as_secs_f64())
            });
            let output = renderer.render(context, &settings, frames)?;
            source = output.timing.source.to_string();
            let error = image_error(&output.linear, reference, settings.exposure)?;
            let point = GpuPoint {
                evaluation: evaluation.clone(),
                ms_per_frame: output.timing.median_ms(),
                samples_ms: output.timing.frame_ms.clone(),
                image_relative_l2: error.relative_l2,
                image_psnr_db: error.psnr_db,
            };
            progress(&format!(
                "GPU: {name}: {}: {:.3} ms/frame, image error {:.3}%",
                brdf.label(),
                point.ms_per_frame,
                100.0 * point.image_relative_l2
            ));
            points.push(point);
        }
        let (covered_pixels, reference_seconds) =
            reference.map_or((0, 0.0), |(image, seconds)| (image.coverage(), seconds));
        fabrics.push(GpuFabric {
            name: name.clone(),
            covered_pixels,
            reference_seconds,
            points,
        });
    }
    Ok((fabrics, source))
}
