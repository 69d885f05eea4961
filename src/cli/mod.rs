//! The commands of the `clothbake` binary: one file each, holding its options and a `run`
//! over the library. Options shared by several commands are in [`options`].

mod albedo;
mod bake;
mod check;
mod eval;
mod export;
mod fabrics;
mod fit;
mod options;
mod sample;
mod weave;
mod wgsl;

#[cfg(feature = "runtime")]
mod render;
#[cfg(feature = "runtime")]
mod report;
#[cfg(feature = "runtime")]
mod view;

use clap::{Parser, Subcommand};

/// What a command returns: the library's typed errors, and the CLI's own about options that
/// do not fit together, are printed the same way (`clothbake: error: ...`, exit 1).
pub type CommandResult = Result<(), Box<dyn std::error::Error>>;

#[derive(Parser)]
#[command(
    version,
    about = "Bake the Sadeghi et al. 2013 cloth model into lookup tables"
)]
pub struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// List the fabrics and their key parameters.
    Fabrics(fabrics::Args),
    /// Evaluate F(wi, wo): JSON lines {"wi":[x,y,z],"wo":[x,y,z]} on stdin, {"f":[r,g,b]} out.
    Eval(eval::Args),
    /// Importance-sample F: JSON lines {"wo":[x,y,z],"u":[u1,u2,u3]} (u in [0, 1)) on stdin,
    /// {"wi":[x,y,z],"pdf":p,"weight":[r,g,b]} out (weight = F/pdf; "wi":null when rejected).
    Sample(sample::Args),
    /// Print each fabric's directional albedo ∫F dwi over outgoing elevation, and its maximum.
    Albedo(albedo::Args),
    /// Bake fabrics into EXR tables (by default the built-in six into tables/).
    Bake(bake::Args),
    /// Measure a table's error against the direct evaluation of the fabric it records.
    Check(check::Args),
    /// Print the lookup specialised for a table (`fn cloth_brdf(wi, wo)` and its bindings,
    /// see src/evaluator/table/gpu.rs), to use the table in another engine: WGSL, or GLSL, HLSL or
    /// MSL translated by naga together with a compute kernel over pairs.
    Wgsl(wgsl::Args),
    /// Make a fabric from a weave draft (a named weave or a WIF file) and yarn knobs, or
    /// print the draft's drawdown.
    Weave(weave::Args),
    /// Export a fabric's best stock material for an engine (glTF, MaterialX/OpenPBR, Filament,
    /// Unreal) and print what it loses against the fabric.
    Export(export::Args),
    /// Fit a fabric to measured samples of F: JSON lines {"wi":[x,y,z],"wo":[x,y,z],"f":[r,g,b]}.
    Fit(fit::Args),
    #[cfg(feature = "runtime")]
    /// Measure speed against error for every fabric (tables of each layout over a range of
    /// resolutions, the evaluators' settings their units list, bake times) and write
    /// REPORT.md, report.json and PNG plots.
    Report(report::Args),
    #[cfg(feature = "runtime")]
    /// Render the scene's cloth headless to PNG by table lookup (or any evaluator's GPU form,
    /// --evaluator), print the adapter and the median GPU time per frame; with --reference
    /// compare with the CPU.
    Render(render::Args),
    #[cfg(feature = "runtime")]
    /// Open an interactive window showing the scene's cloth shaded by the evaluators of
    /// --evaluator (table lookup, paper mode and the resonant quadrature by default; key V
    /// cycles them, +/- their finer or coarser setting). Keys are listed at start.
    View(view::Args),
}

impl Cli {
    /// Runs the command the arguments name.
    pub fn run(self) -> CommandResult {
        match self.command {
            Command::Fabrics(args) => fabrics::run(args),
            Command::Eval(args) => eval::run(args),
            Command::Sample(args) => sample::run(args),
            Command::Albedo(args) => albedo::run(args),
            Command::Bake(args) => bake::run(args),
            Command::Check(args) => check::run(args),
            Command::Wgsl(args) => wgsl::run(args),
            Command::Weave(args) => weave::run(args),
            Command::Export(args) => export::run(args),
            Command::Fit(args) => fit::run(args),
            #[cfg(feature = "runtime")]
            Command::Report(args) => report::run(args),
            #[cfg(feature = "runtime")]
            Command::Render(args) => render::run(args),
            #[cfg(feature = "runtime")]
            Command::View(args) => view::run(args),
        }
    }
}
