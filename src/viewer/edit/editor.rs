//! What `view --edit` shows of the fabric being edited, and when it changes: the model's GPU
//! form updated in place on every edit, the table baked in the background once the edits
//! stop, the plots recomputed off the window's thread.

use crate::editor::background::{BackgroundBake, BakedTable};
use crate::editor::plots::{BrdfPlots, PlotSettings};
use crate::editor::script::{Compare, Shading};
use crate::editor::session::EditSession;
use crate::evaluator::table::TableEvaluation;
use crate::evaluator::{EvaluationContext, Evaluator, EvaluatorError, FabricEvaluator};
use crate::gpu::{GpuBrdf, GpuContext, GpuError, GpuSampleTaps};
use crate::model::Fabric;
use crate::sampling::taps::SampleTaps;
use crate::table::Layout;
use std::sync::Arc;
use std::sync::mpsc::{Receiver, TryRecvError, channel};
use std::time::{Duration, Instant};

/// How long the edits must stop before the table of the edited fabric is baked: a slider
/// dragged across its range should start one bake, not one per frame.
pub const BAKE_AFTER_EDITS_STOP: Duration = Duration::from_millis(400);

/// A GPU form and the fabric it shades.
struct Form {
    brdf: Box<dyn GpuBrdf>,
    fabric: Fabric,
}

/// A baked table of the edited fabric, on the GPU.
pub struct Baked {
    pub table: BakedTable,
    brdf: Box<dyn GpuBrdf>,
    /// The environment light's taps of this table, uploaded (when the scene has one).
    pub taps: Option<GpuSampleTaps>,
}

/// The plots being computed for a fabric.
struct PlotsJob {
    fabric: Fabric,
    result: Receiver<Result<BrdfPlots, String>>,
}

/// The edited fabric's state on the GPU and in the background.
pub struct Editor {
    pub session: EditSession,
    /// The model evaluator the edited fabric is shaded by.
    evaluator: Arc<dyn Evaluator>,
    edited: Form,
    saved: Form,
    pub baked: Option<Baked>,
    bake: Option<BackgroundBake>,
    bake_due: Option<Instant>,
    /// Why the last bake failed, for the panel.
    pub bake_error: Option<String>,
    /// What shades the drape (its left half when comparing).
    pub shown: Shading,
    /// What shades the right half.
    pub compare: Compare,
    /// The plots of the edited fabric (of an earlier edit while new ones are computed).
    pub plots: Option<BrdfPlots>,
    plots_job: Option<PlotsJob>,
    pub plot_settings: PlotSettings,
    pub plots_error: Option<String>,
    layout: Layout,
    resolution: u32,
    environment_samples: Option<u32>,
    /// Set when what shades the drape changed since the renderer last took it.
    pub display_changed: bool,
    /// Set when the environment's taps changed since the renderer last took them.
    pub taps_changed: bool,
    /// The opened fabric's taps as stored beside its table, uploaded: the environment light
    /// until the first bake brings the edited fabric's own.
    opened_taps: Option<GpuSampleTaps>,
    /// When the edit not yet shown by a frame was made.
    pub edit_at: Option<Instant>,
}

/// Why the editor could not prepare a fabric's GPU form.
#[derive(Debug, thiserror::Error)]
pub enum EditorError {
    #[error(transparent)]
    Evaluator(#[from] EvaluatorError),
    #[error(transparent)]
    Gpu(#[from] GpuError),
}

impl Editor {
    /// The editor of `session`, shading by `evaluator`'s GPU form (which updates in place,
    /// [`GpuBrdf::update_fabric`], or is rebuilt per edit where it cannot) and baking
    /// tables of `layout` at `resolution`, with taps for `environment_samples`;
    /// `opened_taps` are the opened fabric's, where they were stored with its table.
    pub fn new(
        session: EditSession,
        evaluator: Arc<dyn Evaluator>,
        gpu: &GpuContext,
        (layout, resolution): (Layout, u32),
        environment_samples: Option<u32>,
        opened_taps: Option<&SampleTaps>,
    ) -> Result<Self, EditorError> {
        let opened_taps = opened_taps
            .map(|taps| GpuSampleTaps::new(gpu, taps))
            .transpose()?;
        let edited = Form::new(evaluator.as_ref(), session.fabric(), gpu)?;
        let saved = Form::new(evaluator.as_ref(), session.saved(), gpu)?;
        let mut editor = Self {
            session,
            evaluator,
            edited,
            saved,
            baked: None,
            bake: None,
            // The opened fabric's table is baked at once.
            bake_due: Some(Instant::now()),
            bake_error: None,
            shown: Shading::Edited,
            compare: Compare::Off,
            plots: None,
            plots_job: None,
            plot_settings: PlotSettings::default(),
            plots_error: None,
            layout,
            resolution,
            environment_samples,
            display_changed: true,
            taps_changed: opened_taps.is_some(),
            opened_taps,
            edit_at: None,
        };
        editor.start_plots();
        Ok(editor)
    }

    /// The spelling of the model evaluator the edits are shaded by.
    pub fn evaluator_spelling(&self) -> String {
        self.evaluator.spelling()
    }

    /// Brings the GPU forms, the bake and the plots up to the session's fabric and takes
    /// what the background finished. Never waits on the bake or the plots.
    pub fn update(&mut self, gpu: &GpuContext) -> Result<(), EditorError> {
        let fabric = self.session.fabric().clone();
        if self.edited.fabric != fabric {
            self.edited.refresh(self.evaluator.as_ref(), &fabric, gpu)?;
            self.edit_at.get_or_insert_with(Instant::now);
            if self.shown == Shading::Table {
                self.shown = Shading::Edited;
            }
            // A bake of the fabric before this edit is of no use now.
            self.bake = None;
            self.bake_due = Some(Instant::now() + BAKE_AFTER_EDITS_STOP);
            self.display_changed = true;
            self.start_plots();
        }
        let saved = self.session.saved().clone();
        if self.saved.fabric != saved {
            self.saved.refresh(self.evaluator.as_ref(), &saved, gpu)?;
            self.display_changed = true;
        }
        self.poll_bake(gpu);
        self.poll_plots();
        Ok(())
    }

    /// Asks every bake from now on for the environment light's taps at `samples` per pixel
    /// (an environment was loaded): the fabric's table is baked again at once, with them.
    pub fn want_taps(&mut self, samples: u32) {
        if self.environment_samples == Some(samples) {
            return;
        }
        self.environment_samples = Some(samples);
        self.bake = None;
        self.bake_due = Some(Instant::now());
    }

    /// The environment light's taps: the last baked table's, else the opened fabric's.
    pub fn environment_taps(&self) -> Option<&GpuSampleTaps> {
        self.baked
            .as_ref()
            .and_then(|baked| baked.taps.as_ref())
            .or(self.opened_taps.as_ref())
    }

    /// Whether the baked table is of the fabric as it is now.
    pub fn table_is_current(&self) -> bool {
        self.baked
            .as_ref()
            .is_some_and(|baked| &baked.table.fabric == self.session.fabric())
    }

    /// The bake in progress: its share done, in [0, 1].
    pub fn bake_progress(&self) -> Option<f32> {
        self.bake.as_ref().map(BackgroundBake::progress)
    }

    /// Whether a bake is waiting for the edits to stop or running.
    pub fn baking(&self) -> bool {
        self.bake.is_some() || self.bake_due.is_some()
    }

    fn poll_bake(&mut self, gpu: &GpuContext) {
        if let Some(due) = self.bake_due
            && Instant::now() >= due
        {
            self.bake_due = None;
            self.bake_error = None;
            self.bake = Some(BackgroundBake::start(
                self.session.fabric().clone(),
                self.layout,
                self.resolution,
                self.environment_samples,
            ));
        }
        let Some(bake) = &mut self.bake else { return };
        let Some(result) = bake.poll() else { return };
        self.bake = None;
        let table = match result {
            Ok(table) => table,
            Err(e) => {
                self.bake_error = Some(e.to_string());
                return;
            }
        };
        match Baked::new(table, gpu) {
            Ok(baked) => {
                let current = &baked.table.fabric == self.session.fabric();
                self.taps_changed = baked.taps.is_some();
                self.baked = Some(baked);
                if current {
                    // The view switches to the table when it shows the fabric as it is.
                    self.shown = Shading::Table;
                    self.display_changed = true;
                }
            }
            Err(e) => self.bake_error = Some(e.to_string()),
        }
    }

    fn start_plots(&mut self) {
        let fabric = self.session.fabric().clone();
        let settings = self.plot_settings.clone();
        let (send, result) = channel();
        let job_fabric = fabric.clone();
        // A thread per recomputation; an outdated one finishes unobserved.
        std::thread::spawn(move || {
            let plots = BrdfPlots::compute(&job_fabric, &settings).map_err(|e| e.to_string());
            let _ = send.send(plots);
        });
        self.plots_job = Some(PlotsJob { fabric, result });
    }

    fn poll_plots(&mut self) {
        let Some(job) = &self.plots_job else { return };
        match job.result.try_recv() {
            Err(TryRecvError::Empty) => {}
            Err(TryRecvError::Disconnected) => {
                self.plots_error = Some("the plots' computation ended without a result".into());
                self.plots_job = None;
            }
            Ok(result) => {
                if &job.fabric == self.session.fabric() {
                    match result {
                        Ok(plots) => {
                            self.plots = Some(plots);
                            self.plots_error = None;
                        }
                        Err(e) => self.plots_error = Some(e),
                    }
                }
                self.plots_job = None;
            }
        }
    }

    /// Recomputes the plots (after their settings changed).
    pub fn replot(&mut self) {
        self.start_plots();
    }

    /// Whether the plots of the fabric as it is now are still being computed.
    pub fn plotting(&self) -> bool {
        self.plots_job.is_some()
    }

    /// Waits for the bake of the fabric as it is now, if one is due or running (a script's
    /// `wait-bake`): starts it at once rather than after the edits' pause.
    pub fn bake_now(&mut self) {
        if self.bake_due.is_some() {
            self.bake_due = Some(Instant::now());
        }
    }

    /// The BRDF shading the drape's left half (all of it unless comparing) and the right
    /// half's, by [`Editor::shown`] and [`Editor::compare`]; the table where there is none
    /// current falls back to the edited fabric's model.
    pub fn display(&self) -> (&dyn GpuBrdf, Option<&dyn GpuBrdf>) {
        let table = self
            .baked
            .as_ref()
            .filter(|_| self.table_is_current())
            .map(|baked| baked.brdf.as_ref());
        let left = match self.shown {
            Shading::Edited => self.edited.brdf.as_ref(),
            Shading::Table => table.unwrap_or(self.edited.brdf.as_ref()),
            Shading::Saved => self.saved.brdf.as_ref(),
        };
        let right = match self.compare {
            Compare::Off => None,
            Compare::Table => table,
            Compare::Saved => Some(self.saved.brdf.as_ref()),
        };
        (left, right)
    }

    /// The shown BRDF's name for the title and the panel.
    pub fn display_label(&self) -> String {
        let (left, right) = self.display();
        match right {
            Some(right) => format!("{} | {}", left.label(), right.label()),
            None => left.label(),
        }
    }
}

impl Form {
    fn new(
        evaluator: &dyn Evaluator,
        fabric: &Fabric,
        gpu: &GpuContext,
    ) -> Result<Self, EditorError> {
        let context = EvaluationContext::default();
        Ok(Self {
            brdf: evaluator.prepare(fabric, &context)?.gpu(gpu)?,
            fabric: fabric.clone(),
        })
    }

    /// Shades `fabric` from now on: in place where the form can, else by a new form.
    fn refresh(
        &mut self,
        evaluator: &dyn Evaluator,
        fabric: &Fabric,
        gpu: &GpuContext,
    ) -> Result<(), EditorError> {
        if !self.brdf.update_fabric(gpu, fabric)? {
            *self = Self::new(evaluator, fabric, gpu)?;
        }
        self.fabric = fabric.clone();
        Ok(())
    }
}

impl Baked {
    fn new(table: BakedTable, gpu: &GpuContext) -> Result<Self, EditorError> {
        let evaluation = TableEvaluation {
            table: table.table.clone(),
        };
        let brdf = evaluation.gpu(gpu)?;
        let taps = table
            .taps
            .as_ref()
            .map(|taps| GpuSampleTaps::new(gpu, taps))
            .transpose()?;
        Ok(Self { table, brdf, taps })
    }
}
