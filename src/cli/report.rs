//! `clothbake report`: speed against error for every built-in fabric.

use super::CommandResult;
use clothbake::formats::fabric_toml::FabricSet;
use clothbake::report::stock::StockConfig;
use clothbake::report::{self, ReportConfig};
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct Args {
    /// Fewer resolutions, pairs and repetitions (every fabric still).
    #[arg(long)]
    quick: bool,
    /// Output directory.
    #[arg(long, default_value = "report")]
    out: PathBuf,
    /// Measure nothing: write OUT/REPORT.md, OUT/report.json and the plots again from the
    /// measurements in OUT/report.json, with the comparisons derived again (after a change to
    /// how the report is written).
    #[arg(long, conflicts_with = "quick")]
    rerender: bool,
    /// Measure and write only this section (with --quick, its quick preset): `stock`, every
    /// engine's stock model against every fabric, written as OUT/stock.md and its PNGs and
    /// merged into OUT/report.json (key `stock`) and OUT/REPORT.md where they exist.
    #[arg(long, value_enum, conflicts_with = "rerender")]
    section: Option<Section>,
}

/// A section of the report that runs alone.
#[derive(Clone, Copy, clap::ValueEnum)]
enum Section {
    Stock,
}

pub fn run(args: Args) -> CommandResult {
    if args.rerender {
        report::rerender(&args.out)?;
        println!(
            "{}: REPORT.md written from {}",
            args.out.display(),
            report::JSON_FILE_NAME
        );
        return Ok(());
    }
    let fabrics = FabricSet::builtin().fabrics().to_vec();
    if let Some(Section::Stock) = args.section {
        return stock(&args, &fabrics);
    }
    let config = if args.quick {
        ReportConfig::quick(fabrics)
    } else {
        ReportConfig::full(fabrics)
    };
    let command_line = std::env::args().collect();
    let written = report::run(&config, &args.out, command_line, &mut |line| {
        eprintln!("report: {line}")
    })?;
    println!(
        "{}: {} in {:.0} s",
        args.out.display(),
        written.files.join(", "),
        written.elapsed_seconds
    );
    Ok(())
}

/// `--section stock`.
fn stock(args: &Args, fabrics: &[clothbake::model::Fabric]) -> CommandResult {
    let config = if args.quick {
        StockConfig::quick()
    } else {
        StockConfig::full()
    };
    let command_line = std::env::args().collect();
    let (section, merged) =
        report::run_stock(&config, fabrics, &args.out, command_line, &mut |line| {
            eprintln!("report: {line}")
        })?;
    println!(
        "{}: {} in {:.0} s; {}",
        args.out.display(),
        section.files.join(", "),
        section.seconds,
        if merged {
            format!("merged into {} and REPORT.md", report::JSON_FILE_NAME)
        } else {
            format!("no {} to merge into", report::JSON_FILE_NAME)
        }
    );
    Ok(())
}
