//! `clothbake view`: the interactive window.

use super::CommandResult;
use super::options::{
    NodeArgs, SHADER_WORDS, SceneArgs, older_shader_word, older_spelling, older_words,
};
use clothbake::editor::script::Script;
use clothbake::editor::session::EditSession;
use clothbake::evaluator::Evaluator;
use clothbake::evaluator::{self, EvaluatorSpec, paper};
use clothbake::render::median;
use clothbake::scene::Scene;
use clothbake::table::Layout;
use clothbake::viewer::{self, EditSetup, EditTimings, ViewOptions};
use std::path::PathBuf;
use std::sync::Arc;

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
    /// resonant[:S/V/B], constant, gltf, openpbr, filament, unreal. Repeat it for a list that key V cycles through, the first
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
    /// Edit a fabric with the panel: a built-in fabric, a named weave (`satin`, `twill:2/1`),
    /// a fabric file (with --fabric to choose among its fabrics) or a WIF file; alone, the
    /// fabric --fabric or the scene names first. The drape is shaded by the first
    /// --evaluator that is not a table, else by the resonant quadrature, and its table is
    /// baked in the background.
    #[arg(long, num_args = 0..=1, default_missing_value = "", value_name = "FABRIC_OR_FILE")]
    edit: Option<String>,
    /// With --edit: run the panel's actions from FILE, one per line, frame by frame, then
    /// exit (docs/editor.md#scripts); exits with an error if a step failed.
    #[arg(long, requires = "edit")]
    script: Option<PathBuf>,
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
        args.evaluator.iter().map(|spec| spec.0.clone()).collect()
    };
    let scene = args.scene.load()?;
    let edit = match &args.edit {
        None => None,
        Some(target) => Some(edit_setup(target, &args, &scene, &evaluators)?),
    };
    let summary = viewer::run(ViewOptions {
        scene,
        fabric: args.fabric,
        tables: args.scene.tables,
        mesh: args.scene.mesh,
        frames: args.frames,
        evaluators,
        edit,
    })?;
    let ms = |v: Option<f64>| v.map_or_else(|| "n/a".to_string(), |v| format!("{v:.2} ms"));
    println!(
        "clothbake view: drew {} frames on {}; median frame time {} (CPU interval), GPU {}",
        summary.frames,
        summary.adapter,
        ms(summary.median_frame_ms),
        ms(summary.median_gpu_ms)
    );
    if let Some(edit) = summary.edit {
        print_edit_summary(&edit.timings);
        if edit.failed_steps > 0 {
            return Err(format!("{} script step(s) failed (see above)", edit.failed_steps).into());
        }
    }
    Ok(())
}

/// The session `--edit TARGET` opens, the evaluator edits are shaded by, the background
/// bake's table and the script.
fn edit_setup(
    target: &str,
    args: &Args,
    scene: &Scene,
    evaluators: &[Arc<dyn Evaluator>],
) -> Result<EditSetup, Box<dyn std::error::Error>> {
    let session = if !target.is_empty() {
        EditSession::from_target(target, args.fabric.as_deref())?
    } else {
        let name = args
            .fabric
            .as_deref()
            .or(scene.fabrics.first().map(String::as_str));
        let name = name.ok_or("the scene names no fabric to edit")?;
        match &scene.fabric_file {
            Some(file) => EditSession::from_file(file, Some(name))?,
            None => EditSession::builtin(name)?,
        }
    };
    let table = |e: &Arc<dyn Evaluator>| {
        evaluator::unit_of(&e.spelling()).is_some_and(|unit| unit.name == "table")
    };
    // The model's live shading: the first evaluator named that is not a table, else the
    // resonant quadrature, whose GPU form takes each edit in its uniforms.
    let named = if args.evaluator.is_empty() {
        None
    } else {
        evaluators.iter().find(|e| !table(e))
    };
    let evaluator = match named {
        Some(e) => e.clone(),
        None => evaluator::parse("resonant")?,
    };
    let script = args.script.as_deref().map(Script::load).transpose()?;
    Ok(EditSetup {
        session,
        evaluator,
        table: (Layout::DEFAULT, Layout::DEFAULT.default_resolution()),
        script,
    })
}

/// The editing session's frame times, as medians (milliseconds).
fn print_edit_summary(timings: &EditTimings) {
    let line = |what: &str, values: &[f64]| match median(values) {
        Some(m) => println!(
            "clothbake view: {what}: median {m:.2} ms over {} frames, longest {:.2} ms",
            values.len(),
            values.iter().copied().fold(0.0, f64::max)
        ),
        None => println!("clothbake view: {what}: no frames"),
    };
    line("frame shaded by the model", &timings.model_frames);
    line("frame shaded by the table", &timings.table_frames);
    line("frame while a bake ran", &timings.baking_frames);
    line("edit to its first shaded frame", &timings.edit_to_frame);
}
