//! `paper[:N]`: the paper's renderer, N stratified tangent samples per thread
//! (docs/model.md#paper-mode), on the CPU and in the shader (`shaders/gpu/paper.wgsl`).

use super::{
    EvaluationContext, Evaluator, EvaluatorError, EvaluatorUnit, FabricEvaluator, ModelEvaluation,
    parameter_error,
};
use crate::model::curve::DEFAULT_PAPER_SAMPLES;
use crate::model::{Fabric, Integration};
use std::sync::Arc;

/// Most samples per thread a spelling may ask for (the shader's own bound is lower, and
/// its constructor names it).
pub const MAX_SAMPLES: u32 = 1_000_000;

pub struct PaperUnit;

impl EvaluatorUnit for PaperUnit {
    fn name(&self) -> &'static str {
        "paper"
    }

    fn syntax(&self) -> &'static str {
        "paper[:N]"
    }

    fn summary(&self) -> &'static str {
        "the paper's renderer: N stratified tangent samples per thread (default 32)"
    }

    fn parse(&self, parameter: Option<&str>) -> Result<Arc<dyn Evaluator>, EvaluatorError> {
        let samples = match parameter {
            None => DEFAULT_PAPER_SAMPLES,
            Some(text) => text
                .parse::<u32>()
                .ok()
                .filter(|n| (1..=MAX_SAMPLES).contains(n))
                .ok_or_else(|| {
                    parameter_error(
                        self,
                        parameter,
                        format!("N must be a whole number in 1..={MAX_SAMPLES}"),
                    )
                })?,
        };
        Ok(Arc::new(Paper { samples }))
    }
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
        let samples = self.samples;
        #[cfg(feature = "runtime")]
        let gpu: super::GpuForm = Ok(Box::new(move |context, fabric| {
            Ok(Box::new(crate::gpu::GpuDirect::new(context, fabric, samples)?) as _)
        }));
        #[cfg(not(feature = "runtime"))]
        let gpu = ();
        Ok(ModelEvaluation::boxed(
            self.spelling(),
            fabric,
            Integration::Paper(samples),
            gpu,
        ))
    }
}
