//! The winit application of `clothbake view`: one window, its wgpu surface, input handling
//! and the frame loop. Every frame requests the next and nothing waits on the GPU except
//! the surface itself, so the frame interval measures what a frame costs.

mod actions;
mod edit;
mod frame;

pub use edit::{EditSetup, EditTimings};

use crate::bake::taps::{stored_fabric_taps, table_taps};
use crate::evaluator::table::{TableError, load_fabric_table};
use crate::evaluator::{EvaluationContext, Evaluator, EvaluatorError};
use crate::formats::table_exr::{TableFile, fabric_table_file};
use crate::gpu::GpuError;
use crate::gpu::{GpuContext, GpuSampleTaps};
use crate::lighting::SplitEnvironment;
use crate::model::Fabric;
use crate::render::{GpuEnvironment, Renderer};
use crate::scene::Scene;
use crate::scene::mesh::Mesh;
use crate::viewer::controls::{
    self, FrameStats, LightControl, OrbitControl, action_for_key, pixels_to_lines,
};
use crate::viewer::edit::editor::Editor;
use crate::viewer::edit::overlay::Overlay;
use crate::viewer::shading::FabricGpu;
use crate::viewer::surface::{Graphics, depth_view, os_message, surface_config};
use crate::viewer::timer::GpuTimer;
use crate::viewer::{ViewError, ViewSummary};
use std::path::PathBuf;
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};
use winit::application::ApplicationHandler;
use winit::dpi::PhysicalSize;
use winit::event::{ElementState, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::window::{Window, WindowId};

/// Initial window size (physical pixels).
const WINDOW_SIZE: PhysicalSize<u32> = PhysicalSize::new(1024, 768);
/// Initial window size with the editing panels, which take the sides (the drape shows
/// between them, as wide as without them).
pub const EDIT_WINDOW_SIZE: PhysicalSize<u32> = PhysicalSize::new(1280, 800);
/// How often the title's frame times are refreshed.
const TITLE_PERIOD: Duration = Duration::from_millis(250);

/// What [`super::run`] prepared.
pub(super) struct Setup {
    pub scene: Scene,
    /// The scene's environment light, split into its bright sources and the rest (key E
    /// switches it off and on).
    pub environment: Option<SplitEnvironment>,
    pub mesh: Mesh,
    /// The fabrics Tab and 1–9 move through.
    pub fabrics: Vec<Fabric>,
    pub first: usize,
    pub tables: PathBuf,
    pub frames: Option<u32>,
    /// The evaluators key V cycles through, the first shown at start.
    pub evaluators: Vec<Arc<dyn Evaluator>>,
    /// `view --edit`: the fabric edited, instead of the fabric list.
    pub edit: Option<EditSetup>,
}

/// Why the viewer could not show a fabric by an evaluator (the view stays as it was).
#[derive(Debug, thiserror::Error)]
pub(super) enum ShowError {
    #[error("no window")]
    NoWindow,
    #[error(transparent)]
    Evaluator(#[from] EvaluatorError),
    #[error(transparent)]
    Gpu(#[from] GpuError),
    #[error("{spelling} unavailable: {source}")]
    Unavailable {
        spelling: String,
        source: Box<ShowError>,
    },
}

/// Runs the event loop until the window closes; `table` is the first fabric's.
pub(super) fn run(setup: Setup, table: Option<TableFile>) -> Result<ViewSummary, ViewError> {
    // winit loads the X11 client libraries at run time and panics when libxkbcommon-x11 is
    // missing (the others give an error): turn that into the same kind of error.
    let event_loop = std::panic::catch_unwind(EventLoop::new)
        .map_err(|_| {
            ViewError::Display(
                "the window system's client libraries could not be loaded (on Debian: \
                 apt-get install libxkbcommon-x11-0 libxcursor1 libxi6 libxrandr2 libx11-xcb1)"
                    .into(),
            )
        })?
        .map_err(|e| ViewError::Display(os_message(&e)))?;
    // Each drawn frame requests the next, so waiting for events costs no frames, and a
    // minimised window (nothing to draw) does not spin.
    event_loop.set_control_flow(ControlFlow::Wait);
    let mut app = App::new(setup, table);
    let result = event_loop.run_app(&mut app);
    if let Some(error) = app.error.take() {
        return Err(error);
    }
    result.map_err(|e| ViewError::Display(os_message(&e)))?;
    let Some(graphics) = &app.graphics else {
        return Err(ViewError::Display(
            "the event loop ended before a window was created".into(),
        ));
    };
    Ok(ViewSummary {
        adapter: graphics.gpu.adapter.to_string(),
        frames: app.stats.frames(),
        median_frame_ms: app.stats.median_interval(),
        median_gpu_ms: app.stats.median_gpu(),
        edit: app.editing.as_ref().map(|editing| super::EditSummary {
            timings: editing.timings.clone(),
            failed_steps: editing.failures,
        }),
    })
}

struct App {
    setup: Setup,
    /// The first fabric's table, read before the window opens, until the window's device
    /// has it.
    first_table: Option<TableFile>,
    orbit: OrbitControl,
    light: LightControl,
    stats: FrameStats,
    /// The evaluators key V cycles through (+ and − replace the one shown by its finer or
    /// coarser setting).
    evaluators: Vec<Arc<dyn Evaluator>>,
    /// The index in `evaluators` of the one shown.
    evaluator: usize,
    /// Whether the environment light is on (there is one and key E has not switched it off).
    environment_on: bool,
    /// The environment's rotation about +y, degrees (keys `[` and `]`).
    environment_rotation_deg: f64,
    current: usize,
    shift: bool,
    dragging: bool,
    cursor: Option<(f64, f64)>,
    last_frame: Option<Instant>,
    last_title: Instant,
    graphics: Option<Graphics>,
    /// `view --edit`: the editor, once the window's device exists.
    editing: Option<edit::Editing>,
    error: Option<ViewError>,
}

impl App {
    fn new(setup: Setup, table: Option<TableFile>) -> Self {
        Self {
            orbit: OrbitControl::new(setup.scene.camera),
            light: LightControl::new(&setup.scene.lights),
            stats: FrameStats::default(),
            evaluators: setup.evaluators.clone(),
            evaluator: 0,
            environment_on: setup.environment.is_some(),
            environment_rotation_deg: 0.0,
            current: setup.first,
            shift: false,
            dragging: false,
            cursor: None,
            last_frame: None,
            last_title: Instant::now(),
            graphics: None,
            editing: None,
            error: None,
            first_table: table,
            setup,
        }
    }

    fn fail(&mut self, event_loop: &ActiveEventLoop, error: ViewError) {
        if self.error.is_none() {
            self.error = Some(error);
        }
        event_loop.exit();
    }

    /// The spelling of the evaluator shown (`table`, `paper:32`, `resonant:6/5/2`).
    fn shown_spelling(&self) -> String {
        self.evaluators[self.evaluator].spelling()
    }

    /// The window, surface, device and renderer, showing the first fabric by lookup.
    fn create_graphics(&mut self, event_loop: &ActiveEventLoop) -> Result<Graphics, ViewError> {
        let size = match self.setup.edit {
            Some(_) => EDIT_WINDOW_SIZE,
            None => WINDOW_SIZE,
        };
        let attributes = Window::default_attributes()
            .with_title("clothbake view")
            .with_inner_size(size);
        let window = Arc::new(
            event_loop
                .create_window(attributes)
                .map_err(|e| ViewError::Display(os_message(&e)))?,
        );
        let instance = GpuContext::instance();
        let surface = instance
            .create_surface(window.clone())
            .map_err(|e| ViewError::Display(format!("cannot create a wgpu surface: {e}")))?;
        let gpu = GpuContext::with_surface(&instance, &surface)?;
        let config = surface_config(&instance, &surface, window.inner_size())?;
        println!(
            "clothbake view: adapter {}; surface {:?}, {:?}; GPU timestamps {}",
            gpu.adapter,
            config.format,
            config.present_mode,
            if gpu.timestamps() { "yes" } else { "no" }
        );
        let uncaptured = Arc::new(Mutex::new(None));
        let slot = uncaptured.clone();
        gpu.device
            .on_uncaptured_error(Arc::new(move |error: wgpu::Error| {
                if let Ok(mut slot) = slot.lock() {
                    slot.get_or_insert_with(|| error.to_string());
                }
            }));
        let environment = self
            .setup
            .environment
            .as_ref()
            .map(|split| GpuEnvironment::split(&gpu, split))
            .transpose()?;
        let mut fabrics: Vec<Option<FabricGpu>> = self.setup.fabrics.iter().map(|_| None).collect();
        let (renderer, overlay) = match self.setup.edit.take() {
            Some(setup) => {
                let samples = environment
                    .as_ref()
                    .map(|_| self.setup.scene.environment.samples);
                let opened_taps = samples.and_then(|samples| {
                    stored_fabric_taps(&self.setup.tables, setup.session.fabric(), samples)
                });
                let editor = Editor::new(
                    setup.session,
                    setup.evaluator,
                    &gpu,
                    setup.table,
                    samples,
                    opened_taps.as_ref(),
                )
                .map_err(|e| ViewError::Render(e.to_string()))?;
                let renderer = Renderer::new(
                    &gpu,
                    config.format,
                    false,
                    &self.setup.mesh,
                    editor.display().0,
                )?;
                let editing = edit::Editing::new(editor, setup.script);
                let overlay = Overlay::new(&window, &gpu, config.format, editing.scripted());
                self.editing = Some(editing);
                (renderer, Some(overlay))
            }
            None => {
                let table = self
                    .first_table
                    .take()
                    .ok_or_else(|| ViewError::Render("the first table was already used".into()))?;
                let first = FabricGpu::with_table(&gpu, table)
                    .map_err(|e| ViewError::Render(e.to_string()))?;
                let renderer = Renderer::new(
                    &gpu,
                    config.format,
                    false,
                    &self.setup.mesh,
                    first.shown[0].brdf.as_ref(),
                )?;
                fabrics[self.current] = Some(first);
                (renderer, None)
            }
        };
        let depth = depth_view(&gpu, &config);
        let timer = GpuTimer::new(&gpu);
        let graphics = Graphics {
            window,
            instance,
            surface,
            config,
            gpu,
            renderer,
            environment,
            depth,
            fabrics,
            timer,
            uncaptured,
            overlay,
        };
        graphics.configure();
        Ok(graphics)
    }

    /// Shows fabric `index` by `evaluator` (at `slot` of the list), preparing what it needs.
    /// Everything that can fail to prepare (the table, the evaluation and its GPU form, the
    /// environment's taps) is prepared before anything shown changes, so on such an error
    /// nothing changes and the message says why.
    fn show(
        &mut self,
        index: usize,
        slot: usize,
        evaluator: Arc<dyn Evaluator>,
    ) -> Result<(), ShowError> {
        let context = EvaluationContext {
            tables: self.setup.tables.clone(),
        };
        let fabric = &self.setup.fabrics[index];
        let Some(g) = &mut self.graphics else {
            return Err(ShowError::NoWindow);
        };
        let f = match &mut g.fabrics[index] {
            Some(f) => f,
            slot => {
                let file =
                    load_fabric_table(&self.setup.tables, fabric).map_err(EvaluatorError::from)?;
                slot.insert(FabricGpu::with_table(&g.gpu, file)?)
            }
        };
        let unavailable = |source| ShowError::Unavailable {
            spelling: evaluator.spelling(),
            source: Box::new(source),
        };
        let i = f
            .entry(&g.gpu, evaluator.as_ref(), fabric, &context)
            .map_err(|e| unavailable(ShowError::Evaluator(e)))?;
        let environment = match (self.environment_on, &g.environment) {
            (true, Some(map)) => {
                if f.taps.is_none() {
                    // The environment light is the table's, whatever is shown: strata of its
                    // sampler's density, each with the table's ∫F over it, read from beside
                    // the table (built and stored there on first use).
                    let path = self.setup.tables.join(fabric_table_file(&fabric.name));
                    let (taps, _) = table_taps(&path, self.setup.scene.environment.samples)
                        .map_err(|e| EvaluatorError::from(TableError::from(e)))?;
                    f.taps = Some(GpuSampleTaps::new(&g.gpu, &taps)?);
                }
                f.taps.as_ref().map(|taps| (map, taps))
            }
            _ => None,
        };
        g.renderer
            .set_brdf(&g.gpu, f.shown[i].brdf.as_ref())
            .map_err(|e| unavailable(ShowError::Gpu(e)))?;
        if let Some((map, taps)) = environment {
            g.renderer.set_environment(&g.gpu, map, taps)?;
        }
        let changed = index != self.current
            || slot != self.evaluator
            || evaluator.spelling() != self.shown_spelling();
        self.current = index;
        self.evaluator = slot;
        self.evaluators[slot] = evaluator;
        if changed {
            self.stats.clear_recent();
            self.announce();
        }
        Ok(())
    }

    /// Prints what is shown and puts it in the title at once; frame times follow with the
    /// title's next update (a slow shader may take seconds per frame).
    fn announce(&self) {
        let Some(g) = &self.graphics else { return };
        let (name, shown) = (
            &self.setup.fabrics[self.current].name,
            self.shown_spelling(),
        );
        println!(
            "clothbake view: {name}, {shown} ({})",
            g.renderer.brdf_label()
        );
        g.window
            .set_title(&controls::title(name, &shown, None, None));
    }

    /// [`App::show`], reporting a failure on stderr (the view stays as it was).
    fn show_or_report(&mut self, index: usize, slot: usize, evaluator: Arc<dyn Evaluator>) {
        if let Err(error) = self.show(index, slot, evaluator) {
            eprintln!("clothbake view: {error}");
        }
    }
}

impl ApplicationHandler for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.graphics.is_some() || self.error.is_some() {
            return;
        }
        match self.create_graphics(event_loop) {
            Ok(graphics) => {
                println!("{}", controls::KEY_HELP);
                graphics.window.request_redraw();
                self.graphics = Some(graphics);
                if self.editing.is_some() {
                    return;
                }
                // Asked for on the command line: failing to build it is an error.
                let first = self.evaluators[0].clone();
                if let Err(error) = self.show(self.current, 0, first) {
                    self.fail(event_loop, ViewError::Render(error.to_string()));
                    return;
                }
                self.announce();
            }
            Err(e) => self.fail(event_loop, e),
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        if self.error.is_some() {
            return;
        }
        if let Some(g) = &mut self.graphics
            && let Some(overlay) = &mut g.overlay
            && overlay.on_window_event(&g.window, &event)
        {
            // The panel took it (a click on it, a key typed into a field).
            g.window.request_redraw();
            return;
        }
        match event {
            WindowEvent::CloseRequested => event_loop.exit(),
            WindowEvent::Resized(size) => {
                if let Some(g) = &mut self.graphics {
                    g.resize(size);
                    g.window.request_redraw();
                }
            }
            WindowEvent::RedrawRequested => self.redraw(event_loop),
            WindowEvent::ModifiersChanged(modifiers) => {
                self.shift = modifiers.state().shift_key();
            }
            WindowEvent::KeyboardInput { event, .. } if event.state == ElementState::Pressed => {
                if let Some(action) = action_for_key(&event.logical_key, self.shift) {
                    self.handle(event_loop, action);
                }
            }
            WindowEvent::MouseInput {
                state,
                button: MouseButton::Left,
                ..
            } => self.dragging = state == ElementState::Pressed,
            WindowEvent::CursorMoved { position, .. } => {
                let now = (position.x, position.y);
                if let (true, Some(last)) = (self.dragging, self.cursor) {
                    self.orbit.drag(now.0 - last.0, now.1 - last.1);
                }
                self.cursor = Some(now);
            }
            WindowEvent::CursorLeft { .. } => self.cursor = None,
            WindowEvent::MouseWheel { delta, .. } => {
                let lines = match delta {
                    MouseScrollDelta::LineDelta(_, y) => y as f64,
                    MouseScrollDelta::PixelDelta(p) => pixels_to_lines(p.y),
                };
                self.orbit.zoom(lines);
            }
            _ => {}
        }
    }
}
