//! The fit: bounded nonlinear least squares ([`super::bounded`]) over a
//! [`Parametrisation`], the resonant quadrature inside the loop, the converged direct rule for
//! the figures reported, and the directions the samples leave unconstrained.
//!
//! Deterministic: every residual and Jacobian entry is computed on its own (in parallel over
//! samples and columns, collected in order), every sum is taken sequentially afterwards, and
//! the extra starts use fixed seeds, so the result does not depend on the thread count.

use super::bounded::{BoundedProblem, forward_differences, minimise, u_of_value, value_of_u};
use super::identifiability::{FlatDirection, flat_directions};
use super::parameters::{FreeParameter, Parametrisation};
use super::samples::{Sample, SampleError, Samples};
use crate::model::{Fabric, Integration, Patch, PatchTerms, ResonantNodes};
use glam::DVec3;
use levenberg_marquardt::LevenbergMarquardt;
use nalgebra::DMatrix;
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64;
use rayon::prelude::*;
use std::cell::Cell;

/// How a residual is scaled.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ResidualScale {
    /// `(F − f) / s` with one `s` (the RMS of f): the objective is the squared relative RMS
    /// the project reports, dominated by the brightest samples (the highlights).
    Absolute,
    /// `(F − f) / (f + floor · s)` per channel: the relative error of each sample, `floor`
    /// (a fraction of the RMS of f) keeping dark samples from dominating.
    Relative { floor: f64 },
}

/// Residual scaling used unless told otherwise. With noise proportional to f
/// (multiplicative, as a camera's shot noise and calibration give), per-sample relative
/// residuals weigh each sample by the inverse of its noise, the efficient estimator, and let
/// the many dim samples of the volume term constrain A, kd and γv, which the few bright
/// highlight samples otherwise outweigh; the better parameters then also give the lower
/// error in the absolute metric the project reports (compared with `Absolute` in
/// docs/notebook/2026-12-06-weaves-and-fitting.md). The floor (a tenth of the RMS of f) keeps
/// samples near F = 0, whose relative noise is unknown in real measurements (a detector's
/// dark noise is additive), from dominating.
pub const DEFAULT_RESIDUAL: ResidualScale = ResidualScale::Relative { floor: 0.1 };

/// The schedules of [`FitOptions::broadening_deg`] by default, one a start: the satin
/// charmeuse, whose narrow highlights sit on an eight-point curve, is recovered only from a
/// wide start, the crêpe de chine only from a narrower one, so no one schedule serves every
/// fabric and these two together serve all six (the notebook of 2026-12-06 has the figures).
pub const DEFAULT_BROADENING_DEG: [&[f64]; 2] =
    [&[20.0, 10.0, 5.0, 2.0, 0.0], &[12.0, 6.0, 3.0, 0.0]];

/// A fit's settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FitOptions {
    /// The resonant node counts of the model inside the loop.
    pub nodes: ResonantNodes,
    /// Starts: the first ones from the parametrisation's own values, one per schedule of
    /// [`FitOptions::broadening_deg`], later ones from seeded perturbations of them; the best
    /// objective is kept. `None` takes the parametrisation's
    /// [`Parametrisation::default_starts`], else one per schedule.
    pub starts: Option<usize>,
    /// Seed of the perturbed starts.
    pub seed: u64,
    /// Largest move of a perturbed start, as a fraction of each parameter's range.
    pub spread: f64,
    /// Most residual evaluations (Jacobians excluded) of one start.
    pub max_evaluations: usize,
    /// Every `holdout_every`-th sample (the 5th, 10th, …) is held out of the fit and measured
    /// after it; 0 holds none out.
    pub holdout_every: usize,
    pub residual: ResidualScale,
    /// Forward-difference step in the normalised parameter scale (fractions of each range).
    /// Large enough to step over the resonant rule's small jumps in F where a node count
    /// changes with a lobe's width, small against any feature of F in the parameters.
    pub step: f64,
    /// A direction in parameter space is reported unconstrained when the samples leave its
    /// standard error above this fraction of the parameters' ranges (see [`FlatDirection`]).
    pub flat_threshold: f64,
    /// Graduated fitting: each start is fitted in stages, stage k with every lobe width γ
    /// widened to `sqrt(γ² + b_k²)` (b_k in degrees), from the previous stage's solution; the
    /// last stage should be 0 (the model itself). Wide lobes make the objective smooth in the
    /// curve offsets, whose narrow highlights otherwise trap the fit in local minima. One
    /// schedule per start: start i < len takes schedule i from the given start, later starts
    /// perturb the given start and take schedule i mod len.
    pub broadening_deg: &'static [&'static [f64]],
    /// Samples the broadened stages fit (every k-th of the fitted samples).
    pub coarse_samples: usize,
}

impl Default for FitOptions {
    fn default() -> Self {
        Self {
            nodes: ResonantNodes::DEFAULT,
            starts: None,
            seed: 0x0f17_5eed,
            spread: 0.1,
            max_evaluations: 60,
            holdout_every: 5,
            residual: DEFAULT_RESIDUAL,
            step: 1e-3,
            flat_threshold: 0.1,
            broadening_deg: &DEFAULT_BROADENING_DEG,
            coarse_samples: usize::MAX,
        }
    }
}

/// What the progress callback is told after every residual evaluation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Progress {
    /// 0-based start being fitted, and how many there are.
    pub start: usize,
    pub starts: usize,
    /// 0-based stage of the graduated fit ([`FitOptions::broadening_deg`]), and how many.
    pub stage: usize,
    pub stages: usize,
    /// Residual evaluations of this start so far, and the most it may take.
    pub evaluations: usize,
    pub max_evaluations: usize,
    /// Objective (half the sum of squared residuals, per residual) of this evaluation, and
    /// the best of all starts so far.
    pub objective: f64,
    pub best: f64,
}

/// The outcome of a fit.
#[derive(Clone, Debug)]
pub struct FitReport {
    pub fabric: Fabric,
    /// The settings it was fitted with.
    pub options: FitOptions,
    pub parameters: Vec<FreeParameter>,
    pub values: Vec<f64>,
    /// Samples fitted and held out.
    pub fit_count: usize,
    pub holdout_count: usize,
    /// Relative RMS `sqrt(Σ w|F − f|² / Σ w|f|²)` of the fitted fabric's direct evaluation
    /// on the fitted and the held-out samples (`None` when none are held out).
    pub fit_relative_rms: f64,
    pub holdout_relative_rms: Option<f64>,
    /// Final objective of each start (half the sum of squared residuals, per residual), and
    /// the start kept.
    pub start_objectives: Vec<f64>,
    pub best_start: usize,
    /// Residual evaluations over all starts (Jacobian columns excluded).
    pub evaluations: usize,
    /// The kept start's termination, in the solver's words.
    pub termination: String,
    /// Singular values of the normalised Jacobian at the solution, largest first.
    pub singular_values: Vec<f64>,
    pub flat_directions: Vec<FlatDirection>,
}

/// Why a fit could not run.
#[derive(Debug, thiserror::Error)]
pub enum FitError {
    #[error(transparent)]
    Samples(#[from] SampleError),
    #[error("the parametrisation has no free parameters")]
    NoParameters,
}

/// Which samples are held out: every `every`-th (1-based: the 5th, 10th, …).
pub fn split(samples: &[Sample], every: usize) -> (Vec<Sample>, Vec<Sample>) {
    let mut fit = Vec::new();
    let mut held = Vec::new();
    for (i, s) in samples.iter().enumerate() {
        if every > 0 && (i + 1) % every == 0 {
            held.push(*s);
        } else {
            fit.push(*s);
        }
    }
    (fit, held)
}

/// `sqrt(Σ w|F − f|² / Σ w|f|²)` of `fabric`'s direct evaluation over `samples`.
pub fn relative_rms(fabric: &Fabric, samples: &[Sample]) -> f64 {
    let patch = Patch::new(fabric, Integration::Direct);
    let values: Vec<DVec3> = samples.par_iter().map(|s| patch.eval(s.wi, s.wo)).collect();
    let (mut err, mut norm) = (0.0, 0.0);
    for (s, f) in samples.iter().zip(values) {
        err += s.weight * (f - s.f).length_squared();
        norm += s.weight * s.f.length_squared();
    }
    if norm > 0.0 {
        (err / norm).sqrt()
    } else {
        err.sqrt()
    }
}

/// Equal apart from the albedos: then F differs only in the linear factor A, and the
/// factored terms of one evaluation serve both.
fn same_but_albedo(a: &Fabric, b: &Fabric) -> bool {
    let strip = |f: &Fabric| {
        let mut f = f.clone();
        for t in [&mut f.thread1, &mut f.thread2] {
            t.albedo = [0.0; 3];
            t.albedo_scale = 0.0;
        }
        f
    };
    strip(a) == strip(b)
}

/// Everything a start shares.
struct Context<'a> {
    parametrisation: &'a dyn Parametrisation,
    samples: &'a [Sample],
    /// Per sample, `sqrt(w) / s` per channel.
    scales: Vec<DVec3>,
    options: FitOptions,
    /// The current stage's lobe broadening b in degrees.
    broaden_deg: f64,
}

impl Context<'_> {
    fn integration(&self) -> Integration {
        Integration::Resonant(self.options.nodes)
    }

    fn values_of_u(&self, u: &[f64]) -> Vec<f64> {
        self.parametrisation
            .parameters()
            .iter()
            .zip(u)
            .map(|(p, &u)| value_of_u(p, u))
            .collect()
    }

    /// The fabric the model evaluates for `u` in the current stage.
    fn fabric_of_u(&self, u: &[f64]) -> Fabric {
        let mut fabric = self.parametrisation.fabric(&self.values_of_u(u));
        let b = self.broaden_deg;
        if b > 0.0 {
            for t in [&mut fabric.thread1, &mut fabric.thread2] {
                t.gamma_s_deg = t.gamma_s_deg.hypot(b);
                t.gamma_v_deg = t.gamma_v_deg.hypot(b);
            }
        }
        fabric
    }

    fn terms(&self, fabric: &Fabric) -> Vec<PatchTerms> {
        let patch = Patch::new(fabric, self.integration());
        self.samples
            .par_iter()
            .map(|s| patch.terms(s.wi, s.wo))
            .collect()
    }

    /// Residuals of `fabric` from its factored terms, three per sample.
    fn residuals(&self, fabric: &Fabric, terms: &[PatchTerms]) -> Vec<f64> {
        let patch = Patch::new(fabric, self.integration());
        let mut r = Vec::with_capacity(3 * terms.len());
        for ((t, s), scale) in terms.iter().zip(self.samples).zip(&self.scales) {
            let d = (patch.combine(t) - s.f) * *scale;
            r.extend_from_slice(&d.to_array());
        }
        r
    }
}

/// The fabric and its factored terms at a point: what the Jacobian there reuses.
type FabricPoint = (Fabric, Vec<PatchTerms>);

impl BoundedProblem for Context<'_> {
    type Point = FabricPoint;

    fn evaluate(&self, u: &[f64]) -> (FabricPoint, Vec<f64>) {
        let fabric = self.fabric_of_u(u);
        let terms = self.terms(&fabric);
        let r = self.residuals(&fabric, &terms);
        ((fabric, terms), r)
    }

    /// Forward differences; a step in an albedo alone reuses the factored terms, F being
    /// linear in A.
    fn jacobian(&self, u0: &[f64], (fabric0, terms0): &FabricPoint, r0: &[f64]) -> DMatrix<f64> {
        forward_differences(u0, r0, self.options.step, |u| {
            let fabric = self.fabric_of_u(u);
            if same_but_albedo(&fabric, fabric0) {
                self.residuals(&fabric, terms0)
            } else {
                self.residuals(&fabric, &self.terms(&fabric))
            }
        })
    }
}

/// Fits `parametrisation` to `samples` (every [`FitOptions::holdout_every`]-th held out);
/// `progress` hears of every residual evaluation.
pub fn fit(
    parametrisation: &dyn Parametrisation,
    samples: &Samples,
    options: &FitOptions,
    progress: &dyn Fn(&Progress),
) -> Result<FitReport, FitError> {
    let parameters = parametrisation.parameters().to_vec();
    let n = parameters.len();
    if n == 0 {
        return Err(FitError::NoParameters);
    }
    let (fit_samples, held) = split(&samples.samples, options.holdout_every);
    // Three residuals a sample; ask for at least one sample per parameter so that a single
    // channel's worth of data still over-determines the fit.
    if fit_samples.len() < n {
        return Err(SampleError::TooFew {
            origin: samples.origin.clone(),
            count: fit_samples.len(),
            needed: n,
            parameters: n,
            what: if held.is_empty() {
                "one per parameter".into()
            } else {
                format!(
                    "one per parameter, after holding out {} of {} samples",
                    held.len(),
                    samples.samples.len()
                )
            },
        }
        .into());
    }
    // Weighted RMS of f over all channels: the unit of the residuals.
    let (mut sum, mut weight) = (0.0, 0.0);
    for s in &fit_samples {
        sum += s.weight * s.f.length_squared() / 3.0;
        weight += s.weight;
    }
    let rms = if sum > 0.0 {
        (sum / weight).sqrt()
    } else {
        1.0
    };
    let scales = fit_samples
        .iter()
        .map(|s| {
            let w = s.weight.sqrt();
            match options.residual {
                ResidualScale::Absolute => DVec3::splat(w / rms),
                ResidualScale::Relative { floor } => w / (s.f + DVec3::splat(floor * rms)),
            }
        })
        .collect();
    let scales: Vec<DVec3> = scales;
    // The broadened stages see every `stride`-th sample only: their smooth model needs far
    // fewer samples, and they cost most of the evaluations.
    let stride = fit_samples
        .len()
        .div_ceil(options.coarse_samples.max(n))
        .max(1);
    let coarse_samples: Vec<Sample> = fit_samples.iter().step_by(stride).copied().collect();
    let coarse_scales: Vec<DVec3> = scales.iter().step_by(stride).copied().collect();
    let context_for = |b: f64| {
        let (samples, scales) = if b > 0.0 {
            (&coarse_samples[..], coarse_scales.clone())
        } else {
            (&fit_samples[..], scales.clone())
        };
        Context {
            parametrisation,
            samples,
            scales,
            options: *options,
            broaden_deg: b,
        }
    };
    let start_u: Vec<f64> = parameters.iter().map(|p| u_of_value(p, p.start)).collect();
    let starts = options
        .starts
        .or_else(|| parametrisation.default_starts())
        .unwrap_or(options.broadening_deg.len())
        .max(1);
    let patience = options.max_evaluations.div_ceil(n + 1).max(1);
    // The objective is a sum of m squared residuals, each about the noise where the model
    // fits: a relative improvement below 1/m (a change of about 1 in χ²) is within the noise,
    // and chasing it costs most of the evaluations (a satin fit's final stage, in
    // docs/notebook/2026-12-07-figures-from-comments-issue-47.md).
    let m = 3 * fit_samples.len();
    let solver = LevenbergMarquardt::new()
        .with_ftol((1.0 / m as f64).clamp(1e-8, 1e-3))
        .with_xtol(1e-5)
        .with_gtol(1e-9)
        .with_patience(patience);
    let best = Cell::new(f64::INFINITY);
    let mut results = Vec::with_capacity(starts);
    let mut evaluations = 0;
    for start in 0..starts {
        let schedules = options.broadening_deg;
        let stages: &[f64] = match schedules.get(start % schedules.len().max(1)) {
            Some(stages) if !stages.is_empty() => stages,
            _ => &[0.0],
        };
        let mut u: Vec<f64> = if start < schedules.len().max(1) {
            start_u.clone()
        } else {
            let mut rng = Pcg64::seed_from_u64(options.seed.wrapping_add(start as u64));
            start_u
                .iter()
                .map(|&u| (u + options.spread * (2.0 * rng.random::<f64>() - 1.0)).clamp(0.0, 1.0))
                .collect()
        };
        let mut objective = f64::INFINITY;
        let mut termination = String::new();
        for (stage, &b) in stages.iter().enumerate() {
            let context = context_for(b);
            let last_stage = stage + 1 == stages.len();
            let report = |evaluations: usize, objective: f64| {
                progress(&Progress {
                    start,
                    starts,
                    stage,
                    stages: stages.len(),
                    evaluations,
                    max_evaluations: patience * (n + 1),
                    objective,
                    best: if last_stage {
                        best.get().min(objective)
                    } else {
                        best.get()
                    },
                })
            };
            let minimum = minimise(&context, &u, &solver, &report);
            u = minimum.u;
            evaluations += minimum.evaluations;
            objective = minimum.objective;
            termination = minimum.termination;
        }
        best.set(best.get().min(objective));
        results.push((objective, u, termination));
    }
    let context = context_for(0.0);
    let best_start = (0..results.len())
        .min_by(|&a, &b| results[a].0.total_cmp(&results[b].0))
        .expect("at least one start");
    let (_, u, termination) = results[best_start].clone();
    let values = context.values_of_u(&u);
    let fabric = parametrisation.fabric(&values);

    // Identifiability, in the normalised scale u.
    let terms = context.terms(&fabric);
    let r = context.residuals(&fabric, &terms);
    let j = BoundedProblem::jacobian(&context, &u, &(fabric.clone(), terms), &r);
    let dof = (r.len() as f64 - n as f64).max(1.0);
    let noise = (r.iter().map(|x| x * x).sum::<f64>() / dof).sqrt();
    let (singular_values, flat_directions) =
        flat_directions(j, &parameters, noise, options.flat_threshold);

    Ok(FitReport {
        options: *options,
        fit_relative_rms: relative_rms(&fabric, &fit_samples),
        holdout_relative_rms: (!held.is_empty()).then(|| relative_rms(&fabric, &held)),
        fabric,
        parameters,
        values,
        fit_count: fit_samples.len(),
        holdout_count: held.len(),
        start_objectives: results.iter().map(|r| r.0).collect(),
        best_start,
        evaluations,
        termination,
        singular_values,
        flat_directions,
    })
}
