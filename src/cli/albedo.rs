//! `clothbake albedo`: each fabric's directional albedo over outgoing elevation.

use super::CommandResult;
use super::options::evaluation_of;
use clothbake::evaluator::EvaluatorSpec;
use clothbake::formats::fabric_toml::FabricSet;
use clothbake::formats::table_exr::read_table;
use clothbake::model::Fabric;
use clothbake::sampling::{Sampler, albedo_curve, describe_albedo};
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct Args {
    /// Fabric names (default: every fabric).
    #[arg(long, num_args = 1.., conflicts_with = "table")]
    fabric: Vec<String>,
    /// Fabric file (TOML) to use instead of the built-in fabrics.
    #[arg(long)]
    fabrics: Option<PathBuf>,
    /// F from this table's lookup (its own fabric) instead of the direct evaluation.
    #[arg(long, conflicts_with = "evaluator")]
    table: Option<PathBuf>,
    /// How F is evaluated (direct, paper[:N], resonant[:S/V/B], table[:PATH], constant, or
    /// a stock model: gltf, openpbr, filament, unreal).
    #[arg(long)]
    evaluator: Option<EvaluatorSpec>,
    /// Importance samples per outgoing direction.
    #[arg(long, default_value_t = 1024, value_parser = clap::value_parser!(u32).range(16..=1_000_000))]
    samples: u32,
}

pub fn run(args: Args) -> CommandResult {
    let set = FabricSet::load_or_builtin(args.fabrics.as_deref())?;
    let chosen: Vec<Fabric> = match &args.table {
        Some(path) => vec![read_table(path)?.table.fabric],
        None => set.select(&args.fabric)?,
    };
    let samples = args.samples as usize;
    for fabric in &chosen {
        let f = evaluation_of(fabric, args.evaluator.as_ref(), args.table.as_deref())?;
        let rows = albedo_curve(
            &Sampler::for_fabric(fabric),
            |wi, wo| f.eval(wi, wo),
            samples,
        );
        print!("{}", describe_albedo(&fabric.name, &rows, samples));
    }
    Ok(())
}
