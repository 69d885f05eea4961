//! The baker: integrates the full patch transfer (all tangent samples, masking,
//! reweighting, normalisation; the direct evaluation of MODEL.md) at every texel of a
//! layout, in parallel over rows with rayon.
//!
//! Each texel is a pure function of its coordinates, and rows are collected in order, so the
//! table is bit-identical whatever the thread count.

use crate::model::{Fabric, Integration, Patch};
use crate::table::{Layout, Table};
use half::f16;
use rayon::prelude::*;

/// Why a bake failed.
#[derive(Debug, thiserror::Error)]
pub enum BakeError {
    #[error("resolution {resolution} is outside 2..={max} for layout {layout}")]
    Resolution {
        layout: Layout,
        resolution: u32,
        max: u32,
    },
    #[error("fabric '{fabric}': texel ({x}, {y}) holds {value:e}, beyond the f16 range (65504)")]
    OutOfRange {
        fabric: String,
        x: usize,
        y: usize,
        value: f64,
    },
}

/// Rounds to the nearest f16, as the table stores it.
fn to_f16(v: f64) -> f32 {
    f16::from_f64(v).to_f32()
}

/// Bakes `fabric` into a table of `layout` at `resolution`. `on_row` is called once per
/// finished image row (from worker threads), for progress reporting.
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
    let patch = Patch::new(fabric, Integration::Direct);
    let (width, height) = layout.image_size(resolution);
    let rows: Vec<Vec<[f64; 3]>> = (0..height)
        .into_par_iter()
        .map(|y| {
            let row = (0..width)
                .map(|x| {
                    let (wi, wo) = layout.texel_directions(resolution, x, y);
                    let terms = patch.terms(wi, wo);
                    [
                        terms.reflection,
                        terms.transmission[0],
                        terms.transmission[1],
                    ]
                })
                .collect();
            on_row();
            row
        })
        .collect();
    let mut texels = Vec::with_capacity(width * height);
    for (y, row) in rows.into_iter().enumerate() {
        for (x, terms) in row.into_iter().enumerate() {
            if let Some(&value) = terms
                .iter()
                .find(|v| !v.is_finite() || **v > f16::MAX.to_f64())
            {
                return Err(BakeError::OutOfRange {
                    fabric: fabric.name.clone(),
                    x,
                    y,
                    value,
                });
            }
            texels.push(terms.map(to_f16));
        }
    }
    let albedo = fabric.threads().map(|t| t.albedo_rgb().map(|c| c as f32));
    Ok(Table::new(layout, resolution, albedo, texels))
}
