//! Where a fitted fabric came from, as the comment lines above it in its fabric file
//! ([`crate::formats::fabric_toml::write_fabric_file`] writes it atomically).

use super::samples::Samples;
use super::solve::FitReport;

/// The provenance of a fit, one fact a line: `command`, the samples' file and SHA-256, the
/// counts, the fit's and the held-out relative RMS, and the directions the samples left
/// unconstrained.
pub fn fit_provenance(report: &FitReport, samples: &Samples, command: &str) -> String {
    let mut lines = vec![
        format!("Fitted by clothbake fit: {command}"),
        format!("samples: {} (SHA-256 {})", samples.origin, samples.sha256),
        format!(
            "{} samples: {} fitted, {} held out (every {}th)",
            report.fit_count + report.holdout_count,
            report.fit_count,
            report.holdout_count,
            report.options.holdout_every
        ),
        format!(
            "relative RMS of the direct evaluation: fitted samples {:.4}%, held out {}",
            100.0 * report.fit_relative_rms,
            report
                .holdout_relative_rms
                .map_or("(none)".to_string(), |r| format!("{:.4}%", 100.0 * r))
        ),
    ];
    if report.flat_directions.is_empty() {
        lines.push("every parameter constrained by the samples".into());
    }
    for d in &report.flat_directions {
        lines.push(format!("unconstrained: {d}"));
    }
    lines.join("\n")
}
