//! `clothbake eval`: F(wi, wo) for JSON lines of direction pairs.

use super::CommandResult;
use super::options::{NodeArgs, UsageError};
use clothbake::evaluator::direct::Direct;
use clothbake::evaluator::paper::Paper;
use clothbake::evaluator::resonant::Resonant;
use clothbake::evaluator::{EvaluationContext, Evaluator, EvaluatorSpec};
use clothbake::formats::fabric_toml::FabricSet;
use clothbake::formats::json_lines::{EvalOutput, eval_stream};
use clothbake::formats::table_exr::read_table;
use clothbake::measure::accuracy::lookup_f32;
use clothbake::model::curve::DEFAULT_PAPER_SAMPLES;
use clothbake::sampling::Sampler;
use std::path::PathBuf;
use std::sync::Arc;

#[derive(clap::Args)]
pub struct Args {
    /// Fabric name.
    #[arg(long)]
    fabric: String,
    /// How F is evaluated, in the spelling every command shares: direct (the default),
    /// paper[:N], resonant[:S/V/B], table[:PATH] (or a path ending in .exr), constant.
    #[arg(long, conflicts_with_all = ["integration", "samples", "surface_nodes", "volume_nodes", "base_nodes"])]
    evaluator: Option<EvaluatorSpec>,
    /// The older spelling of --evaluator: the converged direct rule (default unless
    /// --samples is given), paper mode (--samples N strata per thread), or the resonant
    /// quadrature (--surface-nodes, --volume-nodes, --base-nodes).
    #[arg(long, value_enum)]
    integration: Option<IntegrationArg>,
    /// Paper mode: N stratified samples per thread (alone, it selects paper mode).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=1_000_000))]
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

#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
enum IntegrationArg {
    /// The converged direct rule, the ground truth.
    Direct,
    /// Paper mode: --samples N stratified samples per thread (default 32).
    Paper,
    /// The resonant quadrature (--surface-nodes, --volume-nodes, --base-nodes).
    Resonant,
}

/// The evaluator that `--integration`, `--samples` and the node options select; names the
/// option that does not fit.
fn evaluator_of_rule_options(args: &Args) -> Result<Arc<dyn Evaluator>, UsageError> {
    let samples = args.samples;
    let integration = args.integration.unwrap_or(match samples {
        Some(_) => IntegrationArg::Paper,
        None => IntegrationArg::Direct,
    });
    let nodes = args.nodes.nodes(
        integration == IntegrationArg::Resonant,
        "--integration resonant",
    )?;
    let misplaced = |rule: &str| {
        UsageError(format!(
            "--samples applies to paper mode, not --integration {rule}"
        ))
    };
    match integration {
        IntegrationArg::Direct if samples.is_some() => Err(misplaced("direct")),
        IntegrationArg::Direct => Ok(Arc::new(Direct)),
        IntegrationArg::Paper => Ok(Arc::new(Paper {
            samples: samples.unwrap_or(DEFAULT_PAPER_SAMPLES),
        })),
        IntegrationArg::Resonant if samples.is_some() => Err(misplaced("resonant")),
        IntegrationArg::Resonant => Ok(Arc::new(Resonant { nodes })),
    }
}

pub fn run(args: Args) -> CommandResult {
    let evaluator = match &args.evaluator {
        Some(spec) => spec.0.clone(),
        None => evaluator_of_rule_options(&args)?,
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
