//! What the engines' stock cloth models share: a [`StockModel`] (its parameters, F and its
//! WGSL), a [`StockMaterial`] (a model at parameter values), the fit of a model to a fabric's
//! F ([`fit`]), and the evaluator every stock unit is (`gltf`, `openpbr`, `filament`,
//! `unreal`): for a fabric it fits the model and evaluates the best fit, so that the
//! commands, the renderer and the report show what a user of that engine would see.
//!
//! A stock model has no thread directions and no second thread: at most one anisotropic
//! lobe, which the units lay along the tangent (thread 1) as the exported mesh's tangents run.

pub mod fit;
#[cfg(feature = "runtime")]
pub mod gpu;
pub mod lobes;

use super::{
    EvaluationContext, Evaluator, EvaluatorError, EvaluatorUnit, FabricEvaluator, Parsed,
    parameter_error,
};
use crate::model::Fabric;
use crate::sampling::Sampler;
use glam::DVec3;
use std::sync::Arc;

/// Most parameters a stock model has (the GPU form's uniform block holds this many).
pub const MAX_PARAMETERS: usize = 16;
/// Most constants a model derives from its parameters (a sheen albedo table).
pub const MAX_DERIVED: usize = 32;

/// One input of a stock model, as its engine names it, with the range clothbake fits it in.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StockParameter {
    /// The engine's name of the input (`sheenRoughnessFactor`, `fuzz_roughness`); a colour
    /// is three parameters named `NAME.r`, `NAME.g`, `NAME.b`.
    pub name: &'static str,
    pub lower: f64,
    pub upper: f64,
}

impl StockParameter {
    /// The input `name`, fitted within [`lower`, `upper`].
    pub const fn new(name: &'static str, lower: f64, upper: f64) -> Self {
        Self { name, lower, upper }
    }
}

/// A stock model: one engine's cloth material, as one registered evaluator.
#[derive(Clone, Copy, Debug)]
pub struct StockModel {
    /// The unit's name (`gltf`).
    pub name: &'static str,
    /// The engine and the document it follows, for help texts and the report.
    pub title: &'static str,
    pub parameters: &'static [StockParameter],
    /// Where a fit starts for a fabric (one value per parameter, within its range).
    pub start: fn(&Fabric) -> Vec<f64>,
    /// Constants derived from the parameter values that both forms read (at most
    /// [`MAX_DERIVED`]); most models derive none.
    pub derive: fn(&[f64]) -> Vec<f64>,
    /// F(wi, wo) with the cosine from the parameter values and the derived constants, for
    /// l = wi and v = wo above the horizon and their half vector h (the horizon test and h
    /// are [`StockMaterial::eval`]'s, and `cloth_brdf`'s in stock.wgsl).
    pub eval: fn(&[f64], &[f64], DVec3, DVec3, DVec3) -> DVec3,
    /// Whether F(wi, wo)/cos θi = F(wo, wi)/cos θo for every parameter value.
    pub reciprocal: bool,
    /// Whether the model is built to reflect at most what arrives (a white material's
    /// directional albedo ≤ 1, up to the accuracy of its fitted parts): the white furnace
    /// of tests/model/stock.rs holds it to that.
    pub conserves_energy: bool,
    /// The unit's WGSL file, defining `cloth_stock_f(l, v, h)` (the twin of `eval`) over the
    /// parameters of `stock.wgsl`.
    #[cfg(feature = "runtime")]
    pub wgsl: &'static crate::shader::ShaderFile,
}

/// Derives nothing.
pub fn no_derived(_: &[f64]) -> Vec<f64> {
    Vec::new()
}

/// A stock model at parameter values: the material an export writes and its F.
#[derive(Clone, Debug)]
pub struct StockMaterial {
    pub model: &'static StockModel,
    pub values: Vec<f64>,
    pub derived: Vec<f64>,
}

impl StockMaterial {
    /// `model` at `values`, clamped to the parameters' ranges.
    pub fn new(model: &'static StockModel, values: &[f64]) -> Self {
        let values: Vec<f64> = model
            .parameters
            .iter()
            .zip(values)
            .map(|(p, &v)| v.clamp(p.lower, p.upper))
            .collect();
        let derived = (model.derive)(&values);
        Self {
            model,
            values,
            derived,
        }
    }

    /// F(wi, wo), 0 when either direction is at or below the horizon.
    pub fn eval(&self, wi: DVec3, wo: DVec3) -> DVec3 {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return DVec3::ZERO;
        }
        (self.model.eval)(&self.values, &self.derived, wi, wo, (wi + wo).normalize())
    }

    /// The value of the parameter named `name`.
    pub fn value(&self, name: &str) -> Option<f64> {
        let k = self.model.parameters.iter().position(|p| p.name == name)?;
        Some(self.values[k])
    }

    /// The colour whose parameters are `NAME.r`, `NAME.g`, `NAME.b`.
    pub fn colour(&self, name: &str) -> Option<[f64; 3]> {
        Some([
            self.value(&format!("{name}.r"))?,
            self.value(&format!("{name}.g"))?,
            self.value(&format!("{name}.b"))?,
        ])
    }
}

/// The colour of a fabric seen from afar: its threads' RGB albedos weighted by coverage,
/// clamped to [0, 1] (where a fit's colours start).
pub fn fabric_colour(fabric: &Fabric) -> [f64; 3] {
    let (t1, t2) = (&fabric.thread1, &fabric.thread2);
    let total = (t1.coverage + t2.coverage).max(1e-9);
    let (a1, a2) = (t1.albedo_rgb(), t2.albedo_rgb());
    std::array::from_fn(|c| ((t1.coverage * a1[c] + t2.coverage * a2[c]) / total).clamp(0.0, 1.0))
}

/// The parse function of a stock unit: no parameter.
pub fn parse(model: &'static StockModel, unit: &EvaluatorUnit, parameter: Option<&str>) -> Parsed {
    match parameter {
        None => Ok(Arc::new(StockEvaluator { model })),
        Some(_) => Err(parameter_error(unit, parameter, "takes no parameter")),
    }
}

/// A stock unit's evaluator: fits its model to each fabric it prepares.
#[derive(Debug)]
pub struct StockEvaluator {
    pub model: &'static StockModel,
}

impl Evaluator for StockEvaluator {
    fn spelling(&self) -> String {
        self.model.name.into()
    }

    fn prepare(
        &self,
        fabric: &Fabric,
        _context: &EvaluationContext,
    ) -> Result<Box<dyn FabricEvaluator>, EvaluatorError> {
        let fitted = fit::fit(self.model, fabric);
        Ok(Box::new(StockEvaluation {
            material: fitted.material,
            fabric: fabric.clone(),
        }))
    }
}

/// A fabric's best fit of a stock model.
struct StockEvaluation {
    material: StockMaterial,
    fabric: Fabric,
}

impl FabricEvaluator for StockEvaluation {
    fn label(&self) -> String {
        format!(
            "{} fitted to {}",
            self.material.model.name, self.fabric.name
        )
    }

    fn eval(&self, wi: DVec3, wo: DVec3) -> DVec3 {
        self.material.eval(wi, wo)
    }

    /// The fabric's own sampler: the stock models have no importance sampler of their own
    /// here, and the fabric's covers where their fits are bright.
    fn sampler(&self) -> Sampler {
        Sampler::for_fabric(&self.fabric)
    }

    #[cfg(feature = "runtime")]
    fn gpu(
        &self,
        context: &crate::gpu::GpuContext,
    ) -> Result<Box<dyn crate::gpu::GpuBrdf>, EvaluatorError> {
        Ok(Box::new(gpu::GpuStock::new(context, &self.material)?))
    }

    #[cfg(feature = "runtime")]
    fn gpu_wgsl(&self) -> Result<String, EvaluatorError> {
        Ok(gpu::stock_wgsl(self.material.model))
    }
}
