//! `clothbake report`: speed against error, measured in one run and written as Markdown,
//! JSON and PNG plots.
//!
//! For every fabric it measures, against the direct evaluation (the ground truth, docs/model.md)
//! on the seeded validation sets of [`crate::measure::direction_sets`] (through
//! [`crate::measure::accuracy::Reference`]):
//!
//! - each layout over a range of resolutions: table size, relative RMS error (uniform,
//!   highlight, both directions ≥ 15° above the horizon), CPU nanoseconds per lookup and
//!   bake time;
//! - every evaluator of the registry that says what the report measures of it
//!   ([`crate::evaluator::ReportPlan`]) at each of its spellings, measured through its unit
//!   ([`crate::evaluator::Evaluator::prepare`]): its error, its nanoseconds per evaluation,
//!   the kernel evaluations it makes per light where it counts them (both threads' tangent
//!   samples, averaged over the uniform and the highlight pairs), and the direct
//!   evaluation's cost;
//! - the speed-up of a bake from one to two threads, and whether both give the same texels;
//! - one comparison rule for every point ([`Comparison`], [`dominance`]): every point against
//!   the baseline unit (the one whose plan says so: is it faster at equal error and more
//!   accurate at equal cost, equivalently is no baseline point at least as fast and as
//!   accurate?), and every table against every evaluation of the model measured, so that a
//!   table is judged against the best of them.
//!
//! The GPU section ([`gpu`]) records the adapter and what could be measured on it; without
//! an adapter it says so and measures nothing.
//!
//! Timings are medians of repeated runs ([`timing`]); CPU evaluation timings run on one
//! thread over one fixed pair set, so their ratios compare equal work.
//!
//! REPORT.md is rendered from the [`Report`] alone ([`markdown::render`]): its "Which table
//! or evaluation to pick" ([`pick`]) and its error budgets are computed from the figures, so
//! [`rerender`] rewrites the page from report.json without measuring anything.

mod evaluation;
mod files;
mod format;
pub mod gpu;
pub mod markdown;
mod measure;
pub mod pick;
pub mod plots;
mod provenance;
mod section;
pub mod stock;
mod summary;
pub mod timing;

pub use evaluation::{Evaluation, baseline_unit, default_spelling, planned_units};
pub use files::{JSON_FILE_NAME, read, rerender};
pub use measure::run;
pub use section::run_stock;

use crate::bake::BakeError;
use crate::evaluator::{EVALUATORS, EvaluatorError, EvaluatorUnit, ReportPlan};
use crate::measure::accuracy::TableError;
use crate::model::Fabric;
use crate::table::Layout;
use serde::{Deserialize, Serialize};
use std::path::PathBuf;
use timing::{BakeTiming, EvalTiming};

/// Seed of the pair set every CPU timing evaluates (uniform over the hemisphere pair), apart
/// from the validation seeds so that timing and error sets are independent.
pub const TIMING_SEED: u64 = 0x5eed_0010;

/// What to measure and how often. [`ReportConfig::quick`] and [`ReportConfig::full`] are the
/// two presets of the command; tests build smaller ones.
#[derive(Clone, Debug, Serialize, Deserialize)]
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
    /// The evaluators measured on the CPU, by spelling (`crate::evaluator::parse`), in the
    /// order measured: every unit's [`ReportPlan`] in registry order. A report.json written
    /// before the spellings were recorded leaves this empty, and [`read`] derives it from
    /// the points.
    #[serde(default)]
    pub evaluators: Vec<String>,
    /// The evaluators whose GPU forms the GPU section renders, by spelling (read as
    /// `evaluators` is).
    #[serde(default)]
    pub gpu_evaluators: Vec<String>,
    /// Bakes per table whose median is the bake time.
    pub bake_repetitions: usize,
    /// A bake that takes longer than this (seconds) is not repeated: it bounds the run time
    /// (the largest tables take the longest), and the run-to-run spread of a bake that long
    /// is small next to its length.
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
    /// The section "Every engine's stock model" ([`stock`]), or None to leave it out (and
    /// out of report.json, which a run before the section wrote without it).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stock: Option<stock::StockConfig>,
}

impl ReportConfig {
    /// The `--quick` preset: every fabric, fewer resolutions, pairs and repetitions (minutes
    /// where the full preset takes tens of minutes).
    pub fn quick(fabrics: Vec<Fabric>) -> Self {
        Self {
            mode: "quick".into(),
            fabrics,
            error_pairs: 1000,
            timing_pairs: 256,
            timing_samples: 5,
            min_sample_seconds: 0.01,
            resolutions: report_resolutions(true),
            evaluators: planned_spellings(true, ReportPlan::cpu),
            gpu_evaluators: planned_spellings(true, ReportPlan::gpu),
            bake_repetitions: 1,
            repeat_bakes_below_seconds: 0.0,
            speedup_layout: Layout::DEFAULT,
            speedup_resolution: 16,
            speedup_repetitions: 3,
            gpu: true,
            gpu_frame: [128, 128],
            gpu_frames: 3,
            stock: Some(stock::StockConfig::quick()),
        }
    }

    /// The full preset: every layout's report resolutions, 20,000 pairs per set (as
    /// `clothbake check`), more repetitions.
    pub fn full(fabrics: Vec<Fabric>) -> Self {
        Self {
            mode: "full".into(),
            fabrics,
            error_pairs: 20_000,
            timing_pairs: 1024,
            timing_samples: 11,
            min_sample_seconds: 0.05,
            resolutions: report_resolutions(false),
            evaluators: planned_spellings(false, ReportPlan::cpu),
            gpu_evaluators: planned_spellings(false, ReportPlan::gpu),
            bake_repetitions: 3,
            repeat_bakes_below_seconds: 20.0,
            speedup_layout: Layout::DEFAULT,
            speedup_resolution: 32,
            speedup_repetitions: 3,
            gpu: true,
            gpu_frame: [256, 256],
            gpu_frames: 7,
            stock: Some(stock::StockConfig::full()),
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

/// The spellings every unit's [`ReportPlan`] names for a run (`quick` or full), in
/// registry order; `which` picks the CPU or the GPU list.
fn planned_spellings(
    quick: bool,
    which: fn(&ReportPlan, bool) -> &'static [&'static str],
) -> Vec<String> {
    planned_units()
        .flat_map(|(_, plan)| which(&plan, quick).iter().map(|s| s.to_string()))
        .collect()
}

/// Mean kernel evaluations per light of an evaluator that places its tangent samples per
/// pair ([`crate::evaluator::FabricEvaluator::kernel_evaluations`]): the tangent samples
/// whose terms both threads computed for one (wi, wo), averaged over a validation set.
#[derive(Clone, Copy, Debug, Serialize, Deserialize)]
pub struct EvaluationsPerLight {
    pub uniform: f64,
    pub highlight: f64,
    /// The most any one pair of either set took.
    pub max: usize,
}

/// One evaluation measured on the CPU: its errors against the direct evaluation, its cost,
/// what a table costs in memory and bake time, and how it compares with the others.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Point {
    pub evaluation: Evaluation,
    #[serde(deserialize_with = "files::table_error")]
    pub error: TableError,
    /// One thread over the timing pairs: `FabricEvaluator::eval` pair by pair for an
    /// evaluator, and
    /// `Table::lookup_batch` for a table (the fast CPU path, eight pairs' coordinates at a
    /// time, RGB with the albedos applied, directions converted from f64 to f32 inside the
    /// timed call).
    pub timing: EvalTiming,
    /// A table's bytes of f16 texel data.
    #[serde(default)]
    pub bytes: Option<usize>,
    /// A table's bake on all worker threads of the report's pool.
    #[serde(default)]
    pub bake: Option<BakeTiming>,
    /// The kernel evaluations per light on the error sets, of an evaluator that counts them.
    #[serde(default)]
    pub evaluations_per_light: Option<EvaluationsPerLight>,
    /// Against the baseline unit at every setting measured (every point but the
    /// baseline's own). Derived from the figures above by [`FabricReport::judge`], also
    /// when read back.
    #[serde(default, skip_deserializing)]
    pub vs_baseline: Option<Comparison>,
    /// Against every evaluation of the model measured, every evaluator's points (the
    /// tables). Derived as `vs_baseline` is.
    #[serde(default, skip_deserializing)]
    pub vs_best: Option<Comparison>,
}

impl Point {
    /// The worse of the uniform and highlight relative RMS errors: the error every
    /// comparison and pick uses.
    pub fn worst_error(&self) -> f64 {
        worst(&self.error)
    }

    /// CPU nanoseconds per evaluation.
    pub fn cost(&self) -> f64 {
        self.timing.ns_per_eval
    }

    /// A table's bytes of texel data; 0 for an evaluation of the model.
    pub fn bytes(&self) -> usize {
        self.bytes.unwrap_or(0)
    }
}

/// A point another point is compared with.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Match {
    pub evaluation: Evaluation,
    pub ns_per_eval: f64,
    pub error: f64,
}

/// How a point compares with a set of others, on error (the worse of uniform and
/// highlight) and CPU cost: the one dominance rule of the report ([`dominance`]).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Comparison {
    /// The cheapest other point with an error at most this point's (None: none is that
    /// accurate).
    pub equal_error: Option<Match>,
    /// Its cost over this point's: above 1, this point is faster at equal error.
    pub speed_ratio: Option<f64>,
    /// The most accurate other point costing at most this point's cost (None: every other
    /// point costs more).
    pub equal_cost: Option<Match>,
    /// Its error over this point's: above 1, this point is more accurate at equal cost.
    pub error_ratio: Option<f64>,
    /// True when no other point is both at least as accurate and at least as cheap. Then
    /// (by the choice of the two points above) this point is faster at equal error and more
    /// accurate at equal cost; otherwise one of them dominates it.
    pub wins: bool,
}

impl Comparison {
    /// `point` against `others`.
    pub fn of(point: &Point, others: &[&Point]) -> Self {
        let (error, cost) = (point.worst_error(), point.cost());
        let figures: Vec<(f64, f64)> = others.iter().map(|o| (o.cost(), o.worst_error())).collect();
        let (equal_error, equal_cost, dominated) = dominance(error, cost, &figures);
        let at = |i: usize| Match {
            evaluation: others[i].evaluation.clone(),
            ns_per_eval: figures[i].0,
            error: figures[i].1,
        };
        let (equal_error, equal_cost) = (equal_error.map(at), equal_cost.map(at));
        Self {
            speed_ratio: equal_error.as_ref().map(|m| m.ns_per_eval / cost),
            error_ratio: equal_cost.as_ref().map(|m| m.error / error),
            equal_error,
            equal_cost,
            wins: !dominated,
        }
    }
}

/// The speed-up of a bake from one to two threads.
#[derive(Clone, Debug, Serialize, Deserialize)]
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

/// Everything measured for one fabric.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct FabricReport {
    pub name: String,
    /// The direct evaluation's cost (its error is 0 by definition).
    pub direct: EvalTiming,
    /// Every evaluation measured: each evaluator's spellings in the configuration's order,
    /// then every table.
    pub points: Vec<Point>,
    pub speedup: Speedup,
    /// Wall-clock seconds this fabric's measurements took.
    pub seconds: f64,
}

impl FabricReport {
    /// The points of the baseline unit.
    pub fn baseline(&self) -> impl Iterator<Item = &Point> {
        self.points.iter().filter(|p| p.evaluation.is_baseline())
    }

    /// The points of `unit`.
    pub fn of_unit<'a>(&'a self, unit: &'a EvaluatorUnit) -> impl Iterator<Item = &'a Point> {
        self.points.iter().filter(|p| p.evaluation.is_of(unit))
    }

    /// The points of every evaluator (no table).
    pub fn model(&self) -> impl Iterator<Item = &Point> {
        self.points.iter().filter(|p| p.evaluation.is_model())
    }

    /// The tables.
    pub fn tables(&self) -> impl Iterator<Item = &Point> {
        self.points.iter().filter(|p| !p.evaluation.is_model())
    }

    /// The point of `unit` its figures are quoted for: its default setting's when
    /// measured, else its most accurate.
    pub fn headline<'a>(&'a self, unit: &'a EvaluatorUnit) -> Option<&'a Point> {
        let default = default_spelling(unit).map(Evaluation::evaluator);
        self.of_unit(unit)
            .find(|p| Some(&p.evaluation) == default.as_ref())
            .or_else(|| {
                self.of_unit(unit)
                    .min_by(|a, b| a.worst_error().total_cmp(&b.worst_error()))
            })
    }

    /// Fills every point's comparisons from the figures: each point but the baseline's
    /// against the baseline, and each table against every evaluation of the model.
    pub fn judge(&mut self) {
        let baseline: Vec<&Point> = self.baseline().collect();
        let model: Vec<&Point> = self.model().collect();
        let judged: Vec<(Option<Comparison>, Option<Comparison>)> = self
            .points
            .iter()
            .map(|point| {
                let e = &point.evaluation;
                (
                    (!e.is_baseline()).then(|| Comparison::of(point, &baseline)),
                    (!e.is_model()).then(|| Comparison::of(point, &model)),
                )
            })
            .collect();
        for (point, (vs_baseline, vs_best)) in self.points.iter_mut().zip(judged) {
            point.vs_baseline = vs_baseline;
            point.vs_best = vs_best;
        }
    }
}

/// The machine the report ran on.
#[derive(Clone, Debug, Serialize, Deserialize)]
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
#[derive(Clone, Debug, Serialize, Deserialize)]
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
    /// Every engine's stock model against the fabrics ([`stock`]); None where the run left
    /// it out. `clothbake report --section stock` measures it alone and merges it here.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stock: Option<stock::StockSection>,
    /// Files written, relative to the output directory.
    pub files: Vec<String>,
}

impl Report {
    /// The registered units with points in this report, in registry order (the baseline
    /// among them).
    pub fn units(&self) -> Vec<&'static EvaluatorUnit> {
        let measured = |unit: &EvaluatorUnit| {
            let cpu = self
                .fabrics
                .iter()
                .any(|f| f.of_unit(unit).next().is_some());
            let gpu = self
                .gpu
                .fabrics
                .iter()
                .any(|f| f.points.iter().any(|p| p.evaluation.is_of(unit)));
            cpu || gpu
        };
        EVALUATORS.iter().filter(|unit| measured(unit)).collect()
    }

    /// The units with points in this report other than the baseline, in registry order.
    pub fn other_units(&self) -> Vec<&'static EvaluatorUnit> {
        let baseline = baseline_unit().map(|unit| unit.name);
        self.units()
            .into_iter()
            .filter(|unit| Some(unit.name) != baseline)
            .collect()
    }
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
    #[error("cannot read {path}: {source}")]
    Read {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("{path} is not a report this clothbake can read: {source}")]
    Json {
        path: PathBuf,
        source: serde_json::Error,
    },
    #[error("plot {file}: {message}")]
    Plot { file: String, message: String },
    #[error(transparent)]
    Evaluator(#[from] EvaluatorError),
    #[error("{0}")]
    Config(String),
}

fn worst(error: &TableError) -> f64 {
    error.uniform.relative_rms.max(error.highlight.relative_rms)
}

/// The report's one dominance rule: compares a point of error `error` and cost `cost` with
/// points `(cost, error)`. Returns the index of the cheapest point at most as erroneous, the
/// index of the most accurate point at most as costly, and whether some point is both at
/// most as costly and at most as erroneous (then it dominates).
pub fn dominance(
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

#[cfg(test)]
mod tests {
    use super::dominance;

    #[test]
    fn dominance_of_three_points() {
        // (cost, error) of three points, cheaper ones less accurate.
        let points = [(100.0, 0.5), (200.0, 0.1), (400.0, 0.01)];
        // More accurate than all but the dearest, cheaper than all but the cheapest: wins.
        assert_eq!(dominance(0.05, 150.0, &points), (Some(2), Some(0), false));
        // Point 1 is cheaper and more accurate: it dominates.
        assert_eq!(dominance(0.2, 250.0, &points), (Some(1), Some(1), true));
        // Cheaper than every point and more accurate than none.
        assert_eq!(dominance(0.9, 50.0, &points), (Some(0), None, false));
        // More accurate than every point.
        assert_eq!(dominance(0.001, 500.0, &points), (None, Some(2), false));
    }
}
