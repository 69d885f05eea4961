//! REPORT.md's summary: where table lookup beats the baseline unit and the best evaluation,
//! per error budget the cheapest table and the cheapest setting of every evaluator, and
//! every table's verdict.

use super::format::{NONE_UP_TO_THE_LARGEST, baseline_name, num, pct, ratio, size, unit_names};
use super::{Comparison, Evaluation, FabricReport, Point, Report};
use crate::table::Layout;
use std::fmt::Write;

/// A table's two comparisons, against the baseline and against every evaluation of the
/// model.
fn comparisons(t: &Point) -> (&Comparison, &Comparison) {
    match (&t.vs_baseline, &t.vs_best) {
        (Some(baseline), Some(best)) => (baseline, best),
        _ => unreachable!("FabricReport::judge compares every table with both sets"),
    }
}

fn verdict_row(fabric: &str, t: &Point) -> String {
    let (v, best) = comparisons(t);
    let equal_error = v.equal_error.as_ref().map_or_else(
        || NONE_UP_TO_THE_LARGEST.to_string(),
        |p| format!("{} ({} ns)", p.evaluation, num(p.ns_per_eval)),
    );
    let equal_cost = v.equal_cost.as_ref().map_or_else(
        || "none this cheap".to_string(),
        |p| format!("{} ({})", p.evaluation, pct(p.error)),
    );
    let outcome = if v.wins { "**table**" } else { baseline_name() };
    let best_equal_error = best.equal_error.as_ref().map_or_else(
        || "none measured".to_string(),
        |e| format!("{} ({} ns)", e.evaluation, num(e.ns_per_eval)),
    );
    let best_outcome = if best.wins {
        "**table**".to_string()
    } else {
        // The evaluation that dominates: the cheapest one at least as accurate.
        best.equal_error
            .as_ref()
            .map_or("evaluation".to_string(), |e| e.evaluation.to_string())
    };
    format!(
        "| {fabric} | {} | {} | {} | {} | {equal_error} | {} | {equal_cost} | {} | {outcome} \
         | {best_equal_error} | {} | {best_outcome} |\n",
        t.evaluation,
        size(t.bytes()),
        pct(t.worst_error()),
        num(t.cost()),
        ratio(v.speed_ratio),
        ratio(v.error_ratio),
        ratio(best.speed_ratio),
    )
}

/// A table's layout and resolution.
fn table_of(t: &Point) -> (Layout, u32) {
    match t.evaluation {
        Evaluation::Table { layout, resolution } => (layout, resolution),
        _ => unreachable!("FabricReport::tables yields tables"),
    }
}

/// The summary: where tables beat the baseline and the best evaluation, the error budgets,
/// and every table's verdict.
pub(super) fn section(report: &Report, md: &mut String) {
    let base = baseline_name();
    let all: Vec<(&FabricReport, &Point)> = report
        .fabrics
        .iter()
        .flat_map(|f| f.tables().map(move |t| (f, t)))
        .collect();
    let of_layout = |layout: Layout| {
        all.iter()
            .filter(move |(_, t)| table_of(t).0 == layout)
            .map(|&(f, t)| (f, t, comparisons(t)))
    };
    let _ = writeln!(md, "## {SUMMARY_HEADING}\n");
    let _ = writeln!(
        md,
        "The baseline is the {base} evaluator ({}); the evaluators measured are {}.\n",
        baseline_summary(),
        unit_names(&report.units())
    );
    for &layout in Layout::ALL {
        let of = of_layout(layout).count();
        let won = of_layout(layout).filter(|(_, _, (v, _))| v.wins).count();
        let losers: Vec<String> = of_layout(layout)
            .filter(|(_, _, (v, _))| !v.wins)
            .map(|(f, t, _)| format!("{} at {}", f.name, table_of(t).1))
            .collect();
        let _ = writeln!(
            md,
            "- **{layout}**: the table beats {base} in {won} of {of} (fabric, resolution) \
             cases{}.",
            if losers.is_empty() {
                String::new()
            } else {
                format!(
                    "; {base} is at least as fast and as accurate for {}",
                    losers.join(", ")
                )
            }
        );
    }
    for &layout in Layout::ALL {
        let of = of_layout(layout).count();
        let won = of_layout(layout).filter(|(_, _, (_, b))| b.wins).count();
        let losers: Vec<String> = of_layout(layout)
            .filter(|(_, _, (_, b))| !b.wins)
            .map(|(f, t, (_, b))| {
                let by = b
                    .equal_error
                    .as_ref()
                    .map_or(String::new(), |e| format!(" ({})", e.evaluation));
                format!("{} at {}{by}", f.name, table_of(t).1)
            })
            .collect();
        let _ = writeln!(
            md,
            "- **{layout} against the best evaluation** (any of {}, vs best): the table wins \
             in {won} of {of} cases{}.",
            unit_names(&report.units()),
            if losers.is_empty() {
                String::new()
            } else {
                format!(
                    "; an evaluation is at least as fast and as accurate for {}",
                    losers.join(", ")
                )
            }
        );
    }
    md.push('\n');
    let _ = writeln!(
        md,
        "Per error budget, over the {} fabrics:\n",
        report.fabrics.len()
    );
    budget_bullets(report, md);
    let _ = writeln!(
        md,
        "\n\"Error\" is the worse of the uniform and highlight relative RMS errors; \"cost\" is \
         CPU nanoseconds per evaluation on one thread. *Equal error*: the cheapest setting of \
         {base} at least as accurate as the table, and how many times slower it is than the \
         lookup. *Equal cost*: the most accurate setting of {base} no slower than the lookup, \
         and how many times larger its error is. The table wins when no point of {base} is \
         both at least as accurate and at least as fast, which is the same as winning on both \
         comparisons. *vs best*: the same judgement against every evaluation of the model \
         measured (every setting of {}): the cheapest evaluation at least as accurate as the \
         table, how many times slower it is than the lookup, and the winner (the table, or \
         the evaluation that is at least as fast and as accurate).\n",
        unit_names(&report.units())
    );
    budgets(report, md);
    let _ = writeln!(md, "### {EVERY_TABLE_HEADING}\n");
    let _ = writeln!(
        md,
        "| fabric | table | size | error | ns/lookup | {base} at equal error | table faster by \
         | {base} at equal cost | table more accurate by | winner | best evaluation at equal \
         error | table faster by | winner vs best |"
    );
    let _ = writeln!(
        md,
        "|---|---|---:|---:|---:|---|---:|---|---:|---|---|---:|---|"
    );
    for (f, t) in &all {
        md.push_str(&verdict_row(&f.name, t));
    }
    md.push('\n');
}

/// The summary's heading; its anchor is `#summary-where-table-lookup-beats-the-baseline`.
pub const SUMMARY_HEADING: &str = "Summary: where table lookup beats the baseline";

/// The heading of the error budget table; its anchor is `#error-budgets`.
pub const BUDGETS_HEADING: &str = "Error budgets";

/// The heading of every table's verdict; its anchor is `#every-table-against-the-baseline`.
pub const EVERY_TABLE_HEADING: &str = "Every table against the baseline";

/// What the baseline unit evaluates F by, from the registry.
fn baseline_summary() -> &'static str {
    super::baseline_unit().map_or("none registered", |unit| unit.summary)
}

/// Error budgets of the summary table (worse of uniform and highlight relative RMS).
const BUDGETS: [f64; 6] = [0.01, 0.02, 0.05, 0.1, 0.2, 0.5];

/// The cheapest of `points` within `budget`.
fn cheapest<'a>(points: impl Iterator<Item = &'a Point>, budget: f64) -> Option<&'a Point> {
    points
        .filter(|p| p.worst_error() <= budget)
        .min_by(|a, b| a.cost().total_cmp(&b.cost()))
}

/// One line per error budget: for how many fabrics the table or the baseline is the faster
/// way to meet it, or the only one.
fn budget_bullets(report: &Report, md: &mut String) {
    let base = baseline_name();
    let largest = report
        .config
        .evaluators
        .iter()
        .rfind(|s| Evaluation::evaluator(s.as_str()).is_baseline())
        .map_or(String::new(), |s| format!("up to {s}; "));
    for budget in BUDGETS {
        let mut counts = [0usize; 5];
        for f in &report.fabrics {
            let k = match (cheapest(f.tables(), budget), cheapest(f.baseline(), budget)) {
                (Some(t), Some(p)) if t.cost() <= p.cost() => 0,
                (Some(_), Some(_)) => 1,
                (Some(_), None) => 2,
                (None, Some(_)) => 3,
                (None, None) => 4,
            };
            counts[k] += 1;
        }
        let faster = format!("a table is faster than {base}");
        let slower = format!("{base} is faster than any table");
        let only_baseline = format!("only {base} reaches it ({largest}no table measured does)");
        let labels = [
            faster.as_str(),
            slower.as_str(),
            "only a table reaches it",
            &only_baseline,
            "neither reaches it",
        ];
        let parts: Vec<String> = counts
            .iter()
            .zip(labels)
            .filter(|(n, _)| **n > 0)
            .map(|(n, label)| format!("{n} × {label}"))
            .collect();
        let _ = writeln!(
            md,
            "- error budget {:.0}% (CPU): {}",
            100.0 * budget,
            parts.join("; ")
        );
    }
}

/// For each fabric and error budget, the cheapest table and the cheapest setting of every
/// evaluator that meet it, and which of the table and the baseline is faster.
fn budgets(report: &Report, md: &mut String) {
    let base = baseline_name();
    let others = report.other_units();
    let _ = writeln!(md, "### {BUDGETS_HEADING}\n");
    let _ = writeln!(
        md,
        "**By error budget**: the cheapest table (any layout and resolution measured) and the \
         cheapest setting of {base} whose error is within the budget, their CPU cost per \
         evaluation, and how many times faster the faster one is; then the cheapest setting of \
         every other evaluator within the budget and how the table compares with the fastest \
         evaluation of the model (vs best).\n"
    );
    let other_columns: String = others
        .iter()
        .map(|unit| format!(" cheapest {} |", unit.name))
        .collect();
    let _ = writeln!(
        md,
        "| fabric | budget | cheapest table | cheapest {base} | faster |{other_columns} table vs \
         best evaluation |"
    );
    let _ = writeln!(
        md,
        "|---|---:|---|---|---|{}---|",
        "---|".repeat(others.len())
    );
    for f in &report.fabrics {
        for budget in BUDGETS {
            let (table, baseline) = (cheapest(f.tables(), budget), cheapest(f.baseline(), budget));
            let cell = |p: &Point| {
                format!(
                    "{} ({}, {} ns)",
                    p.evaluation,
                    pct(p.worst_error()),
                    num(p.cost())
                )
            };
            let table_cell = table.map_or("none measured".to_string(), cell);
            let baseline_cell = baseline.map_or(NONE_UP_TO_THE_LARGEST.to_string(), cell);
            let faster = match (table, baseline) {
                (Some(t), Some(p)) => {
                    let r = p.cost() / t.cost();
                    if r >= 1.0 {
                        format!("**table**, {}", ratio(Some(r)))
                    } else {
                        format!("{base}, {}", ratio(Some(1.0 / r)))
                    }
                }
                (Some(_), None) => "**table** (only)".into(),
                (None, Some(_)) => format!("{base} (only)"),
                (None, None) => "–".into(),
            };
            let other_cells: String = others
                .iter()
                .map(|unit| {
                    let cheapest = cheapest(f.of_unit(unit), budget);
                    format!(" {} |", cheapest.map_or("none measured".to_string(), cell))
                })
                .collect();
            let best = cheapest(f.model(), budget).map(|p| (p.evaluation.to_string(), p.cost()));
            let versus = match (table, best) {
                (Some(t), Some((label, ns))) => {
                    let r = ns / t.cost();
                    if r >= 1.0 {
                        format!("**table**, {} (vs {label})", ratio(Some(r)))
                    } else {
                        format!("{label}, {}", ratio(Some(1.0 / r)))
                    }
                }
                (Some(_), None) => "**table** (only)".into(),
                (None, Some((label, _))) => format!("{label} (only)"),
                (None, None) => "–".into(),
            };
            let _ = writeln!(
                md,
                "| {} | {:.0}% | {table_cell} | {baseline_cell} | {faster} |{other_cells} \
                 {versus} |",
                f.name,
                100.0 * budget
            );
        }
    }
    md.push('\n');
}
