//! `clothbake wgsl`: a table's lookup shader, in WGSL or translated by naga.

use super::CommandResult;
use clothbake::formats::table_exr::read_table;
use clothbake::table::shader_language::{ShaderLanguage, lookup_shader};
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct Args {
    /// The table (EXR).
    table: PathBuf,
    /// Shading language: wgsl, glsl (4.50 core), hlsl (shader model 5.1) or msl (2.4).
    #[arg(long, default_value = "wgsl")]
    lang: ShaderLanguage,
}

pub fn run(args: Args) -> CommandResult {
    let file = read_table(&args.table)?;
    print!("{}", lookup_shader(&file.table, args.lang)?);
    Ok(())
}
