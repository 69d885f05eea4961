//! The stock section's page (stock.md) and its summary in REPORT.md, every sentence made
//! from the figures.

use super::super::format::{pct, ratio};
use super::super::plots::stock::{STOCK_ERROR, STOCK_GRID};
use super::super::stock::{PAGE_FILE_NAME, StockFabric, StockPoint, StockSection};
use std::fmt::Write;

/// The section's heading, on its page and in REPORT.md.
pub const HEADING: &str = "Every engine's stock model";

fn opt_pct(x: Option<f64>) -> String {
    x.map_or("–".into(), pct)
}

/// The target's name and its model's, as a cell says them.
fn target_name(section: &StockSection, point: &StockPoint) -> String {
    let model = section
        .targets
        .iter()
        .find(|t| t.name == point.target)
        .map_or("", |t| t.model.as_str());
    if model.is_empty() || model == point.target {
        format!("`{}`", point.target)
    } else {
        format!("`{}` ({model})", point.target)
    }
}

/// Which target comes closest to one fabric, in words: by the worse relative RMS of F, how
/// far the others and the default table are, and by the drape image where that differs.
pub fn closest_sentence(section: &StockSection, f: &StockFabric) -> String {
    let Some(best) = f.closest() else {
        return format!("**{}**: no target measured.", f.name);
    };
    let mut ranked: Vec<&StockPoint> = f.points.iter().collect();
    ranked.sort_by(|a, b| a.worst().total_cmp(&b.worst()));
    let mut text = format!(
        "**{}**: {} comes closest, {} relative RMS of F on its worse set",
        f.name,
        target_name(section, best),
        pct(best.worst())
    );
    if let Some(worst) = ranked.last().filter(|w| w.target != best.target) {
        let _ = write!(
            text,
            " (the farthest, {}, {})",
            target_name(section, worst),
            pct(worst.worst())
        );
    }
    match &f.table {
        Some(t) => {
            let _ = write!(
                text,
                "; that is {} the default table's {}",
                ratio(Some(best.worst() / t.worst()).filter(|r| r.is_finite())),
                pct(t.worst())
            );
        }
        None => text.push_str("; no default table to compare with"),
    }
    if let Some(drape) = f.closest_by(|p| p.image_relative_l2) {
        let e = drape.image_relative_l2.unwrap_or(f64::NAN);
        if drape.target == best.target {
            let _ = write!(text, ". It is also closest on the drape image ({})", pct(e));
        } else {
            let _ = write!(
                text,
                ". On the drape image {} comes closest ({}, against {})",
                target_name(section, drape),
                pct(e),
                opt_pct(best.image_relative_l2)
            );
        }
    }
    text.push('.');
    text
}

fn figures_table(section: &StockSection, md: &mut String) {
    let _ = writeln!(
        md,
        "| fabric | target (model) | F uniform | F highlight | albedo RMS | albedo largest (at \
         elevation) | drape image | drape PSNR | default table uniform | default table \
         highlight |"
    );
    let _ = writeln!(md, "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|");
    for f in &section.fabrics {
        let (tu, th) = f.table.as_ref().map_or(("–".into(), "–".into()), |t| {
            (pct(t.uniform), pct(t.highlight))
        });
        for p in &f.points {
            let _ = writeln!(
                md,
                "| {} | {} | {} | {} | {} | {} (at {:.0}°) | {} | {} | {tu} | {th} |",
                f.name,
                target_name(section, p),
                pct(p.uniform),
                pct(p.highlight),
                pct(p.albedo_rms_relative),
                pct(p.albedo_largest_relative),
                p.albedo_at_elevation_deg,
                opt_pct(p.image_relative_l2),
                p.image_psnr_db
                    .map_or("–".into(), |db| format!("{db:.1} dB")),
            );
        }
    }
    let _ = writeln!(md);
}

fn method(section: &StockSection, md: &mut String) {
    let table = section
        .fabrics
        .iter()
        .find_map(|f| f.table.as_ref())
        .map_or(String::new(), |t| format!(" ({})", t.label));
    let _ = writeln!(
        md,
        "Each fabric fitted by the stock cloth model of every export target (`clothbake export \
         --to TARGET`, the registry `export::TARGETS`), and what the fit loses against the \
         fabric (`export::loss`): the relative RMS of F, `sqrt(Σ|F_stock − F|² / Σ|F|²)`, \
         against the direct evaluation on {pairs} uniform pairs (seed {:#x}) and {pairs} \
         highlight pairs (seed {:#x}); the directional albedo's relative error over outgoing \
         elevations ({} importance samples per direction; RMS over the elevations, and the \
         largest); and the drape's image error (relative L2 of linear radiance, and PSNR of \
         the tone-mapped images) under the standard scene's camera and lights, without \
         environment (`render::drape_loss`). Beside them, the fabric's default table, \
         `{}/NAME.exr` read by the `table` evaluator{table}, on the same pairs.\n",
        crate::measure::accuracy::UNIFORM_SEED,
        crate::measure::accuracy::HIGHLIGHT_SEED,
        section.albedo_samples,
        section.config.tables.display(),
        pairs = section.loss_pairs,
    );
}

/// stock.md: the section on its own page.
pub fn page(section: &StockSection) -> String {
    let mut md = String::new();
    let _ = writeln!(md, "# {HEADING}\n");
    let _ = writeln!(
        md,
        "Generated by `{}` on {}, clothbake {}{}, in {:.0} s; the figures are also in \
         `report.json` under `stock`. Adapter: {}. Status: {}.\n",
        section.command_line.join(" "),
        section.date_utc,
        section.clothbake_version,
        section
            .git_commit
            .as_ref()
            .map_or(String::new(), |c| format!(" (commit {c})")),
        section.seconds,
        section.adapter.as_deref().unwrap_or("none found"),
        section.status,
    );
    method(section, &mut md);
    let _ = writeln!(md, "## Which target comes closest\n");
    for f in &section.fabrics {
        let _ = writeln!(md, "- {}", closest_sentence(section, f));
    }
    let _ = writeln!(md, "\n## Figures\n");
    figures_table(section, &mut md);
    let _ = writeln!(md, "![stock models' errors]({STOCK_ERROR})\n");
    let _ = writeln!(
        md,
        "Per fabric, each target's relative RMS of F on the uniform pairs (circles) and the \
         highlight pairs (triangles) and its drape image error (crosses), then the default \
         table's on the same pairs; log scale.\n"
    );
    if section.files.iter().any(|f| f == STOCK_GRID) {
        let c = &section.config;
        let columns: Vec<String> = std::iter::once("the default table's lookup".to_string())
            .chain(section.targets.iter().map(|t| format!("`{}`", t.name)))
            .collect();
        let _ = writeln!(md, "## The drapes\n");
        let _ = writeln!(
            md,
            "![drapes by the table and each stock model]({STOCK_GRID})\n"
        );
        let _ = writeln!(
            md,
            "The standard scene's drape under its environment ({}, {} filtered importance \
             samples per pixel, taps built from each evaluation's sampler) and lights, \
             {}×{} pixels per tile, rendered headless by the GPU forms: per fabric a row, the \
             columns {}, each target's model as fitted above.",
            section.environment,
            c.environment_samples,
            c.tile,
            c.tile,
            columns.join(", ")
        );
    }
    md
}

/// REPORT.md's summary of the section, linking to its page.
pub fn summary(section: &StockSection, md: &mut String) {
    let _ = writeln!(md, "## {HEADING}\n");
    let _ = writeln!(
        md,
        "The best fit of every export target's stock cloth model to each fabric, against the \
         default table, is on its own page, [{PAGE_FILE_NAME}]({PAGE_FILE_NAME}) (measured {}), \
         with the figures, a plot and the drapes side by side. Per fabric:\n",
        section.date_utc
    );
    for f in &section.fabrics {
        let _ = writeln!(md, "- {}", closest_sentence(section, f));
    }
    let _ = writeln!(md);
}
