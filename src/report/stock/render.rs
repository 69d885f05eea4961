//! The stock section's picture grid: the standard scene's drape rendered headless under the
//! scene's environment (the studio) and lights, once per GPU form, as `clothbake render`
//! renders it ([`crate::render::job`]): the environment split into bright sources and a
//! residual, the residual sampled through sample taps built from the evaluation's sampler.

use crate::evaluator::stock::StockMaterial;
use crate::evaluator::stock::gpu::GpuStock;
use crate::gpu::{GpuBrdf, GpuContext, GpuError, GpuSampleTaps};
use crate::model::Fabric;
use crate::render::image::Rgba8Image;
use crate::render::{FrameSettings, GpuEnvironment, Headless};
use crate::sampling::Sampler;
use crate::sampling::taps::SampleTaps;
use crate::scene::Scene;
use crate::scene::mesh::Mesh;

/// The grid's tiles: one row per fabric, one column per GPU form (None: not rendered).
#[derive(Default)]
pub struct Grid {
    pub columns: Vec<String>,
    pub rows: Vec<(String, Vec<Option<Rgba8Image>>)>,
}

/// Renders tiles of one size under the scene's environment.
pub(super) struct Tiles {
    settings: FrameSettings,
    environment: Option<GpuEnvironment>,
    mesh: Mesh,
    side: u32,
    headless: Option<Headless>,
}

impl Tiles {
    /// The scene's view and lights, its environment split and uploaded, `samples`
    /// environment samples per pixel, tiles of `side` pixels.
    pub fn new(
        context: &GpuContext,
        scene: &Scene,
        mesh: Mesh,
        side: u32,
        samples: u32,
    ) -> Result<Self, String> {
        let environment = scene.environment.source.load().map_err(|e| e.to_string())?;
        let environment = match environment {
            Some(map) => {
                let split = map.split_bright_sources(scene.environment.sources);
                Some(GpuEnvironment::split(context, &split).map_err(|e| e.to_string())?)
            }
            None => None,
        };
        let mut settings = FrameSettings::from_scene(scene);
        settings.environment_samples = if environment.is_some() { samples } else { 0 };
        Ok(Self {
            settings,
            environment,
            mesh,
            side,
            headless: None,
        })
    }

    /// One tile shaded by `brdf`, the environment sampled through taps built from
    /// `sampler` with F from `f` (the evaluation the GPU form is of).
    pub fn tile(
        &mut self,
        context: &GpuContext,
        brdf: &dyn GpuBrdf,
        sampler: &Sampler,
        f: impl Fn(&[(glam::DVec3, glam::DVec3)], &mut [glam::DVec3]) + Sync,
    ) -> Result<Rgba8Image, GpuError> {
        let headless = match &mut self.headless {
            Some(h) => {
                h.renderer.set_brdf(context, brdf)?;
                h
            }
            None => self.headless.insert(Headless::new(
                context, &self.mesh, brdf, self.side, self.side,
            )?),
        };
        if let Some(map) = &self.environment {
            let taps = SampleTaps::build(sampler, self.settings.environment_samples, f);
            let taps = GpuSampleTaps::new(context, &taps)?;
            headless.renderer.set_environment(context, map, &taps)?;
        }
        Ok(headless.render(context, &self.settings, 1)?.display)
    }

    /// A tile of a fitted stock material: its GPU form, and taps from the fabric's sampler
    /// (the stock unit's evaluation samples by the fabric's, having none of its own).
    pub fn stock(
        &mut self,
        context: &GpuContext,
        fabric: &Fabric,
        material: &StockMaterial,
    ) -> Result<Rgba8Image, GpuError> {
        let brdf = GpuStock::new(context, material)?;
        self.tile(
            context,
            &brdf,
            &Sampler::for_fabric(fabric),
            |pairs, out| {
                for (o, &(wi, wo)) in out.iter_mut().zip(pairs) {
                    *o = material.eval(wi, wo);
                }
            },
        )
    }
}
