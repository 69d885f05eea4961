//! The drape's image error of a stock material: the scene's view rasterised once into a
//! G-buffer, shaded on the CPU by the fabric (the resonant quadrature) and by the material,
//! under the scene's lights (its environment left out: a glTF carries none, and the
//! comparison is of F, not of the environment's sampling), and compared on linear radiance.

use super::image::{LinearImage, image_error};
use super::{FrameSettings, GBuffer, Headless, reference};
use crate::evaluator::stock::StockMaterial;
use crate::export::loss::ImageLoss;
use crate::gpu::{GpuContext, GpuError};
use crate::model::{Fabric, Integration, Patch, ResonantNodes};
use crate::scene::Scene;
use crate::scene::mesh::Mesh;

/// Image side of the comparison: enough pixels for the drape's folds and highlights.
pub const DRAPE_LOSS_SIDE: u32 = 256;

/// A fabric's drape under a scene's camera and lights, shaded on the CPU.
pub struct DrapeReference {
    gbuffer: GBuffer,
    settings: FrameSettings,
    fabric: LinearImage,
}

impl DrapeReference {
    /// The G-buffer of `scene`'s view of `mesh` and `fabric`'s image there.
    pub fn new(
        context: &GpuContext,
        scene: &Scene,
        mesh: &Mesh,
        fabric: &Fabric,
    ) -> Result<Self, GpuError> {
        let brdf = crate::evaluator::constant::gpu::GpuConstant::new(context);
        let mut headless = Headless::new(context, mesh, &brdf, DRAPE_LOSS_SIDE, DRAPE_LOSS_SIDE)?;
        let mut settings = FrameSettings::from_scene(scene);
        settings.environment_samples = 0;
        let gbuffer = headless.gbuffer(context, &settings)?;
        let patch = Patch::new(fabric, Integration::Resonant(ResonantNodes::DEFAULT));
        let fabric = reference::shade_with(&gbuffer, &settings, |wi, wo| patch.eval(wi, wo), None);
        Ok(Self {
            gbuffer,
            settings,
            fabric,
        })
    }

    /// The image error of `material` against the fabric.
    pub fn measure(&self, material: &StockMaterial) -> ImageLoss {
        let image = reference::shade_with(
            &self.gbuffer,
            &self.settings,
            |wi, wo| material.eval(wi, wo),
            None,
        );
        let error = image_error(&image, &self.fabric, self.settings.exposure)
            .expect("two shadings of one G-buffer have its size");
        ImageLoss {
            relative_l2: error.relative_l2,
            psnr_db: error.psnr_db,
        }
    }
}
