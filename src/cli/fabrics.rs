//! `clothbake fabrics`: the fabrics and their key parameters.

use super::CommandResult;
use clothbake::formats::fabric_toml::{FabricSet, describe};
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct Args {
    /// Fabric file (TOML) to use instead of the built-in fabrics.
    #[arg(long)]
    fabrics: Option<PathBuf>,
}

pub fn run(args: Args) -> CommandResult {
    let set = FabricSet::load_or_builtin(args.fabrics.as_deref())?;
    print!("{}", describe(&set));
    Ok(())
}
