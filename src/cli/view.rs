//! `clothbake view`: the interactive window.

use super::CommandResult;
use super::options::{
    NodeArgs, SHADER_WORDS, SceneArgs, older_shader_word, older_spelling, older_words,
};
use clothbake::evaluator::{self, EvaluatorSpec, paper};
use clothbake::viewer::{self, ViewOptions};

/// The evaluators key V cycles through when `--evaluator` names none: the table, paper mode,
/// the resonant quadrature.
const DEFAULT_EVALUATORS: [&str; 3] = ["table", "paper", "resonant"];

#[derive(clap::Args)]
pub struct Args {
    #[command(flatten)]
    scene: SceneArgs,
    /// Fabric shown first (default: the scene's first).
    #[arg(long)]
    fabric: Option<String>,
    /// Draw N frames, print the median frame time and exit.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=10_000_000))]
    frames: Option<u32>,
    /// An evaluator to show, in the spelling every command shares: table[:PATH], paper[:N],
    /// resonant[:S/V/B], constant. Repeat it for a list that key V cycles through, the first
    /// shown at start (default: table, paper, resonant).
    #[arg(long, conflicts_with_all = ["shader", "samples", "surface_nodes", "volume_nodes", "base_nodes"])]
    evaluator: Vec<EvaluatorSpec>,
    /// The older spelling of --evaluator: the evaluator shown first, the default list after
    /// it: lookup (table), paper or direct (both paper mode with --samples per thread),
    /// resonant (with the node options), constant.
    #[arg(long, value_parser = older_words(SHADER_WORDS))]
    shader: Option<String>,
    /// Tangent samples per thread of paper mode (default 32); alone, it selects paper mode.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=i64::from(paper::MAX_SHADER_SAMPLES)))]
    samples: Option<u32>,
    #[command(flatten)]
    nodes: NodeArgs,
}

pub fn run(args: Args) -> CommandResult {
    let evaluators = if args.evaluator.is_empty() {
        // The older options name the first evaluator; the default list follows it, less the
        // default of the first one's unit.
        let word = older_shader_word(args.shader.as_deref(), args.samples);
        let spelling = older_spelling("--shader", word, SHADER_WORDS, args.samples, &args.nodes)?;
        let unit = |spelling: &str| evaluator::unit_of(spelling).map(|unit| unit.name);
        let mut evaluators = vec![evaluator::parse(&spelling)?];
        for default in DEFAULT_EVALUATORS {
            if unit(default) != unit(&spelling) {
                evaluators.push(evaluator::parse(default)?);
            }
        }
        evaluators
    } else {
        args.evaluator.into_iter().map(|spec| spec.0).collect()
    };
    let summary = viewer::run(ViewOptions {
        scene: args.scene.load()?,
        fabric: args.fabric,
        tables: args.scene.tables,
        mesh: args.scene.mesh,
        frames: args.frames,
        evaluators,
    })?;
    let ms = |v: Option<f64>| v.map_or_else(|| "n/a".to_string(), |v| format!("{v:.2} ms"));
    println!(
        "clothbake view: drew {} frames on {}; median frame time {} (CPU interval), GPU {}",
        summary.frames,
        summary.adapter,
        ms(summary.median_frame_ms),
        ms(summary.median_gpu_ms)
    );
    Ok(())
}
