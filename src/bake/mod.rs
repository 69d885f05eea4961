//! The baker: integrates the full patch transfer (all tangent samples, masking, reweighting,
//! normalisation, per docs/model.md#baking-rule) at every texel of a layout, in parallel with
//! rayon.
//!
//! Each texel is a pure function of its coordinates and results are collected in order, so a
//! table is bit-identical whatever the thread count.

pub mod job;
pub mod manifest;
pub mod taps;

use crate::model::Fabric;
use crate::table::{Layout, Plane, PlaneSpec, Table};
use half::f16;

pub use crate::table::progress::BakeProgress;

/// Why a bake failed.
#[derive(Debug, thiserror::Error)]
pub enum BakeError {
    #[error("resolution {resolution} is outside 2..={max} for layout {layout}")]
    Resolution {
        layout: Layout,
        resolution: u32,
        max: u32,
    },
    #[error(
        "fabric '{fabric}': plane {plane}, texel ({x}, {y}) holds {value:e}, beyond the f16 range (65504)"
    )]
    OutOfRange {
        fabric: String,
        plane: String,
        x: usize,
        y: usize,
        value: f64,
    },
    #[error("the bake of fabric '{fabric}' was cancelled")]
    Cancelled { fabric: String },
    #[error("internal error: {0}")]
    Internal(String),
}

/// Rows of work a bake reports through [`BakeProgress::row_done`].
pub fn bake_rows(fabric: &Fabric, layout: Layout, resolution: u32) -> u64 {
    layout.unit().bake_rows(fabric, resolution)
}

/// Rounds `values` (channel-interleaved, row by row) to f16 as the plane stores them.
fn quantize(fabric: &Fabric, spec: PlaneSpec, values: &[f64]) -> Result<Plane, BakeError> {
    let channels = spec.channels.len();
    if let Some(i) = values
        .iter()
        .position(|v| !v.is_finite() || *v > f16::MAX.to_f64())
    {
        let texel = i / channels;
        return Err(BakeError::OutOfRange {
            fabric: fabric.name.clone(),
            plane: spec.name.clone(),
            x: texel % spec.width,
            y: texel / spec.width,
            value: values[i],
        });
    }
    let data = values.iter().map(|&v| f16::from_f64(v).to_f32()).collect();
    Ok(Plane { spec, data })
}

/// Bakes `fabric` into a table of `layout` at `resolution`. `progress` hears of each
/// finished row of work (from worker threads); a closure `Fn() + Sync` is one. Once
/// `progress.cancelled()` is true the rows not yet started are skipped and the bake returns
/// [`BakeError::Cancelled`]; a bake that is not cancelled gives the same table as one with
/// no progress reporting.
pub fn bake(
    fabric: &Fabric,
    layout: Layout,
    resolution: u32,
    progress: &dyn BakeProgress,
) -> Result<Table, BakeError> {
    if !(2..=layout.max_resolution()).contains(&resolution) {
        return Err(BakeError::Resolution {
            layout,
            resolution,
            max: layout.max_resolution(),
        });
    }
    let specs = layout.plane_specs(fabric, resolution);
    let values = layout.unit().bake(fabric, resolution, progress);
    if progress.cancelled() {
        return Err(BakeError::Cancelled {
            fabric: fabric.name.clone(),
        });
    }
    if values.len() != specs.len() {
        return Err(BakeError::Internal(format!(
            "layout {layout} baked {} planes, its specs list {}",
            values.len(),
            specs.len()
        )));
    }
    let planes = specs
        .into_iter()
        .zip(&values)
        .map(|(spec, values)| quantize(fabric, spec, values))
        .collect::<Result<Vec<_>, _>>()?;
    Table::new(layout, resolution, fabric, planes).map_err(|e| BakeError::Internal(e.to_string()))
}
