//! The report's PNG plots, drawn with plotters' bitmap backend into a buffer and encoded
//! with the png crate.
//!
//! Text uses DejaVu Sans embedded by the `dejavu` crate and rasterised by ab_glyph, so the
//! plots need no system fonts (plotters' default `ttf` feature would need fontconfig).

#[macro_use]
mod chart;
pub mod stock;

use super::gpu::GpuPoint;
use super::{Evaluation, FabricReport, Point, Report, ReportError};
use crate::table::Layout;
use chart::*;
use plotters::prelude::*;
use std::path::Path;

/// File names of the plots in the output directory.
pub const ERROR_VS_SIZE: &str = "error_vs_size.png";
pub const ERROR_VS_COST: &str = "error_vs_cost.png";
pub const BAKE_TIME: &str = "bake_time.png";
pub const GPU_COST: &str = "gpu_cost.png";

/// The tables of `f` of one layout.
fn of_layout(f: &FabricReport, layout: Layout) -> Vec<&Point> {
    f.tables()
        .filter(|t| matches!(t.evaluation, Evaluation::Table { layout: l, .. } if l == layout))
        .collect()
}

/// Where a CPU point goes in an error-against-cost plot.
fn cost_and_error(p: &Point) -> (f64, f64) {
    lg2((p.cost(), p.worst_error()))
}

/// Error (relative RMS) against table size (MiB), per fabric, one curve per layout and set.
fn error_vs_size(report: &Report, path: &Path) -> PlotResult {
    let size = grid_size(report.fabrics.len());
    write_png(path, size, |root| {
        for (k, (panel, f)) in panels(root, report.fabrics.len())
            .iter()
            .zip(&report.fabrics)
            .enumerate()
        {
            let mib = |b: usize| b as f64 / (1024.0 * 1024.0);
            let xs = log_range(f.tables().map(|t| mib(t.bytes())));
            let ys = log_range(f.tables().flat_map(|t| {
                [
                    t.error.uniform.relative_rms,
                    t.error.highlight.relative_rms,
                    t.error.uniform_above_15deg.relative_rms,
                ]
            }));
            let mut chart = panel_chart(
                panel,
                &f.name,
                xs,
                ys,
                Axes {
                    x: "table size (MiB)".into(),
                    y: "relative RMS error".into(),
                    x_ticks: &fmt_log_number,
                    y_ticks: &fmt_log_percent,
                },
            )?;
            for &layout in Layout::ALL {
                let of = of_layout(f, layout);
                let sets: [(&str, Marker, ErrorOf); 3] = [
                    ("uniform", Marker::Circle, |t| t.error.uniform.relative_rms),
                    ("highlight", Marker::Triangle, |t| {
                        t.error.highlight.relative_rms
                    }),
                    ("≥ 15°", Marker::Cross, |t| {
                        t.error.uniform_above_15deg.relative_rms
                    }),
                ];
                for (set, marker, value) in sets {
                    let points: Vec<(f64, f64)> =
                        of.iter().map(|t| lg2((mib(t.bytes()), value(t)))).collect();
                    let label = format!("{layout} {set}");
                    curve(
                        &mut chart,
                        &points,
                        layout_colour(layout),
                        marker,
                        (k == 0).then_some(label.as_str()),
                    )?;
                }
            }
            if k == 0 {
                draw_legend(&mut chart, SeriesLabelPosition::UpperRight)?;
            }
        }
        Ok(())
    })
}

/// Error (worse of uniform and highlight) against CPU ns per evaluation: each evaluator unit
/// by its settings, each layout by resolution, and the direct evaluation's cost as a
/// vertical line.
fn error_vs_cost(report: &Report, path: &Path) -> PlotResult {
    let size = grid_size(report.fabrics.len());
    write_png(path, size, |root| {
        for (k, (panel, f)) in panels(root, report.fabrics.len())
            .iter()
            .zip(&report.fabrics)
            .enumerate()
        {
            let xs = log_range(
                f.points
                    .iter()
                    .map(Point::cost)
                    .chain([f.direct.ns_per_eval]),
            );
            let ys = log_range(f.points.iter().map(Point::worst_error));
            let (y0, y1) = (ys.start, ys.end);
            let mut chart = panel_chart(
                panel,
                &f.name,
                xs,
                ys,
                Axes {
                    x: "CPU ns per evaluation (one thread)".into(),
                    y: "relative RMS error (worse set)".into(),
                    x_ticks: &fmt_log_number,
                    y_ticks: &fmt_log_percent,
                },
            )?;
            for unit in report.units() {
                let points: Vec<_> = f
                    .of_unit(unit)
                    .map(|p| (cost_and_error(p), p.evaluation.parameter()))
                    .collect();
                unit_series(&mut chart, unit, &points, (k == 0).then_some(unit.syntax))?;
            }
            for &layout in Layout::ALL {
                let points: Vec<(f64, f64)> = of_layout(f, layout)
                    .into_iter()
                    .map(cost_and_error)
                    .collect();
                let label = format!("{layout} lookup");
                curve(
                    &mut chart,
                    &points,
                    layout_colour(layout),
                    Marker::Circle,
                    (k == 0).then_some(label.as_str()),
                )?;
            }
            let direct = lg(f.direct.ns_per_eval);
            let series = chart.draw_series(LineSeries::new(
                [(direct, y0), (direct, y1)],
                DIRECT_COLOUR.stroke_width(2),
            ))?;
            if k == 0 {
                series.label("direct (error 0)").legend(|(x, y)| {
                    PathElement::new(vec![(x, y), (x + 18, y)], DIRECT_COLOUR.stroke_width(2))
                });
                draw_legend(&mut chart, SeriesLabelPosition::UpperRight)?;
            }
        }
        Ok(())
    })
}

/// Bake time against resolution, one panel per layout, one curve per fabric.
fn bake_time(report: &Report, path: &Path) -> PlotResult {
    let layouts = Layout::ALL;
    write_png(path, (PANEL.0 * layouts.len() as u32, PANEL.1), |root| {
        for (panel, &layout) in root.split_evenly((1, layouts.len())).iter().zip(layouts) {
            let points = |f: &FabricReport| -> Vec<(f64, f64)> {
                of_layout(f, layout)
                    .into_iter()
                    .filter_map(|t| {
                        let Evaluation::Table { resolution, .. } = t.evaluation else {
                            return None;
                        };
                        Some((resolution as f64, lg(t.bake.as_ref()?.seconds)))
                    })
                    .collect()
            };
            let all: Vec<(f64, f64)> = report.fabrics.iter().flat_map(points).collect();
            // Resolutions span less than a decade: a linear axis labels them better.
            let (x0, x1) = all.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), p| {
                (lo.min(p.0), hi.max(p.0))
            });
            let (x0, x1) = if x0 <= x1 { (x0, x1) } else { (0.0, 1.0) };
            let pad = 0.08 * (x1 - x0).max(1.0);
            let ys = log_range(all.iter().map(|p| 10f64.powf(p.1)));
            let mut chart = panel_chart(
                panel,
                &format!("{layout} bake"),
                x0 - pad..x1 + pad,
                ys,
                Axes {
                    x: "resolution".into(),
                    y: format!("seconds ({} threads)", report.machine.bake_threads),
                    x_ticks: &fmt_integer,
                    y_ticks: &fmt_log_number,
                },
            )?;
            for (i, f) in report.fabrics.iter().enumerate() {
                let colour = FABRIC_COLOURS[i % FABRIC_COLOURS.len()];
                curve(
                    &mut chart,
                    &points(f),
                    colour,
                    Marker::Circle,
                    Some(&f.name),
                )?;
            }
            draw_legend(&mut chart, SeriesLabelPosition::UpperLeft)?;
        }
        Ok(())
    })
}

/// GPU milliseconds per frame against the image error of the standard scene, per fabric:
/// each evaluator unit's shader by its settings, and the lookup shader.
fn gpu_cost(report: &Report, path: &Path) -> PlotResult {
    let g = &report.gpu;
    let size = grid_size(g.fabrics.len());
    write_png(path, size, |root| {
        for (k, (panel, f)) in panels(root, g.fabrics.len())
            .iter()
            .zip(&g.fabrics)
            .enumerate()
        {
            let xs = log_range(f.points.iter().map(|p| p.ms_per_frame));
            let ys = log_range(f.points.iter().map(|p| p.image_relative_l2));
            let mut chart = panel_chart(
                panel,
                &f.name,
                xs,
                ys,
                Axes {
                    x: "GPU ms per frame".into(),
                    y: "image error (relative L2)".into(),
                    x_ticks: &fmt_log_number,
                    y_ticks: &fmt_log_percent,
                },
            )?;
            let at = |p: &GpuPoint| lg2((p.ms_per_frame, p.image_relative_l2));
            for unit in report.units() {
                let points: Vec<_> = f
                    .points
                    .iter()
                    .filter(|p| p.evaluation.is_of(unit))
                    .map(|p| (at(p), p.evaluation.parameter()))
                    .collect();
                let label = format!("{} shader", unit.syntax);
                unit_series(
                    &mut chart,
                    unit,
                    &points,
                    (k == 0).then_some(label.as_str()),
                )?;
            }
            let lookup: Vec<(f64, f64)> = f.lookup().map(at).into_iter().collect();
            let label = f.lookup().map_or(String::new(), |p| {
                format!("lookup shader ({})", p.evaluation)
            });
            curve(
                &mut chart,
                &lookup,
                layout_colour(Layout::DEFAULT),
                Marker::Circle,
                (k == 0).then_some(label.as_str()),
            )?;
            if k == 0 {
                draw_legend(&mut chart, SeriesLabelPosition::UpperRight)?;
            }
        }
        Ok(())
    })
}

/// The stock section's errors ([`stock::stock_error`]), where the report has the section.
fn stock_error(report: &Report, path: &Path) -> PlotResult {
    match &report.stock {
        Some(section) => stock::stock_error(section, path),
        None => Ok(()),
    }
}

/// Writes every plot the report has data for into `out`; returns their file names.
pub fn write_all(report: &Report, out: &Path) -> Result<Vec<String>, ReportError> {
    let mut plots: Vec<(&str, Plot)> = vec![
        (ERROR_VS_SIZE, error_vs_size),
        (ERROR_VS_COST, error_vs_cost),
        (BAKE_TIME, bake_time),
    ];
    if report.gpu.measured && !report.gpu.fabrics.is_empty() {
        plots.push((GPU_COST, gpu_cost));
    }
    if report.stock.is_some() {
        plots.push((stock::STOCK_ERROR, stock_error));
    }
    let mut written = Vec::new();
    for (file, draw) in plots {
        draw(report, &out.join(file)).map_err(|e| ReportError::Plot {
            file: file.to_string(),
            message: e.to_string(),
        })?;
        written.push(file.to_string());
    }
    Ok(written)
}
