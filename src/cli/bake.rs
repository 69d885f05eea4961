//! `clothbake bake`: fabrics into EXR tables, by the library's bake policy
//! ([`BakeRequest::resolve`]).

use super::CommandResult;
use super::options::parse_layout;
use clothbake::bake::job::{self, BakeRequest, Outcome, TapsOutcome};
use clothbake::model::Fabric;
use clothbake::scene::{MAX_ENVIRONMENT_SAMPLES, Scene};
use clothbake::table::Layout;
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct Args {
    /// Fabrics to bake (default: every fabric in the fabric file).
    #[arg(long, num_args = 1.., conflicts_with = "scene")]
    fabric: Vec<String>,
    /// Scene file (TOML): bake only the fabrics it names, within its budget.
    #[arg(long)]
    scene: Option<PathBuf>,
    /// Fabric file (TOML) to use instead of the built-in fabrics.
    #[arg(long)]
    fabrics: Option<PathBuf>,
    /// Table layout (default: the scene's, else split_frame).
    #[arg(long, value_parser = parse_layout)]
    layout: Option<Layout>,
    /// Layout resolution (default: the layout's own).
    #[arg(long, conflicts_with = "max_error")]
    resolution: Option<u32>,
    /// Choose the smallest resolution whose relative RMS error (uniform and highlight
    /// pairs, against direct evaluation) is at most this, and report it.
    #[arg(long)]
    max_error: Option<f64>,
    /// Output directory.
    #[arg(long, default_value = "tables")]
    out: PathBuf,
    /// Worker threads (default: all cores).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=1024))]
    threads: Option<u32>,
    /// Bake even tables the manifest shows are up to date.
    #[arg(long)]
    force: bool,
    /// Environment samples per pixel of the sample taps stored beside each table
    /// (NAME.taps), which `render` and `view` read instead of building them (default: the
    /// scene's, else the built-in scene's, 96).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=MAX_ENVIRONMENT_SAMPLES as i64), conflicts_with = "no_taps")]
    env_samples: Option<u32>,
    /// Store no sample taps beside the tables (`render` and `view` then build and store them).
    #[arg(long)]
    no_taps: bool,
}

pub fn run(args: Args) -> CommandResult {
    let scene = args.scene.as_deref().map(Scene::load).transpose()?;
    let job = BakeRequest {
        fabrics: args.fabric,
        scene,
        fabric_file: args.fabrics,
        layout: args.layout,
        resolution: args.resolution,
        max_error: args.max_error,
        out: args.out,
        force: args.force,
        environment_samples: args.env_samples,
        no_taps: args.no_taps,
    }
    .resolve()?;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(args.threads.unwrap_or(0) as usize)
        .build()?;
    let progress = |name: &str, resolution: u32, rows: u64| -> Box<dyn Fn() + Sync> {
        let bar = progress_bar(rows, &format!("{name} @ {resolution}"));
        Box::new(move || bar.inc(1))
    };
    let layout = job.layout;
    let mut report = |fabric: &Fabric, outcome: &Outcome| print_outcome(fabric, layout, outcome);
    pool.install(|| job::run(&job, &progress, &mut report))?;
    Ok(())
}

/// One fabric's lines: up to date, or baked (with the resolutions an error budget tried).
fn print_outcome(fabric: &Fabric, layout: Layout, outcome: &Outcome) {
    match outcome {
        Outcome::UpToDate { path, entry, taps } => {
            println!(
                "{}: up to date ({} at resolution {}), not baked again",
                path.display(),
                entry.layout,
                entry.resolution
            );
            print_taps(&fabric.name, taps.as_ref());
        }
        Outcome::Baked {
            path,
            entry,
            bytes,
            tried,
            taps,
        } => {
            for (r, e) in tried {
                println!(
                    "{}: {layout} at resolution {r}: relative RMS {:.2}% uniform, {:.2}% highlight",
                    fabric.name,
                    100.0 * e.uniform.relative_rms,
                    100.0 * e.highlight.relative_rms
                );
            }
            println!(
                "{}: {} at resolution {}{}, {} KiB, baked in {:.1} s on {} threads",
                path.display(),
                entry.layout,
                entry.resolution,
                if tried.is_empty() {
                    ""
                } else {
                    " (chosen for the error budget)"
                },
                bytes / 1024,
                entry.bake_seconds,
                entry.threads
            );
            print_taps(&fabric.name, taps.as_ref());
        }
    }
}

/// The line of a table's sample taps: up to date, or built and stored.
fn print_taps(fabric: &str, taps: Option<&TapsOutcome>) {
    let Some(taps) = taps else { return };
    if taps.origin.loaded() {
        println!(
            "{fabric}: sample taps for {} environment samples up to date ({})",
            taps.samples, taps.origin
        );
    } else {
        println!(
            "{fabric}: sample taps for {} environment samples {} ({:.1} s)",
            taps.samples, taps.origin, taps.seconds
        );
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
