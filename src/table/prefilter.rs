//! Node values for multilinear interpolation: the least-squares fit instead of point samples.
//!
//! A table that stores f at its nodes and interpolates linearly between them is biased:
//! inside a cell of width h the chord misses f by ½f''·x(h − x), on average h²f''/12 of
//! the same sign, so every ridge of the table is flattened and every valley filled. The
//! piecewise-linear function closest to f in L2 has node values c solving the hat basis'
//! mass system (c₋ + 4c + c₊)/6 = (1/h)∫f·φ = f + h²f''/12 + O(h⁴); with c = f + δ the left
//! side is f + h²f''/6 + δ + O(h⁴), so to second order
//!
//! ```text
//! c_i = f_i − (f_{i−1} − 2f_i + f_{i+1})/12
//! ```
//!
//! (h²f'' is the second difference in texel units, whatever the axis' warp, since the
//! lookup interpolates linearly in texel units). The fit of a tensor-product hat basis is the
//! tensor product of the 1D fits, so the correction is applied along each axis in turn.
//! Edge nodes keep their samples (their second difference is one-sided). Values that the
//! correction would make negative are set to 0: the stored quantities are non-negative, and
//! the correction can only take a node below 0 next to a steep rise from 0 (a texel where
//! the facing window closes, beside one where it is open).
//!
//! `clothbake check` measures what the fit gains against point samples; the figures, and
//! the variants tried (the fit along fewer axes, other factors than 1/12), are in
//! docs/notebook/2026-12-07-figures-from-comments-issue-47.md.

/// Replaces the point samples `values` (channel-interleaved, `channels` per node, node axes
/// `counts` fastest first; every axis clamped, none periodic) by the node values of their
/// least-squares multilinear fit, to second order (see the module doc). Each value depends
/// only on the previous pass, so the result is the same for any thread count.
pub fn fit_for_multilinear(values: &mut [f64], channels: usize, counts: &[usize]) {
    use rayon::prelude::*;
    debug_assert_eq!(values.len(), channels * counts.iter().product::<usize>());
    // One scratch copy of the previous pass, refilled per axis.
    let mut samples = vec![0.0; values.len()];
    let mut stride = channels;
    for &count in counts {
        if count >= 3 {
            samples.copy_from_slice(values);
            values.par_iter_mut().enumerate().for_each(|(k, value)| {
                let i = (k / stride) % count;
                if i > 0 && i + 1 < count {
                    let second_difference =
                        samples[k - stride] - 2.0 * samples[k] + samples[k + stride];
                    *value = samples[k] - second_difference / 12.0;
                }
            });
        }
        stride *= count;
    }
    values
        .par_iter_mut()
        .for_each(|value| *value = value.max(0.0));
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Relative RMS of linear interpolation between `nodes` (spacing 1) against `f`, on a
    /// fine grid over the interior cells.
    fn interpolation_error(nodes: &[f64], f: impl Fn(f64) -> f64) -> f64 {
        let (mut err, mut norm) = (0.0, 0.0);
        for cell in 1..nodes.len() - 2 {
            for step in 0..64 {
                let t = (step as f64 + 0.5) / 64.0;
                let x = cell as f64 + t;
                let e = nodes[cell] * (1.0 - t) + nodes[cell + 1] * t - f(x);
                err += e * e;
                norm += f(x) * f(x);
            }
        }
        (err / norm).sqrt()
    }

    #[test]
    fn linear_functions_are_kept_exactly() {
        let counts = [5, 4, 3];
        let mut values: Vec<f64> = (0..120)
            .map(|k| {
                let (c, n) = (k % 2, k / 2);
                let (x, y, z) = (n % 5, (n / 5) % 4, n / 20);
                1.0 + c as f64 + 0.5 * x as f64 - 0.25 * y as f64 + 2.0 * z as f64
            })
            .collect();
        let before = values.clone();
        fit_for_multilinear(&mut values, 2, &counts);
        for (a, b) in values.iter().zip(&before) {
            assert!((a - b).abs() < 1e-12, "{a} != {b}");
        }
    }

    #[test]
    fn a_smooth_ridge_is_fitted_better_than_sampled() {
        // A Gaussian ridge 2 texels wide, the width of a narrow lobe on a βH axis.
        let f = |x: f64| (-(x - 20.3f64).powi(2) / (2.0 * 2.0 * 2.0)).exp() + 0.05;
        let samples: Vec<f64> = (0..40).map(|i| f(i as f64)).collect();
        let mut fitted = samples.clone();
        fit_for_multilinear(&mut fitted, 1, &[40]);
        let (before, after) = (
            interpolation_error(&samples, f),
            interpolation_error(&fitted, f),
        );
        // The fit more than halves this ridge's interpolation error (a pure parabola would
        // gain more, a ridge this narrow less); a fit of the wrong sign or none at all gains
        // nothing (the figures: docs/notebook/2026-12-07-figures-from-comments-issue-47.md).
        assert!(after < 0.6 * before, "{before} -> {after}");
    }

    #[test]
    fn corrections_that_would_go_negative_stop_at_zero() {
        let mut values = vec![0.0, 0.0, 0.0, 1.0, 2.0];
        fit_for_multilinear(&mut values, 1, &[5]);
        assert!(values.iter().all(|&v| v >= 0.0), "{values:?}");
        assert_eq!(values[2], 0.0);
        assert_eq!(values[0], 0.0);
        assert_eq!(values[4], 2.0);
    }
}
