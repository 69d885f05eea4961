//! Per fabric, the GPU forms of the evaluations the viewer has shown so far.

use crate::evaluator::table::{BakedTable, TableEvaluation};
use crate::evaluator::{EvaluationContext, Evaluator, EvaluatorError, FabricEvaluator};
use crate::formats::table_exr::TableFile;
use crate::gpu::{GpuBrdf, GpuContext, GpuSampleTaps};
use crate::model::Fabric;

/// A fabric's evaluations of F, prepared and put on the GPU as they are shown, by evaluator
/// spelling. The first is always the fabric's baked table: the environment light's taps are
/// its, whatever evaluation is shown.
pub(super) struct FabricGpu {
    pub shown: Vec<Shown>,
    /// The sample taps of the fabric's table evaluation, once the environment light needs
    /// them.
    pub taps: Option<GpuSampleTaps>,
}

/// The GPU form of one evaluation of a fabric.
pub(super) struct Shown {
    pub spelling: String,
    pub brdf: Box<dyn GpuBrdf>,
}

impl FabricGpu {
    /// A fabric's entry holding its table's evaluation, put on the GPU.
    pub fn with_table(gpu: &GpuContext, file: TableFile) -> Result<Self, EvaluatorError> {
        let evaluation: Box<dyn FabricEvaluator> = Box::new(TableEvaluation { table: file.table });
        let brdf = evaluation.gpu(gpu)?;
        let spelling = BakedTable { path: None }.spelling();
        Ok(Self {
            shown: vec![Shown { spelling, brdf }],
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
        self.shown.push(Shown { spelling, brdf });
        Ok(self.shown.len() - 1)
    }
}
