//! REPORT.md's "Which table or evaluation to pick": for each need, the table or evaluation
//! the run's own measurements pick per fabric, and the figure and section the pick rests on.
//!
//! Nothing in the section is written by hand: each pick is the extreme of the report's
//! points within the need's budget (the constants below), so a new run, or a re-render of
//! report.json ([`super::rerender`]), rewrites it with the figures it rests on.

use super::format::{num, pct, size, unit_anchor, unit_heading, unit_names};
use super::{Evaluation, FabricReport, Report, planned_units, plots};
use std::fmt::{self, Write};

/// The section's heading; its GitHub anchor is [`ANCHOR`].
pub const HEADING: &str = "Which table or evaluation to pick";

/// The GitHub anchor of [`HEADING`]: `report/REPORT.md#which-table-or-evaluation-to-pick`.
pub const ANCHOR: &str = "which-table-or-evaluation-to-pick";

/// Largest image error of a real-time image against the CPU reference render: 1%, well
/// under what a viewer sees beside the reference.
pub const IMAGE_ERROR: f64 = 0.01;

/// Largest error of the smallest table: 2%, the looser of the two table budgets the
/// project states (1% in 4 MiB, 2% in 1 MiB).
pub const SMALL_TABLE_ERROR: f64 = 0.02;

/// Largest error of the fastest CPU evaluation: 1%, the tighter of the two table budgets.
pub const CPU_ERROR: f64 = 0.01;

/// Largest error of an evaluation of the model without a bake at reference quality:
/// 0.25%, the bound the default node counts of the quadrature evaluator were chosen to meet.
pub const NO_BAKE_ERROR: f64 = 0.0025;

/// What a reader needs F for; one row of the section each.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Need {
    /// The fastest GPU frame within [`IMAGE_ERROR`].
    RealTimeImage,
    /// The smallest table within [`SMALL_TABLE_ERROR`].
    SmallestTable,
    /// The cheapest CPU evaluation of any kind (table, any evaluator measured, direct)
    /// within [`CPU_ERROR`].
    FastestCpu,
    /// The cheapest evaluation of the model itself (any evaluator measured) within
    /// [`NO_BAKE_ERROR`].
    NoBake,
    /// The direct evaluation, every error's reference.
    GroundTruth,
}

impl Need {
    /// The section's rows, in order.
    pub const ALL: [Need; 5] = [
        Need::RealTimeImage,
        Need::SmallestTable,
        Need::FastestCpu,
        Need::NoBake,
        Need::GroundTruth,
    ];

    /// The need's budget (None: ground truth, which has none).
    pub fn budget(self) -> Option<f64> {
        match self {
            Need::RealTimeImage => Some(IMAGE_ERROR),
            Need::SmallestTable => Some(SMALL_TABLE_ERROR),
            Need::FastestCpu => Some(CPU_ERROR),
            Need::NoBake => Some(NO_BAKE_ERROR),
            Need::GroundTruth => None,
        }
    }

    /// The need in the first column of the section's table.
    fn title(self) -> String {
        let b = self.budget().map_or(String::new(), budget);
        match self {
            Need::RealTimeImage => format!("a real-time image within {b} of the model's"),
            Need::SmallestTable => format!("the smallest table within {b}"),
            Need::FastestCpu => format!("the fastest CPU evaluation within {b}"),
            Need::NoBake => format!("reference quality (within {b}) with no bake"),
            Need::GroundTruth => "ground truth".into(),
        }
    }

    /// The need's column in the per-fabric table.
    pub fn column(self) -> String {
        let b = self.budget().map_or(String::new(), budget);
        match self {
            Need::RealTimeImage => format!("real-time image ≤ {b}"),
            Need::SmallestTable => format!("smallest table ≤ {b}"),
            Need::FastestCpu => format!("fastest CPU evaluation ≤ {b}"),
            Need::NoBake => format!("no bake ≤ {b}"),
            Need::GroundTruth => "ground truth".into(),
        }
    }

    /// How the pick is made.
    fn rule(self) -> String {
        let b = self.budget().map_or(String::new(), budget);
        let units: Vec<_> = planned_units().map(|(unit, _)| unit).collect();
        let evaluators = unit_names(&units);
        match self {
            Need::RealTimeImage => format!(
                "the fastest GPU frame (the lookup shader or a shader of {evaluators}) with an \
                 image error ≤ {b}"
            ),
            Need::SmallestTable => format!("the smallest table (any layout) with an error ≤ {b}"),
            Need::FastestCpu => format!(
                "the cheapest CPU evaluation (a table lookup, direct, or any of {evaluators}) \
                 with an error ≤ {b}"
            ),
            Need::NoBake => {
                format!("the cheapest evaluation of the model ({evaluators}) with an error ≤ {b}")
            }
            Need::GroundTruth => "the direct evaluation, every error's reference".into(),
        }
    }

    /// The figure and the sections the pick rests on (links within REPORT.md's folder).
    fn rests_on(self, report: &Report) -> String {
        let figure = |file: &str| format!("[{file}]({file})");
        match self {
            Need::RealTimeImage => format!("{}, [GPU](#gpu)", figure(plots::GPU_COST)),
            Need::SmallestTable => format!(
                "{}, [Error against table size](#error-against-table-size) (Pareto front)",
                figure(plots::ERROR_VS_SIZE)
            ),
            Need::FastestCpu => format!(
                "{}, [Error budgets](#error-budgets)",
                figure(plots::ERROR_VS_COST)
            ),
            Need::NoBake => {
                let sections = report
                    .other_units()
                    .into_iter()
                    .map(|unit| format!("[{}](#{})", unit_heading(unit), unit_anchor(unit)));
                std::iter::once(figure(plots::ERROR_VS_COST))
                    .chain(sections)
                    .collect::<Vec<_>>()
                    .join(", ")
            }
            Need::GroundTruth => {
                "[Error against CPU cost](#error-against-cpu-cost) (its rows \"direct\")".into()
            }
        }
    }
}

/// A budget as a percentage, as short as it is exact ("1%", "0.25%").
fn budget(x: f64) -> String {
    let text = format!("{:.2}", 100.0 * x);
    format!("{}%", text.trim_end_matches('0').trim_end_matches('.'))
}

/// A table or evaluation the section can pick, named as the rest of REPORT.md names it.
#[derive(Clone, Debug, PartialEq)]
pub enum Choice {
    /// The direct evaluation on the CPU.
    Direct,
    /// A point measured on the CPU: a table looked up, or an evaluator.
    Cpu(Evaluation),
    /// A shader of the GPU section: the lookup of a table, or an evaluator's GPU form.
    Gpu(Evaluation),
}

impl fmt::Display for Choice {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Choice::Direct => f.write_str("direct"),
            Choice::Cpu(evaluation) => write!(f, "{evaluation}"),
            Choice::Gpu(table @ Evaluation::Table { .. }) => write!(f, "lookup shader, {table}"),
            Choice::Gpu(evaluator) => write!(f, "{evaluator} shader"),
        }
    }
}

/// One fabric's pick for one need, with the figures it gives.
#[derive(Clone, Debug, PartialEq)]
pub struct Pick {
    pub choice: Choice,
    /// The worse of the uniform and highlight relative RMS errors on the CPU; the image
    /// error for a GPU shader.
    pub error: f64,
    /// CPU nanoseconds per evaluation (None for a GPU shader).
    pub ns_per_eval: Option<f64>,
    /// GPU milliseconds per frame (None on the CPU).
    pub ms_per_frame: Option<f64>,
    /// The table's size (None but for [`Need::SmallestTable`]).
    pub bytes: Option<usize>,
}

impl Pick {
    fn cpu(choice: Choice, error: f64, ns_per_eval: f64) -> Self {
        Self {
            choice,
            error,
            ns_per_eval: Some(ns_per_eval),
            ms_per_frame: None,
            bytes: None,
        }
    }

    /// The per-fabric cell of `need`: the choice and the figures the need is about.
    fn cell(&self, need: Need) -> String {
        let error = pct(self.error);
        let ns = self.ns_per_eval.map_or("–".into(), num);
        let figures = match need {
            Need::RealTimeImage => match self.ms_per_frame {
                Some(ms) => format!("{error}, {ms:.1} ms"),
                None => error,
            },
            Need::SmallestTable => match self.bytes {
                Some(bytes) => format!("{}, {error}", size(bytes)),
                None => error,
            },
            Need::FastestCpu | Need::NoBake => format!("{error}, {ns} ns"),
            Need::GroundTruth => format!("{ns} ns"),
        };
        format!("{} ({figures})", self.choice)
    }
}

/// Every CPU evaluation of `f` as a pick: direct, then every point measured.
fn cpu_points(f: &FabricReport) -> impl Iterator<Item = Pick> + '_ {
    let direct = Pick::cpu(Choice::Direct, 0.0, f.direct.ns_per_eval);
    let points = f.points.iter().map(|p| Pick {
        bytes: p.bytes,
        ..Pick::cpu(Choice::Cpu(p.evaluation.clone()), p.worst_error(), p.cost())
    });
    std::iter::once(direct).chain(points)
}

/// The GPU points of the fabric named `name`, if the GPU section measured it.
fn gpu_points(report: &Report, name: &str) -> Option<Vec<Pick>> {
    let g = &report.gpu;
    let f = g
        .fabrics
        .iter()
        .find(|f| f.name == name)
        .filter(|_| g.measured)?;
    let points = f.points.iter().map(|p| Pick {
        choice: Choice::Gpu(p.evaluation.clone()),
        error: p.image_relative_l2,
        ns_per_eval: None,
        ms_per_frame: Some(p.ms_per_frame),
        bytes: None,
    });
    Some(points.collect())
}

/// The pick of `need` for fabric `f` of `report`; None when nothing measured meets the
/// need's budget (or, for a real-time image, when the GPU section did not measure `f`).
pub fn pick(report: &Report, f: &FabricReport, need: Need) -> Option<Pick> {
    let within = |p: &Pick| need.budget().is_none_or(|b| p.error <= b);
    let by = |key: fn(&Pick) -> f64| move |a: &Pick, b: &Pick| key(a).total_cmp(&key(b));
    let ns = |p: &Pick| p.ns_per_eval.unwrap_or(f64::INFINITY);
    match need {
        Need::RealTimeImage => gpu_points(report, &f.name)?
            .into_iter()
            .filter(within)
            .min_by(by(|p| p.ms_per_frame.unwrap_or(f64::INFINITY))),
        Need::SmallestTable => cpu_points(f)
            .filter(|p| p.bytes.is_some() && within(p))
            .min_by_key(|p| p.bytes),
        Need::FastestCpu => cpu_points(f).filter(within).min_by(by(ns)),
        Need::NoBake => cpu_points(f)
            .filter(|p| matches!(&p.choice, Choice::Cpu(e) if e.is_model()))
            .filter(within)
            .min_by(by(ns)),
        Need::GroundTruth => cpu_points(f).find(|p| p.choice == Choice::Direct),
    }
}

/// What the section says where `need` has no pick for fabric `f`.
fn missing(report: &Report, f: &FabricReport, need: Need) -> String {
    match need.budget() {
        _ if need == Need::RealTimeImage && gpu_points(report, &f.name).is_none() => {
            "not measured".into()
        }
        Some(b) => format!("none within {}", budget(b)),
        None => "not measured".into(),
    }
}

/// The smallest and largest of `values`, formatted, as "a–b" with a unit they share
/// written once ("0.19–0.39%", "296–934 KiB"), or "a" when both read the same.
fn range(values: impl Iterator<Item = f64>, format: impl Fn(f64) -> String) -> String {
    let (lo, hi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
        (lo.min(v), hi.max(v))
    });
    let (lo, hi) = (format(lo), format(hi));
    let unit = |s: &str| {
        let digits = s.trim_end_matches(|c: char| !c.is_ascii_digit()).len();
        s[digits..].to_string()
    };
    if lo == hi {
        lo
    } else if !unit(&lo).is_empty() && unit(&lo) == unit(&hi) {
        format!("{}–{hi}", &lo[..lo.len() - unit(&lo).len()])
    } else {
        format!("{lo}–{hi}")
    }
}

/// The section's row for `need`: the picks grouped by choice, and the range of what they
/// give.
fn row(report: &Report, need: Need, picks: &[Option<Pick>]) -> String {
    let fabrics = &report.fabrics;
    let mut groups: Vec<(String, Vec<&str>)> = Vec::new();
    for (f, p) in fabrics.iter().zip(picks) {
        let label = p
            .as_ref()
            .map_or_else(|| missing(report, f, need), |p| format!("**{}**", p.choice));
        match groups.iter_mut().find(|(l, _)| *l == label) {
            Some((_, names)) => names.push(&f.name),
            None => groups.push((label, vec![&f.name])),
        }
    }
    let choice = if groups.len() == 1 && fabrics.len() > 1 {
        format!("{}, every fabric", groups[0].0)
    } else {
        let parts: Vec<String> = groups
            .iter()
            .map(|(label, names)| format!("{label}: {}", names.join(", ")))
            .collect();
        parts.join("; ")
    };
    let found: Vec<&Pick> = picks.iter().flatten().collect();
    let errors = || range(found.iter().map(|p| p.error), pct);
    let ns = || range(found.iter().filter_map(|p| p.ns_per_eval), num);
    let gives = if found.is_empty() {
        if need == Need::RealTimeImage && !report.gpu.measured {
            format!("no GPU figures in this run ({})", report.gpu.status)
        } else {
            "–".into()
        }
    } else {
        match need {
            Need::RealTimeImage => {
                let [w, h] = report.gpu.frame.unwrap_or_default();
                let ms = range(found.iter().filter_map(|p| p.ms_per_frame), |x| {
                    format!("{x:.1}")
                });
                let adapter = if report.gpu.device_type.as_deref() == Some("Cpu") {
                    " on a software rasteriser"
                } else {
                    ""
                };
                format!(
                    "image error {}, {ms} ms per {w}×{h} frame{adapter}",
                    errors()
                )
            }
            Need::SmallestTable => format!(
                "{}, error {}, {} ns per lookup",
                range(
                    found.iter().filter_map(|p| p.bytes.map(|b| b as f64)),
                    |b| size(b as usize)
                ),
                errors(),
                ns()
            ),
            Need::FastestCpu | Need::NoBake => {
                format!("error {}, {} ns per evaluation", errors(), ns())
            }
            Need::GroundTruth => format!(
                "converged (error 0 by definition), {} ns per evaluation",
                ns()
            ),
        }
    };
    format!(
        "| {} | {} | {choice} | {gives} | {} |\n",
        need.title(),
        need.rule(),
        need.rests_on(report)
    )
}

/// The section, written into `md`.
pub fn section(report: &Report, md: &mut String) {
    let picks: Vec<Vec<Option<Pick>>> = Need::ALL
        .iter()
        .map(|&need| {
            report
                .fabrics
                .iter()
                .map(|f| pick(report, f, need))
                .collect()
        })
        .collect();
    let _ = writeln!(md, "## {HEADING}\n");
    let _ = writeln!(
        md,
        "What this run's measurements pick for each need, per fabric. Error: the worse of the \
         uniform and highlight relative RMS errors against the direct evaluation on the CPU; \
         on the GPU, the image error against the CPU reference render. Each pick is the \
         extreme of the points measured below within the need's budget, so it holds for the \
         layouts, resolutions and evaluator settings of this run; the last column names the \
         figure and the section it rests on, and [Error budgets](#error-budgets) gives the \
         same choice at other budgets.\n"
    );
    let _ = writeln!(
        md,
        "| you need | picked as | pick | what it gives | rests on |"
    );
    let _ = writeln!(md, "|---|---|---|---|---|");
    for (&need, picks) in Need::ALL.iter().zip(&picks) {
        md.push_str(&row(report, need, picks));
    }
    md.push('\n');
    let columns: Vec<String> = Need::ALL.iter().map(|n| n.column()).collect();
    let _ = writeln!(md, "Per fabric:\n");
    let _ = writeln!(md, "| fabric | {} |", columns.join(" | "));
    let _ = writeln!(md, "|---|{}", "---|".repeat(columns.len()));
    for (i, f) in report.fabrics.iter().enumerate() {
        let cells: Vec<String> = Need::ALL
            .iter()
            .zip(&picks)
            .map(|(&need, picks)| {
                picks[i]
                    .as_ref()
                    .map_or_else(|| missing(report, f, need), |p| p.cell(need))
            })
            .collect();
        let _ = writeln!(md, "| {} | {} |", f.name, cells.join(" | "));
    }
    md.push('\n');
}
