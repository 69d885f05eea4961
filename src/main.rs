//! The clothbake command line: parses arguments and dispatches to the library.

use clap::{Parser, Subcommand};
use clothbake::accuracy::measure;
use clothbake::bake::bake;
use clothbake::eval_stream::{EvalOutput, eval_stream};
use clothbake::fabric_file::FabricSet;
use clothbake::model::{Fabric, Integration, Patch};
use clothbake::table::Layout;
use clothbake::table_file::{read_table, write_table};
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
        /// Also look each pair up in this table and print it as "table":[r,g,b].
        #[arg(long)]
        table: Option<PathBuf>,
    },
    /// Bake fabrics into EXR tables (by default the built-in six into tables/).
    Bake {
        /// Fabrics to bake (default: all in the fabric file).
        #[arg(long, num_args = 1..)]
        fabric: Vec<String>,
        /// Fabric file (TOML) to use instead of the built-in fabrics.
        #[arg(long)]
        fabrics: Option<PathBuf>,
        /// Table layout.
        #[arg(long, default_value = "grid4d", value_parser = parse_layout)]
        layout: Layout,
        /// Layout resolution (default: the layout's own).
        #[arg(long)]
        resolution: Option<u32>,
        /// Output directory.
        #[arg(long, default_value = "tables")]
        out: PathBuf,
        /// Worker threads (default: all cores).
        #[arg(long, value_parser = clap::value_parser!(u32).range(1..=1024))]
        threads: Option<u32>,
    },
    /// Measure a table's error against the direct evaluation of the fabric it records.
    Check {
        /// The table (EXR) to check.
        table: PathBuf,
        /// Uniform and highlight pairs to measure on (each).
        #[arg(long, default_value_t = 4000, value_parser = clap::value_parser!(u32).range(1..=1_000_000))]
        pairs: u32,
    },
}

fn parse_layout(name: &str) -> Result<Layout, String> {
    Layout::from_name(name).ok_or_else(|| {
        let names: Vec<&str> = Layout::ALL.iter().map(|l| l.name()).collect();
        format!("unknown layout '{name}'; layouts: {}", names.join(", "))
    })
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
            table,
        } => {
            let set = FabricSet::load_or_builtin(fabrics.as_deref()).map_err(|e| e.to_string())?;
            let fabric = set.require(&fabric)?;
            let integration = samples.map_or(Integration::Direct, Integration::Paper);
            let patch = Patch::new(fabric, integration);
            let table = table
                .map(|path| read_table(&path).map_err(|e| e.to_string()))
                .transpose()?;
            let stdin = std::io::BufReader::new(std::io::stdin());
            let stdout = std::io::stdout().lock();
            eval_stream(stdin, stdout, |wi, wo| EvalOutput {
                f: patch.eval(wi, wo).to_array(),
                table: table.as_ref().map(|t| t.table.lookup(wi, wo).to_array()),
            })
            .map(|_| ())
            .map_err(|e| e.to_string())
        }
        Command::Bake {
            fabric,
            fabrics,
            layout,
            resolution,
            out,
            threads,
        } => {
            let set = FabricSet::load_or_builtin(fabrics.as_deref()).map_err(|e| e.to_string())?;
            let selected: Vec<&Fabric> = if fabric.is_empty() {
                set.fabrics().iter().collect()
            } else {
                fabric
                    .iter()
                    .map(|name| set.require(name))
                    .collect::<Result<_, _>>()?
            };
            let resolution = resolution.unwrap_or(layout.default_resolution());
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads.unwrap_or(0) as usize)
                .build()
                .map_err(|e| e.to_string())?;
            std::fs::create_dir_all(&out)
                .map_err(|e| format!("cannot create {}: {e}", out.display()))?;
            for fabric in selected {
                let started = std::time::Instant::now();
                let (_, rows) = layout.image_size(resolution);
                let progress = progress_bar(rows as u64, &fabric.name);
                let table = pool
                    .install(|| bake(fabric, layout, resolution, &|| progress.inc(1)))
                    .map_err(|e| e.to_string())?;
                progress.finish_and_clear();
                let seconds = started.elapsed().as_secs_f64();
                let path = out.join(format!("{}.exr", fabric.name));
                write_table(&path, &table, fabric).map_err(|e| e.to_string())?;
                println!(
                    "{}: {layout} at resolution {resolution}, {} KiB, baked in {seconds:.1} s",
                    path.display(),
                    table.byte_size() / 1024
                );
            }
            Ok(())
        }
        Command::Check { table, pairs } => {
            let file = read_table(&table).map_err(|e| e.to_string())?;
            let error = measure(&file.table, &file.fabric, pairs as usize);
            let t = &file.table;
            println!(
                "{}: fabric {}, {} at resolution {}, {} KiB of f16 texels, clothbake {}",
                table.display(),
                file.fabric.name,
                t.layout,
                t.resolution,
                t.byte_size() / 1024,
                file.version
            );
            for (label, e) in [
                ("uniform pairs", error.uniform),
                ("highlight pairs", error.highlight),
                ("uniform, both ≥ 15° elevation", error.uniform_above_15deg),
            ] {
                println!(
                    "  {label:<31} relative RMS {:>7.3}%   max |error| {:.3e} (where F = {:.3e})",
                    100.0 * e.relative_rms,
                    e.max_abs,
                    e.max_abs_at_value
                );
            }
            Ok(())
        }
    }
}

/// A progress bar on an interactive terminal, hidden otherwise.
fn progress_bar(length: u64, label: &str) -> indicatif::ProgressBar {
    use std::io::IsTerminal;
    if !std::io::stderr().is_terminal() {
        return indicatif::ProgressBar::hidden();
    }
    let bar = indicatif::ProgressBar::new(length);
    if let Ok(style) =
        indicatif::ProgressStyle::with_template("{msg:32} [{bar:40}] {percent:>3}% {eta}")
    {
        bar.set_style(style);
    }
    bar.set_message(label.to_string());
    bar
}
