//! REPORT.md's summary: where table lookup beats paper mode and the best evaluation, per
//! error budget the cheapest table, paper-mode N and resonant node counts, and every table's
//! verdict.

use super::format::{num, paper_n, pct, ratio, size};
use super::{Comparison, Evaluation, FabricReport, Point, Report};
use crate::table::Layout;
use std::fmt::Write;

/// A table's two comparisons, against paper mode and against every evaluation of the model.
fn comparisons(t: &Point) -> (&Comparison, &Comparison) {
    match (&t.vs_paper, &t.vs_best) {
        (Some(paper), Some(best)) => (paper, best),
        _ => unreachable!("FabricReport::judge compares every table with both sets"),
    }
}

fn verdict_row(fabric: &str, t: &Point) -> String {
    let (v, best) = comparisons(t);
    let equal_error = v.equal_error.as_ref().map_or_else(
        || "none up to the largest N".to_string(),
        |p| format!("{} ({} ns)", paper_n(p.evaluation), num(p.ns_per_eval)),
    );
    let equal_cost = v.equal_cost.as_ref().map_or_else(
        || "none this cheap".to_string(),
        |p| format!("{} ({})", paper_n(p.evaluation), pct(p.error)),
    );
    let outcome = if v.wins { "**table**" } else { "paper mode" };
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

/// The summary: where tables beat paper mode and the best evaluation, the error budgets,
/// and every table's verdict.
pub(super) fn section(report: &Report, md: &mut String) {
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
    let _ = writeln!(md, "## Summary: where table lookup beats paper mode\n");
    for &layout in Layout::ALL {
        let of = of_layout(layout).count();
        let won = of_layout(layout).filter(|(_, _, (v, _))| v.wins).count();
        let losers: Vec<String> = of_layout(layout)
            .filter(|(_, _, (v, _))| !v.wins)
            .map(|(f, t, _)| format!("{} at {}", f.name, table_of(t).1))
            .collect();
        let _ = writeln!(
            md,
            "- **{layout}**: the table beats paper mode in {won} of {of} (fabric, resolution) \
             cases{}.",
            if losers.is_empty() {
                String::new()
            } else {
                format!(
                    "; paper mode is at least as fast and as accurate for {}",
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
            "- **{layout} against the best evaluation** (paper mode or resonant, \
             vs resonant): the table wins in {won} of {of} cases{}.",
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
         CPU nanoseconds per evaluation on one thread. *Equal error*: the cheapest paper-mode N \
         at least as accurate as the table, and how many times slower it is than the lookup. \
         *Equal cost*: the most accurate paper-mode N no slower than the lookup, and how many \
         times larger its error is. The table wins when no paper-mode point is both at least \
         as accurate and at least as fast, which is the same as winning on both comparisons. \
         *vs resonant*: the same judgement against every evaluation of the model measured \
         (paper mode at each N and the resonant quadrature at each node count): the cheapest \
         evaluation at least as accurate as the table, how many times slower it is than the \
         lookup, and the winner (the table, or the evaluation that is at least as fast and as \
         accurate).\n"
    );
    budgets(report, md);
    let _ = writeln!(md, "### {EVERY_TABLE_HEADING}\n");
    let _ = writeln!(
        md,
        "| fabric | table | size | error | ns/lookup | paper at equal error | table faster by \
         | paper at equal cost | table more accurate by | winner | best evaluation at equal \
         error | table faster by | winner vs resonant |"
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

/// The heading of the error budget table; its anchor is `#error-budgets`.
pub const BUDGETS_HEADING: &str = "Error budgets";

/// The heading of every table's verdict; its anchor is `#every-table-against-paper-mode`.
pub const EVERY_TABLE_HEADING: &str = "Every table against paper mode";

/// Error budgets of the summary table (worse of uniform and highlight relative RMS).
const BUDGETS: [f64; 6] = [0.01, 0.02, 0.05, 0.1, 0.2, 0.5];

/// The cheapest of `points` within `budget`.
fn cheapest<'a>(points: impl Iterator<Item = &'a Point>, budget: f64) -> Option<&'a Point> {
    points
        .filter(|p| p.worst_error() <= budget)
        .min_by(|a, b| a.cost().total_cmp(&b.cost()))
}

/// One line per error budget: for how many fabrics the table or paper mode is the faster
/// way to meet it, or the only one.
fn budget_bullets(report: &Report, md: &mut String) {
    for budget in BUDGETS {
        let mut counts = [0usize; 5];
        for f in &report.fabrics {
            let k = match (cheapest(f.tables(), budget), cheapest(f.paper(), budget)) {
                (Some(t), Some(p)) if t.cost() <= p.cost() => 0,
                (Some(_), Some(_)) => 1,
                (Some(_), None) => 2,
                (None, Some(_)) => 3,
                (None, None) => 4,
            };
            counts[k] += 1;
        }
        let only_paper = format!(
            "only paper mode reaches it (N ≤ {}; no table measured does)",
            report.config.paper_samples.iter().max().unwrap_or(&0)
        );
        let labels = [
            "a table is faster than paper mode",
            "paper mode is faster than any table",
            "only a table reaches it",
            &only_paper,
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

/// For each fabric and error budget, the cheapest table and the cheapest paper-mode N that
/// meet it, and which is faster.
fn budgets(report: &Report, md: &mut String) {
    let _ = writeln!(md, "### {BUDGETS_HEADING}\n");
    let _ = writeln!(
        md,
        "**By error budget**: the cheapest table (any layout and resolution measured) and the \
         cheapest paper-mode N whose error is within the budget, their CPU cost per \
         evaluation, and how many times faster the faster one is; then the cheapest resonant \
         node counts within the budget and how the table compares with the faster of paper \
         mode and the resonant quadrature (vs resonant).\n"
    );
    let _ = writeln!(
        md,
        "| fabric | budget | cheapest table | cheapest paper mode | faster | cheapest resonant \
         | table vs best evaluation |"
    );
    let _ = writeln!(md, "|---|---:|---|---|---|---|---|");
    for f in &report.fabrics {
        for budget in BUDGETS {
            let (table, paper) = (cheapest(f.tables(), budget), cheapest(f.paper(), budget));
            let cell = |p: &Point, name: String| {
                format!("{name} ({}, {} ns)", pct(p.worst_error()), num(p.cost()))
            };
            let table_cell = table.map_or("none measured".to_string(), |t| {
                cell(t, t.evaluation.to_string())
            });
            let paper_cell = paper.map_or("none up to the largest N".to_string(), |p| {
                cell(p, paper_n(p.evaluation))
            });
            let faster = match (table, paper) {
                (Some(t), Some(p)) => {
                    let r = p.cost() / t.cost();
                    if r >= 1.0 {
                        format!("**table**, {}", ratio(Some(r)))
                    } else {
                        format!("paper mode, {}", ratio(Some(1.0 / r)))
                    }
                }
                (Some(_), None) => "**table** (only)".into(),
                (None, Some(_)) => "paper mode (only)".into(),
                (None, None) => "–".into(),
            };
            let resonant = cheapest(f.resonant(), budget);
            let resonant_cell =
                resonant.map_or("none measured".to_string(), |r| match r.evaluation {
                    Evaluation::Resonant { nodes } => cell(r, nodes.to_string()),
                    other => cell(r, other.to_string()),
                });
            // The cheaper of paper mode and resonant within the budget.
            let best = [paper, resonant]
                .into_iter()
                .flatten()
                .map(|p| (p.evaluation.to_string(), p.cost()))
                .min_by(|a, b| a.1.total_cmp(&b.1));
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
                "| {} | {:.0}% | {table_cell} | {paper_cell} | {faster} | {resonant_cell} | \
                 {versus} |",
                f.name,
                100.0 * budget
            );
        }
    }
    md.push('\n');
}
