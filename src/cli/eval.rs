//! `clothbake eval`: F(wi, wo) for JSON lines of direction pairs.

use super::CommandResult;
use super::options::{INTEGRATION_WORDS, NodeArgs, older_spelling, older_words};
use clothbake::evaluator::{self, EvaluationContext, EvaluatorSpec, paper};
use clothbake::formats::fabric_toml::FabricSet;
use clothbake::formats::json_lines::{EvalOutput, eval_stream};
use clothbake::formats::table_exr::read_table;
use clothbake::measure::accuracy::lookup_f32;
use clothbake::sampling::Sampler;
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct Args {
    /// Fabric name.
    #[arg(long)]
    fabric: String,
    /// How F is evaluated, in the spelling every command shares: direct (the default),
    /// paper[:N], resonant[:S/V/B], table[:PATH] (or a path ending in .exr), constant, or an
    /// engine's stock model fitted to the fabric: gltf, openpbr, filament, unreal.
    #[arg(long, conflicts_with_all = ["integration", "samples", "surface_nodes", "volume_nodes", "base_nodes"])]
    evaluator: Option<EvaluatorSpec>,
    /// The older spelling of --evaluator: the converged direct rule (default unless
    /// --samples is given), paper mode (--samples N strata per thread), or the resonant
    /// quadrature (--surface-nodes, --volume-nodes, --base-nodes).
    #[arg(long, value_parser = older_words(INTEGRATION_WORDS))]
    integration: Option<String>,
    /// Paper mode: N stratified samples per thread (alone, it selects paper mode).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=i64::from(paper::MAX_SAMPLES)))]
    samples: Option<u32>,
    #[command(flatten)]
    nodes: NodeArgs,
    /// Fabric file (TOML) to use instead of the built-in fabrics.
    #[arg(long)]
    fabrics: Option<PathBuf>,
    /// Also look each pair up in this table and print it as "table":[r,g,b].
    #[arg(long)]
    table: Option<PathBuf>,
    /// Also print the fabric sampler's density of wi given wo as "pdf":p (the density
    /// `sample` draws with).
    #[arg(long)]
    pdf: bool,
}

pub fn run(args: Args) -> CommandResult {
    let evaluator = match &args.evaluator {
        Some(spec) => spec.0.clone(),
        None => {
            // Alone, --samples selects paper mode.
            let default = if args.samples.is_some() {
                "paper"
            } else {
                "direct"
            };
            let word = args.integration.as_deref().unwrap_or(default);
            evaluator::parse(&older_spelling(
                "--integration",
                word,
                INTEGRATION_WORDS,
                args.samples,
                &args.nodes,
            )?)?
        }
    };
    let set = FabricSet::load_or_builtin(args.fabrics.as_deref())?;
    let fabric = set.require(&args.fabric)?;
    let evaluation = evaluator.prepare(fabric, &EvaluationContext::default())?;
    let table = args.table.map(|path| read_table(&path)).transpose()?;
    let sampler = args.pdf.then(|| Sampler::for_fabric(fabric));
    let stdin = std::io::BufReader::new(std::io::stdin());
    let stdout = std::io::stdout().lock();
    eval_stream(stdin, stdout, |wi, wo| EvalOutput {
        f: evaluation.eval(wi, wo).to_array(),
        table: table
            .as_ref()
            .map(|t| lookup_f32(&t.table, wi, wo).to_array()),
        pdf: sampler.as_ref().map(|s| s.pdf(wo, wi)),
    })?;
    Ok(())
}
