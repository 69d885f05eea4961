//! Measures the stock section: every fabric by every export target, the default table
//! beside, and the grid's tiles.

use super::render::{Grid, Tiles};
use super::{
    StockConfig, StockFabric, StockPoint, StockSection, StockTable, StockTarget, StockValue,
};
use crate::evaluator::stock::fit::fit;
use crate::evaluator::{EvaluationContext, FabricEvaluator};
use crate::export::TARGETS;
use crate::export::loss::{ALBEDO_SAMPLES, FabricReference, LOSS_PAIRS};
use crate::gpu::GpuContext;
use crate::model::Fabric;
use crate::render::drape_loss::DrapeReference;
use crate::report::ReportError;
use crate::scene::Scene;
use crate::scene::mesh::Mesh;
use std::time::Instant;

/// The section's figures and, where it was rendered, the grid's tiles (which the section's
/// PNG is drawn from; they are not kept in report.json).
pub struct StockRun {
    pub section: StockSection,
    pub grid: Option<Grid>,
}

/// The GPU side of the section: the adapter, and the grid's renderer while it works.
struct Device {
    context: GpuContext,
    tiles: Option<Tiles>,
}

/// Measures every fabric of `fabrics` by every target of [`TARGETS`]; `progress` receives
/// one line per fit.
pub fn measure(
    config: &StockConfig,
    fabrics: &[Fabric],
    progress: &mut dyn FnMut(&str),
) -> Result<StockRun, ReportError> {
    let started = Instant::now();
    let date_utc = crate::report::provenance::now_utc();
    let scene = Scene::builtin();
    let mesh = Mesh::from_spec(&scene.mesh).map_err(|e| ReportError::Config(e.to_string()))?;
    let mut notes: Vec<String> = Vec::new();
    let mut device = match GpuContext::new() {
        Ok(context) => {
            let tiles = if config.grid {
                let side = config.tile;
                match Tiles::new(
                    &context,
                    &scene,
                    mesh.clone(),
                    side,
                    config.environment_samples,
                ) {
                    Ok(tiles) => Some(tiles),
                    Err(e) => {
                        notes.push(format!("no picture grid: {e}"));
                        None
                    }
                }
            } else {
                None
            };
            Some(Device { context, tiles })
        }
        Err(e) => {
            notes.push(format!(
                "no GPU adapter ({e}): no drape image errors, no picture grid"
            ));
            None
        }
    };
    let adapter = device.as_ref().map(|d| d.context.adapter.to_string());
    let mut grid = Grid {
        columns: std::iter::once("table".to_string())
            .chain(TARGETS.iter().map(|t| t.name.to_string()))
            .collect(),
        rows: Vec::new(),
    };
    let tables = EvaluationContext {
        tables: config.tables.clone(),
    };
    let mut measured = Vec::new();
    for fabric in fabrics {
        let fabric_started = Instant::now();
        let name = &fabric.name;
        progress(&format!(
            "stock: {name}: direct evaluation of {LOSS_PAIRS} uniform and {LOSS_PAIRS} \
             highlight pairs, albedo curve"
        ));
        let reference = FabricReference::new(fabric);
        let table = match crate::evaluator::parse("table").and_then(|t| t.prepare(fabric, &tables))
        {
            Ok(table) => Some(table),
            Err(e) => {
                notes.push(format!("{name}: no default table ({e})"));
                None
            }
        };
        let table_figures = table.as_ref().map(|table| {
            let error = reference.errors(|wi, wo| table.eval(wi, wo));
            StockTable {
                label: table.label(),
                uniform: error.uniform.relative_rms,
                highlight: error.highlight.relative_rms,
            }
        });
        if let Some(t) = &table_figures {
            progress(&format!(
                "stock: {name}: default table ({}): {:.2}% uniform, {:.2}% highlight",
                t.label,
                100.0 * t.uniform,
                100.0 * t.highlight
            ));
        }
        let drape = match &device {
            Some(d) => match DrapeReference::new(&d.context, &scene, &mesh, fabric) {
                Ok(drape) => Some(drape),
                Err(e) => {
                    notes.push(format!("{name}: no drape image ({e})"));
                    None
                }
            },
            None => None,
        };
        let mut row = Vec::new();
        if let Some(d) = &mut device {
            row.push(table.as_deref().and_then(|t| table_tile(d, t, &mut notes)));
        }
        let mut points = Vec::new();
        for target in TARGETS {
            let fit_started = Instant::now();
            let fitted = fit(target.model, fabric);
            let fit_seconds = fit_started.elapsed().as_secs_f64();
            let loss = reference.measure(&fitted.material);
            let image = drape.as_ref().map(|d| d.measure(&fitted.material));
            let point = StockPoint {
                target: target.name.to_string(),
                uniform: loss.uniform.relative_rms,
                highlight: loss.highlight.relative_rms,
                albedo_rms_relative: loss.albedo.rms_relative,
                albedo_largest_relative: loss.albedo.largest_relative,
                albedo_at_elevation_deg: loss.albedo.at_elevation_deg,
                image_relative_l2: image.map(|i| i.relative_l2),
                image_psnr_db: image.map(|i| i.psnr_db),
                parameters: target
                    .model
                    .parameters
                    .iter()
                    .zip(&fitted.material.values)
                    .map(|(p, &value)| StockValue {
                        name: p.name.to_string(),
                        value,
                    })
                    .collect(),
                fit_evaluations: fitted.evaluations,
                fit_seconds,
            };
            progress(&format!(
                "stock: {name}: {} ({}): fitted in {fit_seconds:.1} s; {:.1}% uniform, {:.1}% \
                 highlight, albedo {:.1}% RMS{}",
                target.name,
                target.model.name,
                100.0 * point.uniform,
                100.0 * point.highlight,
                100.0 * point.albedo_rms_relative,
                point.image_relative_l2.map_or(String::new(), |e| format!(
                    ", drape image {:.1}%",
                    100.0 * e
                ))
            ));
            if let Some(d) = &mut device
                && let Some(tiles) = &mut d.tiles
            {
                match tiles.stock(&d.context, fabric, &fitted.material) {
                    Ok(tile) => row.push(Some(tile)),
                    Err(e) => {
                        notes.push(format!("{name}: {}: no tile ({e})", target.name));
                        row.push(None);
                    }
                }
            }
            points.push(point);
        }
        if device.as_ref().is_some_and(|d| d.tiles.is_some()) {
            grid.rows.push((name.clone(), row));
        }
        measured.push(StockFabric {
            name: name.clone(),
            table: table_figures,
            points,
            seconds: fabric_started.elapsed().as_secs_f64(),
        });
    }
    let rendered = device.as_ref().is_some_and(|d| d.tiles.is_some());
    let status = if notes.is_empty() {
        "Measured".to_string()
    } else {
        notes.join("; ")
    };
    let section = StockSection {
        command_line: Vec::new(),
        date_utc,
        git_commit: crate::report::provenance::git_commit(),
        clothbake_version: env!("CARGO_PKG_VERSION").to_string(),
        config: config.clone(),
        loss_pairs: LOSS_PAIRS,
        albedo_samples: ALBEDO_SAMPLES,
        adapter,
        status,
        environment: scene.environment.source.to_string(),
        targets: TARGETS
            .iter()
            .map(|t| StockTarget {
                name: t.name.to_string(),
                model: t.model.name.to_string(),
                title: t.model.title.to_string(),
            })
            .collect(),
        fabrics: measured,
        files: Vec::new(),
        seconds: started.elapsed().as_secs_f64(),
    };
    Ok(StockRun {
        section,
        grid: rendered.then_some(grid),
    })
}

/// The table's tile: its GPU form, and taps from its own sampler.
fn table_tile(
    device: &mut Device,
    table: &dyn FabricEvaluator,
    notes: &mut Vec<String>,
) -> Option<crate::render::image::Rgba8Image> {
    let tiles = device.tiles.as_mut()?;
    let tile = table.gpu(&device.context).and_then(|brdf| {
        tiles
            .tile(
                &device.context,
                brdf.as_ref(),
                &table.sampler(),
                |pairs, out| out.copy_from_slice(&table.eval_batch(pairs)),
            )
            .map_err(Into::into)
    });
    tile.map_err(|e| notes.push(format!("table tile: {e}")))
        .ok()
}
