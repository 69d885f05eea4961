//! What a stock material loses against the fabric it approximates: the relative RMS of F on
//! the validation sets every table is measured on (uniform and highlight pairs, against the
//! direct evaluation), the directional albedo over outgoing elevation, and (with the
//! runtime) the drape's image under a scene's camera and lights ([`crate::render::drape_loss`]).

use crate::evaluator::stock::StockMaterial;
use crate::measure::accuracy::{Reference, SetError, TableError};
use crate::model::{Fabric, Integration, Patch, ResonantNodes};
use crate::sampling::{AlbedoRow, Sampler, albedo_curve};
use glam::DVec3;

/// Pairs of each validation set an export is measured on.
pub const LOSS_PAIRS: usize = 512;
/// Importance samples per outgoing direction of the albedo curves.
pub const ALBEDO_SAMPLES: usize = 256;

/// The directional albedo's error over outgoing elevation (channel means, each elevation's
/// mean over azimuths).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct AlbedoLoss {
    /// The largest `|E_stock − E| / E` over the elevations, and where.
    pub largest_relative: f64,
    pub at_elevation_deg: f64,
    /// The root mean square of `(E_stock − E) / E` over the elevations.
    pub rms_relative: f64,
}

/// The drape's image error: the stock material's render against the fabric's of the same
/// view, on linear radiance ([`crate::render::image::image_error`]).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct ImageLoss {
    pub relative_l2: f64,
    pub psnr_db: f64,
}

/// Everything an export measures.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Loss {
    pub uniform: SetError,
    pub highlight: SetError,
    pub albedo: AlbedoLoss,
    /// `None` without the runtime (no rasteriser for the drape's G-buffer).
    pub image: Option<ImageLoss>,
}

/// The fabric's side of every measurement, computed once and shared by the targets.
pub struct FabricReference {
    reference: Reference,
    sampler: Sampler,
    albedo: Vec<AlbedoRow>,
}

impl FabricReference {
    /// The direct evaluation on the validation sets and the albedo curve of the resonant
    /// quadrature of `fabric` (the curve is estimated by sampling, and the resonant rule's
    /// error is lost in that estimate's; docs/notebook/2026-12-07-export.md).
    pub fn new(fabric: &Fabric) -> Self {
        let sampler = Sampler::for_fabric(fabric);
        let patch = Patch::new(fabric, Integration::Resonant(ResonantNodes::DEFAULT));
        let albedo = albedo_curve(&sampler, |wi, wo| patch.eval(wi, wo), ALBEDO_SAMPLES);
        Self {
            reference: Reference::new(fabric, LOSS_PAIRS),
            sampler,
            albedo,
        }
    }

    /// The errors of any estimate of F (a table's lookup, say) on the validation sets.
    pub fn errors(&self, estimate: impl Fn(DVec3, DVec3) -> DVec3 + Sync) -> TableError {
        self.reference.measure(estimate)
    }

    /// The errors of `material` on the sets and the albedo curve (`image` left to the
    /// caller).
    pub fn measure(&self, material: &StockMaterial) -> Loss {
        let errors = self.errors(|wi, wo| material.eval(wi, wo));
        let stock = albedo_curve(
            &self.sampler,
            |wi, wo| material.eval(wi, wo),
            ALBEDO_SAMPLES,
        );
        Loss {
            uniform: errors.uniform,
            highlight: errors.highlight,
            albedo: albedo_loss(&self.albedo, &stock),
            image: None,
        }
    }
}

/// Compares two albedo curves over the same elevations.
fn albedo_loss(fabric: &[AlbedoRow], stock: &[AlbedoRow]) -> AlbedoLoss {
    let mean = |row: &AlbedoRow| row.mean.element_sum() / 3.0;
    let mut largest = (0.0, 0.0);
    let mut sum2 = 0.0;
    for (f, s) in fabric.iter().zip(stock) {
        let relative = (mean(s) - mean(f)) / mean(f).max(1e-12);
        sum2 += relative * relative;
        if relative.abs() > largest.0 {
            largest = (relative.abs(), f.elevation_deg);
        }
    }
    AlbedoLoss {
        largest_relative: largest.0,
        at_elevation_deg: largest.1,
        rms_relative: (sum2 / fabric.len().max(1) as f64).sqrt(),
    }
}
