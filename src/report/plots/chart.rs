//! The plots' shared drawing: fonts, colours, log axes, panels, curves and markers.

use super::super::Report;
use crate::evaluator::EvaluatorUnit;
use crate::table::Layout;
use plotters::coord::Shift;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;
use std::path::Path;
use std::sync::Once;

pub(super) const FONT: &str = "sans-serif";
pub(super) const PANEL: (u32, u32) = (560, 420);

/// Layout colours, in the registry's order ([`Layout::ALL`]).
pub(super) const LAYOUT_COLOURS: [RGBColor; 4] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(148, 103, 189),
];
/// Evaluator unit colours, in the order of the units with a report plan
/// ([`crate::report::planned_units`]): none of them a layout's, so that a unit's series and a
/// layout's read apart in one panel.
pub(super) const UNIT_COLOURS: [RGBColor; 4] = [
    RGBColor(255, 127, 14),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(188, 189, 34),
];
pub(super) const DIRECT_COLOUR: RGBColor = RGBColor(90, 90, 90);
pub(super) const LIGHT_LINE: RGBColor = RGBColor(245, 245, 245);
pub(super) const FABRIC_COLOURS: [RGBColor; 8] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
];

/// A unit's place among the units with a report plan: its colour, marker and label place.
pub(super) fn unit_index(unit: &EvaluatorUnit) -> usize {
    crate::report::planned_units()
        .position(|(u, _)| u.name == unit.name)
        .unwrap_or(0)
}

pub(super) fn unit_colour(unit: &EvaluatorUnit) -> RGBColor {
    UNIT_COLOURS[unit_index(unit) % UNIT_COLOURS.len()]
}

/// A unit's marker: triangles, crosses, then circles (which the tables use too).
pub(super) fn unit_marker(unit: &EvaluatorUnit) -> Marker {
    [Marker::Triangle, Marker::Cross, Marker::Circle][unit_index(unit) % 3]
}

/// Where a unit's point labels go beside their markers, and their font size: alternately
/// above right and below left, so that two units' labels at nearby points do not overlap.
pub(super) fn unit_label_place(unit: &EvaluatorUnit) -> ((i32, i32), u32) {
    [((7, -3), 13), ((-12, 7), 12)][unit_index(unit) % 2]
}

pub(super) fn layout_colour(layout: Layout) -> RGBColor {
    let index = Layout::ALL.iter().position(|&l| l == layout).unwrap_or(0);
    LAYOUT_COLOURS[index % LAYOUT_COLOURS.len()]
}

pub(super) fn register_font() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        // The embedded font is a valid TrueType file; if ab_glyph ever rejected it, text
        // would fail to draw and the plot would report that error.
        let _ = plotters::style::register_font(FONT, FontStyle::Normal, dejavu::sans::regular());
    });
}

pub(super) type PlotResult = Result<(), Box<dyn std::error::Error>>;

/// Draws `draw` into a white `width`×`height` RGB image and writes it as PNG to `path`.
pub(super) fn write_png(
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
pub(super) fn lg(v: f64) -> f64 {
    v.log10()
}

pub(super) fn lg2((x, y): (f64, f64)) -> (f64, f64) {
    (lg(x), lg(y))
}

/// The log10 range covering the positive finite `values`, with a margin of a factor 1.5.
pub(super) fn log_range(values: impl IntoIterator<Item = f64>) -> std::ops::Range<f64> {
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
pub(super) fn significant(x: f64) -> String {
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
pub(super) fn fmt_log_percent(v: &f64) -> String {
    format!("{}%", significant(100.0 * 10f64.powf(*v)))
}

/// Tick label of a log10 coordinate, as a number (k and M for thousands and millions).
pub(super) fn fmt_log_number(v: &f64) -> String {
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
pub(super) fn panels<'a>(
    root: &DrawingArea<BitMapBackend<'a>, Shift>,
    count: usize,
) -> Vec<DrawingArea<BitMapBackend<'a>, Shift>> {
    let cols = count.clamp(1, 3);
    let rows = count.div_ceil(cols).max(1);
    root.split_evenly((rows, cols))
}

pub(super) fn grid_size(count: usize) -> (u32, u32) {
    let cols = count.clamp(1, 3) as u32;
    let rows = count.div_ceil(cols as usize).max(1) as u32;
    (PANEL.0 * cols, PANEL.1 * rows)
}

/// The chart type every panel uses: f64 coordinates on both axes (log10 where logarithmic).
pub(super) type Chart<'a, 'b> =
    ChartContext<'a, BitMapBackend<'b>, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// Titles and tick formatters of a panel's axes.
pub(super) struct Axes<'f> {
    pub x: String,
    pub y: String,
    pub x_ticks: &'f dyn Fn(&f64) -> String,
    pub y_ticks: &'f dyn Fn(&f64) -> String,
}

/// A captioned panel over `xs` × `ys` with its grid and labelled axes drawn.
pub(super) fn panel_chart<'a, 'b>(
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
pub(super) fn draw_legend<'a, 'b: 'a>(
    chart: &mut Chart<'a, 'b>,
    position: SeriesLabelPosition,
) -> PlotResult {
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
pub(super) fn fmt_integer(v: &f64) -> String {
    if (v - v.round()).abs() < 1e-6 {
        format!("{v:.0}")
    } else {
        String::new()
    }
}

/// Marker shape of an error set: circle (uniform), triangle (highlight), cross (≥ 15°).
#[derive(Clone, Copy)]
pub(super) enum Marker {
    Circle,
    Triangle,
    Cross,
}

/// Draws a line through `points` (axis coordinates) with markers, labelled in the legend when `label` is set.
pub(super) fn curve<'a, DB: DrawingBackend + 'a, X, Y>(
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

pub(super) fn marker_element<DB: DrawingBackend>(
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

/// The label of a unit's point at `at` (its parameter), beside its marker in the unit's
/// colour ([`unit_label_place`]).
macro_rules! unit_label {
    ($unit:expr, $label:expr, $at:expr) => {{
        let (offset, size) = unit_label_place($unit);
        EmptyElement::at($at)
            + Text::new(
                $label,
                offset,
                (FONT, size).into_font().color(&unit_colour($unit)),
            )
    }};
}

/// One evaluator unit's points in a panel: its curve in the unit's colour and marker, in the
/// legend as `legend` where given, and each point's `(position, parameter)` label beside its
/// marker.
pub(super) fn unit_series<'a, DB: DrawingBackend + 'a, X, Y>(
    chart: &mut ChartContext<'a, DB, Cartesian2d<X, Y>>,
    unit: &EvaluatorUnit,
    points: &[((f64, f64), String)],
    legend: Option<&str>,
) -> PlotResult
where
    DB::ErrorType: 'static,
    X: Ranged<ValueType = f64>,
    Y: Ranged<ValueType = f64>,
{
    let at: Vec<(f64, f64)> = points.iter().map(|(at, _)| *at).collect();
    curve(chart, &at, unit_colour(unit), unit_marker(unit), legend)?;
    chart.draw_series(
        points
            .iter()
            .map(|(at, parameter)| unit_label!(unit, parameter.clone(), *at)),
    )?;
    Ok(())
}

/// Picks one error figure of a table.
pub(super) type ErrorOf = fn(&super::super::Point) -> f64;

/// Draws one plot of a report into a file.
pub(super) type Plot = fn(&Report, &Path) -> PlotResult;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn no_unit_shares_a_colour_with_a_layout() {
        for unit in UNIT_COLOURS {
            assert!(!LAYOUT_COLOURS.contains(&unit), "{unit:?}");
        }
    }
}
