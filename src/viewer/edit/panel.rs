//! The editing panel (egui): the fabric's fields, the file, what shades the drape, the bake,
//! the lights, and the plots. Every widget answers with a [`Command`], most of them the very
//! [`Action`]s a script gives, so a script drives the editor as a person does.

use super::editor::Editor;
use super::plots_ui::PlotsUi;
use crate::editor::fields::{ColourSpace, Edit, EditValue, FieldKind, FieldSpec, linear_to_srgb};
use crate::editor::script::{Action, Compare, Exposure, Shading};
use crate::lighting::GeneratedEnvironment;
use crate::weave::yarn::srgb_to_linear;
use std::collections::HashMap;
use std::path::PathBuf;

/// The panels' widths in points: the fabric's on the right, the plots' on the left; the
/// drape shows between them.
pub const FIELDS_WIDTH: f32 = 360.0;
pub const PLOTS_WIDTH: f32 = 340.0;
/// A field's row: its label's column, its slider and its text box, in points (within
/// [`FIELDS_WIDTH`] with the spacing and the panel's margins).
const FIELD_LABEL_WIDTH: f32 = 150.0;
const FIELD_SLIDER_WIDTH: f32 = 80.0;
const FIELD_TEXT_WIDTH: f32 = 85.0;

/// What a widget asks for.
#[derive(Clone, Debug, PartialEq)]
pub enum Command {
    /// What a script line would do.
    Action(Action),
    /// A slider or colour picker moved: one undo step for the whole drag.
    Slide(Edit),
    /// The drag ended.
    EndGesture,
    /// The plots' settings changed.
    Replot,
}

/// The viewer's state the panel shows beside the fabric's.
pub struct ViewState<'a> {
    /// The scene's directional lights: (index, azimuth, elevation) in degrees.
    pub lights: Vec<(usize, f64, f64)>,
    pub environment: Option<bool>,
    /// Where the environment comes from, as `--env` names it.
    pub environment_source: String,
    pub environment_rotation_deg: f64,
    pub exposure: f64,
    /// The median frame interval lately, milliseconds.
    pub frame_ms: Option<f64>,
    pub message: &'a str,
}

/// What the panel keeps between frames: the text typed into each field (kept while the
/// field has the keyboard, refreshed from the fabric otherwise) and the file path box.
#[derive(Default)]
pub struct Panel {
    typed: HashMap<&'static str, String>,
    path: String,
    /// The environment file path box.
    environment_path: String,
    pub plots: PlotsUi,
}

impl Panel {
    /// Lays out both panels over `ui` and returns what their widgets asked for.
    pub fn show(
        &mut self,
        ui: &mut egui::Ui,
        editor: &mut Editor,
        view: &ViewState<'_>,
    ) -> Vec<Command> {
        let mut commands = Vec::new();
        if self.path.is_empty()
            && let Some(path) = editor.session.saved_path()
        {
            self.path = path.display().to_string();
        }
        egui::Panel::right("clothbake_fabric")
            .exact_size(FIELDS_WIDTH)
            .resizable(false)
            .show(ui, |ui| {
                egui::ScrollArea::vertical().show(ui, |ui| {
                    self.file_section(ui, editor, &mut commands);
                    ui.separator();
                    shading_section(ui, editor, &mut commands);
                    ui.separator();
                    self.fields_section(ui, editor, &mut commands);
                    ui.separator();
                    self.lights_section(ui, view, &mut commands);
                });
            });
        egui::Panel::left("clothbake_plots")
            .exact_size(PLOTS_WIDTH)
            .resizable(false)
            .show(ui, |ui| {
                egui::ScrollArea::vertical().show(ui, |ui| {
                    ui.heading("F in pictures");
                    if let Some(error) = &editor.plots_error {
                        ui.colored_label(ui.visuals().error_fg_color, error);
                    }
                    if editor.plotting() {
                        ui.label("computing the plots of this edit…");
                    }
                    if chosen_wi(ui, &mut editor.plot_settings) {
                        commands.push(Command::Replot);
                    }
                    let drawdown = editor
                        .session
                        .draft()
                        .map(crate::editor::plots::Drawdown::of);
                    if let Some(plots) = &editor.plots {
                        self.plots.show(ui, plots, drawdown.as_ref());
                    }
                });
            });
        commands
    }

    fn file_section(&mut self, ui: &mut egui::Ui, editor: &Editor, commands: &mut Vec<Command>) {
        let session = &editor.session;
        ui.heading(format!(
            "{}{}",
            session.fabric().name,
            if session.is_dirty() { " (edited)" } else { "" }
        ));
        ui.horizontal(|ui| {
            ui.label("file");
            ui.add(egui::TextEdit::singleline(&mut self.path).desired_width(200.0));
        });
        ui.horizontal(|ui| {
            if ui.button("Open").clicked() {
                commands.push(Command::Action(Action::Open {
                    target: self.path.clone(),
                    fabric: None,
                }));
            }
            if ui.button("Save").clicked() {
                commands.push(Command::Action(Action::Save {
                    path: PathBuf::from(&self.path),
                }));
            }
            if ui
                .add_enabled(session.can_undo(), egui::Button::new("Undo"))
                .clicked()
            {
                commands.push(Command::Action(Action::Undo));
            }
            if ui
                .add_enabled(session.can_redo(), egui::Button::new("Redo"))
                .clicked()
            {
                commands.push(Command::Action(Action::Redo));
            }
        });
        if let Some(error) = session.error(crate::editor::session::FILE_FIELD) {
            ui.colored_label(ui.visuals().error_fg_color, error);
        }
    }

    fn fields_section(&mut self, ui: &mut egui::Ui, editor: &Editor, commands: &mut Vec<Command>) {
        let session = &editor.session;
        let mut group = "";
        for field in session.fields() {
            if field.group() != group {
                group = field.group();
                ui.add_space(4.0);
                ui.strong(group);
            }
            ui.horizontal(|ui| {
                // Labels in a column of their own width, so that the widgets line up.
                let size = egui::vec2(FIELD_LABEL_WIDTH, ui.spacing().interact_size.y);
                ui.allocate_ui_with_layout(
                    size,
                    egui::Layout::left_to_right(egui::Align::Center),
                    |ui| {
                        ui.set_min_width(FIELD_LABEL_WIDTH);
                        ui.add(egui::Label::new(field.label).truncate())
                            .on_hover_text(field.path);
                    },
                );
                ui.spacing_mut().slider_width = FIELD_SLIDER_WIDTH;
                self.widget(ui, editor, field, commands);
            });
            if let Some(error) = session.error(field.path) {
                ui.colored_label(
                    ui.visuals().error_fg_color,
                    format!("{}: {error}", field.path),
                );
            }
        }
    }

    /// The widgets of one field: a slider, colour button or menu that applies as it moves,
    /// and a text box that applies what was typed when the keyboard leaves it.
    fn widget(
        &mut self,
        ui: &mut egui::Ui,
        editor: &Editor,
        field: &'static FieldSpec,
        commands: &mut Vec<Command>,
    ) {
        let value = editor.session.value(field.path).ok();
        match (field.kind(), &value) {
            (FieldKind::Number, Some(EditValue::Number(v))) => {
                let mut v = *v;
                let response = ui.add(
                    egui::Slider::new(&mut v, field.range.0..=field.range.1)
                        .clamping(egui::SliderClamping::Never)
                        .show_value(false),
                );
                slide(
                    &response,
                    Edit::new(field.path, EditValue::Number(v)),
                    commands,
                );
            }
            (FieldKind::Colour(space), Some(EditValue::Vector(rgb))) if rgb.len() == 3 => {
                let to_linear = |c: f64| match space {
                    ColourSpace::Linear => c,
                    ColourSpace::Srgb => srgb_to_linear(c),
                };
                let mut shown = [0, 1, 2].map(|i| to_linear(rgb[i]).clamp(0.0, 1.0) as f32);
                let response = ui.color_edit_button_rgb(&mut shown);
                let picked = shown.map(|c| match space {
                    ColourSpace::Linear => c as f64,
                    ColourSpace::Srgb => linear_to_srgb(c as f64),
                });
                slide(
                    &response,
                    Edit::new(field.path, EditValue::Vector(picked.to_vec())),
                    commands,
                );
            }
            (FieldKind::Choice(choices), Some(EditValue::Choice(current))) => {
                let mut chosen = current.clone();
                egui::ComboBox::from_id_salt(field.path)
                    .selected_text(chosen.as_str())
                    .show_ui(ui, |ui| {
                        for choice in choices {
                            ui.selectable_value(&mut chosen, choice.to_string(), *choice);
                        }
                    });
                if &chosen != current {
                    commands.push(Command::Action(Action::Set {
                        field: field.path.to_string(),
                        value: chosen,
                    }));
                }
                return;
            }
            _ => {}
        }
        let current = editor.session.text(field.path).unwrap_or_default();
        let typed = self
            .typed
            .entry(field.path)
            .or_insert_with(|| current.clone());
        let response = ui.add(egui::TextEdit::singleline(typed).desired_width(FIELD_TEXT_WIDTH));
        if response.lost_focus() {
            if *typed != current {
                commands.push(Command::Action(Action::Set {
                    field: field.path.to_string(),
                    value: typed.clone(),
                }));
            }
        } else if !response.has_focus() && editor.session.error(field.path).is_none() {
            // Not being typed into and no refused text to keep on show: the fabric's value.
            typed.clone_from(&current);
        }
    }

    /// The scene's lights, environment and exposure.
    fn lights_section(
        &mut self,
        ui: &mut egui::Ui,
        view: &ViewState<'_>,
        commands: &mut Vec<Command>,
    ) {
        ui.strong("light");
        for &(index, azimuth, elevation) in &view.lights {
            let (mut az, mut el) = (azimuth, elevation);
            ui.vertical(|ui| {
                let a = ui.add(
                    egui::Slider::new(&mut az, 0.0..=360.0)
                        .suffix("°")
                        .text(format!("light {index} azimuth")),
                );
                let e = ui.add(
                    egui::Slider::new(&mut el, -85.0..=85.0)
                        .suffix("°")
                        .text(format!("light {index} elevation")),
                );
                if a.changed() || e.changed() {
                    commands.push(Command::Action(Action::Light {
                        index,
                        elevation_deg: el,
                        azimuth_deg: az,
                    }));
                }
            });
        }
        ui.horizontal(|ui| {
            let mut chosen = view.environment_source.clone();
            egui::ComboBox::from_label("environment")
                .selected_text(chosen.as_str())
                .show_ui(ui, |ui| {
                    let names = GeneratedEnvironment::ALL.map(GeneratedEnvironment::name);
                    for name in ["none", "default", "uniform"].into_iter().chain(names) {
                        ui.selectable_value(&mut chosen, name.to_string(), name);
                    }
                });
            if chosen != view.environment_source {
                commands.push(Command::Action(Action::EnvironmentMap { source: chosen }));
            }
        });
        ui.horizontal(|ui| {
            ui.add(
                egui::TextEdit::singleline(&mut self.environment_path)
                    .hint_text(".hdr or .exr file")
                    .desired_width(FIELD_LABEL_WIDTH + FIELD_SLIDER_WIDTH),
            );
            if ui.button("Load").clicked() && !self.environment_path.is_empty() {
                commands.push(Command::Action(Action::EnvironmentMap {
                    source: self.environment_path.clone(),
                }));
            }
        });
        if let Some(on) = view.environment {
            let mut on_now = on;
            if ui.checkbox(&mut on_now, "environment light").changed() {
                commands.push(Command::Action(Action::Environment(on_now)));
            }
            let mut degrees = view.environment_rotation_deg;
            if ui
                .add(egui::Slider::new(&mut degrees, 0.0..=360.0).text("environment rotation °"))
                .changed()
            {
                commands.push(Command::Action(Action::EnvironmentRotation { degrees }));
            }
        }
        let mut stops = view.exposure.log2();
        if ui
            .add(egui::Slider::new(&mut stops, -6.0..=6.0).text("exposure (stops)"))
            .changed()
        {
            commands.push(Command::Action(Action::Exposure(Exposure::Stops(stops))));
        }
        if let Some(ms) = view.frame_ms {
            ui.label(format!("frame {ms:.1} ms"));
        }
        if !view.message.is_empty() {
            ui.label(view.message);
        }
    }
}

/// A slider's or picker's edit: applied while it moves, one undo step per drag.
fn slide(response: &egui::Response, edit: Edit, commands: &mut Vec<Command>) {
    if response.changed() {
        commands.push(Command::Slide(edit));
    }
    if response.drag_stopped() || (response.changed() && !response.dragged()) {
        commands.push(Command::EndGesture);
    }
}

/// What shades the drape, the comparison and the bake's state.
fn shading_section(ui: &mut egui::Ui, editor: &Editor, commands: &mut Vec<Command>) {
    ui.horizontal(|ui| {
        ui.label("shade");
        for (shading, label) in [
            (Shading::Edited, "edited"),
            (Shading::Table, "table"),
            (Shading::Saved, "saved"),
        ] {
            if ui
                .selectable_label(editor.shown == shading, label)
                .clicked()
            {
                commands.push(Command::Action(Action::Show(shading)));
            }
        }
    });
    ui.horizontal(|ui| {
        ui.label("compare");
        for (compare, label) in [
            (Compare::Off, "off"),
            (Compare::Table, "| table"),
            (Compare::Saved, "| saved"),
        ] {
            if ui
                .selectable_label(editor.compare == compare, label)
                .clicked()
            {
                commands.push(Command::Action(Action::Compare(compare)));
            }
        }
    });
    ui.label(format!("drape: {}", editor.display_label()));
    if let Some(progress) = editor.bake_progress() {
        ui.add(egui::ProgressBar::new(progress).text("baking the table"));
    } else if editor.baking() {
        ui.label("the table is baked when the edits stop");
    }
    if let Some(error) = &editor.bake_error {
        ui.colored_label(ui.visuals().error_fg_color, format!("bake: {error}"));
    }
    if let Some(baked) = &editor.baked {
        let error = &baked.table.error;
        ui.label(format!(
            "table{}: relative RMS against the model {:.2}% (uniform pairs), {:.2}% (highlight)",
            if editor.table_is_current() {
                ""
            } else {
                " (of an earlier edit)"
            },
            100.0 * error.uniform.relative_rms,
            100.0 * error.highlight.relative_rms,
        ));
    }
}

/// The incident direction the plots are drawn for: φi from thread 1 (plane and hemisphere)
/// and the hemisphere image's θi. True once a value is settled (a slider let go or a value
/// typed), not on every step of a drag: each recomputation takes a moment off the frame.
fn chosen_wi(ui: &mut egui::Ui, settings: &mut crate::editor::plots::PlotSettings) -> bool {
    let mut settled = false;
    let mut slider = |ui: &mut egui::Ui, value: &mut f64, range, text| {
        let response = ui.add(egui::Slider::new(value, range).text(text).suffix("°"));
        settled |= response.drag_stopped() || (response.changed() && !response.dragged());
    };
    slider(ui, &mut settings.phi_i_deg, 0.0..=180.0, "φi of wi");
    slider(
        ui,
        &mut settings.hemisphere_theta_i_deg,
        0.0..=85.0,
        "θi of the hemisphere",
    );
    settled
}
