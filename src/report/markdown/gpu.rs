//! REPORT.md's GPU section: frame times and image errors of every shader on the standard scene.

use crate::report::format::{NONE_UP_TO_THE_LARGEST, baseline_name, pct, ratio};
use crate::report::{Evaluation, Report, plots};
use std::fmt::Write;

/// The GPU section: the lookup shader against the baseline's shader and every other
/// evaluator's, and every shader's frame time and image error.
pub(super) fn gpu_section(report: &Report, md: &mut String) {
    let g = &report.gpu;
    let _ = writeln!(md, "## GPU\n");
    let _ = writeln!(
        md,
        "Adapter: {}. {}.\n",
        g.adapter.as_deref().unwrap_or("none found"),
        g.status
    );
    if !g.measured {
        return;
    }
    let [w, h] = g.frame.unwrap_or_default();
    let _ = writeln!(
        md,
        "The standard scene (tables/scene.toml: the cloth draped over a sphere, a directional \
         and a point light) rendered headless at {w}×{h} for each fabric, by the lookup shader \
         (of the fabric's tables measured above, the default layout at its default \
         resolution, as `bake` makes it, else the largest of that layout), and by the GPU form \
         of each evaluator: {}. Time: median of {} frames after a warm-up frame ({}). Image \
         error: ‖render − reference‖₂/‖reference‖₂ of the linear radiance over the covered \
         pixels, against the CPU reference render (direct evaluation of the same G-buffer).\n",
        report.config.gpu_evaluators.join(", "),
        g.frames,
        g.timing_source.as_deref().unwrap_or("unknown timing")
    );
    let _ = writeln!(md, "![GPU error against cost]({})\n", plots::GPU_COST);
    let base = baseline_name();
    let _ = writeln!(
        md,
        "| fabric | lookup ms/frame | lookup image error | {base} at equal error | lookup faster \
         by | {base} at equal cost | lookup more accurate by | winner |"
    );
    let _ = writeln!(md, "|---|---:|---:|---|---:|---|---:|---|");
    for f in &g.fabrics {
        let Some(lookup) = f.lookup() else {
            continue;
        };
        let baseline: Vec<&crate::report::gpu::GpuPoint> = f
            .points
            .iter()
            .filter(|p| p.evaluation.is_baseline())
            .collect();
        let points: Vec<(f64, f64)> = baseline
            .iter()
            .map(|p| (p.ms_per_frame, p.image_relative_l2))
            .collect();
        let (error, cost) = (lookup.image_relative_l2, lookup.ms_per_frame);
        let (equal_error, equal_cost, dominated) = crate::report::dominance(error, cost, &points);
        let n = |i: usize| &baseline[i].evaluation;
        let _ = writeln!(
            md,
            "| {} | {:.2} | {} | {} | {} | {} | {} | {} |",
            f.name,
            cost,
            pct(error),
            equal_error.map_or(NONE_UP_TO_THE_LARGEST.into(), |i| format!(
                "{} ({:.2} ms)",
                n(i),
                points[i].0
            )),
            ratio(equal_error.map(|i| points[i].0 / cost)),
            equal_cost.map_or("none this cheap".into(), |i| format!(
                "{} ({})",
                n(i),
                pct(points[i].1)
            )),
            ratio(equal_cost.map(|i| points[i].1 / error)),
            if dominated { base } else { "**table**" }
        );
    }
    md.push('\n');
    let _ = writeln!(
        md,
        "Every other evaluator's shader against the lookup (frame time ratio; image \
         errors):\n\n\
         | fabric | shader | ms/frame | × lookup's frame | image error | lookup's image error |\n\
         |---|---|---:|---:|---:|---:|"
    );
    for f in &g.fabrics {
        let Some(lookup) = f.lookup() else {
            continue;
        };
        for p in &f.points {
            if !p.evaluation.is_model() || p.evaluation.is_baseline() {
                continue;
            }
            let _ = writeln!(
                md,
                "| {} | {} | {:.2} | {:.1}× | {} | {} |",
                f.name,
                p.evaluation,
                p.ms_per_frame,
                p.ms_per_frame / lookup.ms_per_frame,
                pct(p.image_relative_l2),
                pct(lookup.image_relative_l2)
            );
        }
    }
    md.push('\n');
    let _ = writeln!(md, "Every shader:\n");
    let _ = writeln!(
        md,
        "| fabric | shader | ms/frame | image error | PSNR (dB) | reference (s) |"
    );
    let _ = writeln!(md, "|---|---|---:|---:|---:|---:|");
    for f in &g.fabrics {
        for p in &f.points {
            let shader = match &p.evaluation {
                table @ Evaluation::Table { .. } => format!("lookup ({table})"),
                evaluator => evaluator.to_string(),
            };
            let _ = writeln!(
                md,
                "| {} | {shader} | {:.3} | {} | {:.1} | {:.1} |",
                f.name,
                p.ms_per_frame,
                pct(p.image_relative_l2),
                p.image_psnr_db,
                f.reference_seconds
            );
        }
    }
    md.push('\n');
}
