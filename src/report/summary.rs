//! REPORT.md's summary: where table lookup beats paper mode and the best evaluation, per
//! error budget the cheapest table, paper-mode N and resonant node counts, and every table's
//! verdict.

use super::markdown::{num, pct, ratio, size, table_name};
use super::{FabricReport, PaperPoint, Report, ResonantPoint, TablePoint, Verdict, worst};
use crate::table::Layout;
use std::fmt::Write;

fn verdict_row(fabric: &str, t: &TablePoint, v: &Verdict) -> String {
    let equal_error = v.equal_error.as_ref().map_or_else(
        || "none up to the largest N".to_string(),
        |p| format!("N = {} ({} ns)", p.samples, num(p.ns_per_eval)),
    );
    let equal_cost = v.equal_cost.as_ref().map_or_else(
        || "none this cheap".to_string(),
        |p| format!("N = {} ({})", p.samples, pct(p.error)),
    );
    let outcome = if v.table_wins {
        "**table**"
    } else {
        "paper mode"
    };
    let best = &v.vs_best_evaluation;
    let best_equal_error = best.equal_error.as_ref().map_or_else(
        || "none measured".to_string(),
        |e| format!("{} ({} ns)", e.evaluation, num(e.ns_per_eval)),
    );
    let best_outcome = if best.table_wins {
        "**table**".to_string()
    } else {
        // The evaluation that dominates: the cheapest one at least as accurate.
        best.equal_error
            .as_ref()
            .map_or("evaluation".to_string(), |e| e.evaluation.clone())
    };
    format!(
        "| {fabric} | {} | {} | {} | {} | {equal_error} | {} | {equal_cost} | {} | {outcome} \
         | {best_equal_error} | {} | {best_outcome} |\n",
        table_name(t.layout, t.resolution),
        size(t.bytes),
        pct(v.error),
        num(v.ns_per_eval),
        ratio(v.speed_ratio),
        ratio(v.error_ratio),
        ratio(best.speed_ratio),
    )
}

/// The summary: where tables beat paper mode and the best evaluation, the error budgets,
/// and every table's verdict.
pub(super) fn section(report: &Report, md: &mut String) {
    let all: Vec<(&FabricReport, &TablePoint, &Verdict)> = report
        .fabrics
        .iter()
        .flat_map(|f| {
            f.tables
                .iter()
                .zip(&f.verdicts)
                .map(move |(t, v)| (f, t, v))
        })
        .collect();
    let wins = |layout: Layout| {
        let of: Vec<_> = all.iter().filter(|(_, t, _)| t.layout == layout).collect();
        let won = of.iter().filter(|(_, _, v)| v.table_wins).count();
        (won, of.len())
    };
    let _ = writeln!(md, "## Summary: where table lookup beats paper mode\n");
    for &layout in Layout::ALL {
        let (won, of) = wins(layout);
        let losers: Vec<String> = all
            .iter()
            .filter(|(_, t, v)| t.layout == layout && !v.table_wins)
            .map(|(f, t, _)| format!("{} at {}", f.name, t.resolution))
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
        let of: Vec<_> = all.iter().filter(|(_, t, _)| t.layout == layout).collect();
        let won = of
            .iter()
            .filter(|(_, _, v)| v.vs_best_evaluation.table_wins)
            .count();
        let losers: Vec<String> = of
            .iter()
            .filter(|(_, _, v)| !v.vs_best_evaluation.table_wins)
            .map(|(f, t, v)| {
                let by = v
                    .vs_best_evaluation
                    .equal_error
                    .as_ref()
                    .map_or(String::new(), |e| format!(" ({})", e.evaluation));
                format!("{} at {}{by}", f.name, t.resolution)
            })
            .collect();
        let _ = writeln!(
            md,
            "- **{layout} against the best evaluation** (paper mode or resonant, \
             vs resonant): the table wins in {won} of {} cases{}.",
            of.len(),
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
    for (f, t, v) in &all {
        md.push_str(&verdict_row(&f.name, t, v));
    }
    md.push('\n');
}

/// The heading of the error budget table; its anchor is `#error-budgets`.
pub const BUDGETS_HEADING: &str = "Error budgets";

/// The heading of every table's verdict; its anchor is `#every-table-against-paper-mode`.
pub const EVERY_TABLE_HEADING: &str = "Every table against paper mode";

/// Error budgets of the summary table (worse of uniform and highlight relative RMS).
const BUDGETS: [f64; 6] = [0.01, 0.02, 0.05, 0.1, 0.2, 0.5];

/// The cheapest resonant point of `f` within `budget`.
fn cheapest_resonant(f: &FabricReport, budget: f64) -> Option<&ResonantPoint> {
    f.resonant
        .iter()
        .filter(|r| worst(&r.error) <= budget)
        .min_by(|a, b| a.timing.ns_per_eval.total_cmp(&b.timing.ns_per_eval))
}

/// The cheapest table and the cheapest paper-mode point of `f` within `budget`.
fn cheapest(f: &FabricReport, budget: f64) -> (Option<&TablePoint>, Option<&PaperPoint>) {
    let table = f
        .tables
        .iter()
        .filter(|t| worst(&t.error) <= budget)
        .min_by(|a, b| a.lookup.ns_per_eval.total_cmp(&b.lookup.ns_per_eval));
    let paper = f
        .paper
        .iter()
        .filter(|p| worst(&p.error) <= budget)
        .min_by(|a, b| a.timing.ns_per_eval.total_cmp(&b.timing.ns_per_eval));
    (table, paper)
}

/// One line per error budget: for how many fabrics the table or paper mode is the faster
/// way to meet it, or the only one.
fn budget_bullets(report: &Report, md: &mut String) {
    for budget in BUDGETS {
        let mut counts = [0usize; 5];
        for f in &report.fabrics {
            let k = match cheapest(f, budget) {
                (Some(t), Some(p)) if t.lookup.ns_per_eval <= p.timing.ns_per_eval => 0,
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
            let (table, paper) = cheapest(f, budget);
            let table_cell = table.map_or("none measured".to_string(), |t| {
                format!(
                    "{} ({}, {} ns)",
                    table_name(t.layout, t.resolution),
                    pct(worst(&t.error)),
                    num(t.lookup.ns_per_eval)
                )
            });
            let paper_cell = paper.map_or("none up to the largest N".to_string(), |p| {
                format!(
                    "N = {} ({}, {} ns)",
                    p.samples,
                    pct(worst(&p.error)),
                    num(p.timing.ns_per_eval)
                )
            });
            let faster = match (table, paper) {
                (Some(t), Some(p)) => {
                    let r = p.timing.ns_per_eval / t.lookup.ns_per_eval;
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
            let resonant = cheapest_resonant(f, budget);
            let resonant_cell = resonant.map_or("none measured".to_string(), |r| {
                format!(
                    "{} ({}, {} ns)",
                    r.label,
                    pct(worst(&r.error)),
                    num(r.timing.ns_per_eval)
                )
            });
            // The cheaper of paper mode and resonant within the budget.
            let best = [
                paper.map(|p| (format!("paper N = {}", p.samples), p.timing.ns_per_eval)),
                resonant.map(|r| (format!("resonant {}", r.label), r.timing.ns_per_eval)),
            ]
            .into_iter()
            .flatten()
            .min_by(|a, b| a.1.total_cmp(&b.1));
            let versus = match (table, best) {
                (Some(t), Some((label, ns))) => {
                    let r = ns / t.lookup.ns_per_eval;
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
