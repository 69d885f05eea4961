//! `clothbake sample`: importance samples of F for JSON lines of (wo, u).

use super::CommandResult;
use super::options::evaluation_of;
use clothbake::evaluator::EvaluatorSpec;
use clothbake::formats::fabric_toml::FabricSet;
use clothbake::formats::json_lines::{SampleOutput, sample_stream};
use clothbake::sampling::Sampler;
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct Args {
    /// Fabric name.
    #[arg(long)]
    fabric: String,
    /// Fabric file (TOML) to use instead of the built-in fabrics.
    #[arg(long)]
    fabrics: Option<PathBuf>,
    /// F from this table's lookup instead of the direct evaluation (`--evaluator table:PATH`).
    #[arg(long, conflicts_with = "evaluator")]
    table: Option<PathBuf>,
    /// How F is evaluated (direct, paper[:N], resonant[:S/V/B], table[:PATH], constant, or
    /// a stock model: gltf, openpbr, filament, unreal);
    /// the directions are drawn by the fabric's sampler whatever F is.
    #[arg(long)]
    evaluator: Option<EvaluatorSpec>,
}

pub fn run(args: Args) -> CommandResult {
    let set = FabricSet::load_or_builtin(args.fabrics.as_deref())?;
    let fabric = set.require(&args.fabric)?;
    let f = evaluation_of(fabric, args.evaluator.as_ref(), args.table.as_deref())?;
    let sampler = Sampler::for_fabric(fabric);
    let stdin = std::io::BufReader::new(std::io::stdin());
    let stdout = std::io::stdout().lock();
    sample_stream(stdin, stdout, |wo, u| match sampler.sample(wo, u) {
        Some(s) => SampleOutput {
            wi: Some(s.wi.to_array()),
            pdf: s.pdf,
            weight: (f.eval(s.wi, wo) / s.pdf).to_array(),
        },
        None => SampleOutput::REJECTED,
    })?;
    Ok(())
}
