//! `clothbake view`: the interactive window.

use super::CommandResult;
use super::options::{SceneArgs, ShaderArg, UsageError};
use clothbake::gpu::direct::DEFAULT_SAMPLES;
use clothbake::viewer::{self, Shading, ViewOptions};

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
    /// Samples per thread of the paper-mode shader (+/- change it).
    #[arg(long, default_value_t = DEFAULT_SAMPLES,
          value_parser = clap::value_parser!(u32).range(1..=1024))]
    samples: u32,
    /// Shading at start: table lookup, the model in the shader in paper mode (key D
    /// toggles), or the resonant quadrature in the shader (key G toggles); constant is render's only.
    #[arg(long, value_enum, default_value_t = ShaderArg::Lookup)]
    shader: ShaderArg,
}

pub fn run(args: Args) -> CommandResult {
    let shading = match args.shader {
        ShaderArg::Lookup => Shading::Lookup,
        ShaderArg::Paper | ShaderArg::Direct => Shading::Paper,
        ShaderArg::Resonant => Shading::Resonant,
        ShaderArg::Constant => {
            return Err(UsageError(
                "view has no constant shading: --shader lookup, paper or resonant".into(),
            )
            .into());
        }
    };
    let summary = viewer::run(ViewOptions {
        scene: args.scene.load()?,
        fabric: args.fabric,
        tables: args.scene.tables,
        mesh: args.scene.mesh,
        frames: args.frames,
        samples: args.samples,
        shading,
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
