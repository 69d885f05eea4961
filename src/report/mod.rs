//! `clothbake report`: speed against error, measured in one run and written as Markdown,
//! JSON and PNG plots.
//!
//! For every fabric it measures, against the direct evaluation (MODEL.md's ground truth)
//! on the seeded validation sets of [`crate::measure::direction_sets`] (through
//! [`crate::measure::accuracy::Reference`]):
//!
//! - each layout over a range of resolutions: table size, relative RMS error (uniform,
//!   highlight, both directions ≥ 15° above the horizon), CPU nanoseconds per lookup and
//!   bake time;
//! - paper mode at N samples per thread: its error and its nanoseconds per evaluation, and
//!   the direct evaluation's cost;
//! - the resonant quadrature ([`crate::model::ResonantNodes`]) at several node counts: its
//!   error, its nanoseconds per evaluation, the kernel evaluations it makes per light (both
//!   threads' tangent samples, averaged over the uniform and the highlight pairs) and its
//!   cost against paper mode's at equal error;
//! - the speed-up of a bake from one to two threads, and whether both give the same texels;
//! - a verdict per table: is it faster than paper mode at equal error and more accurate at
//!   equal cost (equivalently, is no paper-mode point at least as fast and as accurate)?
//!   And the same against every evaluation of the model measured (paper mode and the
//!   resonant quadrature), so that a table is judged against the best of them.
//!
//! The GPU section ([`gpu`]) records the adapter and what could be measured on it; without
//! an adapter it says so and measures nothing.
//!
//! Timings are medians of repeated runs ([`timing`]); CPU evaluation timings run on one
//! thread over one fixed pair set, so their ratios compare equal work.

pub mod gpu;
pub mod markdown;
pub mod plots;
pub mod timing;

use crate::bake::{BakeError, bake};
use crate::measure::accuracy::{Reference, TableError, lookup_batch_sum, lookup_f32};
use crate::measure::direction_sets::{highlight_pairs, uniform_pairs};
use crate::model::{Fabric, Integration, Patch, ResonantNodes};
use crate::table::{Layout, Table};
use glam::DVec3;
use serde::Serialize;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};
use timing::{BakeTiming, EvalTiming, pair_by_pair, time_interleaved, time_repeated};

/// Seed of the pair set every CPU timing evaluates (uniform over the hemisphere pair), apart
/// from the validation seeds so that timing and error sets are independent.
pub const TIMING_SEED: u64 = 0x5eed_0010;

/// What to measure and how often. [`ReportConfig::quick`] and [`ReportConfig::full`] are the
/// two presets of the command; tests build smaller ones.
#[derive(Clone, Debug, Serialize)]
pub struct ReportConfig {
    /// "quick", "full" or a name for a custom configuration.
    pub mode: String,
    #[serde(skip)]
    pub fabrics: Vec<Fabric>,
    /// Pairs of each validation set (uniform, highlight) on which errors are measured.
    pub error_pairs: usize,
    /// Pairs of the fixed set every CPU timing evaluates.
    pub timing_pairs: usize,
    /// Timed samples per CPU timing; the median is reported.
    pub timing_samples: usize,
    /// Shortest duration of one timed sample, seconds (several passes over the pair set
    /// when one pass is shorter).
    pub min_sample_seconds: f64,
    /// The layouts measured and their resolutions, ascending.
    pub resolutions: Vec<(Layout, Vec<u32>)>,
    /// Paper-mode sample counts N (per thread).
    pub paper_samples: Vec<u32>,
    /// Node counts of the resonant quadrature measured (surface/volume/base per segment).
    pub resonant_nodes: Vec<ResonantNodes>,
    /// Resonant node counts rendered by the resonant shader in the GPU section.
    pub gpu_resonant_nodes: Vec<ResonantNodes>,
    /// Bakes per table whose median is the bake time.
    pub bake_repetitions: usize,
    /// A bake that takes longer than this (seconds) is not repeated: it bounds the run time
    /// (grid4d at 24 takes about a minute on two cores), and the run-to-run spread of a
    /// bake that long is small next to its length.
    pub repeat_bakes_below_seconds: f64,
    /// The bake timed on one and on two threads.
    pub speedup_layout: Layout,
    pub speedup_resolution: u32,
    /// Repetitions of each of the two bakes (alternating).
    pub speedup_repetitions: usize,
    /// Whether to look for a GPU adapter at all.
    pub gpu: bool,
    /// GPU frame size (width, height) for frame timings and image errors.
    pub gpu_frame: [u32; 2],
    /// Timed GPU frames per measurement; the median is reported.
    pub gpu_frames: usize,
}

/// Paper-mode sample counts the full report compares against on the CPU: up to 1024, where
/// paper mode reaches the resonant quadrature's 0.03–0.2% (satin back needs N = 1024).
pub const PAPER_SAMPLES: [u32; 11] = [1, 2, 4, 8, 16, 32, 64, 128, 256, 512, 1024];

/// Paper-mode sample counts of `--quick`.
pub const QUICK_PAPER_SAMPLES: [u32; 7] = [1, 2, 4, 8, 16, 32, 64];

/// Largest paper-mode N rendered in the GPU section: beyond it a frame on a software
/// rasteriser takes seconds.
pub const GPU_PAPER_MAX_SAMPLES: u32 = 64;

/// Resonant node counts of the full report, cheapest first; 6/5/2 is
/// [`ResonantNodes::DEFAULT`].
pub const RESONANT_NODES: [ResonantNodes; 6] = [
    nodes(3, 2, 2),
    nodes(4, 3, 2),
    nodes(5, 4, 2),
    ResonantNodes::DEFAULT,
    nodes(8, 6, 3),
    nodes(10, 8, 4),
];

/// Resonant node counts of `--quick`: a coarse, a middle and the default point.
pub const QUICK_RESONANT_NODES: [ResonantNodes; 3] =
    [nodes(3, 2, 2), nodes(5, 3, 2), ResonantNodes::DEFAULT];

const fn nodes(surface: u32, volume: u32, base: u32) -> ResonantNodes {
    ResonantNodes {
        surface,
        volume,
        base,
    }
}

impl ReportConfig {
    /// The `--quick` preset: every fabric, fewer resolutions, pairs and repetitions (under
    /// two minutes on the 2-core development machine).
    pub fn quick(fabrics: Vec<Fabric>) -> Self {
        Self {
            mode: "quick".into(),
            fabrics,
            error_pairs: 1000,
            timing_pairs: 256,
            timing_samples: 5,
            min_sample_seconds: 0.01,
            resolutions: report_resolutions(true),
            paper_samples: QUICK_PAPER_SAMPLES.to_vec(),
            resonant_nodes: QUICK_RESONANT_NODES.to_vec(),
            gpu_resonant_nodes: vec![ResonantNodes::DEFAULT],
            bake_repetitions: 1,
            repeat_bakes_below_seconds: 0.0,
            speedup_layout: Layout::DEFAULT,
            speedup_resolution: 16,
            speedup_repetitions: 3,
            gpu: true,
            gpu_frame: [128, 128],
            gpu_frames: 3,
        }
    }

    /// The full preset: every resolution of the thread_frame ladder, grid4d up to the size
    /// of the smaller thread_frame tables, 20,000 pairs per set (as `clothbake check`), more
    /// repetitions (under thirty minutes on the 2-core development machine).
    pub fn full(fabrics: Vec<Fabric>) -> Self {
        Self {
            mode: "full".into(),
            fabrics,
            error_pairs: 20_000,
            timing_pairs: 1024,
            timing_samples: 11,
            min_sample_seconds: 0.05,
            resolutions: report_resolutions(false),
            paper_samples: PAPER_SAMPLES.to_vec(),
            resonant_nodes: RESONANT_NODES.to_vec(),
            gpu_resonant_nodes: vec![nodes(3, 2, 2), ResonantNodes::DEFAULT],
            bake_repetitions: 3,
            repeat_bakes_below_seconds: 20.0,
            speedup_layout: Layout::DEFAULT,
            speedup_resolution: 32,
            speedup_repetitions: 3,
            gpu: true,
            gpu_frame: [256, 256],
            gpu_frames: 7,
        }
    }
}

/// Every registered layout with the resolutions its unit gives the report.
fn report_resolutions(quick: bool) -> Vec<(Layout, Vec<u32>)> {
    Layout::ALL
        .iter()
        .map(|&l| (l, l.unit().report_resolutions(quick).to_vec()))
        .collect()
}

/// Errors and cost of paper mode at one N.
#[derive(Clone, Debug, Serialize)]
pub struct PaperPoint {
    pub samples: u32,
    pub error: TableError,
    pub timing: EvalTiming,
}

/// Mean kernel evaluations per light of the resonant quadrature: the tangent samples whose
/// terms both threads computed for one (wi, wo), averaged over a validation set.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct EvaluationsPerLight {
    pub uniform: f64,
    pub highlight: f64,
    /// The most any one pair of either set took.
    pub max: usize,
}

/// Errors and cost of the resonant quadrature at one set of node counts.
#[derive(Clone, Debug, Serialize)]
pub struct ResonantPoint {
    pub nodes: ResonantNodes,
    /// `nodes` as the command line spells them, "surface/volume/base".
    pub label: String,
    /// Whether these are [`ResonantNodes::DEFAULT`].
    pub default: bool,
    pub error: TableError,
    pub timing: EvalTiming,
    /// Kernel evaluations per light on the error sets (uniform and highlight pairs).
    pub evaluations_per_light: EvaluationsPerLight,
    /// The cheapest paper-mode point with an error at most this point's (None: no measured
    /// N is that accurate).
    pub paper_equal_error: Option<PaperMatch>,
    /// This point's cost over that paper-mode point's: below 1, the resonant quadrature is
    /// cheaper at equal error.
    pub cost_ratio_to_paper: Option<f64>,
}

/// One baked table: its size, errors, CPU lookup cost and bake time.
#[derive(Clone, Debug, Serialize)]
pub struct TablePoint {
    pub layout: Layout,
    pub resolution: u32,
    /// Bytes of f16 texel data.
    pub bytes: usize,
    pub error: TableError,
    /// `Table::lookup_batch` (the fast CPU path, eight pairs' coordinates at a time, RGB
    /// with the albedos applied) on one thread over the timing pairs, directions converted
    /// from f64 to f32 inside the timed call.
    pub lookup: EvalTiming,
    /// The bake on all worker threads of the report's pool.
    pub bake: BakeTiming,
}

/// The speed-up of a bake from one to two threads.
#[derive(Clone, Debug, Serialize)]
pub struct Speedup {
    pub layout: Layout,
    pub resolution: u32,
    pub one_thread: BakeTiming,
    pub two_threads: BakeTiming,
    /// Median one-thread time over median two-thread time.
    pub speedup: f64,
    /// Whether both bakes produced bit-identical texels.
    pub identical: bool,
}

/// A paper-mode point a table is compared with.
#[derive(Clone, Debug, Serialize)]
pub struct PaperMatch {
    pub samples: u32,
    pub ns_per_eval: f64,
    pub error: f64,
}

/// How a table compares with paper mode, on the worse of its uniform and highlight
/// relative RMS errors ("error") and its CPU cost per evaluation ("cost").
#[derive(Clone, Debug, Serialize)]
pub struct Verdict {
    pub layout: Layout,
    pub resolution: u32,
    pub error: f64,
    pub ns_per_eval: f64,
    /// The cheapest paper-mode point with an error at most the table's (None: no measured
    /// N is that accurate).
    pub equal_error: Option<PaperMatch>,
    /// Its cost over the table's: above 1, the table is faster at equal error.
    pub speed_ratio: Option<f64>,
    /// The most accurate paper-mode point costing at most the table's cost (None: every
    /// measured N costs more than the lookup).
    pub equal_cost: Option<PaperMatch>,
    /// Its error over the table's: above 1, the table is more accurate at equal cost.
    pub error_ratio: Option<f64>,
    /// True when no paper-mode point is both at least as accurate and at least as cheap.
    /// Then (by the choice of the two points above) the table is faster at equal error and
    /// more accurate at equal cost; otherwise paper mode dominates it.
    pub table_wins: bool,
    /// The same comparison against every evaluation of the model measured: paper mode at
    /// each N and the resonant quadrature at each node count.
    pub vs_best_evaluation: BestVerdict,
}

/// An evaluation of the model (paper mode or resonant) a table is compared with.
#[derive(Clone, Debug, Serialize)]
pub struct EvaluationMatch {
    /// "paper N = 32" or "resonant 6/5/2".
    pub evaluation: String,
    pub ns_per_eval: f64,
    pub error: f64,
}

/// How a table compares with the best evaluation of the model (paper mode or resonant):
/// the fields of [`Verdict`] over both families together.
#[derive(Clone, Debug, Serialize)]
pub struct BestVerdict {
    /// The cheapest evaluation with an error at most the table's.
    pub equal_error: Option<EvaluationMatch>,
    /// Its cost over the table's: above 1, the table is faster at equal error.
    pub speed_ratio: Option<f64>,
    /// The most accurate evaluation costing at most the table's cost.
    pub equal_cost: Option<EvaluationMatch>,
    /// Its error over the table's: above 1, the table is more accurate at equal cost.
    pub error_ratio: Option<f64>,
    /// True when no evaluation is both at least as accurate and at least as cheap.
    pub table_wins: bool,
}

/// Everything measured for one fabric.
#[derive(Clone, Debug, Serialize)]
pub struct FabricReport {
    pub name: String,
    /// The direct evaluation's cost (its error is 0 by definition).
    pub direct: EvalTiming,
    pub paper: Vec<PaperPoint>,
    /// The resonant quadrature at each node count of the configuration.
    pub resonant: Vec<ResonantPoint>,
    pub tables: Vec<TablePoint>,
    pub speedup: Speedup,
    pub verdicts: Vec<Verdict>,
    /// Wall-clock seconds this fabric's measurements took.
    pub seconds: f64,
}

/// The machine the report ran on.
#[derive(Clone, Debug, Serialize)]
pub struct Machine {
    /// `model name` of /proc/cpuinfo, where there is one.
    pub cpu_model: Option<String>,
    /// Logical cores the process may use.
    pub logical_cores: usize,
    /// Worker threads of the report's bake pool.
    pub bake_threads: usize,
    pub os: String,
    pub arch: String,
    /// The 1, 5 and 15 minute load averages (/proc/loadavg) when the run started and when
    /// it ended; they include the run's own threads (up to `bake_threads` at full use).
    pub load_average_start: Option<[f64; 3]>,
    pub load_average_end: Option<[f64; 3]>,
}

/// The whole report, as written to report.json.
#[derive(Clone, Debug, Serialize)]
pub struct Report {
    pub clothbake_version: String,
    /// `git rev-parse HEAD` of the working directory, with "-dirty" when tracked files
    /// differ from it; None outside a git checkout.
    pub git_commit: Option<String>,
    pub command_line: Vec<String>,
    /// When the run started, RFC 3339, UTC.
    pub date_utc: String,
    pub elapsed_seconds: f64,
    pub machine: Machine,
    pub config: ReportConfig,
    pub fabric_names: Vec<String>,
    pub fabrics: Vec<FabricReport>,
    pub gpu: gpu::GpuSection,
    /// Files written, relative to the output directory.
    pub files: Vec<String>,
}

/// Why a report failed.
#[derive(Debug, thiserror::Error)]
pub enum ReportError {
    #[error(transparent)]
    Bake(#[from] BakeError),
    #[error("cannot write {path}: {source}")]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("plot {file}: {message}")]
    Plot { file: String, message: String },
    #[error("{0}")]
    Config(String),
}

fn worst(error: &TableError) -> f64 {
    error.uniform.relative_rms.max(error.highlight.relative_rms)
}

/// Compares an estimate of `error` and `cost` with paper-mode points `(cost, error)`:
/// the index of the cheapest point at most as erroneous, the index of the most accurate
/// point at most as costly, and whether some point is both at most as costly and at most
/// as erroneous (then paper mode dominates the estimate).
pub fn compare_with_paper(
    error: f64,
    cost: f64,
    points: &[(f64, f64)],
) -> (Option<usize>, Option<usize>, bool) {
    let equal_error = (0..points.len())
        .filter(|&i| points[i].1 <= error)
        .min_by(|&a, &b| points[a].0.total_cmp(&points[b].0));
    let equal_cost = (0..points.len())
        .filter(|&i| points[i].0 <= cost)
        .min_by(|&a, &b| points[a].1.total_cmp(&points[b].1));
    let dominated = points.iter().any(|&(c, e)| c <= cost && e <= error);
    (equal_error, equal_cost, dominated)
}

/// Compares one table with the paper-mode points and with every evaluation, paper mode and
/// resonant (see [`Verdict`]).
pub fn verdict(table: &TablePoint, paper: &[PaperPoint], resonant: &[ResonantPoint]) -> Verdict {
    let error = worst(&table.error);
    let cost = table.lookup.ns_per_eval;
    let points: Vec<(f64, f64)> = paper
        .iter()
        .map(|p| (p.timing.ns_per_eval, worst(&p.error)))
        .collect();
    let (equal_error, equal_cost, dominated) = compare_with_paper(error, cost, &points);
    let point = |i: usize| PaperMatch {
        samples: paper[i].samples,
        ns_per_eval: points[i].0,
        error: points[i].1,
    };
    let equal_error = equal_error.map(point);
    let equal_cost = equal_cost.map(point);
    let evaluations: Vec<EvaluationMatch> = paper
        .iter()
        .zip(&points)
        .map(|(p, &(ns_per_eval, error))| EvaluationMatch {
            evaluation: format!("paper N = {}", p.samples),
            ns_per_eval,
            error,
        })
        .chain(resonant.iter().map(|r| EvaluationMatch {
            evaluation: format!("resonant {}", r.label),
            ns_per_eval: r.timing.ns_per_eval,
            error: worst(&r.error),
        }))
        .collect();
    let all: Vec<(f64, f64)> = evaluations
        .iter()
        .map(|e| (e.ns_per_eval, e.error))
        .collect();
    let (best_error, best_cost, best_dominated) = compare_with_paper(error, cost, &all);
    let best_error = best_error.map(|i| evaluations[i].clone());
    let best_cost = best_cost.map(|i| evaluations[i].clone());
    let vs_best_evaluation = BestVerdict {
        speed_ratio: best_error.as_ref().map(|e| e.ns_per_eval / cost),
        error_ratio: best_cost.as_ref().map(|e| e.error / error),
        equal_error: best_error,
        equal_cost: best_cost,
        table_wins: !best_dominated,
    };
    Verdict {
        layout: table.layout,
        resolution: table.resolution,
        error,
        ns_per_eval: cost,
        speed_ratio: equal_error.as_ref().map(|p| p.ns_per_eval / cost),
        error_ratio: equal_cost.as_ref().map(|p| p.error / error),
        equal_error,
        equal_cost,
        table_wins: !dominated,
        vs_best_evaluation,
    }
}

/// Whether two tables hold bit-identical texels.
fn identical(a: &Table, b: &Table) -> bool {
    a.planes().len() == b.planes().len()
        && a.planes().iter().zip(b.planes()).all(|(p, q)| {
            p.spec == q.spec
                && p.data.len() == q.data.len()
                && p.data
                    .iter()
                    .zip(&q.data)
                    .all(|(x, y)| x.to_bits() == y.to_bits())
        })
}

fn pool(threads: usize) -> Result<rayon::ThreadPool, ReportError> {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| ReportError::Config(format!("cannot start a thread pool: {e}")))
}

/// Measures one fabric; `keep` receives each baked table (for the GPU section).
fn measure_fabric(
    config: &ReportConfig,
    fabric: &Fabric,
    bake_pool: &rayon::ThreadPool,
    progress: &mut dyn FnMut(&str),
    keep: &mut dyn FnMut(&Table),
) -> Result<FabricReport, ReportError> {
    let name = &fabric.name;
    let started = Instant::now();
    progress(&format!(
        "{name}: direct evaluation of {} uniform and {} highlight pairs",
        config.error_pairs, config.error_pairs
    ));
    let reference = bake_pool.install(|| Reference::new(fabric, config.error_pairs));

    // Errors first (parallel), timings afterwards, all estimators interleaved.
    let papers: Vec<(u32, Patch, TableError)> = config
        .paper_samples
        .iter()
        .map(|&n| {
            let patch = Patch::new(fabric, Integration::Paper(n));
            let error = bake_pool.install(|| reference.measure(|wi, wo| patch.eval(wi, wo)));
            progress(&format!(
                "{name}: paper N = {n}: {:.2}% uniform, {:.2}% highlight",
                100.0 * error.uniform.relative_rms,
                100.0 * error.highlight.relative_rms,
            ));
            (n, patch, error)
        })
        .collect();
    let uniform_set = uniform_pairs(config.error_pairs, crate::measure::accuracy::UNIFORM_SEED);
    let highlight_set = highlight_pairs(
        fabric,
        config.error_pairs,
        crate::measure::accuracy::HIGHLIGHT_SEED,
    );
    let resonants: Vec<(ResonantNodes, Patch, TableError, EvaluationsPerLight)> = config
        .resonant_nodes
        .iter()
        .map(|&nodes| {
            let patch = Patch::new(fabric, Integration::Resonant(nodes));
            let error = bake_pool.install(|| reference.measure(|wi, wo| patch.eval(wi, wo)));
            let count = |pairs| {
                patch
                    .resonant_evaluations(pairs)
                    .expect("a resonant patch counts its evaluations")
            };
            let (uniform, max_uniform) = count(&uniform_set);
            let (highlight, max_highlight) = count(&highlight_set);
            let evaluations = EvaluationsPerLight {
                uniform,
                highlight,
                max: max_uniform.max(max_highlight),
            };
            progress(&format!(
                "{name}: resonant {nodes}: {:.3}% uniform, {:.3}% highlight, {:.1} uniform and \
                 {:.1} highlight kernel evaluations per light",
                100.0 * error.uniform.relative_rms,
                100.0 * error.highlight.relative_rms,
                uniform,
                highlight,
            ));
            (nodes, patch, error, evaluations)
        })
        .collect();
    let mut tables: Vec<(Table, TableError, BakeTiming)> = Vec::new();
    for &(layout, ref resolutions) in &config.resolutions {
        for &resolution in resolutions {
            let (table, bake_timing) = time_repeated(
                bake_pool,
                config.bake_repetitions,
                config.repeat_bakes_below_seconds,
                || bake(fabric, layout, resolution, &|| {}),
            );
            let table = table?;
            let error =
                bake_pool.install(|| reference.measure(|wi, wo| lookup_f32(&table, wi, wo)));
            progress(&format!(
                "{name}: {layout} {resolution}: {} KiB, baked in {:.2} s, {:.2}% uniform, {:.2}% highlight",
                table.byte_size() / 1024,
                bake_timing.seconds,
                100.0 * error.uniform.relative_rms,
                100.0 * error.highlight.relative_rms,
            ));
            keep(&table);
            tables.push((table, error, bake_timing));
        }
    }

    let pairs = uniform_pairs(config.timing_pairs, TIMING_SEED);
    let direct_patch = Patch::new(fabric, Integration::Direct);
    let direct_eval = pair_by_pair(|wi, wo| direct_patch.eval(wi, wo));
    let paper_evals: Vec<timing::BoxedEval> = papers
        .iter()
        .map(|(_, patch, _)| Box::new(pair_by_pair(|wi, wo| patch.eval(wi, wo))) as Box<_>)
        .collect();
    let resonant_evals: Vec<timing::BoxedEval> = resonants
        .iter()
        .map(|(_, patch, _, _)| Box::new(pair_by_pair(|wi, wo| patch.eval(wi, wo))) as Box<_>)
        .collect();
    let table_evals: Vec<timing::BoxedEval> = tables
        .iter()
        .map(|(table, _, _)| {
            Box::new(move |pairs: &[(DVec3, DVec3)]| lookup_batch_sum(table, pairs)) as Box<_>
        })
        .collect();
    let evals: Vec<timing::Eval> = std::iter::once(&direct_eval as timing::Eval)
        .chain(paper_evals.iter().map(|e| &**e as timing::Eval))
        .chain(resonant_evals.iter().map(|e| &**e as timing::Eval))
        .chain(table_evals.iter().map(|e| &**e as timing::Eval))
        .collect();
    progress(&format!(
        "{name}: timing {} evaluations on {} pairs, {} samples each",
        evals.len(),
        pairs.len(),
        config.timing_samples
    ));
    let mut timings = time_interleaved(
        &pairs,
        config.timing_samples,
        Duration::from_secs_f64(config.min_sample_seconds),
        &evals,
    )
    .into_iter();
    let direct = timings.next().expect("one timing per evaluation");
    let paper: Vec<PaperPoint> = papers
        .iter()
        .zip(timings.by_ref())
        .map(|((n, _, error), timing)| PaperPoint {
            samples: *n,
            error: *error,
            timing,
        })
        .collect();
    let paper_points: Vec<(f64, f64)> = paper
        .iter()
        .map(|p| (p.timing.ns_per_eval, worst(&p.error)))
        .collect();
    let resonant: Vec<ResonantPoint> = resonants
        .iter()
        .zip(timings.by_ref())
        .map(|((nodes, _, error, evaluations), timing)| {
            let (equal_error, _, _) =
                compare_with_paper(worst(error), timing.ns_per_eval, &paper_points);
            let paper_equal_error = equal_error.map(|i| PaperMatch {
                samples: paper[i].samples,
                ns_per_eval: paper_points[i].0,
                error: paper_points[i].1,
            });
            ResonantPoint {
                nodes: *nodes,
                label: nodes.to_string(),
                default: *nodes == ResonantNodes::DEFAULT,
                error: *error,
                cost_ratio_to_paper: paper_equal_error
                    .as_ref()
                    .map(|p| timing.ns_per_eval / p.ns_per_eval),
                paper_equal_error,
                evaluations_per_light: *evaluations,
                timing,
            }
        })
        .collect();
    let tables: Vec<TablePoint> = tables
        .iter()
        .zip(timings)
        .map(|((table, error, bake), lookup)| TablePoint {
            layout: table.layout,
            resolution: table.resolution,
            bytes: table.byte_size(),
            error: *error,
            lookup,
            bake: bake.clone(),
        })
        .collect();
    let cost = |label: String, ns: f64| format!("{label} {ns:.0}");
    let costs: Vec<String> = std::iter::once(cost("direct".into(), direct.ns_per_eval))
        .chain(
            paper
                .iter()
                .map(|p| cost(format!("N={}", p.samples), p.timing.ns_per_eval)),
        )
        .chain(
            resonant
                .iter()
                .map(|r| cost(format!("resonant {}", r.label), r.timing.ns_per_eval)),
        )
        .chain(tables.iter().map(|t| {
            cost(
                format!("{} {}", t.layout, t.resolution),
                t.lookup.ns_per_eval,
            )
        }))
        .collect();
    progress(&format!("{name}: ns/eval: {}", costs.join(", ")));

    let speedup = measure_speedup(config, fabric)?;
    progress(&format!(
        "{name}: {} {} bake: {:.2} s on 1 thread, {:.2} s on 2, speed-up {:.2}×{}",
        speedup.layout,
        speedup.resolution,
        speedup.one_thread.seconds,
        speedup.two_threads.seconds,
        speedup.speedup,
        if speedup.identical {
            ", identical texels"
        } else {
            ", TEXELS DIFFER"
        }
    ));
    let verdicts = tables
        .iter()
        .map(|t| verdict(t, &paper, &resonant))
        .collect();
    Ok(FabricReport {
        name: name.clone(),
        direct,
        paper,
        resonant,
        tables,
        speedup,
        verdicts,
        seconds: started.elapsed().as_secs_f64(),
    })
}

/// Bakes the speed-up table alternately on one and two threads.
fn measure_speedup(config: &ReportConfig, fabric: &Fabric) -> Result<Speedup, ReportError> {
    let (layout, resolution) = (config.speedup_layout, config.speedup_resolution);
    let pools = [pool(1)?, pool(2)?];
    let mut samples: [Vec<f64>; 2] = [Vec::new(), Vec::new()];
    let mut tables: [Option<Table>; 2] = [None, None];
    let mut same = true;
    for _ in 0..config.speedup_repetitions.max(1) {
        for (k, pool) in pools.iter().enumerate() {
            let started = Instant::now();
            let table = pool.install(|| bake(fabric, layout, resolution, &|| {}))?;
            samples[k].push(started.elapsed().as_secs_f64());
            match &tables[k] {
                Some(first) => same &= identical(first, &table),
                None => tables[k] = Some(table),
            }
        }
    }
    let [one, two] = tables;
    let identical = same
        && match (&one, &two) {
            (Some(a), Some(b)) => identical(a, b),
            _ => false,
        };
    let timing = |k: usize, threads: usize| BakeTiming {
        seconds: timing::median(&samples[k]),
        samples_seconds: samples[k].clone(),
        threads,
    };
    let one_thread = timing(0, 1);
    let two_threads = timing(1, 2);
    Ok(Speedup {
        layout,
        resolution,
        speedup: one_thread.seconds / two_threads.seconds,
        one_thread,
        two_threads,
        identical,
    })
}

fn load_average() -> Option<[f64; 3]> {
    let text = std::fs::read_to_string("/proc/loadavg").ok()?;
    let mut fields = text.split_whitespace().map(|f| f.parse::<f64>().ok());
    Some([fields.next()??, fields.next()??, fields.next()??])
}

fn cpu_model() -> Option<String> {
    let info = std::fs::read_to_string("/proc/cpuinfo").ok()?;
    info.lines()
        .find(|l| l.starts_with("model name"))
        .and_then(|l| l.split_once(':'))
        .map(|(_, v)| v.trim().to_string())
}

/// The commit of the working directory's git checkout, "-dirty" when tracked files differ.
fn git_commit() -> Option<String> {
    let run = |args: &[&str]| {
        std::process::Command::new("git")
            .args(args)
            .output()
            .ok()
            .filter(|o| o.status.success())
            .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
    };
    let head = run(&["rev-parse", "HEAD"]).filter(|h| !h.is_empty())?;
    let dirty =
        run(&["status", "--porcelain", "--untracked-files=no"]).is_some_and(|s| !s.is_empty());
    Some(if dirty { format!("{head}-dirty") } else { head })
}

/// Runs the report described by `config`, writing REPORT.md, report.json and the plots
/// into `out`. `progress` receives one line per finished measurement.
pub fn run(
    config: &ReportConfig,
    out: &Path,
    command_line: Vec<String>,
    progress: &mut dyn FnMut(&str),
) -> Result<Report, ReportError> {
    if config.fabrics.is_empty() {
        return Err(ReportError::Config("no fabrics to report on".into()));
    }
    if let Some(Err(e)) = config
        .resonant_nodes
        .iter()
        .chain(&config.gpu_resonant_nodes)
        .map(ResonantNodes::validate)
        .find(Result::is_err)
    {
        return Err(ReportError::Config(e));
    }
    for (layout, resolutions) in &config.resolutions {
        if let Some(&r) = resolutions
            .iter()
            .find(|&&r| !(2..=layout.max_resolution()).contains(&r))
        {
            return Err(ReportError::Config(format!(
                "{layout} resolution {r} is outside 2..={}",
                layout.max_resolution()
            )));
        }
    }
    std::fs::create_dir_all(out).map_err(|source| ReportError::Io {
        path: out.to_path_buf(),
        source,
    })?;
    let started = Instant::now();
    let load_average_start = load_average();
    let date_utc = humantime::format_rfc3339_seconds(std::time::SystemTime::now()).to_string();
    let bake_pool = pool(0)?;
    let mut fabrics = Vec::new();
    // The largest thread_frame table of each fabric, for the GPU section.
    let mut gpu_tables: Vec<Table> = Vec::new();
    for fabric in &config.fabrics {
        let mut largest: Option<Table> = None;
        let report = measure_fabric(config, fabric, &bake_pool, progress, &mut |t| {
            if t.layout == Layout::DEFAULT
                && largest.as_ref().is_none_or(|l| l.resolution < t.resolution)
            {
                largest = Some(t.clone());
            }
        })?;
        fabrics.push(report);
        gpu_tables.extend(largest);
    }
    let gpu_started = Instant::now();
    let mut gpu = if config.gpu {
        gpu::measure(config, &gpu_tables, progress)
    } else {
        gpu::GpuSection::not_requested()
    };
    gpu.seconds = gpu_started.elapsed().as_secs_f64();
    let mut report = Report {
        clothbake_version: env!("CARGO_PKG_VERSION").to_string(),
        git_commit: git_commit(),
        command_line,
        date_utc,
        elapsed_seconds: 0.0,
        machine: Machine {
            cpu_model: cpu_model(),
            logical_cores: std::thread::available_parallelism().map_or(1, |n| n.get()),
            bake_threads: bake_pool.current_num_threads(),
            os: std::env::consts::OS.to_string(),
            arch: std::env::consts::ARCH.to_string(),
            load_average_start,
            load_average_end: load_average(),
        },
        config: config.clone(),
        fabric_names: config.fabrics.iter().map(|f| f.name.clone()).collect(),
        fabrics,
        gpu,
        files: Vec::new(),
    };
    report.files = plots::write_all(&report, out)?;
    report.elapsed_seconds = started.elapsed().as_secs_f64();
    report.files.push(markdown::FILE_NAME.to_string());
    report.files.push(JSON_FILE_NAME.to_string());
    write_file(out, markdown::FILE_NAME, &markdown::render(&report))?;
    let json = serde_json::to_string_pretty(&report)
        .map_err(|e| ReportError::Config(format!("cannot serialise the report: {e}")))?;
    write_file(out, JSON_FILE_NAME, &json)?;
    Ok(report)
}

/// The JSON file's name in the output directory.
pub const JSON_FILE_NAME: &str = "report.json";

fn write_file(out: &Path, name: &str, text: &str) -> Result<(), ReportError> {
    let path = out.join(name);
    std::fs::write(&path, text).map_err(|source| ReportError::Io { path, source })
}

#[cfg(test)]
mod tests {
    use super::compare_with_paper;

    #[test]
    fn comparison_with_paper_mode_points() {
        // (cost, error) of three paper-mode points, cheaper ones less accurate.
        let points = [(100.0, 0.5), (200.0, 0.1), (400.0, 0.01)];
        // More accurate than all but the dearest, cheaper than all but the cheapest: wins.
        assert_eq!(
            compare_with_paper(0.05, 150.0, &points),
            (Some(2), Some(0), false)
        );
        // Point 1 is cheaper and more accurate: paper mode dominates.
        assert_eq!(
            compare_with_paper(0.2, 250.0, &points),
            (Some(1), Some(1), true)
        );
        // Cheaper than every point and more accurate than none.
        assert_eq!(
            compare_with_paper(0.9, 50.0, &points),
            (Some(0), None, false)
        );
        // More accurate than every point.
        assert_eq!(
            compare_with_paper(0.001, 500.0, &points),
            (None, Some(2), false)
        );
    }
}
