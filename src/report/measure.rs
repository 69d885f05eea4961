//! The measurements of `clothbake report`: every fabric's errors, CPU timings, bakes and
//! speed-up, then the GPU section, the plots, REPORT.md and report.json.

use super::files::{JSON_FILE_NAME, json, write_file};
use super::provenance::{git_commit, now_utc};
use super::timing::{self, BakeTiming, pair_by_pair, time_interleaved, time_repeated};
use super::{
    Evaluation, EvaluationsPerLight, FabricReport, Machine, Point, Report, ReportConfig,
    ReportError, Speedup, TIMING_SEED, gpu, markdown, plots, section, stock,
};
use crate::bake::bake;
use crate::evaluator::{EvaluationContext, FabricEvaluator, direct};
use crate::measure::accuracy::{Reference, TableError, lookup_batch_sum, lookup_f32};
use crate::measure::direction_sets::{highlight_pairs, uniform_pairs};
use crate::model::Fabric;
use crate::table::{Layout, Table};
use glam::DVec3;
use std::path::Path;
use std::time::{Duration, Instant};

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

/// One evaluator of the configuration, prepared for a fabric, with its errors and its kernel
/// evaluations per light (where it counts them).
struct MeasuredEvaluator {
    evaluation: Evaluation,
    evaluator: Box<dyn FabricEvaluator>,
    error: TableError,
    per_light: Option<EvaluationsPerLight>,
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
    let context = EvaluationContext::default();
    let uniform_set = uniform_pairs(config.error_pairs, crate::measure::accuracy::UNIFORM_SEED);
    let highlight_set = highlight_pairs(
        fabric,
        config.error_pairs,
        crate::measure::accuracy::HIGHLIGHT_SEED,
    );
    let mut evaluators: Vec<MeasuredEvaluator> = Vec::new();
    for spelling in &config.evaluators {
        let evaluator = crate::evaluator::parse(spelling)?.prepare(fabric, &context)?;
        let error = bake_pool.install(|| reference.measure(|wi, wo| evaluator.eval(wi, wo)));
        let per_light = evaluator
            .kernel_evaluations(&uniform_set)
            .zip(evaluator.kernel_evaluations(&highlight_set))
            .map(
                |((uniform, max_uniform), (highlight, max_highlight))| EvaluationsPerLight {
                    uniform,
                    highlight,
                    max: max_uniform.max(max_highlight),
                },
            );
        progress(&format!(
            "{name}: {spelling}: {:.3}% uniform, {:.3}% highlight{}",
            100.0 * error.uniform.relative_rms,
            100.0 * error.highlight.relative_rms,
            per_light.map_or(String::new(), |n| format!(
                ", {:.1} uniform and {:.1} highlight kernel evaluations per light",
                n.uniform, n.highlight
            )),
        ));
        evaluators.push(MeasuredEvaluator {
            evaluation: Evaluation::evaluator(spelling.clone()),
            evaluator,
            error,
            per_light,
        });
    }
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
    let direct_evaluator = (direct::UNIT.parse)(None)?.prepare(fabric, &context)?;
    let direct_eval = pair_by_pair(|wi, wo| direct_evaluator.eval(wi, wo));
    let evaluator_evals: Vec<timing::BoxedEval> = evaluators
        .iter()
        .map(|m| Box::new(pair_by_pair(|wi, wo| m.evaluator.eval(wi, wo))) as Box<_>)
        .collect();
    let table_evals: Vec<timing::BoxedEval> = tables
        .iter()
        .map(|(table, _, _)| {
            Box::new(move |pairs: &[(DVec3, DVec3)]| lookup_batch_sum(table, pairs)) as Box<_>
        })
        .collect();
    let evals: Vec<timing::Eval> = std::iter::once(&direct_eval as timing::Eval)
        .chain(evaluator_evals.iter().map(|e| &**e as timing::Eval))
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
    let point = |evaluation, error: &TableError, timing| Point {
        evaluation,
        error: *error,
        timing,
        bytes: None,
        bake: None,
        evaluations_per_light: None,
        vs_baseline: None,
        vs_best: None,
    };
    let mut points: Vec<Point> = evaluators
        .iter()
        .zip(timings.by_ref())
        .map(|(m, timing)| Point {
            evaluations_per_light: m.per_light,
            ..point(m.evaluation.clone(), &m.error, timing)
        })
        .collect();
    points.extend(
        tables
            .iter()
            .zip(timings)
            .map(|((table, error, bake), lookup)| {
                let evaluation = Evaluation::Table {
                    layout: table.layout,
                    resolution: table.resolution,
                };
                Point {
                    bytes: Some(table.byte_size()),
                    bake: Some(bake.clone()),
                    ..point(evaluation, error, lookup)
                }
            }),
    );
    let costs: Vec<String> = std::iter::once(format!("direct {:.0}", direct.ns_per_eval))
        .chain(
            points
                .iter()
                .map(|p| format!("{} {:.0}", p.evaluation, p.cost())),
        )
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
    let mut report = FabricReport {
        name: name.clone(),
        direct,
        points,
        speedup,
        seconds: started.elapsed().as_secs_f64(),
    };
    report.judge();
    Ok(report)
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
    // Each evaluator under the spelling it parses back to ("paper" is measured as
    // "paper:32"), so that a point names its setting and is found by it.
    let canonical = |spellings: &[String]| -> Result<Vec<String>, ReportError> {
        spellings
            .iter()
            .map(|s| Ok(crate::evaluator::parse(s)?.spelling()))
            .collect()
    };
    let config = &ReportConfig {
        evaluators: canonical(&config.evaluators)?,
        gpu_evaluators: canonical(&config.gpu_evaluators)?,
        ..config.clone()
    };
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
    let date_utc = now_utc();
    let bake_pool = pool(0)?;
    let mut fabrics = Vec::new();
    // Each fabric's table of the default layout for the GPU section: the one at the
    // default resolution, as `bake` makes it, else the largest measured.
    let mut gpu_tables: Vec<Table> = Vec::new();
    let rank = |t: &Table| {
        (
            t.resolution == Layout::DEFAULT.default_resolution(),
            t.resolution,
        )
    };
    for fabric in &config.fabrics {
        let mut chosen: Option<Table> = None;
        let report = measure_fabric(config, fabric, &bake_pool, progress, &mut |t| {
            if t.layout == Layout::DEFAULT && chosen.as_ref().is_none_or(|c| rank(c) < rank(t)) {
                chosen = Some(t.clone());
            }
        })?;
        fabrics.push(report);
        gpu_tables.extend(chosen);
    }
    let gpu_started = Instant::now();
    let mut gpu = if config.gpu {
        gpu::measure(config, &gpu_tables, progress)
    } else {
        gpu::GpuSection::not_requested()
    };
    gpu.seconds = gpu_started.elapsed().as_secs_f64();
    let stock = match &config.stock {
        Some(stock_config) => {
            let mut run = stock::measure(stock_config, &config.fabrics, progress)?;
            run.section.command_line = command_line.clone();
            Some(section::write_stock(run, out)?)
        }
        None => None,
    };
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
        stock,
        files: Vec::new(),
    };
    report.files = plots::write_all(&report, out)?;
    for file in report.stock.iter().flat_map(|s| &s.files) {
        if !report.files.contains(file) {
            report.files.push(file.clone());
        }
    }
    report.elapsed_seconds = started.elapsed().as_secs_f64();
    report.files.push(markdown::FILE_NAME.to_string());
    report.files.push(JSON_FILE_NAME.to_string());
    write_file(out, markdown::FILE_NAME, &markdown::render(&report))?;
    write_file(out, JSON_FILE_NAME, &json(&report)?)?;
    Ok(report)
}
