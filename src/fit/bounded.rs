//! The one optimiser of every fit in clothbake: bounded nonlinear least squares by
//! Levenberg–Marquardt (the `levenberg-marquardt` crate) over parameters normalised to
//! `u ∈ [0, 1]ⁿ`. A fabric's fit ([`super::solve`]) and a stock model's fit to a fabric
//! ([`crate::evaluator::stock::fit`]) are both a [`BoundedProblem`] solved by [`minimise`].
//!
//! The bounds are kept by the transform `u = (1 + sin z) / 2`: LM works unbounded in z and
//! every z maps inside the bounds.

use super::parameters::FreeParameter;
use levenberg_marquardt::{LeastSquaresProblem, LevenbergMarquardt};
use nalgebra::{DMatrix, DVector, Dyn, Owned};
use rayon::prelude::*;
use std::cell::{Cell, RefCell};

/// A least-squares problem in the normalised parameters u.
pub trait BoundedProblem: Sync {
    /// What one evaluation keeps for the Jacobian at the same point (the fabric's factored
    /// terms; `()` where nothing is worth keeping).
    type Point: Clone;
    /// The residuals at `u`, with what the Jacobian there may reuse.
    fn evaluate(&self, u: &[f64]) -> (Self::Point, Vec<f64>);
    /// The Jacobian of the residuals with respect to u at `u0`, whose evaluation gave
    /// `point` and `r0`.
    fn jacobian(&self, u0: &[f64], point: &Self::Point, r0: &[f64]) -> DMatrix<f64>;
}

/// The Jacobian at `u0` by forward differences of step `h` in u (backward at an upper
/// bound), one column per parameter in parallel; `residuals(u)` is the residual vector at u.
pub fn forward_differences(
    u0: &[f64],
    r0: &[f64],
    h: f64,
    residuals: impl Fn(&[f64]) -> Vec<f64> + Sync,
) -> DMatrix<f64> {
    let columns: Vec<Vec<f64>> = (0..u0.len())
        .into_par_iter()
        .map(|k| {
            let mut u = u0.to_vec();
            let step = if u[k] + h <= 1.0 { h } else { -h };
            u[k] += step;
            let r = residuals(&u);
            r.iter().zip(r0).map(|(a, b)| (a - b) / step).collect()
        })
        .collect();
    DMatrix::from_fn(r0.len(), u0.len(), |i, k| columns[k][i])
}

/// The bound transform: normalised `u = (1 + sin z) / 2` in [0, 1], so LM works unbounded in z.
fn u_of_z(z: f64) -> f64 {
    (0.5 * (1.0 + z.sin())).clamp(0.0, 1.0)
}

/// Inverse of [`u_of_z`] on the principal branch, `u` kept a little inside (0, 1) so that a
/// start on a bound can still move (d u / d z vanishes on the bounds).
fn z_of_u(u: f64) -> f64 {
    (2.0 * u.clamp(1e-3, 1.0 - 1e-3) - 1.0).asin()
}

/// The value of `p` at normalised `u`.
pub fn value_of_u(p: &FreeParameter, u: f64) -> f64 {
    p.clamp(p.lower + (p.upper - p.lower) * u)
}

/// The normalised u of value `x` of `p`.
pub fn u_of_value(p: &FreeParameter, x: f64) -> f64 {
    if p.upper > p.lower {
        ((x - p.lower) / (p.upper - p.lower)).clamp(0.0, 1.0)
    } else {
        0.5
    }
}

/// Half the mean squared residual: the objective every fit reports.
pub fn objective(r: &[f64]) -> f64 {
    0.5 * r.iter().map(|x| x * x).sum::<f64>() / r.len().max(1) as f64
}

/// Where [`minimise`] stopped.
#[derive(Clone, Debug)]
pub struct Minimum {
    pub u: Vec<f64>,
    /// [`objective`] of the residuals at `u`.
    pub objective: f64,
    /// Residual evaluations (Jacobians excluded).
    pub evaluations: usize,
    /// The solver's termination, in its words.
    pub termination: String,
}

/// Minimises `problem`'s squared residuals from `u_start` with `solver`; `report` hears of
/// every residual evaluation (its count and objective).
pub fn minimise<P: BoundedProblem>(
    problem: &P,
    u_start: &[f64],
    solver: &LevenbergMarquardt<f64>,
    report: &dyn Fn(usize, f64),
) -> Minimum {
    let n = u_start.len();
    let lm = Lm {
        problem,
        z: DVector::from_iterator(n, u_start.iter().map(|&u| z_of_u(u))),
        last: RefCell::new(None),
        evaluations: Cell::new(0),
        report,
    };
    let (lm, outcome) = solver.minimize(lm);
    // The objective at the returned point (the solver's own figure is of its last trial).
    let (_, r) = lm.evaluate();
    let objective = objective(&r);
    Minimum {
        u: lm.u(),
        objective: if objective.is_finite() {
            objective
        } else {
            f64::INFINITY
        },
        evaluations: lm.evaluations.get(),
        termination: format!("{:?}", outcome.termination),
    }
}

/// A residual evaluation: its z, what the problem keeps of it, and the residuals.
type Evaluated<P> = (DVector<f64>, <P as BoundedProblem>::Point, Vec<f64>);

/// One minimisation in the unbounded variables z.
struct Lm<'a, P: BoundedProblem> {
    problem: &'a P,
    z: DVector<f64>,
    /// The last residual evaluation (the Jacobian is asked for at the last accepted point,
    /// whose residuals were just computed).
    last: RefCell<Option<Evaluated<P>>>,
    evaluations: Cell<usize>,
    report: &'a dyn Fn(usize, f64),
}

impl<P: BoundedProblem> Lm<'_, P> {
    fn u(&self) -> Vec<f64> {
        self.z.iter().map(|&z| u_of_z(z)).collect()
    }

    /// The point and residuals at the current z, computed once.
    fn evaluate(&self) -> (P::Point, Vec<f64>) {
        if let Some((z, point, r)) = &*self.last.borrow()
            && *z == self.z
        {
            return (point.clone(), r.clone());
        }
        let (point, r) = self.problem.evaluate(&self.u());
        let n = self.evaluations.get() + 1;
        self.evaluations.set(n);
        (self.report)(n, objective(&r));
        *self.last.borrow_mut() = Some((self.z.clone(), point.clone(), r.clone()));
        (point, r)
    }
}

impl<P: BoundedProblem> LeastSquaresProblem<f64, Dyn, Dyn> for Lm<'_, P> {
    type ResidualStorage = Owned<f64, Dyn>;
    type JacobianStorage = Owned<f64, Dyn, Dyn>;
    type ParameterStorage = Owned<f64, Dyn>;

    fn set_params(&mut self, z: &DVector<f64>) {
        self.z.copy_from(z);
    }

    fn params(&self) -> DVector<f64> {
        self.z.clone()
    }

    fn residuals(&self) -> Option<DVector<f64>> {
        let (_, r) = self.evaluate();
        r.iter()
            .all(|x| x.is_finite())
            .then(|| DVector::from_vec(r))
    }

    fn jacobian(&self) -> Option<DMatrix<f64>> {
        let (point, r) = self.evaluate();
        let mut j = self.problem.jacobian(&self.u(), &point, &r);
        // Chain rule: d u / d z = cos z / 2.
        for (k, &z) in self.z.iter().enumerate() {
            j.column_mut(k).scale_mut(0.5 * z.cos());
        }
        j.iter().all(|x| x.is_finite()).then_some(j)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A bounded quadratic whose minimum lies outside the box: the fit stops on the bound.
    struct Outside;

    impl BoundedProblem for Outside {
        type Point = ();
        fn evaluate(&self, u: &[f64]) -> ((), Vec<f64>) {
            ((), vec![u[0] - 2.0, 3.0 * (u[1] - 0.25)])
        }
        fn jacobian(&self, u0: &[f64], _: &(), r0: &[f64]) -> DMatrix<f64> {
            forward_differences(u0, r0, 1e-6, |u| self.evaluate(u).1)
        }
    }

    #[test]
    fn a_minimum_outside_the_bounds_stops_on_the_bound_and_one_inside_is_found() {
        let m = minimise(
            &Outside,
            &[0.5, 0.5],
            &LevenbergMarquardt::new(),
            &|_, _| {},
        );
        assert!(m.u[0] > 0.99, "{:?}", m.u);
        assert!((m.u[1] - 0.25).abs() < 1e-4, "{:?}", m.u);
        assert!(m.evaluations > 0);
    }

    #[test]
    fn values_and_normalised_values_round_trip() {
        let p = FreeParameter::new("x", -2.0, 6.0, 1.0);
        for u in [0.0, 0.3, 1.0] {
            assert!((u_of_value(&p, value_of_u(&p, u)) - u).abs() < 1e-12);
        }
    }
}
