//! `clothbake wgsl`: a table's lookup shader, in WGSL or translated by naga.

use super::CommandResult;
use clothbake::formats::table_exr::read_table;
use clothbake::table::shader_language::{ShaderLanguage, lookup_shader};
use clothbake::table::wgsl::LookupShaderOptions;
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct Args {
    /// The table (EXR).
    table: PathBuf,
    /// Shading language: wgsl, glsl (4.50 core), hlsl (shader model 5.1) or msl (2.4).
    #[arg(long, default_value = "wgsl")]
    lang: ShaderLanguage,
    /// Leave split_frame's horizon band out: pairs within 1° of the horizon read the
    /// table like every other (for software rasterisers, which run the band's resonant
    /// kernel in every pixel).
    #[arg(long)]
    no_horizon_band: bool,
}

pub fn run(args: Args) -> CommandResult {
    let file = read_table(&args.table)?;
    let options = LookupShaderOptions {
        horizon_band: !args.no_horizon_band,
    };
    print!("{}", lookup_shader(&file.table, args.lang, &options)?);
    Ok(())
}
