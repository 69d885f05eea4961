//! `clothbake check`: a table's error against the direct evaluation of its fabric.

use super::CommandResult;
use clothbake::bake::manifest;
use clothbake::formats::table_exr::read_table;
use clothbake::measure::accuracy::measure;
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct Args {
    /// The table (EXR) to check.
    table: PathBuf,
    /// Uniform and highlight pairs to measure on (each).
    #[arg(long, default_value_t = 20000, value_parser = clap::value_parser!(u32).range(1..=1_000_000))]
    pairs: u32,
}

pub fn run(args: Args) -> CommandResult {
    let file = read_table(&args.table)?;
    let t = &file.table;
    let error = measure(t, &t.fabric, args.pairs as usize);
    let baked = manifest::entry_for(&args.table, &file.hash).map_or_else(
        || "bake time not recorded (no matching manifest entry)".to_string(),
        |e| format!("baked in {:.1} s on {} threads", e.bake_seconds, e.threads),
    );
    println!(
        "{}: fabric {}, {} at resolution {}, {} KiB of f16 texels, clothbake {} \
         (baker revision {}), {baked}",
        args.table.display(),
        t.fabric.name,
        t.layout,
        t.resolution,
        t.byte_size() / 1024,
        file.version,
        file.baker_revision
    );
    for (label, e) in [
        ("uniform pairs", error.uniform),
        ("  both ≥ 1° elevation", error.uniform_above_1deg),
        ("  both ≥ 3° elevation", error.uniform_above_3deg),
        ("  both ≥ 15° elevation", error.uniform_above_15deg),
        ("highlight pairs", error.highlight),
        ("  both ≥ 1° elevation", error.highlight_above_1deg),
        ("  both ≥ 3° elevation", error.highlight_above_3deg),
    ] {
        println!(
            "  {label:<31} relative RMS {:>7.3}%   max |error| {:.3e} (where F = {:.3e})",
            100.0 * e.relative_rms,
            e.max_abs,
            e.max_abs_at_value
        );
    }
    Ok(())
}
