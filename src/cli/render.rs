//! `clothbake render`: the scene's cloth rendered headless to PNG.

use super::CommandResult;
use super::options::{
    NodeArgs, SHADER_WORDS, SceneArgs, older_shader_word, older_spelling, older_words,
};
use clothbake::evaluator::{self, EvaluatorSpec, paper};
use clothbake::render::job::{self, RenderJob};
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct Args {
    #[command(flatten)]
    scene: SceneArgs,
    /// Render only this fabric (default: every fabric of the scene, to OUT-STEM-NAME.png).
    #[arg(long)]
    fabric: Option<String>,
    /// Output PNG.
    #[arg(long)]
    out: PathBuf,
    #[arg(long, default_value_t = 1024)]
    width: u32,
    #[arg(long, default_value_t = 1024)]
    height: u32,
    /// Timed frames (after one warm-up frame); the median is printed.
    #[arg(long, default_value_t = 10, value_parser = clap::value_parser!(u32).range(1..=10_000))]
    frames: u32,
    /// How the shader evaluates F, in the spelling every command shares: table[:PATH] (the
    /// default: each fabric's table in --tables), paper[:N], resonant[:S/V/B], constant, or an
    /// engine's stock model fitted to the fabric: gltf, openpbr, filament, unreal.
    #[arg(long, conflicts_with_all = ["shader", "samples", "surface_nodes", "volume_nodes", "base_nodes"])]
    evaluator: Option<EvaluatorSpec>,
    /// The older spelling of --evaluator: lookup (table), paper or direct (both paper mode
    /// with --samples per thread), resonant (with the node options), constant.
    #[arg(long, value_parser = older_words(SHADER_WORDS))]
    shader: Option<String>,
    /// Tangent samples per thread of paper mode (default 32); alone, it selects paper mode.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=i64::from(paper::MAX_SHADER_SAMPLES)))]
    samples: Option<u32>,
    #[command(flatten)]
    nodes: NodeArgs,
    /// Also render the view on the CPU by direct evaluation: writes STEM-reference.png and
    /// STEM-error.png and prints the image error. Under an environment light, F by the
    /// resonant quadrature and the environment by Monte Carlo (--reference-samples).
    #[arg(long)]
    reference: bool,
    /// Importance samples per pixel of the reference's environment term.
    #[arg(long, default_value_t = 1024, value_parser = clap::value_parser!(u32).range(1..=1_000_000))]
    reference_samples: u32,
    /// Also write the linear radiance (before exposure and tone mapping) as an OpenEXR
    /// file of f16 RGBA beside each PNG (STEM.exr; alpha 1 on cloth, 0 on background).
    #[arg(long)]
    linear: bool,
}

pub fn run(args: Args) -> CommandResult {
    let evaluator = match &args.evaluator {
        Some(spec) => spec.0.clone(),
        None => evaluator::parse(&older_spelling(
            "--shader",
            older_shader_word(args.shader.as_deref(), args.samples),
            SHADER_WORDS,
            args.samples,
            &args.nodes,
        )?)?,
    };
    let job = RenderJob {
        scene: args.scene.load()?,
        fabric: args.fabric,
        tables: args.scene.tables,
        out: args.out,
        width: args.width,
        height: args.height,
        frames: args.frames,
        evaluator,
        reference: args.reference,
        reference_samples: args.reference_samples,
        linear: args.linear,
        mesh: args.scene.mesh,
    };
    job::run(&job, &mut |line| println!("{line}"))?;
    Ok(())
}
