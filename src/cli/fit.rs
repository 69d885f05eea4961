//! `clothbake fit`: a fabric fitted to measured samples of F, written as a fabric file.

use super::CommandResult;
use super::options::UsageError;
use super::weave::weave_of;
use clothbake::fit::output::fit_provenance;
use clothbake::fit::solve::FitOptions;
use clothbake::fit::weave::WeaveParameters;
use clothbake::fit::{LikeFabric, Parametrisation, Progress, fit, load_samples};
use clothbake::formats::fabric_toml::FabricSet;
use clothbake::formats::fabric_toml::write_fabric_file;
use clothbake::weave::Fibre;
use std::path::PathBuf;

#[derive(clap::Args)]
#[command(group(clap::ArgGroup::new("start").required(true).args(["like", "weave"])))]
pub struct Args {
    /// JSON lines {"wi":[x,y,z],"wo":[x,y,z],"f":[r,g,b]} (optional "weight":w) in the patch
    /// frame, as `eval` writes them; blank lines and lines starting with # are skipped.
    samples: PathBuf,
    /// Fit the parameters of this fabric (its curves' structure and options kept).
    #[arg(long)]
    like: Option<String>,
    /// Fit the yarn knobs of a weave draft (a named weave or a WIF file).
    #[arg(long)]
    weave: Option<String>,
    /// With --weave: knobs of both yarns, `key=value,...`, where the fit starts (as on
    /// `weave`; a knob given here is still fitted, except cover, which then stays fixed; legs,
    /// squash and sag start no lower than 0.3, 0.3 and 5°, where the fit can move them).
    #[arg(long, default_value = "", requires = "weave")]
    yarn: String,
    /// With --weave: knobs of the warp (thread 1), `key=value,...`.
    #[arg(long, default_value = "", requires = "weave")]
    warp: String,
    /// With --weave: knobs of the weft (thread 2), `key=value,...`.
    #[arg(long, default_value = "", requires = "weave")]
    weft: String,
    /// With --weave: the back of the cloth.
    #[arg(long, requires = "weave")]
    back: bool,
    /// With --weave: warp and weft exchanged.
    #[arg(long, requires = "weave")]
    swap: bool,
    /// Fabric file (TOML) holding the --like fabric instead of the built-in fabrics.
    #[arg(long, requires = "like")]
    fabrics: Option<PathBuf>,
    /// Name of the fitted fabric (default: the --like fabric's name).
    #[arg(long)]
    name: Option<String>,
    /// Fix the refractive index η of both threads to this fibre's (silk, polyester, linen,
    /// cotton, wool, nylon) instead of fitting it.
    #[arg(long)]
    fibre: Option<String>,
    /// Starts (default 2 with --like, 3 with --weave): the first two from the fabric's own
    /// parameters, each with its own schedule of broadened lobes, later ones from seeded
    /// perturbations of them; the best fit is kept.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=64))]
    starts: Option<u32>,
    /// Hold every Nth sample out of the fit and report the error on them (0: none).
    #[arg(long, default_value_t = 5)]
    hold_out: usize,
    /// The fitted fabric file to write (TOML); written only when the fit succeeds.
    #[arg(long)]
    out: PathBuf,
}

/// The command line as typed, quoted where a shell would need it.
fn command_line() -> String {
    std::env::args_os()
        .map(|a| a.to_string_lossy().into_owned())
        .map(|a| {
            if !a.is_empty()
                && a.chars()
                    .all(|c| c.is_ascii_alphanumeric() || "-_./=:,+@%".contains(c))
            {
                a
            } else {
                format!("'{}'", a.replace('\'', "'\\''"))
            }
        })
        .collect::<Vec<_>>()
        .join(" ")
}

fn progress_bar() -> indicatif::ProgressBar {
    use std::io::IsTerminal;
    if !std::io::stderr().is_terminal() {
        return indicatif::ProgressBar::hidden();
    }
    let bar = indicatif::ProgressBar::new_spinner();
    if let Ok(style) = indicatif::ProgressStyle::with_template("{spinner} {elapsed:>4} {msg}") {
        bar.set_style(style);
    }
    bar
}

pub fn run(args: Args) -> CommandResult {
    let eta = args
        .fibre
        .as_deref()
        .map(|fibre| {
            fibre
                .parse::<Fibre>()
                .map(Fibre::eta)
                .map_err(|e| UsageError(e.to_string()))
        })
        .transpose()?;
    let parametrisation: Box<dyn Parametrisation> = match (&args.like, &args.weave) {
        (Some(like), _) => {
            let set = FabricSet::load_or_builtin(args.fabrics.as_deref())?;
            let fabric = set.require(like)?;
            let name = args.name.as_deref().unwrap_or(&fabric.name);
            let mut renamed = fabric.clone();
            renamed.name = name.to_string();
            renamed.validate()?;
            Box::new(LikeFabric::new(fabric, eta).with_name(name))
        }
        (None, Some(draft)) => {
            let knobs = [args.yarn.as_str(), &args.warp, &args.weft];
            let (weave, default_name) = weave_of(draft, args.back, args.swap, knobs)?;
            let name = args.name.clone().unwrap_or(default_name);
            // The start must be a valid fabric of that name.
            weave.fabric(&name)?;
            Box::new(WeaveParameters::new(&weave, &name, eta))
        }
        (None, None) => unreachable!("clap requires --like or --weave"),
    };
    let parametrisation = parametrisation.as_ref();
    let samples = load_samples(&args.samples)?;
    let mut options = FitOptions {
        holdout_every: args.hold_out,
        ..FitOptions::default()
    };
    if let Some(starts) = args.starts {
        options.starts = Some(starts as usize);
    }
    eprintln!(
        "fitting {} free parameters of '{}' to {} samples of {}",
        parametrisation.parameters().len(),
        parametrisation.fabric(&parametrisation.start()).name,
        samples.samples.len(),
        samples.origin
    );
    let bar = progress_bar();
    let report = fit(parametrisation, &samples, &options, &|p: &Progress| {
        bar.set_message(format!(
            "start {}/{} stage {}/{}: evaluation {}/{}, objective {:.4e} (best {:.4e})",
            p.start + 1,
            p.starts,
            p.stage + 1,
            p.stages,
            p.evaluations,
            p.max_evaluations,
            p.objective,
            p.best
        ));
        bar.tick();
    });
    bar.finish_and_clear();
    let report = report?;
    let header = fit_provenance(&report, &samples, &command_line());
    write_fabric_file(&args.out, std::slice::from_ref(&report.fabric), &header)
        .map_err(|e| format!("cannot write {}: {e}", args.out.display()))?;
    println!(
        "fitted '{}' on {} samples ({} held out): relative RMS {:.3}% fitted, {} held out \
         (direct evaluation); best of {} starts, {} evaluations, {}",
        report.fabric.name,
        report.fit_count,
        report.holdout_count,
        100.0 * report.fit_relative_rms,
        report
            .holdout_relative_rms
            .map_or("none".into(), |r| format!("{:.3}%", 100.0 * r)),
        report.start_objectives.len(),
        report.evaluations,
        report.termination
    );
    if report.flat_directions.is_empty() {
        println!("every parameter is constrained by the samples");
    }
    for d in &report.flat_directions {
        println!("unconstrained: {d}");
    }
    println!("wrote {}", args.out.display());
    Ok(())
}
