//! `resonant[:S/V/B]`: the resonant quadrature (docs/model.md#resonant-quadrature) with S
//! Gauss–Legendre nodes per segment on the surface lobe, V on the volume lobe and B for
//! ⟨P⟩ and the kd term; on the CPU and in the shader (`shaders/model/resonant_quadrature.wgsl`).

use super::{
    EvaluationContext, Evaluator, EvaluatorError, EvaluatorUnit, FabricEvaluator, ModelEvaluation,
    parameter_error,
};
use crate::model::{Fabric, Integration, ResonantNodes};
use std::sync::Arc;

pub struct ResonantUnit;

impl EvaluatorUnit for ResonantUnit {
    fn name(&self) -> &'static str {
        "resonant"
    }

    fn syntax(&self) -> &'static str {
        "resonant[:S/V/B]"
    }

    fn summary(&self) -> &'static str {
        "the resonant quadrature: S/V/B nodes per segment (surface, volume, base)"
    }

    fn parse(&self, parameter: Option<&str>) -> Result<Arc<dyn Evaluator>, EvaluatorError> {
        let Some(text) = parameter else {
            return Ok(Arc::new(Resonant {
                nodes: ResonantNodes::DEFAULT,
            }));
        };
        let counts: Vec<Option<u32>> = text.split('/').map(|n| n.parse().ok()).collect();
        let nodes = match counts[..] {
            [Some(surface), Some(volume), Some(base)] => ResonantNodes {
                surface,
                volume,
                base,
            },
            _ => {
                return Err(parameter_error(
                    self,
                    parameter,
                    "give three whole node counts",
                ));
            }
        };
        nodes
            .validate()
            .map_err(|e| parameter_error(self, parameter, e.to_string()))?;
        Ok(Arc::new(Resonant { nodes }))
    }
}

/// The resonant quadrature with these node counts.
#[derive(Debug)]
pub struct Resonant {
    pub nodes: ResonantNodes,
}

impl Evaluator for Resonant {
    fn spelling(&self) -> String {
        format!("resonant:{}", self.nodes)
    }

    fn prepare(
        &self,
        fabric: &Fabric,
        _context: &EvaluationContext,
    ) -> Result<Box<dyn FabricEvaluator>, EvaluatorError> {
        let nodes = self.nodes;
        #[cfg(feature = "runtime")]
        let gpu: super::GpuForm = Ok(Box::new(move |context, fabric| {
            Ok(Box::new(crate::gpu::GpuResonant::new(context, fabric, nodes)?) as _)
        }));
        #[cfg(not(feature = "runtime"))]
        let gpu = ();
        Ok(ModelEvaluation::boxed(
            self.spelling(),
            fabric,
            Integration::Resonant(nodes),
            gpu,
        ))
    }
}
