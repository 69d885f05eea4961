//! `view --edit`: the panel's and the script's commands carried out, the renderer kept on
//! what the editor shows, screenshots, and the edit-to-frame times.

use super::App;
use crate::editor::script::{Action, Script, Shading};
use crate::editor::session::EditSession;
use crate::evaluator::Evaluator;
use crate::lighting::EnvironmentSource;
use crate::render::GpuEnvironment;
use crate::render::image::write_png;
use crate::table::Layout;
use crate::viewer::ViewError;
use crate::viewer::edit::editor::Editor;
use crate::viewer::edit::panel::{Command, Panel, ViewState};
use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;
use winit::event_loop::ActiveEventLoop;

/// What `view --edit` was started with.
#[derive(Clone, Debug)]
pub struct EditSetup {
    pub session: EditSession,
    /// The model evaluator edits are shaded by (its GPU form updated in place).
    pub evaluator: Arc<dyn Evaluator>,
    /// The background bake's layout and resolution.
    pub table: (Layout, u32),
    pub script: Option<Script>,
}

/// The editing session of the window.
pub(in crate::viewer) struct Editing {
    pub editor: Editor,
    pub panel: Panel,
    script: Option<ScriptRun>,
    /// Script steps that failed (each reported on stderr as it failed).
    pub failures: usize,
    /// The last command's outcome, for the panel.
    message: String,
    /// A screenshot to take of the next frame drawn.
    screenshot: Option<(usize, PathBuf)>,
    pub timings: EditTimings,
}

/// Where a script is and what it waits for.
struct ScriptRun {
    script: Script,
    next: usize,
    wait: Option<Wait>,
}

enum Wait {
    Bake,
    Frames(u32),
}

/// Frame intervals while the drape is shaded by the model and by the table, and the time
/// from each edit to the first frame showing it, milliseconds.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct EditTimings {
    pub model_frames: Vec<f64>,
    pub table_frames: Vec<f64>,
    /// Frame intervals while a bake ran.
    pub baking_frames: Vec<f64>,
    pub edit_to_frame: Vec<f64>,
}

impl Editing {
    pub fn new(editor: Editor, script: Option<Script>) -> Self {
        Self {
            editor,
            panel: Panel::default(),
            script: script.map(|script| ScriptRun {
                script,
                next: 0,
                wait: None,
            }),
            failures: 0,
            message: String::new(),
            screenshot: None,
            timings: EditTimings::default(),
        }
    }

    /// Whether a script drives the session.
    pub fn scripted(&self) -> bool {
        self.script.is_some()
    }
}

impl App {
    /// Before a frame is drawn in edit mode: the script's next steps, the panel's layout and
    /// commands, the editor brought up to date and the renderer set to what it shows.
    pub(super) fn edit_frame(&mut self, event_loop: &ActiveEventLoop) {
        let Some(mut editing) = self.editing.take() else {
            return;
        };
        let steps = Self::script_steps(&mut editing, event_loop);
        let mut commands = Vec::new();
        let view = ViewState {
            lights: self.light.directional_angles(),
            environment: self.setup.environment.as_ref().map(|_| self.environment_on),
            environment_source: self.setup.scene.environment.source.to_string(),
            environment_rotation_deg: self.environment_rotation_deg,
            exposure: self.setup.scene.exposure,
            frame_ms: self.stats.median_recent(),
            message: &editing.message,
        };
        if let Some(g) = &mut self.graphics
            && let Some(overlay) = &mut g.overlay
        {
            let window = g.window.clone();
            let (panel, editor) = (&mut editing.panel, &mut editing.editor);
            overlay.run(&window, |ui| commands.extend(panel.show(ui, editor, &view)));
        }
        for (line, action) in steps {
            self.command(&mut editing, Command::Action(action), Some(line));
        }
        for command in commands {
            self.command(&mut editing, command, None);
        }
        if let Some(g) = &mut self.graphics {
            if let Err(e) = editing.editor.update(&g.gpu) {
                editing.message = e.to_string();
            }
            if let Err(e) = sync_renderer(&mut editing.editor, g) {
                self.fail(event_loop, ViewError::Render(e.to_string()));
            }
        }
        self.editing = Some(editing);
    }

    /// After a frame was presented in edit mode: its interval by what shaded it, the
    /// edit-to-frame time, and the screenshot a script asked for.
    pub(super) fn edit_presented(&mut self, interval_ms: Option<f64>, now: Instant) {
        let settings = self.frame_settings();
        let Some(editing) = &mut self.editing else {
            return;
        };
        let timings = &mut editing.timings;
        if let Some(ms) = interval_ms {
            let table = editing.editor.shown == Shading::Table && editing.editor.table_is_current();
            match table {
                true => timings.table_frames.push(ms),
                false => timings.model_frames.push(ms),
            }
            if editing.editor.bake_progress().is_some() {
                timings.baking_frames.push(ms);
            }
        }
        if let Some(at) = editing.editor.edit_at.take() {
            timings
                .edit_to_frame
                .push((now - at).as_secs_f64() * 1000.0);
        }
        if let Some((line, path)) = editing.screenshot.take()
            && let Some(g) = &mut self.graphics
        {
            let result = g
                .capture(&settings)
                .map_err(|e| e.to_string())
                .and_then(|image| {
                    // A script's shots go in folders of their own (`turntable/00.png`).
                    if let Some(parent) = path.parent().filter(|p| !p.as_os_str().is_empty()) {
                        std::fs::create_dir_all(parent).map_err(|e| e.to_string())?;
                    }
                    write_png(&path, &image).map_err(|e| e.to_string())
                });
            match result {
                Ok(()) => println!("clothbake view: line {line}: screenshot {}", path.display()),
                Err(e) => {
                    eprintln!(
                        "clothbake view: line {line}: screenshot {}: {e}",
                        path.display()
                    );
                    editing.failures += 1;
                }
            }
        }
    }

    /// The script's steps up to the next one that waits (for frames, for the bake, for a
    /// screenshot); the rest come back with their lines, to run as the panel's commands do.
    fn script_steps(editing: &mut Editing, event_loop: &ActiveEventLoop) -> Vec<(usize, Action)> {
        let mut steps = Vec::new();
        let Some(run) = &mut editing.script else {
            return steps;
        };
        match &mut run.wait {
            Some(Wait::Frames(n)) if *n > 1 => {
                *n -= 1;
                return steps;
            }
            Some(Wait::Bake) if editing.editor.baking() => {
                editing.editor.bake_now();
                return steps;
            }
            _ => run.wait = None,
        }
        while let Some((line, action)) = run.script.steps.get(run.next).cloned() {
            run.next += 1;
            match action {
                Action::Frames(n) => {
                    run.wait = Some(Wait::Frames(n));
                    break;
                }
                Action::WaitBake => {
                    editing.editor.bake_now();
                    run.wait = Some(Wait::Bake);
                    break;
                }
                Action::Screenshot { path } => {
                    editing.screenshot = Some((line, path));
                    break;
                }
                Action::Exit => {
                    run.next = run.script.steps.len();
                    break;
                }
                action => steps.push((line, action)),
            }
        }
        if run.next >= run.script.steps.len() && run.wait.is_none() && editing.screenshot.is_none()
        {
            // A script that ends, with `exit` or without, ends the session.
            event_loop.exit();
        }
        steps
    }

    /// Carries out one command of the panel (`line` None) or of the script.
    fn command(&mut self, editing: &mut Editing, command: Command, line: Option<usize>) {
        let session = &mut editing.editor.session;
        let (text, result) = match command {
            // A slider's refused value shows beside its field (the session keeps it).
            Command::Slide(edit) => {
                let _ = session.apply_coalesced(&edit);
                return;
            }
            Command::EndGesture => {
                session.end_gesture();
                return;
            }
            Command::Replot => {
                editing.editor.replot();
                return;
            }
            Command::Action(action) => {
                let result = if action.is_editor() {
                    session
                        .run_editor_action(&action)
                        .map(|_| ())
                        .map_err(|e| e.to_string())
                } else {
                    self.viewer_action(editing, &action)
                };
                (action.to_string(), result)
            }
        };
        let place = line.map_or_else(String::new, |line| format!("line {line}: "));
        match result {
            Ok(()) => editing.message = text,
            Err(e) => {
                eprintln!("clothbake view: {place}{text}: {e}");
                editing.message = format!("{text}: {e}");
                if line.is_some() {
                    editing.failures += 1;
                }
            }
        }
    }

    /// The actions that change the view rather than the fabric.
    fn viewer_action(&mut self, editing: &mut Editing, action: &Action) -> Result<(), String> {
        let editor = &mut editing.editor;
        match action {
            Action::Show(shading) => {
                if *shading == Shading::Table && !editor.table_is_current() {
                    return Err("no table of the fabric as it is now yet (it is baked when \
                                the edits stop; `wait-bake` waits for it)"
                        .into());
                }
                editor.shown = *shading;
                editor.display_changed = true;
            }
            Action::Compare(compare) => {
                editor.compare = *compare;
                editor.display_changed = true;
            }
            Action::Exposure(exposure) => self.setup.scene.exposure = exposure.scale(),
            Action::Environment(on) => {
                if self.setup.environment.is_none() {
                    return Err("the scene has no environment light (--env)".into());
                }
                self.environment_on = *on;
                editor.taps_changed = true;
            }
            Action::EnvironmentMap { source } => self.load_environment(editor, source)?,
            Action::EnvironmentRotation { degrees } => {
                self.environment_rotation_deg = degrees.rem_euclid(360.0);
            }
            Action::Light {
                index,
                elevation_deg,
                azimuth_deg,
            } => self.light.aim(*index, *azimuth_deg, *elevation_deg)?,
            Action::Orbit { yaw_deg, pitch_deg } => self.orbit.aim(*yaw_deg, *pitch_deg),
            Action::SaveTable { dir } => {
                let baked = editor
                    .baked
                    .as_ref()
                    .filter(|_| editor.table_is_current())
                    .ok_or("no table of the fabric as it is now is baked yet (`wait-bake` waits for it)")?;
                std::fs::create_dir_all(dir)
                    .map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
                crate::editor::background::write_baked(dir, &baked.table)
                    .map_err(|e| e.to_string())?;
            }
            other => return Err(format!("{other} is not carried out here")),
        }
        Ok(())
    }
}

impl App {
    /// Lights the scene by the environment `source` names (`--env`'s words or a file), or by
    /// none: loaded, its bright sources split off as at the start, uploaded, and the editor's
    /// bakes asked for taps from then on.
    fn load_environment(&mut self, editor: &mut Editor, source: &str) -> Result<(), String> {
        let source: EnvironmentSource = source.parse().map_err(|e| format!("{e}"))?;
        let sources = self.setup.scene.environment.sources;
        let split = source
            .load()
            .map_err(|e| e.to_string())?
            .map(|map| map.split_bright_sources(sources));
        let g = self.graphics.as_mut().ok_or("no window")?;
        g.environment = split
            .as_ref()
            .map(|split| GpuEnvironment::split(&g.gpu, split))
            .transpose()
            .map_err(|e| e.to_string())?;
        self.environment_on = split.is_some();
        self.setup.environment = split;
        self.setup.scene.environment.source = source;
        if self.environment_on {
            editor.want_taps(self.setup.scene.environment.samples);
        }
        editor.taps_changed = true;
        Ok(())
    }
}

/// Sets the renderer to what the editor shows (when that changed) and the environment
/// light to the shown table's taps.
fn sync_renderer(
    editor: &mut Editor,
    g: &mut crate::viewer::surface::Graphics,
) -> Result<(), crate::gpu::GpuError> {
    if editor.display_changed {
        let (left, right) = editor.display();
        g.renderer.set_brdf(&g.gpu, left)?;
        let right = right
            .map(|brdf| g.renderer.prepare_brdf(&g.gpu, brdf))
            .transpose()?;
        g.renderer.set_split(right);
        editor.display_changed = false;
    }
    if editor.taps_changed {
        if let (Some(map), Some(taps)) = (&g.environment, editor.environment_taps()) {
            g.renderer.set_environment(&g.gpu, map, taps)?;
        }
        editor.taps_changed = false;
    }
    Ok(())
}
