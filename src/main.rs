//! The clothbake command line: parses arguments and dispatches to the library.

use clap::{Parser, Subcommand};
use clothbake::eval_stream::{EvalOutput, eval_stream};
use clothbake::fabric_file::FabricSet;
use clothbake::model::{Integration, Patch};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    version,
    about = "Bake the Sadeghi et al. 2013 cloth model into lookup tables"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// List the fabrics and their key parameters.
    Fabrics {
        /// Fabric file (TOML) to use instead of the built-in fabrics.
        #[arg(long)]
        fabrics: Option<PathBuf>,
    },
    /// Evaluate F(wi, wo): JSON lines {"wi":[x,y,z],"wo":[x,y,z]} on stdin, {"f":[r,g,b]} out.
    Eval {
        /// Fabric name.
        #[arg(long)]
        fabric: String,
        /// Paper mode: N stratified samples per thread instead of the converged evaluation.
        #[arg(long, value_parser = clap::value_parser!(u32).range(1..=1_000_000))]
        samples: Option<u32>,
        /// Fabric file (TOML) to use instead of the built-in fabrics.
        #[arg(long)]
        fabrics: Option<PathBuf>,
    },
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("clothbake: error: {message}");
            ExitCode::FAILURE
        }
    }
}

fn run(cli: Cli) -> Result<(), String> {
    match cli.command {
        Command::Fabrics { fabrics } => {
            let set = FabricSet::load_or_builtin(fabrics.as_deref()).map_err(|e| e.to_string())?;
            print!("{}", clothbake::fabric_file::describe(&set));
            Ok(())
        }
        Command::Eval {
            fabric,
            samples,
            fabrics,
        } => {
            let set = FabricSet::load_or_builtin(fabrics.as_deref()).map_err(|e| e.to_string())?;
            let fabric = set.require(&fabric)?;
            let integration = samples.map_or(Integration::Direct, Integration::Paper);
            let patch = Patch::new(fabric, integration);
            let stdin = std::io::BufReader::new(std::io::stdin());
            let stdout = std::io::stdout().lock();
            eval_stream(stdin, stdout, |wi, wo| EvalOutput {
                f: patch.eval(wi, wo).to_array(),
                table: None,
            })
            .map(|_| ())
            .map_err(|e| e.to_string())
        }
    }
}
