//! A bake job as the `bake` command runs it: for each fabric, choose the resolution (fixed,
//! smallest meeting an error budget, or largest within a memory budget), skip tables that
//! the manifest shows are up to date, bake, write atomically, record in the manifest.

use crate::bake::manifest::{Entry, Manifest};
use crate::bake::taps::{TapsOrigin, build_table_taps, table_taps};
use crate::bake::{BakeError, bake, bake_rows};
use crate::formats::atomic::write_atomically;
use crate::formats::fabric_toml::{FabricFileError, FabricSet};
use crate::formats::table_exr::{
    TableFileError, expected_hash, fabric_table_file, read_table, table_bytes,
};
use crate::formats::taps_file::{TableDigest, TapsFileError, taps_path, write_taps};
use crate::lighting::EnvironmentSource;
use crate::measure::accuracy::{TableError, measure};
use crate::model::Fabric;
use crate::sampling::taps::{SampleTaps, TAP_NODES};
use crate::scene::Scene;
use crate::table::{Layout, Table};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Direction pairs per set used to choose a resolution for an error budget: enough for the
/// relative RMS to be stable between seeds on the built-in fabrics (the spread:
/// docs/notebook/2026-12-07-figures-from-comments-issue-47.md), and cheap next to the bake.
pub const BUDGET_VALIDATION_PAIRS: usize = 1000;

/// How to choose each table's resolution.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ResolutionChoice {
    Fixed(u32),
    /// The smallest resolution of the layout's ladder whose relative RMS error, on uniform
    /// and on highlight pairs, is at most this.
    MaxError(f64),
    /// The largest resolution of the ladder whose texels fit in this many bytes.
    MaxBytes(u64),
}

/// One bake job.
#[derive(Clone, Debug)]
pub struct BakeJob {
    pub fabrics: Vec<Fabric>,
    pub layout: Layout,
    pub resolution: ResolutionChoice,
    pub out: PathBuf,
    /// Bake even when the manifest shows the table is up to date.
    pub force: bool,
    /// Store each table's sample taps for this many environment samples per pixel beside
    /// it (`NAME.taps`), building them where they are missing or stale; `None`: no taps.
    pub environment_samples: Option<u32>,
}

/// What a user asked to bake (the `bake` command's options), before [`BakeRequest::resolve`]
/// turns it into a [`BakeJob`] by the bake policy.
#[derive(Clone, Debug, Default)]
pub struct BakeRequest {
    /// Fabrics to bake by name; empty: every fabric of the fabric file.
    pub fabrics: Vec<String>,
    /// A scene whose fabrics, fabric file, layout and budget are used where the options
    /// below leave them open.
    pub scene: Option<Scene>,
    /// A fabric file to use instead of the scene's or the built-in fabrics.
    pub fabric_file: Option<PathBuf>,
    pub layout: Option<Layout>,
    pub resolution: Option<u32>,
    /// The largest relative RMS error accepted (uniform and highlight pairs).
    pub max_error: Option<f64>,
    pub out: PathBuf,
    pub force: bool,
    /// Environment samples per pixel of the taps stored with each table (the option's,
    /// else the scene's, else the built-in scene's).
    pub environment_samples: Option<u32>,
    /// Store no sample taps.
    pub no_taps: bool,
}

impl BakeRequest {
    /// The job the bake policy makes of this request:
    /// - fabrics: the scene's (when a scene is given) or the ones named, else every fabric of
    ///   the fabric file (the option's, else the scene's, else the built-in one);
    /// - layout: the option's, else the scene's, else [`Layout::DEFAULT`];
    /// - resolution: a fixed `resolution` wins; else the smallest meeting `max_error` (the
    ///   option's, else the scene budget's); else the largest within the scene's bytes per
    ///   fabric; else the layout's default;
    /// - sample taps: none with `no_taps`; else for the option's environment samples, else
    ///   the scene's (none when the scene has no environment light), else the built-in
    ///   scene's.
    pub fn resolve(self) -> Result<BakeJob, BakeJobError> {
        let scene = self.scene.as_ref();
        let fabric_file = self
            .fabric_file
            .or_else(|| scene.and_then(|s| s.fabric_file.clone()));
        let set = FabricSet::load_or_builtin(fabric_file.as_deref())?;
        let names = scene.map_or(&self.fabrics, |s| &s.fabrics);
        let fabrics = set.select(names)?;
        let layout = self
            .layout
            .unwrap_or_else(|| scene.map_or(Layout::DEFAULT, |s| s.layout_or(Layout::DEFAULT)));
        let budget = scene.map(|s| s.budget).unwrap_or_default();
        let resolution = match (
            self.resolution,
            self.max_error.or(budget.max_error),
            budget.max_bytes_per_fabric,
        ) {
            (Some(r), _, _) => ResolutionChoice::Fixed(r),
            (None, Some(e), _) if e.is_finite() && e > 0.0 => ResolutionChoice::MaxError(e),
            (None, Some(e), _) => return Err(BakeJobError::BadMaxError(e)),
            (None, None, Some(bytes)) => ResolutionChoice::MaxBytes(bytes),
            (None, None, None) => ResolutionChoice::Fixed(layout.default_resolution()),
        };
        let environment_samples = match (self.no_taps, self.environment_samples, scene) {
            (true, _, _) => None,
            (false, Some(samples), _) => Some(samples),
            (false, None, Some(scene)) => (scene.environment.source != EnvironmentSource::None)
                .then_some(scene.environment.samples),
            (false, None, None) => Some(Scene::builtin().environment.samples),
        };
        Ok(BakeJob {
            fabrics,
            layout,
            resolution,
            out: self.out,
            force: self.force,
            environment_samples,
        })
    }
}

/// What happened to one fabric.
#[derive(Clone, Debug)]
pub enum Outcome {
    UpToDate {
        path: PathBuf,
        entry: Entry,
        taps: Option<TapsOutcome>,
    },
    Baked {
        path: PathBuf,
        entry: Entry,
        bytes: usize,
        tried: Vec<(u32, TableError)>,
        taps: Option<TapsOutcome>,
    },
}

/// What happened to one table's sample taps.
#[derive(Clone, Debug)]
pub struct TapsOutcome {
    /// Environment samples per pixel they serve.
    pub samples: u32,
    /// Found up to date, or built (and why).
    pub origin: TapsOrigin,
    /// Seconds spent reading or building them.
    pub seconds: f64,
}

#[derive(Debug, thiserror::Error)]
pub enum BakeJobError {
    #[error(transparent)]
    Bake(#[from] BakeError),
    #[error(transparent)]
    File(#[from] TableFileError),
    #[error(transparent)]
    Fabrics(#[from] FabricFileError),
    #[error(transparent)]
    Taps(#[from] TapsFileError),
    #[error("the sample taps of {table} could not be stored: {message}", table = .table.display())]
    TapsNotStored { table: PathBuf, message: String },
    #[error("--max-error must be a positive number, got {0}")]
    BadMaxError(f64),
    #[error("cannot write to {path}: {source}")]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error(
        "fabric '{fabric}': no {layout} resolution up to {largest} meets a relative RMS error of {target} (it reaches {reached:.4})"
    )]
    BudgetUnreachable {
        fabric: String,
        layout: Layout,
        largest: u32,
        target: f64,
        reached: f64,
    },
    #[error("no {layout} resolution fits {bytes} bytes per fabric (the smallest needs {smallest})")]
    BudgetTooSmall {
        layout: Layout,
        bytes: u64,
        smallest: usize,
    },
}

fn worst(error: &TableError) -> f64 {
    error.uniform.relative_rms.max(error.highlight.relative_rms)
}

/// The manifest entry for `path` if the table there is exactly what this job would bake.
fn up_to_date(
    manifest: &Manifest,
    path: &Path,
    fabric: &Fabric,
    layout: Layout,
    choice: ResolutionChoice,
) -> Option<Entry> {
    let file_name = path.file_name()?.to_string_lossy().into_owned();
    let entry = manifest.tables.get(&file_name)?;
    let resolution_ok = match choice {
        ResolutionChoice::Fixed(r) => entry.resolution == r,
        ResolutionChoice::MaxError(e) => entry.error.is_some_and(|(u, h)| u.max(h) <= e),
        ResolutionChoice::MaxBytes(b) => layout.byte_size(fabric, entry.resolution) as u64 <= b,
    };
    let hash = expected_hash(fabric, layout, entry.resolution);
    let file_ok = read_table(path).is_ok_and(|f| f.hash == hash);
    (resolution_ok && entry.hash == hash && entry.layout == layout.name() && file_ok)
        .then(|| entry.clone())
}

/// The taps beside the up-to-date table at `path` for `samples` per pixel: read, or built
/// and stored where missing or stale ([`table_taps`]); an error where they cannot be stored.
fn stored_taps(path: &Path, samples: u32) -> Result<TapsOutcome, BakeJobError> {
    let started = Instant::now();
    let (_, origin) = table_taps(path, samples)?;
    if let TapsOrigin::Built {
        stored: Err(message),
        ..
    } = &origin
    {
        return Err(BakeJobError::TapsNotStored {
            table: path.to_path_buf(),
            message: message.clone(),
        });
    }
    Ok(TapsOutcome {
        samples,
        origin,
        seconds: started.elapsed().as_secs_f64(),
    })
}

/// Stores one baked table in the directory `out` as `bake` does: its file's bytes `exr` as
/// `NAME.exr` (`name` the fabric's), then its sample `taps` (if any) as `NAME.taps` naming
/// those bytes, then its manifest `entry` (saved at once); each file atomically. Returns the
/// table's path.
pub fn store_table(
    out: &Path,
    manifest: &mut Manifest,
    name: &str,
    exr: &[u8],
    entry: Entry,
    taps: Option<&SampleTaps>,
) -> Result<PathBuf, BakeJobError> {
    let io = |path: &Path| {
        let path = path.to_path_buf();
        move |source| BakeJobError::Io { path, source }
    };
    std::fs::create_dir_all(out).map_err(io(out))?;
    let path = out.join(fabric_table_file(name));
    write_atomically(&path, exr).map_err(io(&path))?;
    if let Some(taps) = taps {
        write_taps(&taps_path(&path), &TableDigest::of(exr), taps)?;
    }
    manifest.tables.insert(fabric_table_file(name), entry);
    manifest.save(out).map_err(io(out))?;
    Ok(path)
}

/// Makes the per-row callback of one bake from (fabric name, resolution, rows).
pub type ProgressFactory = dyn Fn(&str, u32, u64) -> Box<dyn Fn() + Sync>;

/// Removes temporaries that an interrupted bake of `file_name` left in `directory`
/// (`.NAME.exr.PID.tmp` of another process).
fn remove_stale_temporaries(directory: &Path, file_name: &str) {
    let prefix = format!(".{file_name}.");
    let ours = format!("{prefix}{}.tmp", std::process::id());
    let Ok(entries) = std::fs::read_dir(directory) else {
        return;
    };
    for entry in entries.flatten() {
        let name = entry.file_name().to_string_lossy().into_owned();
        let pid = name
            .strip_prefix(&prefix)
            .and_then(|rest| rest.strip_suffix(".tmp"));
        if pid.is_some_and(|p| !p.is_empty() && p.bytes().all(|b| b.is_ascii_digit()))
            && name != ours
        {
            let _ = std::fs::remove_file(entry.path());
        }
    }
}

/// Runs `job`; `progress(fabric, resolution, rows)` returns the per-row callback of one bake.
pub fn run(
    job: &BakeJob,
    progress: &ProgressFactory,
    on_outcome: &mut dyn FnMut(&Fabric, &Outcome),
) -> Result<(), BakeJobError> {
    std::fs::create_dir_all(&job.out).map_err(|source| BakeJobError::Io {
        path: job.out.clone(),
        source,
    })?;
    let mut manifest = Manifest::load(&job.out);
    let layout = job.layout;
    for fabric in &job.fabrics {
        let path = job.out.join(fabric_table_file(&fabric.name));
        remove_stale_temporaries(&job.out, &fabric_table_file(&fabric.name));
        if let Some(name) = taps_path(&path).file_name() {
            remove_stale_temporaries(&job.out, &name.to_string_lossy());
        }
        if !job.force
            && let Some(entry) = up_to_date(&manifest, &path, fabric, layout, job.resolution)
        {
            let taps = job
                .environment_samples
                .map(|samples| stored_taps(&path, samples))
                .transpose()?;
            on_outcome(fabric, &Outcome::UpToDate { path, entry, taps });
            continue;
        }
        let started = Instant::now();
        let bake_at = |resolution: u32| -> Result<Table, BakeError> {
            let on_row = progress(
                &fabric.name,
                resolution,
                bake_rows(fabric, layout, resolution),
            );
            bake(fabric, layout, resolution, &on_row)
        };
        let mut tried = Vec::new();
        let (table, error) = match job.resolution {
            ResolutionChoice::Fixed(r) => (bake_at(r)?, None),
            ResolutionChoice::MaxBytes(bytes) => {
                let fitting = layout
                    .resolution_ladder()
                    .into_iter()
                    .rfind(|&r| layout.byte_size(fabric, r) as u64 <= bytes);
                let r = fitting.ok_or(BakeJobError::BudgetTooSmall {
                    layout,
                    bytes,
                    smallest: layout.byte_size(fabric, layout.resolution_ladder()[0]),
                })?;
                (bake_at(r)?, None)
            }
            ResolutionChoice::MaxError(target) => {
                let mut chosen = None;
                for r in layout.resolution_ladder() {
                    let table = bake_at(r)?;
                    let error = measure(&table, fabric, BUDGET_VALIDATION_PAIRS);
                    tried.push((r, error));
                    if worst(&error) <= target {
                        chosen = Some((table, Some(error)));
                        break;
                    }
                }
                chosen.ok_or_else(|| BakeJobError::BudgetUnreachable {
                    fabric: fabric.name.clone(),
                    layout,
                    largest: *layout.resolution_ladder().last().unwrap_or(&0),
                    target,
                    reached: tried
                        .iter()
                        .map(|(_, e)| worst(e))
                        .fold(f64::INFINITY, f64::min),
                })?
            }
        };
        let (exr, hash) = table_bytes(&table, &path)?;
        let bake_seconds = started.elapsed().as_secs_f64();
        let taps = match job.environment_samples {
            Some(samples) => {
                let started = Instant::now();
                let label = format!("{} sample taps", fabric.name);
                let on_node = progress(&label, samples, TAP_NODES as u64);
                let taps = build_table_taps(&table, samples, &on_node).ok_or_else(|| {
                    BakeError::Cancelled {
                        fabric: fabric.name.clone(),
                    }
                })?;
                Some((taps, started.elapsed().as_secs_f64()))
            }
            None => None,
        };
        let entry = Entry {
            hash,
            layout: layout.name().to_string(),
            resolution: table.resolution,
            bake_seconds,
            threads: rayon::current_num_threads(),
            error: error.map(|e| (e.uniform.relative_rms, e.highlight.relative_rms)),
        };
        let stored = store_table(
            &job.out,
            &mut manifest,
            &fabric.name,
            &exr,
            entry.clone(),
            taps.as_ref().map(|(taps, _)| taps),
        )?;
        let taps = taps.map(|(taps, seconds)| TapsOutcome {
            samples: taps.samples(),
            origin: TapsOrigin::Built {
                path: taps_path(&path),
                reason: Some("the table was baked".into()),
                stored: Ok(()),
            },
            seconds,
        });
        on_outcome(
            fabric,
            &Outcome::Baked {
                path: stored,
                entry,
                bytes: table.byte_size(),
                tried,
                taps,
            },
        );
    }
    Ok(())
}
