//! `constant`: F = 1/π for every pair above the horizon. Not a cloth model: the cost floor
//! of a frame (rasterisation, shading frame, tone mapping without BRDF work), so a BRDF's
//! own cost is its frame time minus this one's.

#[cfg(feature = "runtime")]
pub mod gpu;

use super::{
    EvaluationContext, Evaluator, EvaluatorError, EvaluatorUnit, FabricEvaluator, Parsed,
    parameter_error,
};
use crate::model::Fabric;
use crate::sampling::Sampler;
use glam::DVec3;
use std::f64::consts::FRAC_1_PI;
use std::sync::Arc;

/// The unit's entry in the registry.
pub const UNIT: EvaluatorUnit = EvaluatorUnit {
    name: "constant",
    syntax: "constant",
    summary: "F = 1/π above the horizon: a frame's cost floor, not a model",
    parse,
    report: None,
};

fn parse(parameter: Option<&str>) -> Parsed {
    match parameter {
        None => Ok(Arc::new(Constant)),
        Some(_) => Err(parameter_error(&UNIT, parameter, "takes no parameter")),
    }
}

#[derive(Debug)]
pub struct Constant;

impl Evaluator for Constant {
    fn spelling(&self) -> String {
        "constant".into()
    }

    fn prepare(
        &self,
        fabric: &Fabric,
        _context: &EvaluationContext,
    ) -> Result<Box<dyn FabricEvaluator>, EvaluatorError> {
        Ok(Box::new(ConstantEvaluation {
            fabric: fabric.clone(),
        }))
    }
}

struct ConstantEvaluation {
    fabric: Fabric,
}

impl FabricEvaluator for ConstantEvaluation {
    fn label(&self) -> String {
        "constant".into()
    }

    /// The CPU twin of `GpuConstant`'s WGSL.
    fn eval(&self, wi: DVec3, wo: DVec3) -> DVec3 {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            DVec3::ZERO
        } else {
            DVec3::splat(FRAC_1_PI)
        }
    }

    fn sampler(&self) -> Sampler {
        Sampler::for_fabric(&self.fabric)
    }

    #[cfg(feature = "runtime")]
    fn gpu(
        &self,
        context: &crate::gpu::GpuContext,
    ) -> Result<Box<dyn crate::gpu::GpuBrdf>, EvaluatorError> {
        Ok(Box::new(gpu::GpuConstant::new(context)))
    }

    #[cfg(feature = "runtime")]
    fn gpu_wgsl(&self) -> Result<String, EvaluatorError> {
        Ok(gpu::constant_wgsl())
    }
}
