//! The stock section's two pictures: its errors per fabric (`stock_error.png`) and the grid
//! of drapes (`stock_grid.png`).

use super::chart::*;
use crate::render::image::Rgba8Image;
use crate::report::stock::{StockFabric, StockSection};
use plotters::prelude::*;
use std::path::Path;

/// File names in the output directory.
pub const STOCK_ERROR: &str = "stock_error.png";
pub const STOCK_GRID: &str = "stock_grid.png";

/// Colours of the three figures: relative RMS on the uniform pairs, on the highlight pairs,
/// and the drape's image error.
pub const UNIFORM_COLOUR: RGBColor = RGBColor(31, 119, 180);
pub const HIGHLIGHT_COLOUR: RGBColor = RGBColor(255, 127, 14);
pub const DRAPE_COLOUR: RGBColor = RGBColor(44, 160, 44);

/// The label of the last column, the default table's.
const TABLE_COLUMN: &str = "default table";

/// Markers at `points` (axis coordinates), in the legend as `label` where given.
fn markers<'a, 'b: 'a>(
    chart: &mut Chart<'a, 'b>,
    points: &[(f64, f64)],
    colour: RGBColor,
    marker: Marker,
    label: Option<&str>,
) -> PlotResult {
    let series = chart.draw_series(
        points
            .iter()
            .filter(|(x, y)| x.is_finite() && y.is_finite())
            .map(|&p| EmptyElement::at(p) + marker_element((0, 0), marker, colour)),
    )?;
    if let Some(label) = label {
        series
            .label(label)
            .legend(move |(x, y)| marker_element((x + 9, y), marker, colour));
    }
    Ok(())
}

/// One fabric's figures at their columns: every target's in registry order, then the
/// table's (uniform and highlight only).
fn columns(f: &StockFabric) -> [Vec<(f64, f64)>; 3] {
    let at = |k: usize, v: f64| (k as f64, lg(v));
    let table = f.points.len();
    let mut uniform: Vec<(f64, f64)> = f
        .points
        .iter()
        .enumerate()
        .map(|(k, p)| at(k, p.uniform))
        .collect();
    let mut highlight: Vec<(f64, f64)> = f
        .points
        .iter()
        .enumerate()
        .map(|(k, p)| at(k, p.highlight))
        .collect();
    let drape = f
        .points
        .iter()
        .enumerate()
        .filter_map(|(k, p)| Some(at(k, p.image_relative_l2?)))
        .collect();
    if let Some(t) = &f.table {
        uniform.push(at(table, t.uniform));
        highlight.push(at(table, t.highlight));
    }
    [uniform, highlight, drape]
}

/// Per fabric a panel: each target's errors, and the default table's, on a log scale.
pub fn stock_error(section: &StockSection, path: &Path) -> PlotResult {
    let n = section.fabrics.len();
    let names: Vec<String> = section
        .targets
        .iter()
        .map(|t| t.name.clone())
        .chain([TABLE_COLUMN.to_string()])
        .collect();
    let label = |v: &f64| {
        let k = v.round();
        if (v - k).abs() < 1e-6 && k >= 0.0 {
            names.get(k as usize).cloned().unwrap_or_default()
        } else {
            String::new()
        }
    };
    write_png(path, grid_size(n), |root| {
        for (k, (panel, f)) in panels(root, n).iter().zip(&section.fabrics).enumerate() {
            let [uniform, highlight, drape] = columns(f);
            let ys = log_range(
                uniform
                    .iter()
                    .chain(&highlight)
                    .chain(&drape)
                    .map(|p| 10f64.powf(p.1)),
            );
            let xs = -0.5..names.len() as f64 - 0.5;
            let mut chart = panel_chart(
                panel,
                &f.name,
                xs,
                ys,
                Axes {
                    x: String::new(),
                    y: "error".into(),
                    x_ticks: &label,
                    y_ticks: &fmt_log_percent,
                },
            )?;
            let first = k == 0;
            let sets = [
                (uniform, UNIFORM_COLOUR, Marker::Circle, "F, uniform pairs"),
                (
                    highlight,
                    HIGHLIGHT_COLOUR,
                    Marker::Triangle,
                    "F, highlight pairs",
                ),
                (drape, DRAPE_COLOUR, Marker::Cross, "drape image"),
            ];
            for (points, colour, marker, name) in sets {
                markers(&mut chart, &points, colour, marker, first.then_some(name))?;
            }
            if first {
                draw_legend(&mut chart, SeriesLabelPosition::LowerLeft)?;
            }
        }
        Ok(())
    })
}

/// Gap between tiles, and the heights of the column header and a row's caption.
const GAP: u32 = 6;
const HEADER: u32 = 26;
const CAPTION: u32 = 22;

/// The tiles as one picture: a header naming the columns, and per row the fabric's name
/// above its tiles (a tile not rendered is left blank).
pub fn stock_grid(
    columns: &[String],
    rows: &[(String, Vec<Option<Rgba8Image>>)],
    path: &Path,
) -> PlotResult {
    let side = rows
        .iter()
        .flat_map(|(_, tiles)| tiles.iter().flatten())
        .map(|t| t.width.max(t.height))
        .max()
        .unwrap_or(128);
    let cols = columns.len() as u32;
    let width = GAP + cols * (side + GAP);
    let height = HEADER + rows.len() as u32 * (CAPTION + side + GAP);
    write_png(path, (width, height), |root| {
        let column_x = |c: u32| (GAP + c * (side + GAP)) as i32;
        for (c, name) in columns.iter().enumerate() {
            root.draw(&Text::new(
                name.clone(),
                (column_x(c as u32), 6),
                (FONT, 15).into_font(),
            ))?;
        }
        for (r, (name, tiles)) in rows.iter().enumerate() {
            let top = HEADER + r as u32 * (CAPTION + side + GAP);
            root.draw(&Text::new(
                name.clone(),
                (GAP as i32, top as i32 + 3),
                (FONT, 14).into_font(),
            ))?;
            for (c, tile) in tiles.iter().enumerate() {
                let Some(tile) = tile else { continue };
                let (x0, y0) = (column_x(c as u32), (top + CAPTION) as i32);
                for (i, p) in tile.pixels.iter().enumerate() {
                    let (x, y) = (
                        (i as u32 % tile.width) as i32,
                        (i as u32 / tile.width) as i32,
                    );
                    root.draw_pixel((x0 + x, y0 + y), &RGBColor(p[0], p[1], p[2]))?;
                }
            }
        }
        Ok(())
    })
}
