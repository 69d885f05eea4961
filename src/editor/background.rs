//! The bake behind the editor: one fabric baked on a worker thread with a rayon pool of its
//! own, so that the thread that draws frames only ever asks how far it got
//! ([`BackgroundBake::progress`]) and whether it is done ([`BackgroundBake::poll`]); the
//! next edit cancels it ([`BackgroundBake::cancel`], also on drop).
//!
//! A finished bake is what `clothbake bake` makes of the same fabric, layout and resolution:
//! the table and its file's bytes (the same writer, so the same bytes), the table's error as
//! the bake job measures it for an error budget, and the sample taps the environment light
//! needs; [`write_baked`] stores it in a tables directory as `bake` would.
//!
//! Stages, in order: the bake's rows, the file's bytes, the error, the taps. Each checks for
//! cancellation: the bake before each row and the taps before each node, so a cancelled
//! bake's thread ends within about one row or node per worker; the error's measurement runs
//! to its end once started.

use crate::bake::job::{BUDGET_VALIDATION_PAIRS, BakeJobError, store_table};
use crate::bake::manifest::{Entry, Manifest};
use crate::bake::taps::build_table_taps;
use crate::bake::{BakeError, BakeProgress, bake, bake_rows};
use crate::formats::table_exr::{TableFileError, fabric_table_file, table_bytes};
use crate::measure::accuracy::{TableError, measure};
use crate::model::Fabric;
use crate::sampling::taps::{SampleTaps, TAP_NODES};
use crate::table::{Layout, Table};
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU8, AtomicU64, Ordering};
use std::sync::mpsc::{Receiver, TryRecvError, channel};
use std::thread::JoinHandle;
use std::time::Instant;

/// A finished background bake.
#[derive(Clone, Debug)]
pub struct BakedTable {
    pub fabric: Fabric,
    pub table: Table,
    /// The table file's bytes, exactly as `clothbake bake` writes them.
    pub exr: Vec<u8>,
    /// The provenance hash the file records (what the bake manifest keys on).
    pub hash: String,
    /// The table's error against the direct evaluation as the bake job measures it
    /// (relative RMS and more on [`BUDGET_VALIDATION_PAIRS`] uniform and highlight pairs).
    pub error: TableError,
    /// The environment light's sample taps, when asked for.
    pub taps: Option<SampleTaps>,
    /// Seconds from the start to the file's bytes (the bake manifest's bake time).
    pub bake_seconds: f64,
    /// Seconds measuring the error.
    pub measure_seconds: f64,
    /// Seconds building the taps (0 without).
    pub taps_seconds: f64,
    /// Worker threads of the bake's pool.
    pub threads: usize,
}

/// Why a background bake gave no table.
#[derive(Debug, thiserror::Error)]
pub enum BackgroundError {
    #[error("the background bake was cancelled")]
    Cancelled,
    #[error(transparent)]
    Bake(BakeError),
    #[error(transparent)]
    File(#[from] TableFileError),
    #[error("the background bake could not start its threads: {0}")]
    Threads(String),
    #[error("the background bake's worker thread stopped without a result")]
    Worker,
}

impl From<BakeError> for BackgroundError {
    fn from(error: BakeError) -> Self {
        match error {
            BakeError::Cancelled { .. } => Self::Cancelled,
            other => Self::Bake(other),
        }
    }
}

/// What a background bake is doing.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stage {
    /// Baking the table's rows.
    Baking,
    /// Writing the file's bytes and measuring the table's error.
    Measuring,
    /// Building the sample taps.
    Taps,
    /// Finished, cancelled or failed.
    Done,
}

/// Shares of the progress bar by stage (baking, measuring, taps), in proportion to the
/// stages' summed times over the built-in fabrics at the default layout and resolution
/// with taps for the default scene (`examples/background_bake_stages.rs`,
/// docs/notebook/2026-12-07-taps-with-the-table.md); without taps the first two share it.
const STAGE_SHARES: [f32; 3] = [0.6, 0.02, 0.38];

/// The state the worker updates and the owner reads.
struct Shared {
    cancelled: AtomicBool,
    stage: AtomicU8,
    rows: AtomicU64,
    nodes: AtomicU64,
}

/// A [`BakeProgress`] counting into one of the shared counters.
struct Counter<'a> {
    shared: &'a Shared,
    count: &'a AtomicU64,
}

impl BakeProgress for Counter<'_> {
    fn row_done(&self) {
        self.count.fetch_add(1, Ordering::Relaxed);
    }
    fn cancelled(&self) -> bool {
        self.shared.cancelled.load(Ordering::Relaxed)
    }
}

/// One fabric baking on a worker thread (module doc).
pub struct BackgroundBake {
    shared: Arc<Shared>,
    total_rows: u64,
    taps: bool,
    threads: usize,
    receiver: Receiver<Result<BakedTable, BackgroundError>>,
    worker: Option<JoinHandle<()>>,
    /// A result that came before the worker could start.
    early: Option<Result<BakedTable, BackgroundError>>,
}

/// Worker threads a background bake uses by default: every core but one, which stays with
/// the window, and at least one.
pub fn default_threads() -> usize {
    std::thread::available_parallelism()
        .map_or(1, |n| n.get())
        .saturating_sub(1)
        .max(1)
}

impl BackgroundBake {
    /// Starts baking `fabric` as `clothbake bake` would by default ([`Layout::DEFAULT`] at
    /// its default resolution), with taps for `environment_samples` per pixel if given.
    pub fn start_default(fabric: Fabric, environment_samples: Option<u32>) -> Self {
        let layout = Layout::DEFAULT;
        Self::start(
            fabric,
            layout,
            layout.default_resolution(),
            environment_samples,
        )
    }

    /// Starts baking `fabric` into a table of `layout` at `resolution` on
    /// [`default_threads`] worker threads; with `environment_samples`, its sample taps for
    /// that many samples per pixel too. Returns at once.
    pub fn start(
        fabric: Fabric,
        layout: Layout,
        resolution: u32,
        environment_samples: Option<u32>,
    ) -> Self {
        Self::start_with_threads(
            fabric,
            layout,
            resolution,
            environment_samples,
            default_threads(),
        )
    }

    /// [`Self::start`] on `threads` worker threads (at least one).
    pub fn start_with_threads(
        fabric: Fabric,
        layout: Layout,
        resolution: u32,
        environment_samples: Option<u32>,
        threads: usize,
    ) -> Self {
        let threads = threads.max(1);
        let shared = Arc::new(Shared {
            cancelled: AtomicBool::new(false),
            stage: AtomicU8::new(Stage::Baking as u8),
            rows: AtomicU64::new(0),
            nodes: AtomicU64::new(0),
        });
        // A resolution out of range is the bake's error to report; no rows to count then.
        let total_rows = if (2..=layout.max_resolution()).contains(&resolution) {
            bake_rows(&fabric, layout, resolution).max(1)
        } else {
            1
        };
        let (sender, receiver) = channel();
        let worker_shared = Arc::clone(&shared);
        let spawned = std::thread::Builder::new()
            .name("clothbake-background-bake".into())
            .spawn(move || {
                let pool = rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .thread_name(|i| format!("clothbake-background-bake-{i}"))
                    .build();
                let result = match pool {
                    Ok(pool) => pool.install(|| {
                        run(
                            &worker_shared,
                            fabric,
                            layout,
                            resolution,
                            environment_samples,
                        )
                    }),
                    Err(error) => Err(BackgroundError::Threads(error.to_string())),
                };
                worker_shared
                    .stage
                    .store(Stage::Done as u8, Ordering::Release);
                // The owner may be gone (dropped after cancelling): nobody wants the result.
                let _ = sender.send(result);
            });
        let (worker, early) = match spawned {
            Ok(handle) => (Some(handle), None),
            Err(error) => {
                shared.stage.store(Stage::Done as u8, Ordering::Release);
                (None, Some(Err(BackgroundError::Threads(error.to_string()))))
            }
        };
        Self {
            shared,
            total_rows,
            taps: environment_samples.is_some(),
            threads,
            receiver,
            worker,
            early,
        }
    }

    /// The worker threads of the bake's pool.
    pub fn threads(&self) -> usize {
        self.threads
    }

    /// What the bake is doing now.
    pub fn stage(&self) -> Stage {
        match self.shared.stage.load(Ordering::Acquire) {
            0 => Stage::Baking,
            1 => Stage::Measuring,
            2 => Stage::Taps,
            _ => Stage::Done,
        }
    }

    /// How far the bake got, from 0 to 1 (1 once it is finished): the stages' shares
    /// ([`STAGE_SHARES`]), the bake's by rows done and the taps' by nodes done. Never
    /// decreases.
    pub fn progress(&self) -> f32 {
        let [bake_share, measure_share, taps_share] = if self.taps {
            STAGE_SHARES
        } else {
            let sum = STAGE_SHARES[0] + STAGE_SHARES[1];
            [STAGE_SHARES[0] / sum, STAGE_SHARES[1] / sum, 0.0]
        };
        let fraction = |done: &AtomicU64, total: u64| {
            (done.load(Ordering::Relaxed) as f32 / total as f32).min(1.0)
        };
        let rows = fraction(&self.shared.rows, self.total_rows);
        let nodes = fraction(&self.shared.nodes, TAP_NODES as u64);
        let progress = match self.stage() {
            Stage::Baking => bake_share * rows,
            Stage::Measuring => bake_share,
            Stage::Taps => bake_share + measure_share + taps_share * nodes,
            Stage::Done => 1.0,
        };
        progress.clamp(0.0, 1.0)
    }

    /// Asks the bake to stop: the worker skips what is left and reports
    /// [`BackgroundError::Cancelled`]. Returns at once.
    pub fn cancel(&self) {
        self.shared.cancelled.store(true, Ordering::Relaxed);
    }

    /// Whether the worker thread has ended (after its result was sent).
    pub fn is_finished(&self) -> bool {
        self.worker.as_ref().is_none_or(|w| w.is_finished())
    }

    /// The result once the bake has finished, failed or been cancelled, else `None`;
    /// never blocks. The result is handed over once; later calls return `None`.
    pub fn poll(&mut self) -> Option<Result<BakedTable, BackgroundError>> {
        if let Some(result) = self.early.take() {
            return Some(result);
        }
        match self.receiver.try_recv() {
            Ok(result) => Some(result),
            Err(TryRecvError::Empty) => None,
            Err(TryRecvError::Disconnected) => {
                // Gone without a result (its thread panicked), or the result was taken.
                let panicked = self.worker.take().is_some_and(|w| w.join().is_err());
                panicked.then_some(Err(BackgroundError::Worker))
            }
        }
    }

    /// Blocks until the bake ends and returns its result (for scripts and tests); the
    /// worker thread has ended when it returns.
    pub fn wait(mut self) -> Result<BakedTable, BackgroundError> {
        let result = match self.early.take() {
            Some(result) => result,
            None => self.receiver.recv().unwrap_or(Err(BackgroundError::Worker)),
        };
        if let Some(worker) = self.worker.take() {
            // The result is sent last: the thread is ending, and a panic was reported.
            let _ = worker.join();
        }
        result
    }
}

impl Drop for BackgroundBake {
    /// Cancels the bake without waiting for its thread, which ends on its own.
    fn drop(&mut self) {
        self.cancel();
    }
}

/// The worker: every stage of the module doc in the calling thread's rayon pool.
fn run(
    shared: &Shared,
    fabric: Fabric,
    layout: Layout,
    resolution: u32,
    environment_samples: Option<u32>,
) -> Result<BakedTable, BackgroundError> {
    let started = Instant::now();
    let cancelled = || {
        if shared.cancelled.load(Ordering::Relaxed) {
            Err(BackgroundError::Cancelled)
        } else {
            Ok(())
        }
    };
    let rows = Counter {
        shared,
        count: &shared.rows,
    };
    let table = bake(&fabric, layout, resolution, &rows)?;
    shared
        .stage
        .store(Stage::Measuring as u8, Ordering::Release);
    cancelled()?;
    let (exr, hash) = table_bytes(&table, Path::new(&fabric_table_file(&fabric.name)))?;
    let bake_seconds = started.elapsed().as_secs_f64();
    cancelled()?;
    let measuring = Instant::now();
    let error = measure(&table, &fabric, BUDGET_VALIDATION_PAIRS);
    let measure_seconds = measuring.elapsed().as_secs_f64();
    let building = Instant::now();
    let taps = match environment_samples {
        Some(samples) => {
            shared.stage.store(Stage::Taps as u8, Ordering::Release);
            let nodes = Counter {
                shared,
                count: &shared.nodes,
            };
            Some(build_table_taps(&table, samples, &nodes).ok_or(BackgroundError::Cancelled)?)
        }
        None => None,
    };
    cancelled()?;
    Ok(BakedTable {
        fabric,
        table,
        exr,
        hash,
        error,
        bake_seconds,
        measure_seconds,
        taps_seconds: if taps.is_some() {
            building.elapsed().as_secs_f64()
        } else {
            0.0
        },
        taps,
        threads: rayon::current_num_threads(),
    })
}

/// Stores `baked` in the tables directory `out` as `clothbake bake` would: `NAME.exr`, its
/// `NAME.taps` when it has taps, and its entry in the bake manifest (with the measured
/// error), each written atomically. Returns the table's path.
pub fn write_baked(out: &Path, baked: &BakedTable) -> Result<PathBuf, BakeJobError> {
    let entry = Entry {
        hash: baked.hash.clone(),
        layout: baked.table.layout.name().to_string(),
        resolution: baked.table.resolution,
        bake_seconds: baked.bake_seconds,
        threads: baked.threads,
        error: Some((
            baked.error.uniform.relative_rms,
            baked.error.highlight.relative_rms,
        )),
    };
    let mut manifest = Manifest::load(out);
    store_table(
        out,
        &mut manifest,
        &baked.fabric.name,
        &baked.exr,
        entry,
        baked.taps.as_ref(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::evaluator::FabricEvaluator;
    use crate::evaluator::table::TableEvaluation;
    use crate::formats::fabric_toml::FabricSet;
    use std::time::Duration;

    fn fabric(name: &str) -> Fabric {
        FabricSet::builtin().require(name).unwrap().clone()
    }

    /// Cancelled during its rows, a bake stops within the row in flight (one worker
    /// thread), its thread ends, and it reports that it was cancelled.
    #[test]
    fn a_cancelled_bake_skips_its_remaining_rows_and_its_thread_ends() {
        let layout = Layout::DEFAULT;
        let mut bake = BackgroundBake::start_with_threads(
            fabric("velvet"),
            layout,
            layout.default_resolution(),
            Some(8),
            1,
        );
        while bake.shared.rows.load(Ordering::Relaxed) == 0 && !bake.is_finished() {
            std::thread::sleep(Duration::from_millis(1));
        }
        bake.cancel();
        let at_cancel = bake.shared.rows.load(Ordering::Relaxed);
        while !bake.is_finished() {
            std::thread::sleep(Duration::from_millis(1));
        }
        let rows = bake.shared.rows.load(Ordering::Relaxed);
        assert!(
            rows <= at_cancel + 1 && rows < bake.total_rows,
            "{rows} of {} rows done, {at_cancel} when cancelled",
            bake.total_rows
        );
        assert!(matches!(bake.poll(), Some(Err(BackgroundError::Cancelled))));
        assert!(bake.poll().is_none());
    }

    /// Progress only grows, reaches 1 with the result, and the result is what the
    /// synchronous bake, the table file writer, the bake job's measurement and the table
    /// evaluator's taps give.
    #[test]
    fn progress_grows_to_one_and_the_result_is_the_synchronous_bakes() {
        let (layout, fabric) = (Layout::DEFAULT, fabric("linen_plain"));
        let resolution = layout.resolution_ladder()[0];
        let mut background =
            BackgroundBake::start_with_threads(fabric.clone(), layout, resolution, Some(2), 2);
        let mut seen = vec![background.progress()];
        let baked = loop {
            if let Some(result) = background.poll() {
                break result.unwrap();
            }
            seen.push(background.progress());
            std::thread::sleep(Duration::from_millis(5));
        };
        seen.push(background.progress());
        assert!(seen.windows(2).all(|w| w[0] <= w[1]), "{seen:?}");
        assert!(seen[0] < 1.0 && *seen.last().unwrap() == 1.0, "{seen:?}");
        assert!(seen.iter().any(|&p| p > 0.0 && p < 1.0), "{seen:?}");

        let table = bake(&fabric, layout, resolution, &|| {}).unwrap();
        let (exr, hash) = table_bytes(&table, Path::new("linen_plain.exr")).unwrap();
        assert!(baked.exr == exr && baked.hash == hash);
        assert_eq!(baked.table, table);
        let error = measure(&table, &fabric, BUDGET_VALIDATION_PAIRS);
        assert_eq!(baked.error.uniform.relative_rms, error.uniform.relative_rms);
        assert_eq!(
            baked.error.highlight.relative_rms,
            error.highlight.relative_rms
        );
        let evaluation = TableEvaluation { table };
        assert_eq!(
            baked.taps.unwrap(),
            evaluation.sample_taps(&evaluation.sampler(), 2)
        );
        assert_eq!(baked.threads, 2);
    }

    /// A bad request is the bake's error, reported like any result.
    #[test]
    fn a_resolution_out_of_range_is_reported() {
        let bake = BackgroundBake::start(fabric("velvet"), Layout::DEFAULT, 1, None);
        assert!(matches!(
            bake.wait(),
            Err(BackgroundError::Bake(BakeError::Resolution { .. }))
        ));
    }
}
