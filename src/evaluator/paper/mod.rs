//! `paper[:N]`: the paper's renderer, N stratified tangent samples per thread
//! (docs/model.md#paper-mode), on the CPU and in the shader ([`gpu::GpuPaper`], `paper.wgsl`
//! in this folder).

#[cfg(feature = "runtime")]
pub mod gpu;

use super::{
    EvaluationContext, Evaluator, EvaluatorError, EvaluatorUnit, FabricEvaluator, ModelEvaluation,
    Parsed, ReportPlan, parameter_error,
};
use crate::model::curve::DEFAULT_PAPER_SAMPLES;
use crate::model::{Fabric, Integration};
use std::sync::Arc;

/// Most samples per thread a spelling may ask for (the shader's own bound,
/// [`MAX_SHADER_SAMPLES`], is lower, and its constructor names it).
pub const MAX_SAMPLES: u32 = 1_000_000;

/// Most tangent samples per thread the shader accepts: the per-pair cost grows linearly
/// with N, and far beyond the paper's handful of samples a table or the CPU's converged
/// rule is the better tool.
pub const MAX_SHADER_SAMPLES: u32 = 1024;

/// The unit's entry in the registry.
pub const UNIT: EvaluatorUnit = EvaluatorUnit {
    name: "paper",
    syntax: "paper[:N]",
    summary: "the paper's renderer: N stratified tangent samples per thread (default 32)",
    parse,
    report: Some(ReportPlan {
        cpu_quick: &[
            "paper:1", "paper:2", "paper:4", "paper:8", "paper:16", "paper:32", "paper:64",
        ],
        // Up to 1024, where paper mode reaches the resonant quadrature's error (satin back
        // needs it).
        cpu_full: &[
            "paper:1",
            "paper:2",
            "paper:4",
            "paper:8",
            "paper:16",
            "paper:32",
            "paper:64",
            "paper:128",
            "paper:256",
            "paper:512",
            "paper:1024",
        ],
        // The GPU section stops where a software rasteriser's frame gets too slow to time
        // repeatedly.
        gpu_quick: &[
            "paper:1", "paper:2", "paper:4", "paper:8", "paper:16", "paper:32", "paper:64",
        ],
        gpu_full: &[
            "paper:1", "paper:2", "paper:4", "paper:8", "paper:16", "paper:32", "paper:64",
        ],
        baseline: true,
        setting: "N stratified tangent samples per thread",
    }),
};

fn parse(parameter: Option<&str>) -> Parsed {
    let samples = match parameter {
        None => DEFAULT_PAPER_SAMPLES,
        Some(text) => text
            .parse::<u32>()
            .ok()
            .filter(|n| (1..=MAX_SAMPLES).contains(n))
            .ok_or_else(|| {
                parameter_error(
                    &UNIT,
                    parameter,
                    format!("N must be a whole number in 1..={MAX_SAMPLES}"),
                )
            })?,
    };
    Ok(Arc::new(Paper { samples }))
}

/// Paper mode with `samples` tangent samples per thread.
#[derive(Debug)]
pub struct Paper {
    pub samples: u32,
}

impl Evaluator for Paper {
    fn spelling(&self) -> String {
        format!("paper:{}", self.samples)
    }

    fn prepare(
        &self,
        fabric: &Fabric,
        _context: &EvaluationContext,
    ) -> Result<Box<dyn FabricEvaluator>, EvaluatorError> {
        Ok(ModelEvaluation::boxed(
            self.spelling(),
            fabric,
            Integration::Paper(self.samples),
            Ok(Box::new(Paper {
                samples: self.samples,
            })),
        ))
    }

    /// Twice or half the samples, within what the shader accepts.
    fn step(&self, finer: bool) -> Option<Arc<dyn Evaluator>> {
        let samples = if finer {
            self.samples.checked_mul(2)?
        } else {
            self.samples / 2
        };
        (1..=MAX_SHADER_SAMPLES)
            .contains(&samples)
            .then(|| Arc::new(Paper { samples }) as _)
    }
}

impl super::ModelGpuForm for Paper {
    #[cfg(feature = "runtime")]
    fn wgsl(&self, _fabric: &Fabric) -> String {
        gpu::paper_wgsl()
    }

    #[cfg(feature = "runtime")]
    fn build(
        &self,
        context: &crate::gpu::GpuContext,
        fabric: &Fabric,
    ) -> Result<Box<dyn crate::gpu::GpuBrdf>, EvaluatorError> {
        Ok(Box::new(gpu::GpuPaper::new(context, fabric, self.samples)?))
    }
}
