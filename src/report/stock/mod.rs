//! The report's section "Every engine's stock model": for every fabric and every export
//! target of [`crate::export::TARGETS`], the target's stock model fitted to the fabric
//! ([`crate::evaluator::stock::fit::fit`]) and what it loses ([`crate::export::loss`]: the
//! relative RMS of F on the uniform and highlight pairs against the direct evaluation, the
//! directional albedo's error, and the drape's image error under the standard scene's camera
//! and lights, [`crate::render::drape_loss`]), beside the error of the fabric's default table
//! (the baked table of the tables directory, read through the `table` evaluator) on the same
//! pairs.
//!
//! The section also renders the drape under the scene's environment (the studio) for a
//! picture grid: per fabric the table's GPU form, then each target's fitted model's.
//!
//! The targets are taken from the registry alone, so a new target gets its columns, rows,
//! plot series and grid column without an edit here.

mod measure;
mod render;

pub use measure::{StockRun, measure};

use serde::{Deserialize, Serialize};
use std::path::PathBuf;

/// The section's page, beside REPORT.md.
pub const PAGE_FILE_NAME: &str = "stock.md";

/// What the section measures and draws.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct StockConfig {
    /// Directory of the baked default tables (`NAME.exr`), the `table` evaluator's.
    pub tables: PathBuf,
    /// Side of one tile of the picture grid, pixels.
    pub tile: u32,
    /// Filtered importance samples per pixel of the environment in the grid's renders.
    pub environment_samples: u32,
    /// Whether to render the picture grid at all.
    pub grid: bool,
}

impl StockConfig {
    /// The quick preset: smaller tiles and fewer environment samples.
    pub fn quick() -> Self {
        Self {
            tables: PathBuf::from("tables"),
            tile: 128,
            environment_samples: 32,
            grid: true,
        }
    }

    /// The full preset: the standard scene's environment samples.
    pub fn full() -> Self {
        Self {
            tables: PathBuf::from("tables"),
            tile: 192,
            environment_samples: crate::scene::Scene::builtin().environment.samples,
            grid: true,
        }
    }
}

/// One export target as the section names it.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct StockTarget {
    /// The target's word (`clothbake export --to`).
    pub name: String,
    /// Its stock model's evaluator name and title.
    pub model: String,
    pub title: String,
}

/// A fitted parameter of a stock material.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct StockValue {
    pub name: String,
    pub value: f64,
}

/// One fabric fitted by one target's model, and what it loses.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct StockPoint {
    pub target: String,
    /// Relative RMS of F on the uniform and on the highlight pairs.
    pub uniform: f64,
    pub highlight: f64,
    /// The directional albedo's root mean square relative error over outgoing elevations,
    /// its largest, and where.
    pub albedo_rms_relative: f64,
    pub albedo_largest_relative: f64,
    pub albedo_at_elevation_deg: f64,
    /// The drape's image error (relative L2 of linear radiance, PSNR of the tone-mapped
    /// images); None without a GPU adapter to rasterise the drape.
    pub image_relative_l2: Option<f64>,
    pub image_psnr_db: Option<f64>,
    pub parameters: Vec<StockValue>,
    /// Evaluations of F the fit made, and its wall-clock seconds.
    pub fit_evaluations: usize,
    pub fit_seconds: f64,
}

impl StockPoint {
    /// The worse of the uniform and highlight relative RMS errors, as the report judges
    /// every evaluation.
    pub fn worst(&self) -> f64 {
        self.uniform.max(self.highlight)
    }
}

/// The default table's error on the same pairs.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct StockTable {
    /// What the table evaluator says it is ("lookup split_frame R=31").
    pub label: String,
    pub uniform: f64,
    pub highlight: f64,
}

impl StockTable {
    pub fn worst(&self) -> f64 {
        self.uniform.max(self.highlight)
    }
}

/// Every target of one fabric.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct StockFabric {
    pub name: String,
    /// None where the fabric has no table in the tables directory.
    pub table: Option<StockTable>,
    /// One per target, in the registry's order.
    pub points: Vec<StockPoint>,
    pub seconds: f64,
}

impl StockFabric {
    /// The target whose model comes closest to the fabric by `figure`, if any has one.
    pub fn closest_by(&self, figure: impl Fn(&StockPoint) -> Option<f64>) -> Option<&StockPoint> {
        self.points
            .iter()
            .filter_map(|p| figure(p).filter(|x| x.is_finite()).map(|x| (p, x)))
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .map(|(p, _)| p)
    }

    /// The closest by the worse relative RMS of F.
    pub fn closest(&self) -> Option<&StockPoint> {
        self.closest_by(|p| Some(p.worst()))
    }
}

/// The section as written to report.json (key `stock`).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct StockSection {
    /// The run that measured the section (it may be a run of this section alone).
    pub command_line: Vec<String>,
    /// When that run started, RFC 3339, UTC, and the checkout it ran in.
    pub date_utc: String,
    pub git_commit: Option<String>,
    pub clothbake_version: String,
    pub config: StockConfig,
    /// Pairs of each validation set and importance samples per direction of the albedo
    /// curves ([`crate::export::loss`]).
    pub loss_pairs: usize,
    pub albedo_samples: usize,
    /// The adapter the drape and the grid were rendered on, if any.
    pub adapter: Option<String>,
    /// What could be measured: the drape images and the grid need an adapter.
    pub status: String,
    /// The grid's environment, as the scene names it.
    pub environment: String,
    pub targets: Vec<StockTarget>,
    pub fabrics: Vec<StockFabric>,
    /// Files written, relative to the output directory.
    pub files: Vec<String>,
    pub seconds: f64,
}
