//! The report's PNG plots, drawn with plotters' bitmap backend into a buffer and encoded
//! with the png crate.
//!
//! Text uses DejaVu Sans embedded by the `dejavu` crate and rasterised by ab_glyph, so the
//! plots need no system fonts (plotters' default `ttf` feature would need fontconfig).

use super::{Report, ReportError, worst};
use crate::table::Layout;
use plotters::coord::Shift;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;
use std::path::Path;
use std::sync::Once;

/// File names of the plots in the output directory.
pub const ERROR_VS_SIZE: &str = "error_vs_size.png";
pub const ERROR_VS_COST: &str = "error_vs_cost.png";
pub const BAKE_TIME: &str = "bake_time.png";
pub const GPU_COST: &str = "gpu_cost.png";

const FONT: &str = "sans-serif";
const PANEL: (u32, u32) = (560, 420);

/// Layout colours, in the registry's order ([`Layout::ALL`]).
const LAYOUT_COLOURS: [RGBColor; 4] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(148, 103, 189),
];
const PAPER_COLOUR: RGBColor = RGBColor(44, 160, 44);
const RESONANT_COLOUR: RGBColor = RGBColor(148, 103, 189);
const DIRECT_COLOUR: RGBColor = RGBColor(90, 90, 90);
const LIGHT_LINE: RGBColor = RGBColor(245, 245, 245);
const FABRIC_COLOURS: [RGBColor; 8] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
];

fn layout_colour(layout: Layout) -> RGBColor {
    let index = Layout::ALL.iter().position(|&l| l == layout).unwrap_or(0);
    LAYOUT_COLOURS[index % LAYOUT_COLOURS.len()]
}

fn register_font() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        // The embedded font is a valid TrueType file; if ab_glyph ever rejected it, text
        // would fail to draw and the plot would report that error.
        let _ = plotters::style::register_font(FONT, FontStyle::Normal, dejavu::sans::regular());
    });
}

type PlotResult = Result<(), Box<dyn std::error::Error>>;

/// Draws `draw` into a white `width`×`height` RGB image and writes it as PNG to `path`.
fn write_png(
    path: &Path,
    (width, height): (u32, u32),
    draw: impl FnOnce(&DrawingArea<BitMapBackend, Shift>) -> PlotResult,
) -> PlotResult {
    register_font();
    let mut buffer = vec![0u8; width as usize * height as usize * 3];
    {
        let root = BitMapBackend::with_buffer(&mut buffer, (width, height)).into_drawing_area();
        root.fill(&WHITE)?;
        draw(&root)?;
        root.present()?;
    }
    let file = std::io::BufWriter::new(std::fs::File::create(path)?);
    let mut encoder = png::Encoder::new(file, width, height);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    let mut writer = encoder.write_header()?;
    writer.write_image_data(&buffer)?;
    writer.finish()?;
    Ok(())
}

/// Logarithmic axes are drawn as linear axes over log10 of the values, so that ranges
/// spanning less than a decade still get labelled ticks (plotters' own log axis labels
/// powers of ten only). `lg` maps a value (or a point) to those coordinates; non-positive
/// values map to -inf or NaN and are left out of curves.
fn lg(v: f64) -> f64 {
    v.log10()
}

fn lg2((x, y): (f64, f64)) -> (f64, f64) {
    (lg(x), lg(y))
}

/// The log10 range covering the positive finite `values`, with a margin of a factor 1.5.
fn log_range(values: impl IntoIterator<Item = f64>) -> std::ops::Range<f64> {
    let (lo, hi) = values
        .into_iter()
        .filter(|v| v.is_finite() && *v > 0.0)
        .fold((f64::INFINITY, 0.0f64), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    if lo > hi {
        return -3.0..0.0;
    }
    let hi = if hi <= lo { lo * 10.0 } else { hi };
    lg(lo / 1.5)..lg(hi * 1.5)
}

/// `x` with two significant digits, without exponent.
fn significant(x: f64) -> String {
    if !(x.is_finite() && x > 0.0) {
        return String::new();
    }
    let decimals = (1.0 - x.log10().floor()).max(0.0) as usize;
    let text = format!("{x:.decimals$}");
    if text.contains('.') {
        text.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        text
    }
}

/// Tick label of a log10 coordinate, as a percentage.
fn fmt_log_percent(v: &f64) -> String {
    format!("{}%", significant(100.0 * 10f64.powf(*v)))
}

/// Tick label of a log10 coordinate, as a number (k and M for thousands and millions).
fn fmt_log_number(v: &f64) -> String {
    let x = 10f64.powf(*v);
    if x >= 1e6 {
        format!("{}M", significant(x / 1e6))
    } else if x >= 1e3 {
        format!("{}k", significant(x / 1e3))
    } else {
        significant(x)
    }
}

/// Splits `root` into one panel per fabric, three to a row.
fn panels<'a>(
    root: &DrawingArea<BitMapBackend<'a>, Shift>,
    count: usize,
) -> Vec<DrawingArea<BitMapBackend<'a>, Shift>> {
    let cols = count.clamp(1, 3);
    let rows = count.div_ceil(cols).max(1);
    root.split_evenly((rows, cols))
}

fn grid_size(count: usize) -> (u32, u32) {
    let cols = count.clamp(1, 3) as u32;
    let rows = count.div_ceil(cols as usize).max(1) as u32;
    (PANEL.0 * cols, PANEL.1 * rows)
}

/// The chart type every panel uses: f64 coordinates on both axes (log10 where logarithmic).
type Chart<'a, 'b> =
    ChartContext<'a, BitMapBackend<'b>, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// Titles and tick formatters of a panel's axes.
struct Axes<'f> {
    x: String,
    y: String,
    x_ticks: &'f dyn Fn(&f64) -> String,
    y_ticks: &'f dyn Fn(&f64) -> String,
}

/// A captioned panel over `xs` × `ys` with its grid and labelled axes drawn.
fn panel_chart<'a, 'b>(
    panel: &'a DrawingArea<BitMapBackend<'b>, Shift>,
    caption: &str,
    xs: std::ops::Range<f64>,
    ys: std::ops::Range<f64>,
    axes: Axes<'_>,
) -> Result<Chart<'a, 'b>, Box<dyn std::error::Error>> {
    let mut chart = ChartBuilder::on(panel)
        .caption(caption, (FONT, 18))
        .margin(10)
        .x_label_area_size(40)
        .y_label_area_size(56)
        .build_cartesian_2d(xs, ys)?;
    chart
        .configure_mesh()
        .x_desc(axes.x)
        .y_desc(axes.y)
        .x_label_formatter(axes.x_ticks)
        .y_label_formatter(axes.y_ticks)
        .x_labels(8)
        .y_labels(8)
        .light_line_style(LIGHT_LINE)
        .label_style((FONT, 12))
        .draw()?;
    Ok(chart)
}

/// The legend of the labelled series, boxed, at `position`.
fn draw_legend<'a, 'b: 'a>(chart: &mut Chart<'a, 'b>, position: SeriesLabelPosition) -> PlotResult {
    chart
        .configure_series_labels()
        .label_font((FONT, 12))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .position(position)
        .draw()?;
    Ok(())
}

/// Integers only (resolutions): other tick positions stay unlabelled.
fn fmt_integer(v: &f64) -> String {
    if (v - v.round()).abs() < 1e-6 {
        format!("{v:.0}")
    } else {
        String::new()
    }
}

/// Marker shape of an error set: circle (uniform), triangle (highlight), cross (≥ 15°).
#[derive(Clone, Copy)]
enum Marker {
    Circle,
    Triangle,
    Cross,
}

/// Draws a line through `points` (axis coordinates) with markers, labelled in the legend when `label` is set.
fn curve<'a, DB: DrawingBackend + 'a, X, Y>(
    chart: &mut ChartContext<'a, DB, Cartesian2d<X, Y>>,
    points: &[(f64, f64)],
    colour: RGBColor,
    marker: Marker,
    label: Option<&str>,
) -> PlotResult
where
    DB::ErrorType: 'static,
    X: Ranged<ValueType = f64>,
    Y: Ranged<ValueType = f64>,
{
    let points: Vec<(f64, f64)> = points
        .iter()
        .copied()
        .filter(|&(x, y)| x.is_finite() && y.is_finite())
        .collect();
    let series = chart.draw_series(LineSeries::new(points.clone(), colour.stroke_width(2)))?;
    if let Some(label) = label {
        series.label(label).legend(move |(x, y)| {
            EmptyElement::at((x, y))
                + PathElement::new(vec![(0, 0), (18, 0)], colour.stroke_width(2))
                + marker_element((9, 0), marker, colour)
        });
    }
    chart.draw_series(
        points
            .iter()
            .map(|&p| EmptyElement::at(p) + marker_element((0, 0), marker, colour)),
    )?;
    Ok(())
}

fn marker_element<DB: DrawingBackend>(
    at: (i32, i32),
    marker: Marker,
    colour: RGBColor,
) -> DynElement<'static, DB, (i32, i32)> {
    match marker {
        Marker::Circle => Circle::new(at, 4, colour.filled()).into_dyn(),
        Marker::Triangle => TriangleMarker::new(at, 5, colour.filled()).into_dyn(),
        Marker::Cross => Cross::new(at, 4, colour.stroke_width(2)).into_dyn(),
    }
}

/// The label "N" of a paper-mode point at `at`, beside its marker.
macro_rules! paper_label {
    ($samples:expr, $at:expr) => {
        EmptyElement::at($at)
            + Text::new(
                format!("{}", $samples),
                (7, -3),
                (FONT, 13).into_font().color(&PAPER_COLOUR),
            )
    };
}

/// The label "S/V/B" of a resonant point at `at`, under its marker.
macro_rules! resonant_label {
    ($label:expr, $at:expr) => {
        EmptyElement::at($at)
            + Text::new(
                $label.to_string(),
                (-12, 7),
                (FONT, 12).into_font().color(&RESONANT_COLOUR),
            )
    };
}

/// Picks one error figure of a table.
type ErrorOf = fn(&super::TablePoint) -> f64;

/// Draws one plot of a report into a file.
type Plot = fn(&Report, &Path) -> PlotResult;

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
            let xs = log_range(f.tables.iter().map(|t| mib(t.bytes)));
            let ys = log_range(f.tables.iter().flat_map(|t| {
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
                let of: Vec<_> = f.tables.iter().filter(|t| t.layout == layout).collect();
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
                        of.iter().map(|t| lg2((mib(t.bytes), value(t)))).collect();
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

/// Error (worse of uniform and highlight) against CPU ns per evaluation: paper mode by N,
/// the resonant quadrature by node counts, each layout by resolution, and the direct
/// evaluation's cost as a vertical line.
fn error_vs_cost(report: &Report, path: &Path) -> PlotResult {
    let size = grid_size(report.fabrics.len());
    write_png(path, size, |root| {
        for (k, (panel, f)) in panels(root, report.fabrics.len())
            .iter()
            .zip(&report.fabrics)
            .enumerate()
        {
            let xs = log_range(
                f.paper
                    .iter()
                    .map(|p| p.timing.ns_per_eval)
                    .chain(f.resonant.iter().map(|r| r.timing.ns_per_eval))
                    .chain(f.tables.iter().map(|t| t.lookup.ns_per_eval))
                    .chain([f.direct.ns_per_eval]),
            );
            let ys = log_range(
                f.paper
                    .iter()
                    .map(|p| worst(&p.error))
                    .chain(f.resonant.iter().map(|r| worst(&r.error)))
                    .chain(f.tables.iter().map(|t| worst(&t.error))),
            );
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
            let paper: Vec<(f64, f64)> = f
                .paper
                .iter()
                .map(|p| lg2((p.timing.ns_per_eval, worst(&p.error))))
                .collect();
            curve(
                &mut chart,
                &paper,
                PAPER_COLOUR,
                Marker::Triangle,
                (k == 0).then_some("paper mode (N)"),
            )?;
            chart.draw_series(
                f.paper
                    .iter()
                    .map(|p| paper_label!(p.samples, lg2((p.timing.ns_per_eval, worst(&p.error))))),
            )?;
            let resonant: Vec<(f64, f64)> = f
                .resonant
                .iter()
                .map(|r| lg2((r.timing.ns_per_eval, worst(&r.error))))
                .collect();
            curve(
                &mut chart,
                &resonant,
                RESONANT_COLOUR,
                Marker::Cross,
                (k == 0).then_some("resonant (surface/volume/base)"),
            )?;
            chart.draw_series(
                f.resonant.iter().map(|r| {
                    resonant_label!(r.label, lg2((r.timing.ns_per_eval, worst(&r.error))))
                }),
            )?;
            for &layout in Layout::ALL {
                let points: Vec<(f64, f64)> = f
                    .tables
                    .iter()
                    .filter(|t| t.layout == layout)
                    .map(|t| lg2((t.lookup.ns_per_eval, worst(&t.error))))
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
            let points = |f: &super::FabricReport| -> Vec<(f64, f64)> {
                f.tables
                    .iter()
                    .filter(|t| t.layout == layout)
                    .map(|t| (t.resolution as f64, lg(t.bake.seconds)))
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
/// the paper-mode shader by N, the resonant shader by node counts and the lookup shader.
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
            let paper: Vec<(f64, f64)> = f
                .points
                .iter()
                .filter(|p| p.samples.is_some())
                .map(|p| lg2((p.ms_per_frame, p.image_relative_l2)))
                .collect();
            curve(
                &mut chart,
                &paper,
                PAPER_COLOUR,
                Marker::Triangle,
                (k == 0).then_some("paper-mode shader (N)"),
            )?;
            chart.draw_series(f.points.iter().filter_map(|p| {
                p.samples
                    .map(|n| paper_label!(n, lg2((p.ms_per_frame, p.image_relative_l2))))
            }))?;
            let resonant: Vec<_> = f.points.iter().filter(|p| p.nodes.is_some()).collect();
            let at = |p: &super::gpu::GpuPoint| lg2((p.ms_per_frame, p.image_relative_l2));
            curve(
                &mut chart,
                &resonant.iter().map(|p| at(p)).collect::<Vec<_>>(),
                RESONANT_COLOUR,
                Marker::Cross,
                (k == 0).then_some("resonant shader (nodes)"),
            )?;
            chart.draw_series(
                resonant
                    .iter()
                    .filter_map(|p| p.nodes.map(|n| resonant_label!(n, at(p)))),
            )?;
            let lookup: Vec<(f64, f64)> = f
                .points
                .iter()
                .filter(|p| p.shader == "lookup")
                .map(|p| lg2((p.ms_per_frame, p.image_relative_l2)))
                .collect();
            let label = format!("lookup shader ({})", f.table);
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
