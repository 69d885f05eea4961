//! The sample taps' weights matched to F's spherical-harmonic moments.
//!
//! A tap does not read the map at a point: the fetch at the level `sampling_lod` picks
//! (`shaders/sampling/sample_taps.wgsl`) reads texels of area Ω_k/2 through a bilinear tent,
//! a kernel g_k about the tap's direction c_k with a variance of h²/4 = Ω_k/8 per axis
//! ([`FETCH_VARIANCE_PER_SOLID_ANGLE`]), for a stratum of solid angle Ω_k. So the K taps
//! estimate ∫ F_eff L dwi with F_eff = Σ_k u_k g_k(· − c_k), not ∫ F L dwi: F blurred at each
//! stratum's scale, which moves light from F's peak to its flanks (too little where a soft box
//! sits in the lobe, too much beside it; that smooth bias was most of the studio's error).
//!
//! For a map band-limited to order N the two integrals agree when F_eff and F have the same
//! spherical-harmonic moments up to order N. By the Funk–Hecke theorem the moment of the
//! isotropic g_k(· − c_k) against Y_lm is ĝ_l·Y_lm(c_k); for a kernel narrow against the
//! band, ĝ_l ≈ exp(−l(l + 1)σ²/2), the heat kernel's. So with A_jk = ĝ_l(j)(σ_k)·Y_j(c_k) and
//! b_j = ∫ F Y_j dwi (from the node's points), the stratum integrals u⁰_k are moved as little as
//! possible relative to their size to satisfy A u ≈ b: u = u⁰ + S d, S = diag(mean of u⁰_k's
//! RGB), d minimising ‖d‖² + ‖A S d − r‖²/λ for the residual r = b − A u⁰, that is
//! d = (AS)ᵀ ((AS)(AS)ᵀ + λ I)⁻¹ r, one (N + 1)² system per node, the same for the three
//! channels; then clamped at 0. The ridge λ (relative to the mean of (AS)(AS)ᵀ's diagonal)
//! keeps the weights from ringing: exact moment matching (λ → 0) made them oscillate, and
//! order 10 sharpened the hard edges of the interior's windows and the overcast horizon
//! (docs/notebook/2026-12-07-sampling.md#what-was-tried).

use super::Tap;
use glam::DVec3;

/// Highest order of the moments matched ((N + 1)² = 81 of them).
pub const MOMENT_ORDER: usize = 8;
/// The ridge λ, relative to the mean diagonal of the normal matrix.
pub const MOMENT_RIDGE: f64 = 0.03;
/// Per-axis variance of a tap's fetch kernel over its stratum's solid angle (above). If
/// `sampling_lod`'s level changes, so does this.
pub const FETCH_VARIANCE_PER_SOLID_ANGLE: f64 = 1.0 / 8.0;

/// Real spherical harmonics Y_lm up to a fixed order, orthonormal on the sphere, at index
/// l(l + 1) + m.
pub struct ShBasis {
    order: usize,
    /// √((2l + 1)/4π · (l − m)!/(l + m)!), times √2 for m > 0, at l(l + 1)/2 + m.
    norms: Vec<f64>,
}

impl ShBasis {
    /// The basis up to order `order`.
    pub fn new(order: usize) -> Self {
        let mut norms = Vec::with_capacity((order + 1) * (order + 2) / 2);
        for l in 0..=order {
            for m in 0..=l {
                let ratio: f64 = ((l - m + 1)..=(l + m)).map(|i| 1.0 / i as f64).product();
                let k = (2 * l + 1) as f64 / (4.0 * std::f64::consts::PI) * ratio;
                norms.push(if m == 0 { k.sqrt() } else { (2.0 * k).sqrt() });
            }
        }
        Self { order, norms }
    }

    /// The number of functions, (order + 1)².
    pub fn count(&self) -> usize {
        (self.order + 1) * (self.order + 1)
    }

    /// Y_lm(w) of unit `w` for every l ≤ order, into `out` (at least `count()` long).
    pub fn eval(&self, w: DVec3, out: &mut [f64]) {
        let z = w.z.clamp(-1.0, 1.0);
        // cos(mφ)·sin^m θ and sin(mφ)·sin^m θ are the parts of (x + iy)^m, and the associated
        // Legendre functions divided by sin^m θ follow the usual recurrence in z: no
        // trigonometry. (No Condon–Shortley phase: any consistent sign serves.)
        let (mut cos_m, mut sin_m) = (1.0, 0.0);
        let mut p_mm = 1.0; // (2m − 1)!!
        for m in 0..=self.order {
            if m > 0 {
                (cos_m, sin_m) = (cos_m * w.x - sin_m * w.y, cos_m * w.y + sin_m * w.x);
                p_mm *= (2 * m - 1) as f64;
            }
            let (mut previous, mut p) = (0.0, p_mm);
            for l in m..=self.order {
                if l > m {
                    let next = ((2 * l - 1) as f64 * z * p - (l + m - 1) as f64 * previous)
                        / (l - m) as f64;
                    (previous, p) = (p, next);
                }
                let y = self.norms[l * (l + 1) / 2 + m] * p;
                let at = l * l + l;
                if m == 0 {
                    out[at] = y;
                } else {
                    out[at + m] = y * cos_m;
                    out[at - m] = y * sin_m;
                }
            }
        }
    }

    /// ∫ F Y_j dwi for every j, from F's `values` at `points` (wi and the density they were
    /// placed with): the mean of F/pdf · Y_j.
    pub fn moments(&self, points: &[(DVec3, f64)], values: &[DVec3]) -> Vec<DVec3> {
        let mut sums = vec![DVec3::ZERO; self.count()];
        let mut y = vec![0.0; self.count()];
        for (&(wi, pdf), &value) in points.iter().zip(values) {
            self.eval(wi, &mut y);
            let weight = value / pdf;
            for (sum, &y) in sums.iter_mut().zip(&y) {
                *sum += weight * y;
            }
        }
        sums.iter()
            .map(|&s| s / points.len().max(1) as f64)
            .collect()
    }
}

/// The moments ∫ g(w − c)·Y_j(w) dw of a tap's fetch kernel g about its direction c, for a
/// stratum of `solid_angle`, into `out`: ĝ_l(σ)·Y_j(c), σ² its variance per axis.
pub fn fetch_moments(basis: &ShBasis, tap: &Tap, out: &mut [f64]) {
    basis.eval(tap.wi.as_dvec3(), out);
    let variance = FETCH_VARIANCE_PER_SOLID_ANGLE * (tap.log2_solid_angle as f64).exp2();
    for l in 0..=basis.order {
        let g = (-((l * (l + 1)) as f64) * variance / 2.0).exp();
        for y in &mut out[l * l..(l + 1) * (l + 1)] {
            *y *= g;
        }
    }
}

/// Moves the weights of one node's `taps` (K·u_k, K = `taps.len()`) so that their fetches'
/// moments match `moments` (∫ F Y_j dwi for `basis`), as the module doc derives.
pub fn match_moments(basis: &ShBasis, taps: &mut [Tap], moments: &[DVec3]) {
    let (n, k) = (basis.count(), taps.len());
    let samples = k as f64;
    let u0: Vec<DVec3> = taps.iter().map(|t| t.weight.as_dvec3() / samples).collect();
    let scales: Vec<f64> = u0.iter().map(|u| u.element_sum() / 3.0).collect();
    // A·S, row by row (row j holds Y_j's column for every tap).
    let mut a = vec![0.0; n * k];
    let mut y = vec![0.0; n];
    for (c, tap) in taps.iter().enumerate() {
        fetch_moments(basis, tap, &mut y);
        for (j, &y) in y.iter().enumerate() {
            a[j * k + c] = y * scales[c];
        }
    }
    let mut normal = vec![0.0; n * n];
    for i in 0..n {
        for j in 0..=i {
            let s = dot(&a[i * k..(i + 1) * k], &a[j * k..(j + 1) * k]);
            normal[i * n + j] = s;
            normal[j * n + i] = s;
        }
    }
    let ridge = MOMENT_RIDGE * (0..n).map(|i| normal[i * n + i]).sum::<f64>() / n as f64;
    for i in 0..n {
        normal[i * n + i] += ridge;
    }
    // r = b − A u⁰, with A u⁰ = (A S)(S⁻¹ u⁰).
    let ratios: Vec<DVec3> = u0
        .iter()
        .zip(&scales)
        .map(|(&u, &s)| if s > 0.0 { u / s } else { DVec3::ZERO })
        .collect();
    let mut r: Vec<DVec3> = (0..n)
        .map(|j| {
            let row = &a[j * k..(j + 1) * k];
            moments[j] - row.iter().zip(&ratios).map(|(&x, &q)| x * q).sum::<DVec3>()
        })
        .collect();
    if !cholesky_solve(&mut normal, n, &mut r) {
        return;
    }
    let u: Vec<DVec3> = (0..k)
        .map(|c| {
            let d: DVec3 = (0..n).map(|j| a[j * k + c] * r[j]).sum();
            (u0[c] + scales[c] * d).max(DVec3::ZERO)
        })
        .collect();
    // The clamp adds light where the solution rang below zero; the total, ∫F dwi, is what a
    // constant map reads through any kernel, so it is restored exactly (the white furnace).
    let total = |u: &[DVec3]| u.iter().sum::<DVec3>();
    let (before, after) = (total(&u0), total(&u));
    let restore = DVec3::select(after.cmpgt(DVec3::ZERO), before / after, DVec3::ONE);
    for (tap, u) in taps.iter_mut().zip(u) {
        tap.weight = (samples * u * restore).as_vec3();
    }
}

/// Σ p_i q_i in four partial sums (so that the loop vectorises).
fn dot(p: &[f64], q: &[f64]) -> f64 {
    let (p4, q4) = (p.chunks_exact(4), q.chunks_exact(4));
    let tail: f64 = p4
        .remainder()
        .iter()
        .zip(q4.remainder())
        .map(|(a, b)| a * b)
        .sum();
    let mut sums = [0.0; 4];
    for (a, b) in p4.zip(q4) {
        for i in 0..4 {
            sums[i] += a[i] * b[i];
        }
    }
    sums.iter().sum::<f64>() + tail
}

/// Solves M x = b in place for a symmetric positive definite `m` (n × n, row-major, its
/// lower triangle overwritten by the Cholesky factor) and three right-hand sides; false if
/// M is not positive definite.
fn cholesky_solve(m: &mut [f64], n: usize, b: &mut [DVec3]) -> bool {
    for j in 0..n {
        let d = m[j * n + j] - dot(&m[j * n..j * n + j], &m[j * n..j * n + j]);
        if d <= 0.0 || !d.is_finite() {
            return false;
        }
        let d = d.sqrt();
        m[j * n + j] = d;
        for i in j + 1..n {
            let s = dot(&m[i * n..i * n + j], &m[j * n..j * n + j]);
            m[i * n + j] = (m[i * n + j] - s) / d;
        }
    }
    for i in 0..n {
        let s: DVec3 = (0..i).map(|c| m[i * n + c] * b[c]).sum();
        b[i] = (b[i] - s) / m[i * n + i];
    }
    for i in (0..n).rev() {
        let s: DVec3 = (i + 1..n).map(|c| m[c * n + i] * b[c]).sum();
        b[i] = (b[i] - s) / m[i * n + i];
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::{PI, TAU};

    /// The basis is orthonormal on the sphere: ∫ Y_i Y_j = δ_ij by the midpoint rule in z
    /// and azimuth (uniform in solid angle). In azimuth the rule is exact for these
    /// trigonometric polynomials (degree ≤ 16 < 64); in z, on polynomials of degree ≤ 16, it
    /// errs by about 1e-4 over 2,000 intervals; bound 1e-3.
    #[test]
    fn the_basis_is_orthonormal() {
        let basis = ShBasis::new(MOMENT_ORDER);
        let n = basis.count();
        let mut gram = vec![0.0; n * n];
        let mut y = vec![0.0; n];
        let (nz, na) = (2000, 64);
        for i in 0..nz {
            let z = -1.0 + 2.0 * (i as f64 + 0.5) / nz as f64;
            let r = (1.0 - z * z).sqrt();
            for j in 0..na {
                let a = (j as f64 + 0.5) * TAU / na as f64;
                basis.eval(DVec3::new(r * a.cos(), r * a.sin(), z), &mut y);
                for p in 0..n {
                    for q in 0..=p {
                        gram[p * n + q] += y[p] * y[q];
                    }
                }
            }
        }
        let area = 4.0 * PI / (nz * na) as f64;
        for p in 0..n {
            for q in 0..=p {
                let expected = if p == q { 1.0 } else { 0.0 };
                let value = gram[p * n + q] * area;
                assert!((value - expected).abs() < 1e-3, "Y{p}·Y{q}: {value}");
            }
        }
    }

    /// Y_00 is 1/√(4π), Y_1,0 is √(3/4π)·z, and Y_2,2 is √(15/16π)·(x² − y²).
    #[test]
    fn the_basis_has_the_textbook_normalisation() {
        let basis = ShBasis::new(2);
        let mut y = vec![0.0; basis.count()];
        let w = DVec3::new(0.48, -0.6, 0.64);
        basis.eval(w, &mut y);
        assert!((y[0] - 1.0 / (4.0 * PI).sqrt()).abs() < 1e-12);
        assert!((y[2] - (3.0 / (4.0 * PI)).sqrt() * w.z).abs() < 1e-12);
        assert!((y[8] - (15.0 / (16.0 * PI)).sqrt() * (w.x * w.x - w.y * w.y)).abs() < 1e-12);
    }

    /// Taps blurred by their fetches: matching brings their moments (blurred as the module
    /// doc models the fetch) near F's, keeps the total exactly, and keeps every weight
    /// non-negative. 64 taps spread over the hemisphere (a Fibonacci set) with weights of a
    /// lobe around 30° elevation, each of a stratum of 2π/64 sr; F's moments those of the
    /// unblurred point masses, order 4.
    #[test]
    fn matching_brings_the_fetches_moments_to_fs() {
        let basis = ShBasis::new(4);
        let n = basis.count();
        let count = 64;
        let axis = DVec3::new(0.87, 0.0, 0.5);
        let mut taps: Vec<Tap> = (0..count)
            .map(|i| {
                let z = (i as f64 + 0.5) / count as f64;
                let a = i as f64 * PI * (3.0 - 5f64.sqrt());
                let r = (1.0 - z * z).sqrt();
                let w = DVec3::new(r * a.cos(), r * a.sin(), z);
                let lobe = (4.0 * (w.dot(axis) - 1.0)).exp();
                Tap {
                    wi: w.as_vec3(),
                    log2_solid_angle: (TAU / count as f64).log2() as f32,
                    weight: (lobe * DVec3::new(1.0, 0.7, 0.4)).as_vec3(),
                }
            })
            .collect();
        let mut y = vec![0.0; n];
        let moments_of = |taps: &[Tap], blurred: bool, y: &mut [f64]| -> Vec<DVec3> {
            let mut sums = vec![DVec3::ZERO; n];
            for tap in taps {
                if blurred {
                    fetch_moments(&basis, tap, y);
                } else {
                    basis.eval(tap.wi.as_dvec3(), y);
                }
                for (sum, &y) in sums.iter_mut().zip(y.iter()) {
                    *sum += tap.weight.as_dvec3() / count as f64 * y;
                }
            }
            sums
        };
        let moments = moments_of(&taps, false, &mut y);
        let distance = |taps: &[Tap], y: &mut [f64]| -> f64 {
            let blurred = moments_of(taps, true, y);
            let d: f64 = blurred
                .iter()
                .zip(&moments)
                .map(|(b, m)| (*b - *m).length_squared())
                .sum();
            d.sqrt()
        };
        let total = |taps: &[Tap]| taps.iter().map(|t| t.weight.as_dvec3()).sum::<DVec3>();
        let (before, sum_before) = (distance(&taps, &mut y), total(&taps));
        match_moments(&basis, &mut taps, &moments);
        let (after, sum_after) = (distance(&taps, &mut y), total(&taps));
        println!("moment distance {before:.5} → {after:.5}");
        assert!(after < 0.25 * before, "{before} → {after}");
        assert!((sum_after - sum_before).abs().max_element() < 1e-5 * sum_before.x);
        assert!(taps.iter().all(|t| t.weight.min_element() >= 0.0));
    }
}
