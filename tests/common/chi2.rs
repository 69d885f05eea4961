//! Chi-square goodness of fit of a direction sampler against its own density, in the manner
//! of Mitsuba 3's `mitsuba.chi2` and pbrt-v4's hair sampling test: draws are histogrammed
//! into equal-area bins over the upper hemisphere (uniform in z = cos θ and in azimuth), the
//! expected count of each bin is the sample count times the density's exact integral over
//! the bin, bins expecting fewer than [`MIN_EXPECTED`] are merged, and Pearson's statistic is
//! compared with the chi-square quantile at a Šidák-corrected significance.
//!
//! Included with `#[path]` by the binaries with sampling tests, `sampling` and `gpu`, only (not
//! through `common`).

use clothbake::sampling::{COLUMNS, ROWS};
use glam::DVec3;
use std::f64::consts::{FRAC_PI_2, TAU};

/// Outgoing directions (elevation, azimuth in degrees): the normal, then down to 1° above
/// the horizon, azimuths spread so that each falls between sampler nodes.
pub const OUTGOING: [(f64, f64); 8] = [
    (90.0, 0.0),
    (63.0, 17.0),
    (41.0, 131.0),
    (24.0, 222.0),
    (11.0, 305.0),
    (5.0, 48.0),
    (2.0, 170.0),
    (1.0, 261.0),
];
/// Bins of the test over z (equal area: uniform in z) …
pub const Z_BINS: usize = 24;
/// … and over azimuth: 32 divides the sampler's 64 sectors, so no sector straddles a bin.
pub const AZIMUTH_BINS: usize = 32;
/// Bins expecting fewer draws are merged (the chi-square approximation needs ~5 per bin).
pub const MIN_EXPECTED: f64 = 5.0;

/// Probes per side of a piece when looking for the support's edge inside it.
const PROBES: usize = 9;
/// Midpoints per side of the sub-grid that integrates a piece the support's edge crosses.
pub const FINE: usize = 96;

/// The integral of `pdf` over every test bin (row-major, z then azimuth). The sampler's
/// density is a constant per cell plus the cosine share's term linear in z, so splitting
/// each bin at the sampler's row edges and evaluating the density at the midpoint of each
/// piece integrates it exactly (up to rounding); the sampler's sectors nest in the bins.
///
/// Where F's support is smaller than the hemisphere the density is also cut by the
/// support's edge (great circles through a thread's axis), which crosses cells: 0 on one
/// side, or the cosine share's term counted once or twice where two lunes meet. Such a
/// piece is found by the density not having its in-cell form (the same in azimuth, linear in
/// z) on a grid of probes reaching the piece's corners, and is integrated by the midpoint
/// rule on a fine sub-grid instead: its error is then that of the sub-cells the edge crosses,
/// a small part of a few pieces, where the midpoint of a whole piece could be off by all of
/// it.
pub fn expected_mass(pdf: impl Fn(DVec3) -> f64) -> Vec<f64> {
    expected_mass_at(pdf, FINE)
}

/// [`expected_mass`] with `fine` midpoints per side in the pieces the support's edge crosses.
pub fn expected_mass_at(pdf: impl Fn(DVec3) -> f64, fine: usize) -> Vec<f64> {
    let sampler_row_z: Vec<f64> = (0..=ROWS)
        .map(|r| (r as f64 * FRAC_PI_2 / ROWS as f64).sin())
        .collect();
    let sectors_per_bin = COLUMNS / AZIMUTH_BINS;
    let sector = TAU / COLUMNS as f64;
    let at = |z: f64, azimuth: f64| {
        let r = (1.0 - z * z).max(0.0).sqrt();
        pdf(DVec3::new(r * azimuth.cos(), r * azimuth.sin(), z))
    };
    let mut mass = vec![0.0; Z_BINS * AZIMUTH_BINS];
    for zb in 0..Z_BINS {
        let (z0, z1) = (zb as f64 / Z_BINS as f64, (zb + 1) as f64 / Z_BINS as f64);
        let mut edges: Vec<f64> = sampler_row_z
            .iter()
            .copied()
            .filter(|&z| z > z0 && z < z1)
            .collect();
        edges.insert(0, z0);
        edges.push(z1);
        for ab in 0..AZIMUTH_BINS {
            let mut sum = 0.0;
            for piece in edges.windows(2) {
                for s in 0..sectors_per_bin {
                    let a0 = (ab * sectors_per_bin + s) as f64 * sector;
                    let (lo, hi) = (piece[0], piece[1]);
                    let area = (hi - lo) * sector;
                    if in_cell_form(|fz, fa| at(lo + fz * (hi - lo), a0 + fa * sector)) {
                        sum += at(0.5 * (lo + hi), a0 + 0.5 * sector) * area;
                    } else {
                        let n = fine as f64;
                        let mut sub = 0.0;
                        for i in 0..fine {
                            let z = lo + (i as f64 + 0.5) / n * (hi - lo);
                            for k in 0..fine {
                                sub += at(z, a0 + (k as f64 + 0.5) / n * sector);
                            }
                        }
                        sum += sub * area / (n * n);
                    }
                }
            }
            mass[zb * AZIMUTH_BINS + ab] = sum;
        }
    }
    mass
}

/// Whether `value(fz, fa)` over a piece (fz, fa in [0, 1] across its z and azimuth spans)
/// has the density's form inside one cell and the support: the same across the azimuth, and
/// linear in z. Probed on a grid from edge to edge (inset by a hair, so the probes stay in
/// the piece's cell), to the rounding of f64 arithmetic.
fn in_cell_form(value: impl Fn(f64, f64) -> f64) -> bool {
    const INSET: f64 = 1e-9;
    let f = |i: usize| INSET + (1.0 - 2.0 * INSET) * i as f64 / (PROBES - 1) as f64;
    let rows: Vec<Vec<f64>> = (0..PROBES)
        .map(|i| (0..PROBES).map(|k| value(f(i), f(k))).collect())
        .collect();
    let scale = rows.iter().flatten().fold(0.0_f64, |m, v| m.max(v.abs()));
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-9 * scale;
    let (first, last) = (rows[0][0], rows[PROBES - 1][0]);
    rows.iter().enumerate().all(|(i, row)| {
        let t = i as f64 / (PROBES - 1) as f64;
        row.iter().all(|&v| close(v, row[0])) && close(row[0], first + t * (last - first))
    })
}

/// The test bin of a direction above the horizon.
pub fn bin_of(w: DVec3) -> usize {
    let zb = ((w.z * Z_BINS as f64) as usize).min(Z_BINS - 1);
    let mut azimuth = w.y.atan2(w.x);
    if azimuth < 0.0 {
        azimuth += TAU;
    }
    let ab = ((azimuth / TAU * AZIMUTH_BINS as f64) as usize).min(AZIMUTH_BINS - 1);
    zb * AZIMUTH_BINS + ab
}

/// The outcome of one test.
#[derive(Debug)]
pub struct ChiSquare {
    pub statistic: f64,
    pub dof: usize,
    /// P(χ² ≥ statistic) under the hypothesis that the draws follow the density.
    pub p_value: f64,
}

/// Pearson's statistic of `observed` counts against `expected` ones (same bins), merging
/// bins in order of increasing expectation until each merged group expects ≥ MIN_EXPECTED.
pub fn chi_square(observed: &[u64], expected: &[f64]) -> ChiSquare {
    let mut order: Vec<usize> = (0..expected.len()).collect();
    order.sort_by(|&a, &b| expected[a].total_cmp(&expected[b]));
    let (mut statistic, mut groups) = (0.0, 0usize);
    let (mut pool_o, mut pool_e) = (0.0, 0.0);
    for k in order {
        pool_o += observed[k] as f64;
        pool_e += expected[k];
        if pool_e >= MIN_EXPECTED {
            statistic += (pool_o - pool_e).powi(2) / pool_e;
            groups += 1;
            pool_o = 0.0;
            pool_e = 0.0;
        }
    }
    // Left over when even the largest bins together expect under MIN_EXPECTED: its own term,
    // so that draws where almost nothing was expected still count against the sampler.
    if pool_e > 0.0 {
        statistic += (pool_o - pool_e).powi(2) / pool_e.max(MIN_EXPECTED);
    }
    let dof = groups.saturating_sub(1).max(1);
    ChiSquare {
        statistic,
        dof,
        p_value: upper_regularized_gamma(dof as f64 / 2.0, statistic / 2.0),
    }
}

/// One test of `observed` counts of `draws` draws against the density's `mass` per bin:
/// prints the statistic under `label`, and returns the failure when the p-value is below
/// `threshold`.
pub fn test(
    label: &str,
    observed: &[u64],
    mass: &[f64],
    draws: usize,
    threshold: f64,
) -> Option<String> {
    let expected: Vec<f64> = mass.iter().map(|m| m * draws as f64).collect();
    let result = chi_square(observed, &expected);
    println!(
        "{label}: χ² {:>8.1} dof {:>4} p {:.3}",
        result.statistic, result.dof, result.p_value
    );
    (result.p_value < threshold).then(|| format!("{label}: {result:?}"))
}

/// The per-test significance for an overall significance `alpha` over `tests` tests
/// (Šidák): 1 − (1 − α)^(1/tests).
pub fn sidak(alpha: f64, tests: usize) -> f64 {
    1.0 - (1.0 - alpha).powf(1.0 / tests as f64)
}

/// Q(a, x) = Γ(a, x)/Γ(a): the series of P for x < a + 1, Lentz's continued fraction of Q
/// otherwise (both converge fast there).
pub fn upper_regularized_gamma(a: f64, x: f64) -> f64 {
    if x <= 0.0 {
        return 1.0;
    }
    let log_prefactor = a * x.ln() - x - ln_gamma(a);
    if x < a + 1.0 {
        let (mut term, mut sum) = (1.0 / a, 1.0 / a);
        for n in 1..10_000 {
            term *= x / (a + n as f64);
            sum += term;
            if term < sum * 1e-15 {
                break;
            }
        }
        1.0 - sum * log_prefactor.exp()
    } else {
        let tiny = 1e-300;
        let mut b = x + 1.0 - a;
        let mut c = 1.0 / tiny;
        let mut d = 1.0 / b;
        let mut h = d;
        for i in 1..10_000 {
            let an = -(i as f64) * (i as f64 - a);
            b += 2.0;
            d = an * d + b;
            if d.abs() < tiny {
                d = tiny;
            }
            c = b + an / c;
            if c.abs() < tiny {
                c = tiny;
            }
            d = 1.0 / d;
            let delta = d * c;
            h *= delta;
            if (delta - 1.0).abs() < 1e-15 {
                break;
            }
        }
        log_prefactor.exp() * h
    }
}

/// ln Γ(x) for x > 0 (Lanczos, g = 7, nine coefficients: ~1e-15 relative).
fn ln_gamma(x: f64) -> f64 {
    const G: [f64; 9] = [
        0.999_999_999_999_809_9,
        676.520_368_121_885_1,
        -1_259.139_216_722_402_8,
        771.323_428_777_653_1,
        -176.615_029_162_140_6,
        12.507_343_278_686_905,
        -0.138_571_095_265_720_12,
        9.984_369_578_019_572e-6,
        1.505_632_735_149_311_6e-7,
    ];
    let x = x - 1.0;
    let mut sum = G[0];
    for (k, g) in G.iter().enumerate().skip(1) {
        sum += g / (x + k as f64);
    }
    let t = x + 7.5;
    0.5 * (TAU).ln() + (x + 0.5) * t.ln() - t + sum.ln()
}
