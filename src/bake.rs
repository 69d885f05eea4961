//! The baker: integrates the full patch transfer (all tangent samples, masking, reweighting,
//! normalisation, per MODEL.md) at every texel of a layout, in parallel with rayon.
//!
//! Each texel is a pure function of its coordinates and results are collected in order, so a
//! table is bit-identical whatever the thread count.

use crate::accuracy::{TableError, measure};
use crate::model::Fabric;
use crate::table::thread_frame::{self, ReflectionScale};
use crate::table::{Layout, Plane, PlaneSpec, Table, grid4d};
use half::f16;

/// Pairs per set on which `thread_frame` picks its reflection scale (see
/// [`thread_frame::ReflectionScale`]): the two candidates differ by factors, not percent, on
/// the fabrics where the choice matters, so a thousand pairs decide it.
pub const SCALE_SELECTION_PAIRS: usize = 1000;

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
            Table::new(layout, resolution, fabric, None, vec![plane]).map_err(BakeError::Internal)
        }
        Layout::ThreadFrame => {
            bake_thread_frame(fabric, resolution, on_row).map(|(table, _)| table)
        }
    }
}

/// Bakes a `thread_frame` table: the curve means once per texel, then both reflection
/// scales encoded, and the one with the lower measured error kept.
fn bake_thread_frame(
    fabric: &Fabric,
    resolution: u32,
    on_row: &(dyn Fn() + Sync),
) -> Result<(Table, TableError), BakeError> {
    let geometry = thread_frame::Geometry::new(fabric, resolution, ReflectionScale::SqrtMasking);
    let specs = geometry.specs();
    let means: Vec<Vec<[f64; 3]>> = (0..2)
        .map(|j| thread_frame::bake_thread_means(fabric, &geometry.threads[j], j, on_row))
        .collect();
    let mut masking_planes = Vec::new();
    for j in 0..2 {
        let values = thread_frame::bake_masking(fabric, &geometry.threads[j], j);
        masking_planes.push(quantize(fabric, specs[2 + j].clone(), &values)?);
    }
    let mut best: Option<(Table, TableError)> = None;
    for scale in [ReflectionScale::SqrtMasking, ReflectionScale::Masking] {
        let mut planes = Vec::new();
        for j in 0..2 {
            let dims = thread_frame::plane_dims(&geometry.threads[j]);
            let encoded = thread_frame::encode_thread(&means[j], dims, scale);
            let flat: Vec<f64> = encoded.iter().flatten().copied().collect();
            planes.push(quantize(fabric, specs[j].clone(), &flat)?);
        }
        planes.extend(masking_planes.iter().cloned());
        let table = Table::new(Layout::ThreadFrame, resolution, fabric, Some(scale), planes)
            .map_err(BakeError::Internal)?;
        let error = measure(&table, fabric, SCALE_SELECTION_PAIRS);
        let worst = |e: &TableError| e.uniform.relative_rms.max(e.highlight.relative_rms);
        if best.as_ref().is_none_or(|(_, e)| worst(&error) < worst(e)) {
            best = Some((table, error));
        }
    }
    best.ok_or_else(|| BakeError::Internal("no reflection scale baked".into()))
}
