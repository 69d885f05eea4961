//! The report's files: REPORT.md and report.json written atomically, and report.json read
//! back, so that REPORT.md can be rendered again from the data without measuring anything
//! ([`rerender`]).

use super::{Evaluation, Report, ReportError, markdown};
use crate::measure::accuracy::{SetError, TableError};
use serde::{Deserialize, Deserializer};
use std::path::Path;

/// The JSON file's name in the output directory.
pub const JSON_FILE_NAME: &str = "report.json";

/// Writes `text` to `out/name` atomically: a temporary file beside it, synced, then renamed
/// over it, so that a reader never sees half a page.
pub(super) fn write_file(out: &Path, name: &str, text: &str) -> Result<(), ReportError> {
    let path = out.join(name);
    crate::formats::atomic::write_atomically(&path, text.as_bytes())
        .map_err(|source| ReportError::Io { path, source })
}

/// Reads `out/report.json`, as a report run wrote it, and derives every point's comparisons
/// from its figures ([`super::FabricReport::judge`]).
pub fn read(out: &Path) -> Result<Report, ReportError> {
    let path = out.join(JSON_FILE_NAME);
    let text = std::fs::read_to_string(&path).map_err(|source| ReportError::Read {
        path: path.clone(),
        source,
    })?;
    let mut report: Report =
        serde_json::from_str(&text).map_err(|source| ReportError::Json { path, source })?;
    derive_spellings(&mut report);
    report
        .fabrics
        .iter_mut()
        .for_each(super::FabricReport::judge);
    Ok(report)
}

/// Fills the configuration's evaluator spellings from the points where a report.json written
/// before they were recorded left them out: every evaluator measured, in the order of the
/// points.
fn derive_spellings(report: &mut Report) {
    fn spellings<'a>(evaluations: impl Iterator<Item = &'a Evaluation>) -> Vec<String> {
        let mut out: Vec<String> = Vec::new();
        for evaluation in evaluations {
            if let Evaluation::Evaluator { spelling } = evaluation
                && !out.contains(spelling)
            {
                out.push(spelling.clone());
            }
        }
        out
    }
    let config = &mut report.config;
    if config.evaluators.is_empty() {
        config.evaluators = spellings(
            report
                .fabrics
                .iter()
                .flat_map(|f| f.points.iter().map(|p| &p.evaluation)),
        );
    }
    if config.gpu_evaluators.is_empty() {
        config.gpu_evaluators = spellings(
            report
                .gpu
                .fabrics
                .iter()
                .flat_map(|f| f.points.iter().map(|p| &p.evaluation)),
        );
    }
}

/// report.json's text.
pub(super) fn json(report: &Report) -> Result<String, ReportError> {
    serde_json::to_string_pretty(report)
        .map_err(|e| ReportError::Config(format!("cannot serialise the report: {e}")))
}

/// Renders `out/REPORT.md`, the stock section's page and the plots (not the stock
/// section's grid of renders, which report.json does not hold) again from the measurements
/// in `out/report.json`, measuring nothing, and writes REPORT.md and report.json atomically with the comparisons
/// derived again; returns the report read.
pub fn rerender(out: &Path) -> Result<Report, ReportError> {
    let report = read(out)?;
    super::plots::write_all(&report, out)?;
    write_file(out, markdown::FILE_NAME, &markdown::render(&report))?;
    if let Some(section) = &report.stock {
        let page = super::stock::PAGE_FILE_NAME;
        write_file(out, page, &markdown::stock::page(section))?;
    }
    write_file(out, JSON_FILE_NAME, &json(&report)?)?;
    Ok(report)
}

/// serde's view of [`SetError`] for reading: `crate::measure::accuracy` writes its errors but does
/// not read them, so the report reads them through these mirrors (serde's remote derive,
/// which checks at compile time that the mirror names every field).
#[derive(Deserialize)]
#[serde(remote = "SetError")]
struct SetErrorDef {
    relative_rms: f64,
    max_abs: f64,
    max_abs_at_value: f64,
}

/// serde's view of [`TableError`] for reading (see [`SetErrorDef`]).
#[derive(Deserialize)]
#[serde(remote = "TableError")]
struct TableErrorDef {
    #[serde(with = "SetErrorDef")]
    uniform: SetError,
    #[serde(with = "SetErrorDef")]
    highlight: SetError,
    #[serde(with = "SetErrorDef")]
    uniform_above_1deg: SetError,
    #[serde(with = "SetErrorDef")]
    uniform_above_3deg: SetError,
    #[serde(with = "SetErrorDef")]
    uniform_above_15deg: SetError,
    #[serde(with = "SetErrorDef")]
    highlight_above_1deg: SetError,
    #[serde(with = "SetErrorDef")]
    highlight_above_3deg: SetError,
}

/// Reads a [`TableError`] (`#[serde(deserialize_with)]` of the report's points).
pub(super) fn table_error<'de, D: Deserializer<'de>>(d: D) -> Result<TableError, D::Error> {
    TableErrorDef::deserialize(d)
}
