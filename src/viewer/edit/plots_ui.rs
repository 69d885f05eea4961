//! The editor's pictures of F drawn with egui and egui_plot: the data of
//! [`crate::editor::plots`] (computed off the frame): F in the plane of incidence always, and
//! under a row of tabs one more picture, each at a fixed height in points so that
//! screenshots of the panel are stable.

use crate::editor::plots::{BrdfPlots, CurveDistribution, Drawdown, HemisphereImage, colour_map};
use egui::{
    Align2, Color32, FontId, Rect, Sense, Stroke, TextureHandle, TextureOptions, pos2, vec2,
};
use egui_plot::{
    Bar, BarChart, GridInput, GridMark, Legend, Line, Plot, PlotPoints, Points, VLine,
};
use std::ops::RangeInclusive;

/// Height of a plot, in points (its width is the panel's).
pub const PLOT_HEIGHT: f32 = 200.0;
/// Side of the hemisphere image, in points (its colour bar and labels come below).
pub const HEMISPHERE_SIDE: f32 = 220.0;
/// Side of the square the drawdown fills at most, in points.
pub const DRAWDOWN_SIDE: f32 = 220.0;
/// Decades the plane of incidence shows below its largest luminance on the log scale:
/// one more than the hemisphere image, as the lines also show where the grazing fall-off
/// starts.
pub const PLANE_LOG_DECADES: f64 = 4.0;

/// The pictures under the plane of incidence, one per tab.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum PlotTab {
    /// F over the outgoing hemisphere.
    #[default]
    Hemisphere,
    /// The directional albedo over elevation.
    Albedo,
    /// The threads' tangent-curve distributions and control points.
    Curves,
    /// The weave's drawdown.
    Drawdown,
}

impl PlotTab {
    pub const ALL: [Self; 4] = [Self::Hemisphere, Self::Albedo, Self::Curves, Self::Drawdown];

    /// The tab's label.
    pub fn label(self) -> &'static str {
        match self {
            Self::Hemisphere => "Hemisphere",
            Self::Albedo => "Albedo",
            Self::Curves => "Curves",
            Self::Drawdown => "Drawdown",
        }
    }
}

/// The state of the plots' part of the panel: which picture, the plane's scale, and the
/// hemisphere image's texture with the key of the picture it holds.
pub struct PlotsUi {
    /// The picture shown.
    pub tab: PlotTab,
    /// The plane of incidence on a log scale of luminance (else linear).
    pub log_scale: bool,
    texture: Option<(u64, TextureHandle)>,
}

impl Default for PlotsUi {
    /// The hemisphere image under the plane, on the log scale: F's peak is decades above its
    /// diffuse floor, which a linear scale flattens to a line.
    fn default() -> Self {
        Self {
            tab: PlotTab::default(),
            log_scale: true,
            texture: None,
        }
    }
}

/// Line colours of the plane's series, in the order of the settings' θi.
const SERIES: [Color32; 4] = [
    Color32::from_rgb(86, 180, 233),
    Color32::from_rgb(230, 159, 0),
    Color32::from_rgb(0, 158, 115),
    Color32::from_rgb(204, 121, 167),
];
/// Thread 1's and thread 2's colours in the curves' plots.
const THREADS: [Color32; 2] = [
    Color32::from_rgb(86, 180, 233),
    Color32::from_rgb(230, 159, 0),
];

impl PlotsUi {
    /// Draws the plane of incidence of `plots`, then the tabs and the chosen picture;
    /// `drawdown` is the weave's, where the fabric was made from one (its tab then shows it,
    /// else says there is none).
    pub fn show(&mut self, ui: &mut egui::Ui, plots: &BrdfPlots, drawdown: Option<&Drawdown>) {
        ui.small(format!("{}, F by {}", plots.fabric, plots.evaluator));
        ui.checkbox(&mut self.log_scale, "log scale");
        plane(ui, plots, self.log_scale);
        ui.separator();
        ui.horizontal(|ui| {
            for tab in PlotTab::ALL {
                ui.selectable_value(&mut self.tab, tab, tab.label());
            }
        });
        match self.tab {
            PlotTab::Hemisphere => self.hemisphere(ui, &plots.hemisphere, plots.phi_i_deg),
            PlotTab::Albedo => albedo(ui, plots),
            PlotTab::Curves => curves(ui, &plots.curves),
            PlotTab::Drawdown => match drawdown {
                Some(d) => drawdown_grid(ui, d),
                None => {
                    ui.label("no weave: this fabric was not made from a draft");
                }
            },
        }
    }

    /// The hemisphere image with the circle of the horizon, the threads' axes, wi's mirror
    /// direction, and a colour bar labelled in decades of luminance.
    fn hemisphere(&mut self, ui: &mut egui::Ui, image: &HemisphereImage, phi_i_deg: f64) {
        let texture = match &mut self.texture {
            Some((key, handle)) if *key == image.key => handle,
            slot => {
                let handle = ui.ctx().load_texture(
                    "clothbake-hemisphere",
                    colour_image(image),
                    TextureOptions::NEAREST,
                );
                &mut slot.insert((image.key, handle)).1
            }
        };
        ui.label(format!(
            "F(wi, wo) over wo, θi = {:.0}°, φi = {:.0}° (orthographic; x: thread 1, y: thread 2)",
            image.theta_i_deg, phi_i_deg
        ));
        let bar = 12.0;
        let (response, painter) = ui.allocate_painter(
            vec2(HEMISPHERE_SIDE, HEMISPHERE_SIDE + bar + 18.0),
            Sense::hover(),
        );
        let square = Rect::from_min_size(response.rect.min, vec2(HEMISPHERE_SIDE, HEMISPHERE_SIDE));
        let uv = Rect::from_min_max(pos2(0.0, 0.0), pos2(1.0, 1.0));
        painter.image(texture.id(), square, uv, Color32::WHITE);
        let (centre, radius) = (square.center(), HEMISPHERE_SIDE / 2.0);
        let faint = Stroke::new(1.0, Color32::from_gray(140));
        painter.circle_stroke(centre, radius, faint);
        painter.line_segment(
            [centre - vec2(radius, 0.0), centre + vec2(radius, 0.0)],
            faint,
        );
        painter.line_segment(
            [centre - vec2(0.0, radius), centre + vec2(0.0, radius)],
            faint,
        );
        // The mirror direction of wi, (−wi.x, −wi.y) in the projection (y up on screen).
        let mirror = centre + vec2(-image.wi[0] as f32, image.wi[1] as f32) * radius;
        painter.circle_stroke(mirror, 4.0, Stroke::new(1.5, Color32::WHITE));
        let top = square.bottom() + 4.0;
        let steps = 64;
        for k in 0..steps {
            let c = colour_map((k as f64 + 0.5) / steps as f64);
            let x0 = square.left() + HEMISPHERE_SIDE * k as f32 / steps as f32;
            let cell = Rect::from_min_max(
                pos2(x0, top),
                pos2(x0 + HEMISPHERE_SIDE / steps as f32 + 0.5, top + bar),
            );
            painter.rect_filled(cell, 0.0, Color32::from_rgb(c[0], c[1], c[2]));
        }
        let (lo, hi) = image.log10_range;
        let text = ui.visuals().text_color();
        let font = FontId::proportional(11.0);
        for (x, value, align) in [(0.0, lo, Align2::LEFT_TOP), (1.0, hi, Align2::RIGHT_TOP)] {
            let at = pos2(square.left() + HEMISPHERE_SIDE * x, top + bar + 2.0);
            painter.text(
                at,
                align,
                format!("{:.2e}", 10f64.powf(value)),
                font.clone(),
                text,
            );
        }
        let middle = pos2(square.center().x, top + bar + 2.0);
        painter.text(
            middle,
            Align2::CENTER_TOP,
            "luminance of F (log)",
            font,
            text,
        );
    }
}

/// The hemisphere image as an egui image (its RGBA8 pixels are sRGB, unpremultiplied).
pub fn colour_image(image: &HemisphereImage) -> egui::ColorImage {
    let bytes: Vec<u8> = image.rgba.iter().flatten().copied().collect();
    egui::ColorImage::from_rgba_unmultiplied([image.size, image.size], &bytes)
}

/// A plot of fixed size with no zoom, drag or scroll (the panel's pictures are read, not
/// explored), its x range fixed.
fn fixed_plot(id: &str, x: RangeInclusive<f64>) -> Plot<'static> {
    Plot::new(id)
        .height(PLOT_HEIGHT)
        .allow_zoom(false)
        .allow_drag(false)
        .allow_scroll(false)
        .allow_boxed_zoom(false)
        .allow_double_click_reset(false)
        .default_x_bounds(*x.start(), *x.end())
        .legend(Legend::default())
}

/// Grid marks at every decade of a log10 axis.
fn decades(input: GridInput) -> Vec<GridMark> {
    let (lo, hi) = input.bounds;
    (lo.ceil() as i32..=hi.floor() as i32)
        .map(|n| GridMark {
            value: n as f64,
            step_size: 1.0,
        })
        .collect()
}

/// The luminance of F against signed θo, one line per θi; on the log scale log10 of it,
/// clamped to [`PLANE_LOG_DECADES`] below the largest value, decades labelled `10^n`.
fn plane(ui: &mut egui::Ui, plots: &BrdfPlots, log_scale: bool) {
    let top = plots
        .plane
        .iter()
        .flat_map(|s| &s.points)
        .map(|p| p.luminance())
        .fold(0.0f64, f64::max);
    let floor = if top > 0.0 {
        top.log10() - PLANE_LOG_DECADES
    } else {
        -1.0
    };
    let y = |v: f64| {
        if log_scale {
            v.max(10f64.powf(floor)).log10()
        } else {
            v
        }
    };
    let mut plot = fixed_plot("clothbake-plane", -90.0..=90.0)
        .x_axis_label("θo (°), + mirror side")
        .y_axis_label("luminance of F");
    plot = if log_scale {
        plot.y_grid_spacer(decades)
            .y_axis_formatter(|mark, _| format!("10^{}", mark.value.round() as i32))
    } else {
        plot.include_y(0.0)
    };
    plot.show(ui, |plot_ui| {
        for (k, series) in plots.plane.iter().enumerate() {
            let points: PlotPoints = series
                .points
                .iter()
                .map(|p| [p.theta_o_deg, y(p.luminance())])
                .collect();
            let name = format!("θi = {:.0}°", series.theta_i_deg);
            plot_ui.line(Line::new(name, points).color(SERIES[k % SERIES.len()]));
        }
        plot_ui.vline(VLine::new("normal", 0.0).color(Color32::from_gray(120)));
    });
    ui.small(format!("φi = {:.0}° from thread 1", plots.phi_i_deg));
}

/// The directional albedo's R, G and B over outgoing elevation.
fn albedo(ui: &mut egui::Ui, plots: &BrdfPlots) {
    fixed_plot("clothbake-albedo", 0.0..=90.0)
        .x_axis_label("elevation of wo (°)")
        .y_axis_label("∫F dwi")
        .include_y(0.0)
        .show(ui, |plot_ui| {
            let channels = [
                ("R", Color32::from_rgb(220, 60, 50)),
                ("G", Color32::from_rgb(60, 170, 60)),
                ("B", Color32::from_rgb(60, 100, 220)),
            ];
            for (c, (name, colour)) in channels.into_iter().enumerate() {
                let points: Vec<[f64; 2]> = plots
                    .albedo
                    .iter()
                    .map(|row| [row.elevation_deg, row.mean[c]])
                    .collect();
                plot_ui.line(Line::new(name, points.clone()).color(colour));
                plot_ui.points(Points::new(name, points).color(colour).radius(2.5));
            }
        });
    let error = plots
        .albedo
        .iter()
        .map(|r| r.standard_error)
        .fold(0.0, f64::max);
    ui.small(format!("largest standard error {error:.1e}"));
}

/// Both threads' distributions of tangent offset (histogram bars and point masses as stems,
/// each the share of the curve) and their control points against arc length.
fn curves(ui: &mut egui::Ui, curves: &[CurveDistribution; 2]) {
    fixed_plot("clothbake-curve-distribution", -90.0..=90.0)
        .x_axis_label("tangent offset α (°)")
        .y_axis_label("share of the curve")
        .include_y(0.0)
        .show(ui, |plot_ui| {
            for (t, curve) in curves.iter().enumerate() {
                let colour = THREADS[t];
                let width = curve.bin_width_deg();
                let bars = (0..curve.histogram.len())
                    .filter(|&k| curve.histogram[k] > 0.0)
                    .map(|k| {
                        Bar::new(curve.bin_centre_deg(k), curve.histogram[k])
                            .width(width)
                            .fill(colour.gamma_multiply(0.6))
                    })
                    .collect();
                let name = format!("thread {}", t + 1);
                plot_ui.bar_chart(BarChart::new(name.clone(), bars).color(colour));
                let masses: Vec<[f64; 2]> =
                    curve.point_masses.iter().map(|&(a, m)| [a, m]).collect();
                plot_ui.points(
                    Points::new(name, masses)
                        .color(colour)
                        .radius(3.0)
                        .stems(0.0),
                );
            }
        });
    fixed_plot("clothbake-curve-points", 0.0..=1.0)
        .x_axis_label("arc length (fraction)")
        .y_axis_label("offset (°)")
        .show(ui, |plot_ui| {
            for (t, curve) in curves.iter().enumerate() {
                let points: Vec<[f64; 2]> =
                    curve.control_points.iter().map(|&(s, o)| [s, o]).collect();
                let name = format!("thread {}", t + 1);
                plot_ui.line(Line::new(name.clone(), points.clone()).color(THREADS[t]));
                plot_ui.points(Points::new(name, points).color(THREADS[t]).radius(2.5));
            }
        });
}

/// The drawdown as painted squares, pick 1 at the top and end 1 at the left, the warp's
/// crossings dark and the weft's light.
fn drawdown_grid(ui: &mut egui::Ui, drawdown: &Drawdown) {
    let side = drawdown.ends.max(drawdown.picks).max(1);
    let cell = (DRAWDOWN_SIDE / side as f32).min(16.0);
    let size = vec2(cell * drawdown.ends as f32, cell * drawdown.picks as f32);
    let (response, painter) = ui.allocate_painter(size, Sense::hover());
    let (warp, weft) = (
        Color32::from_rgb(40, 60, 110),
        Color32::from_rgb(225, 215, 190),
    );
    for pick in 0..drawdown.picks {
        for end in 0..drawdown.ends {
            let min = response.rect.min + vec2(end as f32 * cell, pick as f32 * cell);
            let colour = if drawdown.warp_up(end, pick) {
                warp
            } else {
                weft
            };
            painter.rect_filled(Rect::from_min_size(min, vec2(cell, cell)), 0.0, colour);
        }
    }
    let cut = (drawdown.ends, drawdown.picks) != (drawdown.draft_ends, drawdown.draft_picks);
    ui.small(if cut {
        format!(
            "{} ends × {} picks shown of {} × {}; dark: warp (thread 1) on top",
            drawdown.ends, drawdown.picks, drawdown.draft_ends, drawdown.draft_picks
        )
    } else {
        format!(
            "{} ends × {} picks; dark: warp (thread 1) on top",
            drawdown.ends, drawdown.picks
        )
    });
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::editor::plots::PlotSettings;
    use crate::formats::fabric_toml::FabricSet;
    use crate::weave::draft::NamedWeave;

    fn plots(name: &str) -> BrdfPlots {
        let fabric = FabricSet::builtin().require(name).unwrap().clone();
        let settings = PlotSettings {
            plane_points: 61,
            hemisphere_size: 32,
            albedo_samples: 32,
            ..PlotSettings::default()
        };
        BrdfPlots::compute(&fabric, &settings).unwrap()
    }

    /// One frame of `ui` headless, 800 × 600 points at 1 pixel per point.
    fn frame(ctx: &egui::Context, mut ui: impl FnMut(&mut egui::Ui)) -> egui::FullOutput {
        let input = egui::RawInput {
            screen_rect: Some(Rect::from_min_size(pos2(0.0, 0.0), vec2(800.0, 600.0))),
            time: Some(0.0),
            ..Default::default()
        };
        ctx.run_ui(input, |ui_| ui(ui_))
    }

    /// Triangles of one headless frame of the plots' part of the panel.
    fn triangles(
        ctx: &egui::Context,
        state: &mut PlotsUi,
        plots: &BrdfPlots,
        drawdown: Option<&Drawdown>,
    ) -> usize {
        let out = frame(ctx, |ui| state.show(ui, plots, drawdown));
        ctx.tessellate(out.shapes, out.pixels_per_point)
            .iter()
            .map(|p| match &p.primitive {
                egui::epaint::Primitive::Mesh(m) => m.indices.len() / 3,
                _ => 0,
            })
            .sum()
    }

    #[test]
    fn every_tab_draws_its_picture_without_a_window() {
        let ctx = egui::Context::default();
        let satin = plots("polyester_satin_charmeuse");
        let drawdown = Drawdown::of(&"satin:5".parse::<NamedWeave>().unwrap().draft());
        let mut state = PlotsUi {
            tab: PlotTab::Drawdown,
            ..PlotsUi::default()
        };
        // The tabs, the caption and one line of text: what every tab draws besides its
        // picture.
        let bare = triangles(&ctx, &mut state, &satin, None);
        for tab in PlotTab::ALL {
            for log_scale in [false, true] {
                state.tab = tab;
                state.log_scale = log_scale;
                let drawn = triangles(&ctx, &mut state, &satin, Some(&drawdown));
                println!("{tab:?} log {log_scale}: {drawn} triangles, bare {bare}");
                // The smallest picture, the drawdown's 25 squares, is 50 triangles.
                assert!(drawn >= bare + 50, "{tab:?} {log_scale}: {drawn} vs {bare}");
            }
        }
        // The labels' symbols are in egui's built-in proportional font, the one the panel's
        // labels and plots are drawn in (no box for a missing glyph).
        assert!(ctx.fonts_mut(|f| f.has_glyphs(&FontId::proportional(12.0), "θφα∫×°−")));
    }

    #[test]
    fn the_hemisphere_texture_is_uploaded_once_per_picture() {
        let ctx = egui::Context::default();
        let (satin, velvet) = (plots("polyester_satin_charmeuse"), plots("velvet"));
        let mut state = PlotsUi {
            tab: PlotTab::Hemisphere,
            ..PlotsUi::default()
        };
        let image_uploads = |out: &egui::FullOutput| {
            out.textures_delta
                .set
                .values()
                .flatten()
                .filter(|delta| delta.image.size() == [32, 32])
                .count()
        };
        let first = frame(&ctx, |ui| state.show(ui, &satin, None));
        assert_eq!(image_uploads(&first), 1);
        let again = frame(&ctx, |ui| state.show(ui, &satin, None));
        assert_eq!(image_uploads(&again), 0);
        assert_ne!(satin.hemisphere.key, velvet.hemisphere.key);
        let other = frame(&ctx, |ui| state.show(ui, &velvet, None));
        assert_eq!(image_uploads(&other), 1);
    }

    #[test]
    fn the_colour_image_keeps_the_pixels_and_the_transparent_corners() {
        let satin = plots("polyester_satin_charmeuse");
        let image = colour_image(&satin.hemisphere);
        assert_eq!(image.size, [32, 32]);
        assert_eq!(image.pixels[0], Color32::TRANSPARENT);
        let centre = 16 * 32 + 16;
        let [r, g, b, a] = satin.hemisphere.rgba[centre];
        assert_eq!(a, 255);
        assert_eq!(image.pixels[centre], Color32::from_rgb(r, g, b));
    }
}
