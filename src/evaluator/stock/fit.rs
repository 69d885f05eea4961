//! The best fit of a stock model to a fabric's F, by the optimiser every fit shares
//! ([`crate::fit::bounded`]).
//!
//! The objective is what the project reports of every approximation of F: the squared
//! relative RMS on uniform pairs plus that on highlight pairs. Each set's residuals are
//! `(F_stock − F) / sqrt(Σ|F|²)` over its own pairs, so the sum of squares is exactly
//! `rms_uniform² + rms_highlight²`: neither the dim many nor the bright few decide alone.
//! The pairs are drawn with seeds of their own, apart from the validation sets that the
//! errors are measured on ([`crate::measure::accuracy`]), and F there is the resonant
//! quadrature: the direct rule's accuracy is not needed to fit models this far from the
//! fabric, and the resonant rule costs far less (both errors compared in
//! docs/notebook/2026-12-07-export.md).

use super::{StockMaterial, StockModel};
use crate::fit::bounded::{BoundedProblem, forward_differences, minimise, u_of_value, value_of_u};
use crate::fit::parameters::FreeParameter;
use crate::measure::direction_sets::{highlight_pairs, uniform_pairs};
use crate::model::{Fabric, Integration, Patch, ResonantNodes};
use glam::DVec3;
use levenberg_marquardt::LevenbergMarquardt;
use nalgebra::DMatrix;
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64;
use rayon::prelude::*;

/// Pairs of each set the fit sees.
pub const FIT_PAIRS: usize = 256;
/// Seeds of the fit's pairs (the validation sets use others).
const UNIFORM_FIT_SEED: u64 = 0x5eed_5f01;
const HIGHLIGHT_FIT_SEED: u64 = 0x5eed_5f02;
/// Starts: the model's own for the fabric, then seeded perturbations of it.
const STARTS: usize = 3;
/// Largest move of a perturbed start, as a fraction of each parameter's range.
const SPREAD: f64 = 0.3;
/// Forward-difference step in the normalised parameters: F of a stock model is smooth.
const STEP: f64 = 1e-5;

/// A stock model fitted to a fabric.
#[derive(Clone, Debug)]
pub struct StockFit {
    pub material: StockMaterial,
    /// Half the mean squared residual at the fit ([`crate::fit::bounded::objective`]).
    pub objective: f64,
    /// Residual evaluations over all starts.
    pub evaluations: usize,
}

/// One set of pairs with the fabric's F on them and the set's residual scale.
struct FitSet {
    pairs: Vec<(DVec3, DVec3)>,
    f: Vec<DVec3>,
    scale: f64,
}

impl FitSet {
    fn new(patch: &Patch, pairs: Vec<(DVec3, DVec3)>) -> Self {
        let f: Vec<DVec3> = pairs
            .par_iter()
            .map(|&(wi, wo)| patch.eval(wi, wo))
            .collect();
        let norm: f64 = f.iter().map(|f| f.length_squared()).sum();
        Self {
            pairs,
            f,
            scale: 1.0 / norm.sqrt().max(1e-300),
        }
    }
}

struct StockProblem<'a> {
    model: &'static StockModel,
    parameters: &'a [FreeParameter],
    sets: [FitSet; 2],
}

impl StockProblem<'_> {
    fn material(&self, u: &[f64]) -> StockMaterial {
        let values: Vec<f64> = self
            .parameters
            .iter()
            .zip(u)
            .map(|(p, &u)| value_of_u(p, u))
            .collect();
        StockMaterial::new(self.model, &values)
    }

    fn residuals(&self, u: &[f64]) -> Vec<f64> {
        let material = self.material(u);
        let mut r = Vec::new();
        for set in &self.sets {
            let values: Vec<DVec3> = set
                .pairs
                .par_iter()
                .map(|&(wi, wo)| material.eval(wi, wo))
                .collect();
            for (value, f) in values.iter().zip(&set.f) {
                r.extend_from_slice(&((*value - *f) * set.scale).to_array());
            }
        }
        r
    }
}

impl BoundedProblem for StockProblem<'_> {
    type Point = ();

    fn evaluate(&self, u: &[f64]) -> ((), Vec<f64>) {
        ((), self.residuals(u))
    }

    fn jacobian(&self, u0: &[f64], _: &(), r0: &[f64]) -> DMatrix<f64> {
        forward_differences(u0, r0, STEP, |u| self.residuals(u))
    }
}

/// The best fit of `model` to `fabric`'s F (deterministic: fixed pairs and seeds, sums in
/// order).
pub fn fit(model: &'static StockModel, fabric: &Fabric) -> StockFit {
    let patch = Patch::new(fabric, Integration::Resonant(ResonantNodes::DEFAULT));
    let start = (model.start)(fabric);
    let parameters: Vec<FreeParameter> = model
        .parameters
        .iter()
        .zip(&start)
        .map(|(p, &s)| FreeParameter::new(p.name, p.lower, p.upper, s.clamp(p.lower, p.upper)))
        .collect();
    let problem = StockProblem {
        model,
        parameters: &parameters,
        sets: [
            FitSet::new(&patch, uniform_pairs(FIT_PAIRS, UNIFORM_FIT_SEED)),
            FitSet::new(
                &patch,
                highlight_pairs(fabric, FIT_PAIRS, HIGHLIGHT_FIT_SEED),
            ),
        ],
    };
    let start_u: Vec<f64> = parameters.iter().map(|p| u_of_value(p, p.start)).collect();
    let solver = LevenbergMarquardt::new().with_patience(40);
    let mut best: Option<(f64, Vec<f64>)> = None;
    let mut evaluations = 0;
    for k in 0..STARTS {
        let u: Vec<f64> = if k == 0 {
            start_u.clone()
        } else {
            let mut rng = Pcg64::seed_from_u64(0x5f0c_c000 + k as u64);
            start_u
                .iter()
                .map(|&u| (u + SPREAD * (2.0 * rng.random::<f64>() - 1.0)).clamp(0.0, 1.0))
                .collect()
        };
        let minimum = minimise(&problem, &u, &solver, &|_, _| {});
        evaluations += minimum.evaluations;
        if best.as_ref().is_none_or(|(o, _)| minimum.objective < *o) {
            best = Some((minimum.objective, minimum.u));
        }
    }
    let (objective, u) = best.expect("at least one start");
    StockFit {
        material: problem.material(&u),
        objective,
        evaluations,
    }
}
