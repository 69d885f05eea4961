//! Evaluators: the ways clothbake computes F(wi, wo) of a fabric, each one unit behind one
//! interface, reached by one spelling on every command (`eval`, `sample`, `albedo`,
//! `render`):
//!
//! | spelling | unit | F from |
//! |---|---|---|
//! | `direct` | [`direct`] | the converged direct rule, the ground truth (CPU only) |
//! | `paper[:N]` | [`paper`] | the paper's renderer: N stratified tangent samples per thread |
//! | `resonant[:S/V/B]` | [`resonant`] | the resonant quadrature with these nodes per segment |
//! | `table[:PATH]`, `PATH.exr` | [`table`] | a baked table's lookup (default: the fabric's table in the tables directory) |
//! | `constant` | [`constant`] | F = 1/π above the horizon: the cost floor of a frame, not a model |
//! | `gltf` | [`gltf`] | glTF 2.0 with KHR_materials_sheen and _anisotropy, fitted to the fabric |
//! | `openpbr` | [`openpbr`] | OpenPBR Surface's fuzz and specular (MaterialX 1.39), fitted |
//! | `filament` | [`filament`] | Filament's cloth model, fitted |
//! | `unreal` | [`unreal`] | Unreal Engine's Cloth shading model, fitted |
//!
//! A unit is one module here: a file, or a folder holding its CPU evaluation (`mod.rs`), its
//! GPU form (`gpu.rs`, a [`GpuBrdf`], with the runtime) and its own WGSL (added to the
//! composer by the GPU form, [`crate::shader::Composer::unit_file`]). It describes itself by
//! one [`EvaluatorUnit`] constant (its name, the syntax of its parameter, and the function that
//! parses it into an [`Evaluator`]), which is one line in [`EVALUATORS`]. An [`Evaluator`] is a
//! configured spelling; for a fabric it prepares a [`FabricEvaluator`] (reading and checking
//! files on the CPU), whose CPU evaluation and, with the runtime, GPU form the commands, the
//! renderer, the viewer, the report and the tests use without naming the unit.

pub mod constant;
pub mod direct;
pub mod filament;
pub mod gltf;
pub mod openpbr;
pub mod paper;
pub mod resonant;
pub mod stock;
pub mod table;
pub mod unreal;

use crate::model::Fabric;
use crate::sampling::{SampleTaps, Sampler};
use glam::DVec3;
use rayon::prelude::*;
use std::fmt;
use std::path::{Path, PathBuf};
use std::str::FromStr;
use std::sync::Arc;

#[cfg(feature = "runtime")]
use crate::gpu::{GpuBrdf, GpuContext};

/// The registry: every evaluator, by the name its spelling starts with.
pub const EVALUATORS: &[EvaluatorUnit] = &[
    direct::UNIT,
    paper::UNIT,
    resonant::UNIT,
    table::UNIT,
    constant::UNIT,
    gltf::UNIT,
    openpbr::UNIT,
    filament::UNIT,
    unreal::UNIT,
];

/// One kind of evaluation, as plain data: its name and how its parameter is written and
/// read.
#[derive(Clone, Copy, Debug)]
pub struct EvaluatorUnit {
    /// The word a spelling starts with (`paper` in `paper:32`).
    pub name: &'static str,
    /// The whole spelling with its parameter, for help texts (`paper[:N]`).
    pub syntax: &'static str,
    /// What F comes from, in a few words.
    pub summary: &'static str,
    /// The evaluator that the parameter (the text after `name:`, `None` without a colon)
    /// configures; the error names what is wrong with it.
    pub parse: fn(Option<&str>) -> Parsed,
    /// What `clothbake report` measures of this unit (`None`: nothing; the tables the
    /// report measures are the layouts', [`crate::table::Layout::ALL`]).
    pub report: Option<ReportPlan>,
}

/// The spellings of one unit that `clothbake report` measures against the direct rule:
/// on the CPU (error, cost) and rendered in the GPU section, in its quick and full runs.
#[derive(Clone, Copy, Debug)]
pub struct ReportPlan {
    pub cpu_quick: &'static [&'static str],
    pub cpu_full: &'static [&'static str],
    pub gpu_quick: &'static [&'static str],
    pub gpu_full: &'static [&'static str],
    /// Whether every other point is compared with this unit's (paper mode: the paper's own
    /// renderer, the baseline a table or another rule has to beat).
    pub baseline: bool,
    /// What the report's section on this unit says its setting is, in a sentence.
    pub setting: &'static str,
}

impl ReportPlan {
    /// The spellings measured on the CPU (`quick`: the quick run's).
    pub fn cpu(&self, quick: bool) -> &'static [&'static str] {
        if quick { self.cpu_quick } else { self.cpu_full }
    }

    /// The spellings rendered in the GPU section.
    pub fn gpu(&self, quick: bool) -> &'static [&'static str] {
        if quick { self.gpu_quick } else { self.gpu_full }
    }
}

/// What parsing a spelling gives: the configured evaluator, or what is wrong with it.
pub type Parsed = Result<Arc<dyn Evaluator>, EvaluatorError>;

/// Where evaluators find files that the spelling leaves implicit.
#[derive(Clone, Debug)]
pub struct EvaluationContext {
    /// Directory of baked tables, `NAME.exr` per fabric (the `table` evaluator's default).
    pub tables: PathBuf,
}

impl Default for EvaluationContext {
    fn default() -> Self {
        Self {
            tables: PathBuf::from("tables"),
        }
    }
}

/// A configured evaluator: a unit with its parameter.
pub trait Evaluator: Send + Sync + fmt::Debug {
    /// The spelling that parses back to this evaluator (`paper:32`, `resonant:6/5/2`).
    fn spelling(&self) -> String;
    /// The evaluation of `fabric`, its files read and checked (no GPU work).
    fn prepare(
        &self,
        fabric: &Fabric,
        context: &EvaluationContext,
    ) -> Result<Box<dyn FabricEvaluator>, EvaluatorError>;
    /// The same unit one setting finer (`true`) or coarser, where its parameter has such
    /// steps (the viewer's + and − keys); `None` at the end of its range or without steps.
    fn step(&self, _finer: bool) -> Option<Arc<dyn Evaluator>> {
        None
    }
}

/// One fabric's evaluation of F, on the CPU and (with the runtime) on the GPU.
pub trait FabricEvaluator: Send + Sync {
    /// A short description for logs (`table LAYOUT R=31`, `paper N=32`).
    fn label(&self) -> String;
    /// F(wi, wo), cosines included, for unit directions in the patch frame.
    fn eval(&self, wi: DVec3, wo: DVec3) -> DVec3;
    /// [`Self::eval`] of every pair, in order (in parallel; units override where a batch
    /// is cheaper than its pairs).
    fn eval_batch(&self, pairs: &[(DVec3, DVec3)]) -> Vec<DVec3> {
        pairs
            .par_iter()
            .map(|&(wi, wo)| self.eval(wi, wo))
            .collect()
    }
    /// The importance sampler that fits this evaluation (a table's own, or the fabric's).
    fn sampler(&self) -> Sampler;
    /// For a rule that places its tangent samples per pair, the mean and the largest
    /// number of kernel evaluations per light (tangent samples of both threads) over
    /// `pairs`; `None` where the count is fixed or there are none.
    fn kernel_evaluations(&self, _pairs: &[(DVec3, DVec3)]) -> Option<(f64, usize)> {
        None
    }
    /// The environment light's sample taps for `samples` per pixel: `samples` strata of
    /// `sampler`'s density (this evaluation's, [`Self::sampler`]), each with this
    /// evaluation's ∫F over it.
    fn sample_taps(&self, sampler: &Sampler, samples: u32) -> SampleTaps {
        SampleTaps::build(sampler, samples, |pairs, out| {
            out.copy_from_slice(&self.eval_batch(pairs))
        })
    }
    /// The GPU form of this evaluation, or [`EvaluatorError::NoGpuForm`].
    #[cfg(feature = "runtime")]
    fn gpu(&self, context: &GpuContext) -> Result<Box<dyn GpuBrdf>, EvaluatorError>;
    /// The WGSL module of the GPU form ([`GpuBrdf::wgsl`] of [`Self::gpu`]'s), made without
    /// a device, or [`EvaluatorError::NoGpuForm`].
    #[cfg(feature = "runtime")]
    fn gpu_wgsl(&self) -> Result<String, EvaluatorError>;
}

/// Why an evaluator could not be parsed, prepared or put on the GPU.
#[derive(Debug, thiserror::Error)]
pub enum EvaluatorError {
    #[error("unknown evaluator '{spelling}'; evaluators: {known}")]
    Unknown { spelling: String, known: String },
    #[error("evaluator '{spelling}': {message} (write it as {syntax})")]
    Parameter {
        spelling: String,
        syntax: &'static str,
        message: String,
    },
    #[error("evaluator '{spelling}' has no GPU form; on the GPU use {instead}")]
    NoGpuForm {
        spelling: String,
        instead: &'static str,
    },
    #[error(transparent)]
    Table(table::TableError),
    #[cfg(feature = "runtime")]
    #[error(transparent)]
    Gpu(#[from] crate::gpu::GpuError),
}

/// A spelling's unit name and parameter: `NAME` or `NAME:PARAMETER`.
pub fn split(spelling: &str) -> (&str, Option<&str>) {
    match spelling.split_once(':') {
        Some((name, parameter)) => (name, Some(parameter)),
        None => (spelling, None),
    }
}

/// The registered unit a spelling names (by the text before its ':'), if any.
pub fn unit_of(spelling: &str) -> Option<&'static EvaluatorUnit> {
    let (name, _) = split(spelling);
    EVALUATORS.iter().find(|unit| unit.name == name)
}

/// Parses an evaluator's spelling: `NAME` or `NAME:PARAMETER` of a registered unit, or a
/// path ending in `.exr` (a table file).
pub fn parse(spelling: &str) -> Result<Arc<dyn Evaluator>, EvaluatorError> {
    if let Some(unit) = unit_of(spelling) {
        return (unit.parse)(split(spelling).1);
    }
    if Path::new(spelling)
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("exr"))
    {
        return (table::UNIT.parse)(Some(spelling));
    }
    Err(EvaluatorError::Unknown {
        spelling: spelling.to_string(),
        known: EVALUATORS
            .iter()
            .map(|u| u.syntax)
            .collect::<Vec<_>>()
            .join(", "),
    })
}

/// An evaluator's spelling as a command-line value: parses with [`parse`], prints its
/// [`Evaluator::spelling`].
#[derive(Clone, Debug)]
pub struct EvaluatorSpec(pub Arc<dyn Evaluator>);

impl FromStr for EvaluatorSpec {
    type Err = EvaluatorError;

    fn from_str(spelling: &str) -> Result<Self, Self::Err> {
        parse(spelling).map(Self)
    }
}

impl fmt::Display for EvaluatorSpec {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0.spelling())
    }
}

/// How a model evaluation is put on the GPU: its unit's form, or (`Err`) what to use instead
/// where it has none.
type GpuForm = Result<Box<dyn ModelGpuForm>, &'static str>;

/// A model evaluation's GPU form for a fabric: its WGSL, and its [`GpuBrdf`] on a device
/// (without the runtime, a marker with nothing to do).
trait ModelGpuForm: Send + Sync {
    #[cfg(feature = "runtime")]
    fn wgsl(&self, fabric: &Fabric) -> String;
    #[cfg(feature = "runtime")]
    fn build(
        &self,
        context: &GpuContext,
        fabric: &Fabric,
    ) -> Result<Box<dyn GpuBrdf>, EvaluatorError>;
}

/// A fabric evaluated by the model itself with one integration rule (the `direct`, `paper`
/// and `resonant` units), sampled by the fabric's own sampler.
struct ModelEvaluation {
    spelling: String,
    fabric: Fabric,
    patch: crate::model::Patch,
    #[cfg_attr(not(feature = "runtime"), allow(dead_code))]
    gpu: GpuForm,
}

impl ModelEvaluation {
    fn boxed(
        spelling: String,
        fabric: &Fabric,
        integration: crate::model::Integration,
        gpu: GpuForm,
    ) -> Box<dyn FabricEvaluator> {
        Box::new(Self {
            spelling,
            fabric: fabric.clone(),
            patch: crate::model::Patch::new(fabric, integration),
            gpu,
        })
    }
}

impl FabricEvaluator for ModelEvaluation {
    fn label(&self) -> String {
        self.spelling.clone()
    }

    fn eval(&self, wi: DVec3, wo: DVec3) -> DVec3 {
        self.patch.eval(wi, wo)
    }

    fn sampler(&self) -> Sampler {
        Sampler::for_fabric(&self.fabric)
    }

    fn kernel_evaluations(&self, pairs: &[(DVec3, DVec3)]) -> Option<(f64, usize)> {
        self.patch.resonant_evaluations(pairs)
    }

    #[cfg(feature = "runtime")]
    fn gpu(&self, context: &GpuContext) -> Result<Box<dyn GpuBrdf>, EvaluatorError> {
        self.gpu_form()?.build(context, &self.fabric)
    }

    #[cfg(feature = "runtime")]
    fn gpu_wgsl(&self) -> Result<String, EvaluatorError> {
        Ok(self.gpu_form()?.wgsl(&self.fabric))
    }
}

#[cfg(feature = "runtime")]
impl ModelEvaluation {
    fn gpu_form(&self) -> Result<&dyn ModelGpuForm, EvaluatorError> {
        match &self.gpu {
            Ok(form) => Ok(form.as_ref()),
            Err(instead) => Err(EvaluatorError::NoGpuForm {
                spelling: self.spelling.clone(),
                instead,
            }),
        }
    }
}

/// The parameter error of `unit` for `parameter`.
fn parameter_error(
    unit: &EvaluatorUnit,
    parameter: Option<&str>,
    message: impl Into<String>,
) -> EvaluatorError {
    EvaluatorError::Parameter {
        spelling: match parameter {
            Some(p) => format!("{}:{p}", unit.name),
            None => unit.name.to_string(),
        },
        syntax: unit.syntax,
        message: message.into(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_spelling_parses_back_to_itself() {
        for spelling in [
            "direct",
            "paper:32",
            "paper:1",
            "resonant:6/5/2",
            "resonant:3/2/2",
            "table",
            "table:tables/velvet.exr",
            "constant",
        ] {
            let evaluator = parse(spelling).unwrap();
            assert_eq!(evaluator.spelling(), spelling);
            assert_eq!(parse(&evaluator.spelling()).unwrap().spelling(), spelling);
        }
        assert_eq!(parse("paper").unwrap().spelling(), "paper:32");
        assert_eq!(
            parse("resonant").unwrap().spelling(),
            format!("resonant:{}", crate::model::ResonantNodes::DEFAULT)
        );
        assert_eq!(
            parse("my tables/velvet.EXR").unwrap().spelling(),
            "table:my tables/velvet.EXR"
        );
    }

    #[test]
    fn bad_spellings_name_what_is_wrong() {
        let message = |s: &str| parse(s).unwrap_err().to_string();
        assert!(message("nearest").contains("unknown evaluator 'nearest'"));
        assert!(message("nearest").contains("paper[:N]"));
        assert!(message("paper:0").contains("paper[:N]"));
        assert!(message("paper:x").contains("'paper:x'"));
        assert!(message("resonant:6/5").contains("resonant[:S/V/B]"));
        assert!(message("resonant:0/5/2").contains("'resonant:0/5/2'"));
        assert!(message("direct:3").contains("takes no parameter"));
        assert!(message("table:").contains("empty"));
    }

    #[test]
    fn paper_mode_steps_double_and_halve_within_the_shader_s_range() {
        let step =
            |spelling: &str, finer| parse(spelling).unwrap().step(finer).map(|e| e.spelling());
        assert_eq!(step("paper:32", true).as_deref(), Some("paper:64"));
        assert_eq!(step("paper:32", false).as_deref(), Some("paper:16"));
        assert_eq!(step("paper:1", false), None);
        let max = paper::MAX_SHADER_SAMPLES;
        assert_eq!(step(&format!("paper:{max}"), true), None);
        assert_eq!(step("paper:1000000", false), None);
        assert_eq!(step("resonant", true), None);
        assert_eq!(step("table", false), None);
    }

    #[test]
    fn every_spelling_a_report_plan_names_parses_to_its_unit_and_one_unit_is_the_baseline() {
        for unit in EVALUATORS {
            let Some(plan) = unit.report else { continue };
            for quick in [true, false] {
                for spelling in plan.cpu(quick).iter().chain(plan.gpu(quick)) {
                    assert_eq!(parse(spelling).unwrap().spelling(), *spelling);
                    assert!(spelling.starts_with(unit.name), "{spelling}");
                }
                assert!(plan.gpu(quick).iter().all(|s| plan.cpu(quick).contains(s)));
            }
        }
        let baselines = EVALUATORS
            .iter()
            .filter(|u| u.report.is_some_and(|p| p.baseline))
            .count();
        assert_eq!(baselines, 1);
    }

    #[test]
    fn every_registered_unit_has_a_distinct_name_and_parses_its_own_name() {
        let mut names: Vec<&str> = EVALUATORS.iter().map(|u| u.name).collect();
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), EVALUATORS.len());
        for unit in EVALUATORS {
            assert!(unit.syntax.starts_with(unit.name));
            let evaluator = parse(unit.name).unwrap();
            assert!(evaluator.spelling().starts_with(unit.name));
        }
    }
}
