//! `clothbake weave`: a fabric from a weave draft and yarn knobs, or the draft's drawdown.

use super::CommandResult;
use super::options::UsageError;
use clothbake::formats::draft_source::load_draft;
use clothbake::formats::fabric_toml::write_fabric_file;
use clothbake::weave::{Family, FamilySummary, NamedWeave, Weave, YARN_KEYS, Yarn};
use std::path::PathBuf;

#[derive(clap::Args)]
#[command(after_help = format!("DRAFT: {}\nYarn knobs: {YARN_KEYS}", NamedWeave::SYNTAX))]
pub struct Args {
    /// The draft: a named weave or a WIF file (see below).
    draft: String,
    /// Print the drawdown of the whole draft (one line per pick, pick 1 first; `#` where the
    /// warp is on top, `.` where the weft is) and nothing else.
    #[arg(long, conflicts_with_all = ["out", "name", "yarn", "warp", "weft"])]
    drawdown: bool,
    /// Knobs of both yarns, `key=value,...` (the warp's and weft's own follow).
    #[arg(long, default_value = "")]
    yarn: String,
    /// Knobs of the warp (thread 1, along x), `key=value,...`.
    #[arg(long, default_value = "")]
    warp: String,
    /// Knobs of the weft (thread 2, along y), `key=value,...`.
    #[arg(long, default_value = "")]
    weft: String,
    /// Weave the back of the cloth (the draft turned over).
    #[arg(long)]
    back: bool,
    /// Exchange warp and weft before the knobs apply, so that the weft runs along x.
    #[arg(long)]
    swap: bool,
    /// The fabric's name (default: from the weave's spelling or the WIF file's name).
    #[arg(long)]
    name: Option<String>,
    /// The fabric file to write (TOML, one [[fabric]]).
    #[arg(long, required_unless_present = "drawdown")]
    out: Option<PathBuf>,
}

/// One line of `weave`'s summary for a family.
fn describe(label: &str, s: &FamilySummary) -> String {
    let floats: Vec<String> = s.floats.iter().map(|(l, n)| format!("{n}×{l}")).collect();
    format!(
        "{label}: face {:.4}, cover {:.4}, coverage {:.4}, floats {}, offsets_deg {:?}, lengths {:?}",
        s.face_fraction,
        s.cover,
        s.coverage,
        if floats.is_empty() {
            "none".into()
        } else {
            floats.join(" ")
        },
        s.offsets_deg,
        s.lengths
            .iter()
            .map(|l| (l * 1e4).round() / 1e4)
            .collect::<Vec<_>>()
    )
}

/// The weave that a draft spelling and the yarn knob options make: shared by `weave` and
/// `fit --weave`.
pub fn weave_of(
    spelling: &str,
    back: bool,
    swap: bool,
    [both, warp, weft]: [&str; 3],
) -> Result<(Weave, String), Box<dyn std::error::Error>> {
    let (draft, name) = load_draft(spelling)?;
    let draft = draft.oriented(back, swap);
    let knobs = |own: &str, option: &str| -> Result<Yarn, UsageError> {
        let mut yarn = Yarn::default();
        yarn.set_all(both)
            .map_err(|e| UsageError(format!("--yarn: {e}")))?;
        yarn.set_all(own)
            .map_err(|e| UsageError(format!("{option}: {e}")))?;
        Ok(yarn)
    };
    let weave = Weave {
        warp: knobs(warp, "--warp")?,
        weft: knobs(weft, "--weft")?,
        draft,
    };
    Ok((weave, name))
}

pub fn run(args: Args) -> CommandResult {
    let knobs = [args.yarn.as_str(), &args.warp, &args.weft];
    let (weave, default_name) = weave_of(&args.draft, args.back, args.swap, knobs)?;
    if args.drawdown {
        print!("{}", weave.draft.drawdown());
        return Ok(());
    }
    let name = args.name.unwrap_or(default_name);
    let fabric = weave.fabric(&name)?;
    let out = args.out.expect("clap requires --out without --drawdown");
    let header = format!(
        "Woven by clothbake {} from {}: {} ends × {} picks.\nclothbake weave {} --yarn '{}' --warp '{}' --weft '{}'{}{}",
        env!("CARGO_PKG_VERSION"),
        args.draft,
        weave.draft.ends(),
        weave.draft.picks(),
        args.draft,
        args.yarn,
        args.warp,
        args.weft,
        if args.back { " --back" } else { "" },
        if args.swap { " --swap" } else { "" },
    );
    write_fabric_file(&out, std::slice::from_ref(&fabric), &header)
        .map_err(|e| format!("cannot write {}: {e}", out.display()))?;
    println!(
        "{}",
        describe("thread 1 (warp)", &weave.summary(Family::Warp))
    );
    println!(
        "{}",
        describe("thread 2 (weft)", &weave.summary(Family::Weft))
    );
    println!("wrote fabric '{name}' to {}", out.display());
    Ok(())
}
