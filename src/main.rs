//! The clothbake command line: parses arguments and runs one command (`src/cli/`, a file per
//! command over the library).

mod cli;

use clap::Parser;
use std::process::ExitCode;

fn main() -> ExitCode {
    match cli::Cli::parse().run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) => {
            eprintln!("clothbake: error: {error}");
            ExitCode::FAILURE
        }
    }
}
