//! The viewer's shading modes and, per fabric, the evaluations shown so far with their GPU
//! forms.

use crate::evaluator::paper::Paper;
use crate::evaluator::resonant::Resonant;
use crate::evaluator::table::{TableEvaluation, TableLookup};
use crate::evaluator::{EvaluationContext, Evaluator, EvaluatorError, FabricEvaluator};
use crate::formats::table_exr::TableFile;
use crate::gpu::{GpuBrdf, GpuContext, GpuSampleTaps};
use crate::model::{Fabric, ResonantNodes};
use std::sync::Arc;

/// The viewer's shading modes (keys D and G switch them), each an evaluator of the registry
/// ([`crate::evaluator`]) shown through its GPU form.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Shading {
    /// The fabric's baked table (`table`).
    Lookup,
    /// The model in the shader, paper mode with the current samples per thread (`paper:N`).
    Paper,
    /// The resonant quadrature in the shader with the default nodes (`resonant`).
    Resonant,
}

impl Shading {
    /// The evaluator this mode shows, with `samples` tangent samples per thread in paper
    /// mode.
    pub fn evaluator(self, samples: u32) -> Arc<dyn Evaluator> {
        match self {
            Shading::Lookup => Arc::new(TableLookup { path: None }),
            Shading::Paper => Arc::new(Paper { samples }),
            Shading::Resonant => Arc::new(Resonant {
                nodes: ResonantNodes::DEFAULT,
            }),
        }
    }
}

/// A fabric's evaluations of F, prepared and put on the GPU as the modes are shown (the
/// table's first), by evaluator spelling.
pub(super) struct FabricGpu {
    pub shown: Vec<Shown>,
    /// The sample taps of the fabric's table evaluation, once the environment light needs
    /// them.
    pub taps: Option<GpuSampleTaps>,
}

/// One evaluation of a fabric and its GPU form.
pub(super) struct Shown {
    pub spelling: String,
    pub evaluation: Box<dyn FabricEvaluator>,
    pub brdf: Box<dyn GpuBrdf>,
}

impl FabricGpu {
    /// A fabric's entry holding its table's evaluation, put on the GPU.
    pub fn with_table(gpu: &GpuContext, file: TableFile) -> Result<Self, EvaluatorError> {
        let evaluation: Box<dyn FabricEvaluator> = Box::new(TableEvaluation { table: file.table });
        let brdf = evaluation.gpu(gpu)?;
        let spelling = Shading::Lookup.evaluator(0).spelling();
        Ok(Self {
            shown: vec![Shown {
                spelling,
                evaluation,
                brdf,
            }],
            taps: None,
        })
    }

    /// The index in `shown` of `evaluator`'s entry, prepared and put on the GPU on first use.
    pub fn entry(
        &mut self,
        gpu: &GpuContext,
        evaluator: &dyn Evaluator,
        fabric: &Fabric,
        context: &EvaluationContext,
    ) -> Result<usize, EvaluatorError> {
        let spelling = evaluator.spelling();
        if let Some(i) = self
            .shown
            .iter()
            .position(|shown| shown.spelling == spelling)
        {
            return Ok(i);
        }
        let evaluation = evaluator.prepare(fabric, context)?;
        let brdf = evaluation.gpu(gpu)?;
        self.shown.push(Shown {
            spelling,
            evaluation,
            brdf,
        });
        Ok(self.shown.len() - 1)
    }
}
