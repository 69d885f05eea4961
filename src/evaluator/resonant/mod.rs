//! `resonant[:S/V/B]`: the resonant quadrature (docs/model.md#resonant-quadrature) with S
//! Gauss–Legendre nodes per segment on the surface lobe, V on the volume lobe and B for
//! ⟨P⟩ and the kd term; on the CPU and in the shader ([`gpu::GpuResonant`], the WGSL files
//! in this folder, one shader per node counts with the fabric in a buffer that an edit
//! rewrites in place).

#[cfg(feature = "runtime")]
pub mod gpu;
#[cfg(feature = "runtime")]
pub mod kernel;

use super::{
    EvaluationContext, Evaluator, EvaluatorError, EvaluatorUnit, FabricEvaluator, ModelEvaluation,
    Parsed, ReportPlan, parameter_error,
};
use crate::model::{Fabric, Integration, ResonantNodes};
use std::sync::Arc;

/// The unit's entry in the registry.
pub const UNIT: EvaluatorUnit = EvaluatorUnit {
    name: "resonant",
    syntax: "resonant[:S/V/B]",
    summary: "the resonant quadrature: S/V/B nodes per segment (surface, volume, base)",
    parse,
    report: Some(ReportPlan {
        // A coarse, a middle and the default point.
        cpu_quick: &["resonant:3/2/2", "resonant:5/3/2", "resonant:6/5/2"],
        cpu_full: &[
            "resonant:3/2/2",
            "resonant:4/3/2",
            "resonant:5/4/2",
            "resonant:6/5/2",
            "resonant:8/6/3",
            "resonant:10/8/4",
        ],
        gpu_quick: &["resonant:6/5/2"],
        gpu_full: &["resonant:3/2/2", "resonant:6/5/2"],
        baseline: false,
        setting: "Gauss–Legendre nodes per curve segment on the surface lobe, the volume lobe \
                  and for ⟨P⟩ and the kd term (surface/volume/base)",
    }),
};

fn parse(parameter: Option<&str>) -> Parsed {
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
                &UNIT,
                parameter,
                "give three whole node counts",
            ));
        }
    };
    nodes
        .validate()
        .map_err(|e| parameter_error(&UNIT, parameter, e.to_string()))?;
    Ok(Arc::new(Resonant { nodes }))
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
        Ok(ModelEvaluation::boxed(
            self.spelling(),
            fabric,
            Integration::Resonant(self.nodes),
            Ok(Box::new(Resonant { nodes: self.nodes })),
        ))
    }
}

impl super::ModelGpuForm for Resonant {
    #[cfg(feature = "runtime")]
    fn wgsl(&self, _fabric: &Fabric) -> String {
        // The fabric is in the form's buffer, not its WGSL.
        gpu::resonant_wgsl(self.nodes)
    }

    #[cfg(feature = "runtime")]
    fn build(
        &self,
        context: &crate::gpu::GpuContext,
        fabric: &Fabric,
    ) -> Result<Box<dyn crate::gpu::GpuBrdf>, EvaluatorError> {
        Ok(Box::new(gpu::GpuResonant::new(
            context, fabric, self.nodes,
        )?))
    }
}
