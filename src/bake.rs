//! The baker: integrates the full patch transfer (all tangent samples, masking, reweighting,
//! normalisation, per MODEL.md) at every texel of a layout, in parallel with rayon.
//!
//! Each texel is a pure function of its coordinates and results are collected in order, so a
//! table is bit-identical whatever the thread count.

use crate::model::Fabric;
use crate::table::thread_frame;
use crate::table::{Layout, Plane, PlaneSpec, Table, grid4d};
use half::f16;

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
    #[error("internal error: {0}")]
    Internal(String),
}

/// Rows of work a bake reports through `on_row`.
pub fn bake_rows(fabric: &Fabric, layout: Layout, resolution: u32) -> u64 {
    let specs = layout.plane_specs(fabric, resolution);
    let baked = if layout == Layout::ThreadFrame {
        &specs[..2]
    } else {
        &specs[..]
    };
    baked.iter().map(|s| s.height as u64).sum()
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

/// Bakes `fabric` into a table of `layout` at `resolution`. `on_row` is called once per
/// finished row of work (from worker threads), for progress reporting.
pub fn bake(
    fabric: &Fabric,
    layout: Layout,
    resolution: u32,
    on_row: &(dyn Fn() + Sync),
) -> Result<Table, BakeError> {
    if !(2..=layout.max_resolution()).contains(&resolution) {
        return Err(BakeError::Resolution {
            layout,
            resolution,
            max: layout.max_resolution(),
        });
    }
    match layout {
        Layout::Grid4d => {
            let values = grid4d::bake(fabric, resolution, on_row);
            let plane = quantize(fabric, grid4d::spec(resolution), &values)?;
            Table::new(layout, resolution, fabric, vec![plane]).map_err(BakeError::Internal)
        }
        Layout::ThreadFrame => bake_thread_frame(fabric, resolution, on_row),
    }
}

/// Bakes a `thread_frame` table: the curve means of every texel of both threads, encoded
/// as the layout documents, and the masking planes.
fn bake_thread_frame(
    fabric: &Fabric,
    resolution: u32,
    on_row: &(dyn Fn() + Sync),
) -> Result<Table, BakeError> {
    let geometry = thread_frame::Geometry::new(fabric, resolution);
    let specs = geometry.specs();
    let mut planes = Vec::with_capacity(specs.len());
    for (j, thread) in geometry.threads.iter().enumerate() {
        let means = thread_frame::bake_thread_means(fabric, thread, j, on_row);
        let flat: Vec<f64> = thread_frame::encode_thread(&means, thread)
            .into_iter()
            .flatten()
            .collect();
        planes.push(quantize(fabric, specs[j].clone(), &flat)?);
    }
    for (j, thread) in geometry.threads.iter().enumerate() {
        let values = thread_frame::bake_masking(fabric, thread, j);
        planes.push(quantize(fabric, specs[2 + j].clone(), &values)?);
    }
    Table::new(Layout::ThreadFrame, resolution, fabric, planes).map_err(BakeError::Internal)
}
