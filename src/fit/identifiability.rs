//! Which directions in parameter space a fit's samples leave unconstrained: the singular
//! value decomposition of the Jacobian at the solution, in parameters scaled to their ranges,
//! cut by the standard error the residuals' own noise gives each direction.

use super::parameters::FreeParameter;
use nalgebra::DMatrix;

/// A direction of the normalised parameter space along which the samples barely constrain
/// the fit: a right singular vector `v` of the Jacobian `J` of the residuals with respect to
/// the parameters scaled to [0, 1] over their ranges.
///
/// With residual noise of standard deviation `σr` (estimated as the residuals' RMS at the
/// solution), the least-squares estimate along `v` has standard error `σr / s` where `s` is
/// `v`'s singular value. A direction is reported when that error exceeds
/// [`FitOptions::flat_threshold`](super::FitOptions::flat_threshold) of the range: the
/// samples then cannot tell apart fabrics a tenth of the parameters' ranges apart along it.
/// This ties the cut to the data's own noise and count rather than to a fixed ratio of
/// singular values.
#[derive(Clone, Debug, PartialEq)]
pub struct FlatDirection {
    /// `s / s_max`.
    pub relative_singular_value: f64,
    /// `σr / s`, in fractions of the ranges.
    pub standard_error: f64,
    /// The parameters that make up the direction (|component| ≥ 0.25), largest first.
    pub components: Vec<(String, f64)>,
}

impl std::fmt::Display for FlatDirection {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let terms: Vec<String> = self
            .components
            .iter()
            .map(|(name, w)| format!("{w:+.2} {name}"))
            .collect();
        write!(
            f,
            "{} (±{:.2} of range, singular value {:.1e} of the largest)",
            terms.join(" "),
            self.standard_error,
            self.relative_singular_value
        )
    }
}

/// The singular values of `j` (largest first) and its directions whose standard error
/// `noise / s` exceeds `threshold`.
pub(super) fn flat_directions(
    j: DMatrix<f64>,
    parameters: &[FreeParameter],
    noise: f64,
    threshold: f64,
) -> (Vec<f64>, Vec<FlatDirection>) {
    // The SVD of JᵀJ (n × n) gives J's right singular vectors and squared singular values,
    // cheaper than the SVD of the tall J and accurate enough for a threshold on σ.
    let jtj = j.transpose() * &j;
    let svd = jtj.svd(false, true);
    let Some(v_t) = svd.v_t else {
        return (Vec::new(), Vec::new());
    };
    let mut order: Vec<usize> = (0..svd.singular_values.len()).collect();
    order.sort_by(|&a, &b| svd.singular_values[b].total_cmp(&svd.singular_values[a]));
    let singular: Vec<f64> = order
        .iter()
        .map(|&i| svd.singular_values[i].max(0.0).sqrt())
        .collect();
    let largest = singular.first().copied().unwrap_or(0.0);
    let mut flat = Vec::new();
    for (rank, &i) in order.iter().enumerate() {
        let s = singular[rank];
        let error = if s > 0.0 { noise / s } else { f64::INFINITY };
        if error <= threshold {
            continue;
        }
        let row = v_t.row(i);
        // Sign convention: the largest component positive.
        let sign = row
            .iter()
            .fold(0.0f64, |m, &x| if x.abs() > m.abs() { x } else { m })
            .signum();
        let mut components: Vec<(String, f64)> = row
            .iter()
            .zip(parameters)
            .filter(|(w, _)| w.abs() >= 0.25)
            .map(|(&w, p)| (p.name.clone(), sign * w))
            .collect();
        components.sort_by(|a, b| b.1.abs().total_cmp(&a.1.abs()));
        flat.push(FlatDirection {
            relative_singular_value: if largest > 0.0 { s / largest } else { 0.0 },
            standard_error: error,
            components,
        });
    }
    (singular, flat)
}
