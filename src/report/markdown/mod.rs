//! REPORT.md: the report's figures as Markdown tables, with the plots and the method.

use super::format::{
    NONE_UP_TO_THE_LARGEST, baseline_name, num, pct, ratio, size, table_name, unit_heading,
    unit_names,
};
use super::{Evaluation, EvaluationsPerLight, Point, Report, pick, plots, summary};
use crate::evaluator::EvaluatorUnit;
use std::fmt::Write;

mod gpu;
pub mod stock;
use gpu::gpu_section;

/// The Markdown file's name in the output directory.
pub const FILE_NAME: &str = "REPORT.md";

fn method(report: &Report, md: &mut String) {
    let c = &report.config;
    let _ = writeln!(md, "## Method\n");
    let _ = writeln!(
        md,
        "- **Errors**: relative RMS over RGB, `sqrt(Σ|F_est − F|² / Σ|F|²)`, against the direct \
         evaluation (the ground truth, docs/model.md) on {} uniform pairs (both directions uniform \
         over the upper hemisphere, seed {:#x}), {} highlight pairs (on the specular cones \
         of tangent samples, seed {:#x}), and the uniform pairs with both directions at \
         least 15° above the horizon — the sets of `clothbake check` (src/measure/accuracy.rs, \
         src/measure/direction_sets.rs).",
        c.error_pairs,
        crate::measure::accuracy::UNIFORM_SEED,
        c.error_pairs,
        crate::measure::accuracy::HIGHLIGHT_SEED
    );
    let _ = writeln!(
        md,
        "- **CPU cost**: nanoseconds per evaluation on one thread over a fixed set of {} \
         uniform pairs (seed {:#x}), the median of {} samples, each at least {} ms long \
         (whole passes over the set) after one warm-up pass. Table lookups are \
         `Table::lookup_batch` (the f32 CPU path, eight pairs at a time, the texels of a \
         batch prefetched, the albedos applied) on the pairs rounded to f32; the random \
         pairs read the table at scattered places, a lookup's worst case for the caches, \
         where a renderer's neighbouring pixels read neighbouring texels. Every evaluator and \
         the direct evaluation are `FabricEvaluator::eval`, pair by pair, as its registry unit \
         prepares it. All timings of a fabric come from the same run, so their ratios compare \
         like with like.",
        c.timing_pairs,
        super::TIMING_SEED,
        c.timing_samples,
        (c.min_sample_seconds * 1000.0).round()
    );
    let _ = writeln!(
        md,
        "- **Bake time**: wall-clock seconds of `bake::bake` on all {} worker threads, median \
         of {} bake(s) per table{}. Speed-up: {} {} baked alternately on a 1-thread and a \
         2-thread rayon pool, {} time(s) each, median over median.",
        report.machine.bake_threads,
        c.bake_repetitions,
        if c.bake_repetitions > 1 {
            format!(
                " (a bake over {:.0} s is timed once, to bound the run time)",
                c.repeat_bakes_below_seconds
            )
        } else {
            String::new()
        },
        c.speedup_layout,
        c.speedup_resolution,
        c.speedup_repetitions
    );
    let counting: Vec<&EvaluatorUnit> = report
        .units()
        .into_iter()
        .filter(|&unit| counts_per_light(report, unit))
        .collect();
    if !counting.is_empty() {
        let _ = writeln!(
            md,
            "- **Kernel evaluations per light** ({}): the tangent samples whose terms the two \
             threads compute for one (wi, wo) (`FabricEvaluator::kernel_evaluations`, summed \
             over both threads), averaged over the uniform and over the highlight pairs of the \
             error sets.",
            unit_names(&counting)
        );
    }
    let layouts: Vec<String> = c
        .resolutions
        .iter()
        .map(|(l, r)| format!("{l} {r:?}"))
        .collect();
    let _ = writeln!(
        md,
        "- Resolutions: {}; evaluators {}.\n",
        layouts.join(", "),
        c.evaluators.join(", ")
    );
}

/// Whether some point of `unit` in `report` has its kernel evaluations per light.
fn counts_per_light(report: &Report, unit: &EvaluatorUnit) -> bool {
    report
        .fabrics
        .iter()
        .flat_map(|f| f.of_unit(unit))
        .any(|p| p.evaluations_per_light.is_some())
}

fn tables_section(report: &Report, md: &mut String) {
    let _ = writeln!(md, "## Error against table size\n");
    let _ = writeln!(md, "![error against size]({})\n", plots::ERROR_VS_SIZE);
    let _ = writeln!(
        md,
        "| fabric | layout | resolution | size | uniform | ≥ 1° | ≥ 3° | ≥ 15° | highlight | ≥ 1° | ≥ 3° | ns/lookup | bake (s) |"
    );
    let _ = writeln!(
        md,
        "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
    );
    for f in &report.fabrics {
        for t in f.tables() {
            let Evaluation::Table { layout, resolution } = t.evaluation else {
                continue;
            };
            let _ = writeln!(
                md,
                "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {:.2} |",
                f.name,
                layout,
                resolution,
                size(t.bytes()),
                pct(t.error.uniform.relative_rms),
                pct(t.error.uniform_above_1deg.relative_rms),
                pct(t.error.uniform_above_3deg.relative_rms),
                pct(t.error.uniform_above_15deg.relative_rms),
                pct(t.error.highlight.relative_rms),
                pct(t.error.highlight_above_1deg.relative_rms),
                pct(t.error.highlight_above_3deg.relative_rms),
                num(t.cost()),
                t.bake.as_ref().map_or(f64::NAN, |b| b.seconds)
            );
        }
    }
    md.push('\n');
    let _ = writeln!(
        md,
        "**Pareto front** (size against error, every layout): the tables no other table of \
         the fabric beats on both size and error (worse of uniform and highlight). To meet an \
         error budget, pick the first entry at or under it; for a memory budget, the last \
         entry that fits.\n"
    );
    for f in &report.fabrics {
        let mut front: Vec<&Point> = f
            .tables()
            .filter(|t| {
                !f.tables().any(|o| {
                    o.bytes() <= t.bytes()
                        && o.worst_error() <= t.worst_error()
                        && (o.bytes() < t.bytes() || o.worst_error() < t.worst_error())
                })
            })
            .collect();
        front.sort_by_key(|t| t.bytes());
        let entries: Vec<String> = front
            .iter()
            .map(|t| {
                format!(
                    "{} ({}, {})",
                    t.evaluation,
                    size(t.bytes()),
                    pct(t.worst_error())
                )
            })
            .collect();
        let _ = writeln!(md, "- {}: {}", f.name, entries.join(" → "));
    }
    md.push('\n');
}

/// The baseline's points against the direct evaluation, with the direct evaluation's cost.
fn baseline_section(report: &Report, md: &mut String) {
    let _ = writeln!(md, "## Error against CPU cost\n");
    let _ = writeln!(md, "![error against cost]({})\n", plots::ERROR_VS_COST);
    let _ = writeln!(
        md,
        "The baseline, `{}` ({}), against the direct evaluation (whose own cost is the first \
         row of each fabric). Table lookups are in the table above and the plot; every other \
         evaluator is in a section of its own below and in the plot.\n",
        super::baseline_unit().map_or("", |unit| unit.syntax),
        super::baseline_unit().map_or("", |unit| unit.summary)
    );
    let _ = writeln!(
        md,
        "| fabric | evaluation | uniform | highlight | both ≥ 15° | ns/eval | × cheaper than direct |"
    );
    let _ = writeln!(md, "|---|---|---:|---:|---:|---:|---:|");
    for f in &report.fabrics {
        let _ = writeln!(
            md,
            "| {} | direct | 0 | 0 | 0 | {} | 1 |",
            f.name,
            num(f.direct.ns_per_eval)
        );
        for p in f.baseline() {
            let _ = writeln!(
                md,
                "| {} | {} | {} | {} | {} | {} | {} |",
                f.name,
                p.evaluation,
                pct(p.error.uniform.relative_rms),
                pct(p.error.highlight.relative_rms),
                pct(p.error.uniform_above_15deg.relative_rms),
                num(p.cost()),
                ratio(Some(f.direct.ns_per_eval / p.cost()))
            );
        }
    }
    md.push('\n');
}

/// The section of one evaluator other than the baseline: its points against the direct
/// evaluation and against the baseline at equal error, with its kernel evaluations per light
/// where it counts them.
fn unit_section(report: &Report, unit: &EvaluatorUnit, md: &mut String) {
    let base = baseline_name();
    let _ = writeln!(md, "## {}\n", unit_heading(unit));
    let setting = unit.report.map_or(String::new(), |plan| {
        format!(" Its settings: {}.", plan.setting)
    });
    let default = super::default_spelling(unit);
    let per_light = counts_per_light(report, unit);
    let _ = writeln!(
        md,
        "`{}`: {}.{setting}{} Errors against the same direct evaluation as {base}; cost in CPU \
         ns per evaluation, timed in the same interleaved run as {base} and the tables{}. \
         *{base} at equal error*: the cheapest setting of {base} at least as accurate as the \
         point; *{} / {base}*: the point's cost over that setting's (below 1, {} is cheaper \
         at equal error).\n",
        unit.syntax,
        unit.summary,
        default
            .as_ref()
            .map_or(String::new(), |d| format!(" The default is {d}.")),
        if per_light {
            "; kernel evaluations per light on the uniform and the highlight pairs"
        } else {
            ""
        },
        unit.name,
        unit.name,
    );
    let (per_light_header, per_light_rule) = if per_light {
        (
            " evaluations/light (uniform) | evaluations/light (highlight) |",
            "---:|---:|",
        )
    } else {
        ("", "")
    };
    let _ = writeln!(
        md,
        "| fabric | evaluation | uniform | highlight | both ≥ 15° | ns/eval | × cheaper than \
         direct |{per_light_header} {base} at equal error | {} / {base} |",
        unit.name
    );
    let _ = writeln!(
        md,
        "|---|---|---:|---:|---:|---:|---:|{per_light_rule}---|---:|"
    );
    for f in &report.fabrics {
        for r in f.of_unit(unit) {
            let counts = if per_light {
                let n = r.evaluations_per_light.unwrap_or(EvaluationsPerLight {
                    uniform: f64::NAN,
                    highlight: f64::NAN,
                    max: 0,
                });
                format!(" {:.1} | {:.1} |", n.uniform, n.highlight)
            } else {
                String::new()
            };
            let baseline = r.vs_baseline.as_ref().and_then(|c| c.equal_error.as_ref());
            let is_default = default
                .as_ref()
                .is_some_and(|d| r.evaluation.to_string() == *d);
            let _ = writeln!(
                md,
                "| {} | {}{} | {} | {} | {} | {} | {} |{counts} {} | {} |",
                f.name,
                r.evaluation,
                if is_default { " (default)" } else { "" },
                pct(r.error.uniform.relative_rms),
                pct(r.error.highlight.relative_rms),
                pct(r.error.uniform_above_15deg.relative_rms),
                num(r.cost()),
                ratio(Some(f.direct.ns_per_eval / r.cost())),
                baseline.map_or_else(
                    || NONE_UP_TO_THE_LARGEST.to_string(),
                    |p| format!(
                        "{} ({}, {} ns)",
                        p.evaluation,
                        pct(p.error),
                        num(p.ns_per_eval)
                    )
                ),
                ratio(baseline.map(|p| r.cost() / p.ns_per_eval)),
            );
        }
    }
    md.push('\n');
    let _ = writeln!(
        md,
        "**{} against {base} at equal error** (the default setting, or the most accurate \
         measured when the default was not; error = the worse of uniform and highlight):\n",
        unit.name
    );
    for f in &report.fabrics {
        let Some(r) = f.headline(unit) else {
            continue;
        };
        headline(f, r, md);
    }
    md.push('\n');
}

/// One fabric's line of a unit's headline point against the baseline at equal error.
fn headline(f: &super::FabricReport, r: &Point, md: &mut String) {
    let base = baseline_name();
    let head = format!(
        "- {}: {} ({}, {} ns)",
        f.name,
        r.evaluation,
        pct(r.worst_error()),
        num(r.cost())
    );
    let baseline = r.vs_baseline.as_ref().and_then(|c| c.equal_error.as_ref());
    let _ = match baseline {
        Some(p) => {
            let c = r.cost() / p.ns_per_eval;
            writeln!(
                md,
                "{head} costs {} of {base} at equal error, {} ({}, {} ns){}.",
                ratio(Some(c)),
                p.evaluation,
                pct(p.error),
                num(p.ns_per_eval),
                if c < 1.0 {
                    format!(": {} faster", ratio(Some(1.0 / c)))
                } else {
                    String::new()
                }
            )
        }
        None => {
            let best = f
                .baseline()
                .min_by(|a, b| a.worst_error().total_cmp(&b.worst_error()));
            writeln!(
                md,
                "{head}: no setting of {base} measured is as accurate{}, so there is no cost \
                 ratio at equal error.",
                best.map_or(String::new(), |p| format!(
                    " (the most accurate, {}, is at {}, {} ns)",
                    p.evaluation,
                    pct(p.worst_error()),
                    num(p.cost())
                ))
            )
        }
    };
}

fn bake_section(report: &Report, md: &mut String) {
    let _ = writeln!(md, "## Bake time\n");
    let _ = writeln!(
        md,
        "![bake time against resolution]({})\n",
        plots::BAKE_TIME
    );
    let _ = writeln!(
        md,
        "Bake times are in the table of errors above. Speed-up from one to two threads \
         (\"identical\": the two bakes gave bit-identical texels):\n"
    );
    let _ = writeln!(
        md,
        "| fabric | table | 1 thread (s) | 2 threads (s) | speed-up | identical |"
    );
    let _ = writeln!(md, "|---|---|---:|---:|---:|---|");
    for f in &report.fabrics {
        let s = &f.speedup;
        let _ = writeln!(
            md,
            "| {} | {} | {:.2} | {:.2} | {:.2}× | {} |",
            f.name,
            table_name(s.layout, s.resolution),
            s.one_thread.seconds,
            s.two_threads.seconds,
            s.speedup,
            if s.identical { "yes" } else { "**no**" }
        );
    }
    md.push('\n');
}

fn load(l: Option<[f64; 3]>) -> String {
    l.map_or("unknown".into(), |l| format!("{:.1}", l[0]))
}

/// The whole REPORT.md.
pub fn render(report: &Report) -> String {
    let mut md = String::new();
    let _ = writeln!(md, "# clothbake: speed against error\n");
    let _ = writeln!(
        md,
        "Generated by `{}` ({} preset) on {}, clothbake {}{}, in {:.0} s. Regenerate with \
         `cargo run --release -- report{}`; every figure below comes from that one run.\n",
        report.command_line.join(" "),
        report.config.mode,
        report.date_utc,
        report.clothbake_version,
        report
            .git_commit
            .as_ref()
            .map_or(String::new(), |c| format!(" (commit {c})")),
        report.elapsed_seconds,
        if report.config.mode == "quick" {
            " --quick"
        } else {
            ""
        }
    );
    let m = &report.machine;
    let _ = writeln!(
        md,
        "Machine: {}, {} logical cores ({} bake threads), {}/{}. GPU adapter: {}. All figures \
         are also in `report.json`. Time taken: {}; GPU section {:.0} s. Load average \
         (1 min) {} at the start, {} at the end (the 1-minute average includes this run's own \
         work, up to {} at full use of the cores; a higher value means other processes shared \
         them and slowed the absolute times, while ratios measured within the run hold \
         better).\n",
        m.cpu_model.as_deref().unwrap_or("unknown CPU"),
        m.logical_cores,
        m.bake_threads,
        m.os,
        m.arch,
        report.gpu.adapter.as_deref().unwrap_or("none found"),
        report
            .fabrics
            .iter()
            .map(|f| format!("{} {:.0} s", f.name, f.seconds))
            .collect::<Vec<_>>()
            .join(", "),
        report.gpu.seconds,
        load(m.load_average_start),
        load(m.load_average_end),
        // The average lags and counts this run's own threads, so it cannot say by itself
        // whether other work slowed the run: the reader gets the figures and how to read them.
        m.bake_threads,
    );
    pick::section(report, &mut md);
    summary::section(report, &mut md);
    method(report, &mut md);
    tables_section(report, &mut md);
    baseline_section(report, &mut md);
    for unit in report.other_units() {
        unit_section(report, unit, &mut md);
    }
    bake_section(report, &mut md);
    gpu_section(report, &mut md);
    if let Some(section) = &report.stock {
        stock::summary(section, &mut md);
    }
    md
}
