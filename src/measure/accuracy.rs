//! A table's error against the direct evaluation, on the seeded direction sets of
//! [`crate::measure::direction_sets`].

use crate::measure::direction_sets::{highlight_pairs, uniform_pairs};
use crate::model::{Fabric, Integration, Patch};
use crate::table::Table;
use glam::{DVec3, Vec3};
use rayon::prelude::*;

/// Seeds of the validation sets; fixed so every `check` measures the same pairs.
pub const UNIFORM_SEED: u64 = 0x5eed_0001;
pub const HIGHLIGHT_SEED: u64 = 0x5eed_0002;

/// Errors of a table on one set of pairs.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct SetError {
    /// `sqrt(Σ|F_table − F|² / Σ|F|²)` over all RGB components.
    pub relative_rms: f64,
    /// Largest `|F_table − F|` over components and pairs.
    pub max_abs: f64,
    /// The value of F (largest component) at that pair.
    pub max_abs_at_value: f64,
}

/// A table's errors on uniform pairs, highlight pairs, and on the pairs of each set with
/// both directions at least 1°, 3° (and, uniform, 15°) above the horizon. Pairs below 1°
/// are few in the uniform set but can carry most of a table's squared error, so the
/// bands show how much of it lies at the horizon.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct TableError {
    pub uniform: SetError,
    pub highlight: SetError,
    pub uniform_above_1deg: SetError,
    pub uniform_above_3deg: SetError,
    pub uniform_above_15deg: SetError,
    pub highlight_above_1deg: SetError,
    pub highlight_above_3deg: SetError,
}

fn set_error(values: &[(DVec3, DVec3)]) -> SetError {
    let mut err = 0.0;
    let mut norm = 0.0;
    let mut max_abs = 0.0;
    let mut max_abs_at_value = 0.0;
    for &(table, truth) in values {
        err += (table - truth).length_squared();
        norm += truth.length_squared();
        let abs = (table - truth).abs().max_element();
        if abs > max_abs {
            max_abs = abs;
            max_abs_at_value = truth.max_element();
        }
    }
    SetError {
        relative_rms: (err / norm).sqrt(),
        max_abs,
        max_abs_at_value,
    }
}

/// The direct evaluation of a fabric on `count` uniform and `count` highlight pairs of the
/// validation sets, computed once so that many estimates (tables of several resolutions,
/// paper mode at several N) are measured on the same pairs without evaluating it again.
#[derive(Clone, Debug)]
pub struct Reference {
    /// (wi, wo, direct F) per uniform pair.
    uniform: Vec<(DVec3, DVec3, DVec3)>,
    /// (wi, wo, direct F) per highlight pair.
    highlight: Vec<(DVec3, DVec3, DVec3)>,
}

impl Reference {
    /// Evaluates `fabric` directly on `count` pairs of each validation set (in parallel).
    pub fn new(fabric: &Fabric, count: usize) -> Self {
        let patch = Patch::new(fabric, Integration::Direct);
        let direct = |pairs: Vec<(DVec3, DVec3)>| -> Vec<(DVec3, DVec3, DVec3)> {
            pairs
                .into_par_iter()
                .map(|(wi, wo)| (wi, wo, patch.eval(wi, wo)))
                .collect()
        };
        Self {
            uniform: direct(uniform_pairs(count, UNIFORM_SEED)),
            highlight: direct(highlight_pairs(fabric, count, HIGHLIGHT_SEED)),
        }
    }

    /// Pairs per set.
    pub fn count(&self) -> usize {
        self.uniform.len()
    }

    /// The errors of `estimate(wi, wo)` (an RGB estimate of F) against the direct values.
    pub fn measure(&self, estimate: impl Fn(DVec3, DVec3) -> DVec3 + Sync) -> TableError {
        // (wi, wo, estimate, direct value) per pair.
        let compare = |set: &[(DVec3, DVec3, DVec3)]| -> Vec<(DVec3, DVec3, DVec3, DVec3)> {
            set.par_iter()
                .map(|&(wi, wo, truth)| (wi, wo, estimate(wi, wo), truth))
                .collect()
        };
        let uniform = compare(&self.uniform);
        let highlight = compare(&self.highlight);
        let above = |set: &[(DVec3, DVec3, DVec3, DVec3)], degrees: f64| -> SetError {
            let z = degrees.to_radians().sin();
            let kept: Vec<(DVec3, DVec3)> = set
                .iter()
                .filter(|s| s.0.z >= z && s.1.z >= z)
                .map(|s| (s.2, s.3))
                .collect();
            set_error(&kept)
        };
        TableError {
            uniform: above(&uniform, 0.0),
            highlight: above(&highlight, 0.0),
            uniform_above_1deg: above(&uniform, 1.0),
            uniform_above_3deg: above(&uniform, 3.0),
            uniform_above_15deg: above(&uniform, 15.0),
            highlight_above_1deg: above(&highlight, 1.0),
            highlight_above_3deg: above(&highlight, 3.0),
        }
    }
}

/// Measures `table` (its f32 lookup, the CPU path, on the pairs rounded to f32) against the
/// direct evaluation of `fabric` on `count` uniform and `count` highlight pairs.
pub fn measure(table: &Table, fabric: &Fabric, count: usize) -> TableError {
    Reference::new(fabric, count).measure(|wi, wo| lookup_f32(table, wi, wo))
}

/// [`Table::lookup_f32`] on f64 directions (rounded to f32 as a renderer passes them).
pub fn lookup_f32(table: &Table, wi: DVec3, wo: DVec3) -> DVec3 {
    table.lookup_f32(wi.as_vec3(), wo.as_vec3()).as_dvec3()
}

/// [`Table::lookup_batch`] on f64 pairs (rounded to f32 as a renderer passes them), into
/// `out` (same length).
pub fn lookup_batch_f64(table: &Table, pairs: &[(DVec3, DVec3)], out: &mut [DVec3]) {
    let pairs: Vec<(Vec3, Vec3)> = pairs
        .iter()
        .map(|&(wi, wo)| (wi.as_vec3(), wo.as_vec3()))
        .collect();
    let mut values = vec![Vec3::ZERO; pairs.len()];
    table.lookup_batch(&pairs, &mut values);
    for (f, v) in out.iter_mut().zip(values) {
        *f = v.as_dvec3();
    }
}

/// The sum of [`lookup_batch_f64`] over `pairs`: what the report times as a table's cost.
pub fn lookup_batch_sum(table: &Table, pairs: &[(DVec3, DVec3)]) -> DVec3 {
    let mut out = vec![DVec3::ZERO; pairs.len()];
    lookup_batch_f64(table, pairs, &mut out);
    out.iter().sum()
}
