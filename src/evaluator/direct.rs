//! `direct`: the converged direct rule (docs/model.md#direct-evaluation), the ground truth
//! every table and rule is measured against. CPU only: its sample count per pair, in the
//! thousands, has no place in a shader.

use super::{
    EvaluationContext, Evaluator, EvaluatorError, EvaluatorUnit, FabricEvaluator, ModelEvaluation,
    Parsed, parameter_error,
};
use crate::model::{Fabric, Integration};
use std::sync::Arc;

/// The unit's entry in the registry.
pub const UNIT: EvaluatorUnit = EvaluatorUnit {
    name: "direct",
    syntax: "direct",
    summary: "the converged direct rule, the ground truth (CPU only)",
    parse,
    report: None,
};

fn parse(parameter: Option<&str>) -> Parsed {
    match parameter {
        None => Ok(Arc::new(Direct)),
        Some(_) => Err(parameter_error(&UNIT, parameter, "takes no parameter")),
    }
}

#[derive(Debug)]
pub struct Direct;

impl Evaluator for Direct {
    fn spelling(&self) -> String {
        "direct".into()
    }

    fn prepare(
        &self,
        fabric: &Fabric,
        _context: &EvaluationContext,
    ) -> Result<Box<dyn FabricEvaluator>, EvaluatorError> {
        Ok(ModelEvaluation::boxed(
            self.spelling(),
            fabric,
            Integration::Direct,
            Err("paper:N or resonant"),
        ))
    }
}
