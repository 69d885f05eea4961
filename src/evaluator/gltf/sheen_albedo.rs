//! E(μ, r): the directional albedo of KHR_materials_sheen's sheen BRDF with white sheen
//! colour, the Charlie distribution and its visibility, which the extension's albedo
//! scaling of the base layer reads. The extension leaves E to the implementation (a table
//! or a fit); here it is a table over μ = n·v and the sheen roughness r, integrated once
//! per process.

use crate::evaluator::stock::lobes::{charlie_d, charlie_visibility, midpoint_integral};
use glam::DVec3;
use rayon::prelude::*;
use std::f64::consts::PI;
use std::sync::OnceLock;

/// Nodes in μ (at k / (N − 1)) and in r (from [`MIN_SHEEN_ROUGHNESS`] to 1).
pub const MU_NODES: usize = 32;
pub const ROUGHNESS_NODES: usize = 32;
/// The smallest sheen roughness the table covers, and so the smallest a fit may choose:
/// α = r² ≈ 0.005 must stay above 0 (the Charlie exponent is 1/(2α)). The table's rule
/// follows E at this end as closely as across the rest of its range, and no fit rests on this
/// bound where its sheen shows (docs/notebook/2026-12-07-export.md).
pub const MIN_SHEEN_ROUGHNESS: f64 = 0.07;
/// Cells of the midpoint rule in n·l and in φ that integrates each entry.
const CELLS: usize = 128;

/// The roughness of row `j`.
fn roughness_of_row(j: usize) -> f64 {
    MIN_SHEEN_ROUGHNESS + (1.0 - MIN_SHEEN_ROUGHNESS) * j as f64 / (ROUGHNESS_NODES - 1) as f64
}

/// E at μ for sheen roughness r: `∫ D(h) V(v, l) (n·l) dωl`, by the midpoint rule in
/// (n·l, φ) with `cells` × `cells` cells.
fn integrate(mu: f64, roughness: f64, cells: usize) -> f64 {
    let alpha = roughness * roughness;
    let mu = mu.max(1e-3);
    let v = DVec3::new((1.0 - mu * mu).sqrt(), 0.0, mu);
    // Both halves in φ: the integrand is even in φ.
    2.0 * midpoint_integral(cells, cells, PI, |l| {
        let h = (l + v).normalize();
        charlie_d(alpha, h.z, 0.0) * charlie_visibility(alpha, mu, l.z) * l.z
    })
}

/// The table, row j (roughness) by column k (μ). The Λ of the Charlie visibility is a fit,
/// not a masking function: towards grazing view at small roughness its albedo passes 1, which
/// would turn the base's scaling negative, so the table holds E clamped to 1.
fn table() -> &'static [f64] {
    static TABLE: OnceLock<Vec<f64>> = OnceLock::new();
    TABLE.get_or_init(|| {
        (0..ROUGHNESS_NODES * MU_NODES)
            .into_par_iter()
            .map(|n| {
                let (j, k) = (n / MU_NODES, n % MU_NODES);
                integrate(k as f64 / (MU_NODES - 1) as f64, roughness_of_row(j), CELLS).min(1.0)
            })
            .collect()
    })
}

/// E over the μ nodes for sheen roughness `r`, linear between the table's rows: the
/// constants the glTF unit derives and both its forms read.
pub fn albedo_row(roughness: f64) -> Vec<f64> {
    let x = ((roughness - MIN_SHEEN_ROUGHNESS) / (1.0 - MIN_SHEEN_ROUGHNESS)).clamp(0.0, 1.0)
        * (ROUGHNESS_NODES - 1) as f64;
    let j = (x.floor() as usize).min(ROUGHNESS_NODES - 2);
    let t = x - j as f64;
    let table = table();
    (0..MU_NODES)
        .map(|k| {
            let (a, b) = (table[j * MU_NODES + k], table[(j + 1) * MU_NODES + k]);
            a + (b - a) * t
        })
        .collect()
}

/// E(μ) from a row of [`albedo_row`], linear between its nodes (`cloth_gltf_sheen_albedo`'s
/// twin).
pub fn albedo_at(row: &[f64], mu: f64) -> f64 {
    let x = mu.clamp(0.0, 1.0) * (MU_NODES - 1) as f64;
    let k = (x.floor() as usize).min(MU_NODES - 2);
    let t = x - k as f64;
    row[k] + (row[k + 1] - row[k]) * t
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_sheen_albedo_lies_in_zero_one_and_grows_with_roughness_at_normal_incidence() {
        let rows: Vec<Vec<f64>> = [0.07, 0.3, 0.6, 1.0].map(albedo_row).into();
        for row in &rows {
            assert!(row.iter().all(|&e| (0.0..=1.0).contains(&e)), "{row:?}");
        }
        let at_normal: Vec<f64> = rows.iter().map(|r| albedo_at(r, 1.0)).collect();
        assert!(at_normal.windows(2).all(|w| w[0] < w[1]), "{at_normal:?}");
    }

    #[test]
    fn the_tables_rule_follows_a_finer_one_across_the_roughness_range() {
        // Against a rule of four times the cells per axis, over every μ node, E clamped as
        // the table holds it. E scales the base layer by 1 − max(sheen) E, so an error of
        // 2e-3 in E moves the base by at most that fraction of its unscaled value, far inside
        // what any stock model loses against a fabric; the measured errors against finer
        // rules are in docs/notebook/2026-12-07-export.md.
        for roughness in [MIN_SHEEN_ROUGHNESS, 0.3, 1.0] {
            let worst = (0..MU_NODES)
                .map(|k| {
                    let mu = k as f64 / (MU_NODES - 1) as f64;
                    let table = integrate(mu, roughness, CELLS).min(1.0);
                    let finer = integrate(mu, roughness, 4 * CELLS).min(1.0);
                    (table - finer).abs()
                })
                .fold(0.0, f64::max);
            println!("r = {roughness}: largest |E − E(finer rule)| = {worst:.2e}");
            assert!(worst < 2e-3, "r = {roughness}: {worst}");
        }
    }
}
