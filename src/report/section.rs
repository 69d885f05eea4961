//! The stock section's files ([`super::stock`]): stock.md, its plot and its picture grid,
//! written by a whole report run and by `clothbake report --section stock`, which measures
//! the section alone and merges it into the report.json of the output directory.

use super::files::{JSON_FILE_NAME, json, read, write_file};
use super::plots::stock::{STOCK_ERROR, STOCK_GRID, stock_error, stock_grid};
use super::stock::{self, PAGE_FILE_NAME, StockConfig, StockRun, StockSection};
use super::{ReportError, markdown};
use crate::model::Fabric;
use std::path::Path;

fn plot_error(file: &str, e: Box<dyn std::error::Error>) -> ReportError {
    ReportError::Plot {
        file: file.to_string(),
        message: e.to_string(),
    }
}

/// Writes the section's plot, its grid (where rendered) and stock.md into `out`; records
/// the files in the section and returns it.
pub(super) fn write_stock(run: StockRun, out: &Path) -> Result<StockSection, ReportError> {
    let mut section = run.section;
    stock_error(&section, &out.join(STOCK_ERROR)).map_err(|e| plot_error(STOCK_ERROR, e))?;
    section.files = vec![PAGE_FILE_NAME.to_string(), STOCK_ERROR.to_string()];
    if let Some(grid) = &run.grid {
        stock_grid(&grid.columns, &grid.rows, &out.join(STOCK_GRID))
            .map_err(|e| plot_error(STOCK_GRID, e))?;
        section.files.push(STOCK_GRID.to_string());
    }
    write_file(out, PAGE_FILE_NAME, &markdown::stock::page(&section))?;
    Ok(section)
}

/// `clothbake report --section stock`: measures the stock section of `fabrics` alone,
/// writes its files into `out`, and where `out` holds a report.json, sets its `stock` key
/// and writes REPORT.md again from it (with the section's summary and link). Returns the
/// section and whether a report.json took it.
pub fn run_stock(
    config: &StockConfig,
    fabrics: &[Fabric],
    out: &Path,
    command_line: Vec<String>,
    progress: &mut dyn FnMut(&str),
) -> Result<(StockSection, bool), ReportError> {
    if fabrics.is_empty() {
        return Err(ReportError::Config("no fabrics to report on".into()));
    }
    std::fs::create_dir_all(out).map_err(|source| ReportError::Io {
        path: out.to_path_buf(),
        source,
    })?;
    let mut run = stock::measure(config, fabrics, progress)?;
    run.section.command_line = command_line;
    let section = write_stock(run, out)?;
    if !out.join(JSON_FILE_NAME).is_file() {
        return Ok((section, false));
    }
    let mut report = read(out)?;
    for file in &section.files {
        if !report.files.contains(file) {
            report.files.push(file.clone());
        }
    }
    report.stock = Some(section.clone());
    write_file(out, markdown::FILE_NAME, &markdown::render(&report))?;
    write_file(out, JSON_FILE_NAME, &json(&report)?)?;
    Ok((section, true))
}
