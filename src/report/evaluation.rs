//! What a point of the report evaluates F by ([`Evaluation`]), and the registry's units as
//! the report sees them: the units with a [`ReportPlan`], the baseline among them and a
//! unit's default spelling.

use crate::evaluator::{EVALUATORS, EvaluatorUnit, ReportPlan, unit_of};
use crate::table::Layout;
use serde::{Deserialize, Serialize};

/// The registered units that say what the report measures of them, in registry order.
pub fn planned_units() -> impl Iterator<Item = (&'static EvaluatorUnit, ReportPlan)> {
    EVALUATORS
        .iter()
        .filter_map(|unit| unit.report.map(|plan| (unit, plan)))
}

/// The unit every other point is compared with: the one whose plan says `baseline`.
pub fn baseline_unit() -> Option<&'static EvaluatorUnit> {
    planned_units()
        .find(|(_, plan)| plan.baseline)
        .map(|(unit, _)| unit)
}

/// The spelling a unit's evaluator has without a parameter (its default setting).
pub fn default_spelling(unit: &EvaluatorUnit) -> Option<String> {
    (unit.parse)(None)
        .ok()
        .map(|evaluator| evaluator.spelling())
}

/// What a point of the report evaluates F by: a registered evaluator at one spelling, or a
/// baked table looked up. The CPU points, the GPU points, the comparisons, the picks and
/// the plots all name what they measured by this one type.
///
/// Written as `{"family": "evaluator", "spelling": ...}` or `{"family": "table", ...}`; the
/// forms of earlier reports are read too ([`StoredForm`]).
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(tag = "family", rename_all = "snake_case", from = "StoredForm")]
pub enum Evaluation {
    /// A registered evaluator at this spelling (`crate::evaluator::parse`).
    Evaluator { spelling: String },
    /// A table of this layout and resolution.
    Table { layout: Layout, resolution: u32 },
}

impl Evaluation {
    /// The evaluator of this spelling.
    pub fn evaluator(spelling: impl Into<String>) -> Self {
        Evaluation::Evaluator {
            spelling: spelling.into(),
        }
    }

    /// The registered unit that evaluates it (None for a table).
    pub fn unit(&self) -> Option<&'static EvaluatorUnit> {
        match self {
            Evaluation::Evaluator { spelling } => unit_of(spelling),
            Evaluation::Table { .. } => None,
        }
    }

    /// Whether this is an evaluator of `unit`.
    pub fn is_of(&self, unit: &EvaluatorUnit) -> bool {
        self.unit().is_some_and(|u| u.name == unit.name)
    }

    /// Whether this evaluates the model itself (no bake): the points a table is judged
    /// against.
    pub fn is_model(&self) -> bool {
        !matches!(self, Evaluation::Table { .. })
    }

    /// Whether this is of the baseline unit, the one every other point is compared with.
    pub fn is_baseline(&self) -> bool {
        self.unit()
            .and_then(|unit| unit.report)
            .is_some_and(|plan| plan.baseline)
    }

    /// The label beside its marker in a plot: the evaluator's parameter (`32` of
    /// `paper:32`), or a table's resolution.
    pub fn parameter(&self) -> String {
        match self {
            Evaluation::Evaluator { spelling } => {
                let (name, parameter) = crate::evaluator::split(spelling);
                parameter.unwrap_or(name).to_string()
            }
            Evaluation::Table { resolution, .. } => resolution.to_string(),
        }
    }
}

/// How REPORT.md names an evaluation: an evaluator by its spelling on every command
/// ("paper:32"), a table by layout and resolution ("thread_frame 48").
impl std::fmt::Display for Evaluation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Evaluation::Evaluator { spelling } => f.write_str(spelling),
            Evaluation::Table { layout, resolution } => write!(f, "{layout} {resolution}"),
        }
    }
}

/// An [`Evaluation`] as report.json holds it: the form this clothbake writes, or the forms
/// of reports written before points named their evaluator by its spelling (one family per
/// integration rule), read as the spellings those rules have now.
#[derive(Deserialize)]
#[serde(tag = "family", rename_all = "snake_case")]
enum StoredForm {
    Evaluator { spelling: String },
    Table { layout: Layout, resolution: u32 },
    Paper { samples: u32 },
    Resonant { nodes: StoredNodes },
}

/// The node counts of an earlier report's resonant point.
#[derive(Deserialize)]
struct StoredNodes {
    surface: u32,
    volume: u32,
    base: u32,
}

impl From<StoredForm> for Evaluation {
    fn from(stored: StoredForm) -> Self {
        match stored {
            StoredForm::Evaluator { spelling } => Evaluation::Evaluator { spelling },
            StoredForm::Table { layout, resolution } => Evaluation::Table { layout, resolution },
            StoredForm::Paper { samples } => Evaluation::evaluator(format!("paper:{samples}")),
            StoredForm::Resonant { nodes } => Evaluation::evaluator(format!(
                "resonant:{}/{}/{}",
                nodes.surface, nodes.volume, nodes.base
            )),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::Evaluation;

    #[test]
    fn points_read_in_the_current_and_the_earlier_forms() {
        let read = |text: &str| serde_json::from_str::<Evaluation>(text).unwrap();
        let current = Evaluation::evaluator("paper:8");
        let written = serde_json::to_string(&current).unwrap();
        assert_eq!(written, r#"{"family":"evaluator","spelling":"paper:8"}"#);
        assert_eq!(read(&written), current);
        assert_eq!(read(r#"{"family":"paper","samples":8}"#), current);
        assert_eq!(
            read(r#"{"family":"resonant","nodes":{"surface":6,"volume":5,"base":2}}"#),
            Evaluation::evaluator("resonant:6/5/2")
        );
        let layout = crate::table::Layout::DEFAULT.name();
        let table = format!(r#"{{"family":"table","layout":"{layout}","resolution":12}}"#);
        assert_eq!(serde_json::to_string(&read(&table)).unwrap(), table);
    }
}
