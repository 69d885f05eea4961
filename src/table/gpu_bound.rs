//! How far a layout's WGSL lookup may be from its f64 CPU lookup ([`super::Table::lookup`])
//! on the same pair: each layout declares its bound ([`super::TableLookup::gpu_error_bound`])
//! and the GPU test of every registered layout checks it.
//!
//! Both sides read the same f16 texels (the upload is lossless) and interpolate the same
//! corners with the same weights, so the differences come from these sources:
//! 1. Hardware filtering quantises each filter weight: lavapipe (like most GPUs) computes
//!    them in 8-bit fixed point, so a weight is off by at most δ = 1/256. On one filtered
//!    axis this moves the result by at most δ·|difference across that axis| ≤ δ·(range of
//!    the corners); over k filtered axes by k·δ·range. thread_frame filters 3 axes of the 4D
//!    table (βH, θd', v; u is blended in f32 by the shader) and 2 of ⟨P⟩; grid4d filters
//!    the 2 wo axes (the wi blend is in f32).
//! 2. f32 arithmetic: the coordinates (atan2, asin, sin βH and cos βH as h.x/|h∥|, h.z/|h∥|,
//!    the warps with their constant factors folded in f64 and rounded once to f32) carry
//!    errors of a few ulp, which shift every interpolation weight by far less than ε = 1e-4
//!    of a texel (so ≤ ε·range per axis, 4 axes), cos²θd' = 1 − s² carries ~1e-7 absolute
//!    error (relative 1e-7/cos²θd' in reflection/cos²θd'), and the final sums ~1e-6
//!    relative.
//!
//!    For the thread layouts, F = Σ_j a_j ⟨P⟩_j (r_j / c_j + A_j t_j) / Q with
//!    Q = Σ_j a_j ⟨P⟩_j + gap·wo.z is nonlinear in the interpolated r_j, t_j, ⟨P⟩_j, so the
//!    interpolation errors above are propagated to F with its partial derivatives (first
//!    order, evaluated at the CPU's values).
//! 3. The fold u → |u| of thread_frame (u = (φi' + φo')/2, see its module doc): pairs with
//!    u within f32 error of 0 (highlight pairs produce them) may be folded to the other side
//!    on the GPU, reading the table at (|u|, −v) instead of (|u|, v). The model is symmetric
//!    there, but the baked table need not be exactly (measured: up to ~4% on satin's
//!    grazing texels at R = 16), so for |u| < 1e-5 the difference between the two
//!    interpolations is added, propagated like the filtering error.
//! 4. split_frame evaluates its point masses with the shared f32 sample kernel where the
//!    CPU uses the f64 model. The GPU test of that kernel bounds its relative error by
//!    R = 2e-5 + 6·δθh/σ_min, δθh the device's atan2 error (3.4e-6 on lavapipe): 5e-4 for
//!    satin's σs = 2.5°, the narrowest lobe of the built-in fabrics. The point sums enter
//!    both ⟨s⟩ and Q, so F moves by at most 2R relative: 1e-3·|F| is added. In the horizon
//!    band (a direction below 1°) the sloped segments come from the resonant quadrature
//!    instead of the table, in f32 on the GPU and f64 on the CPU: no interpolation error,
//!    and the same 1e-3·|F| covers the kernel (its GPU test measures at most 1.4e-4
//!    relative where |F| > 1e-4).
//!
//! The bound per pair and channel is that propagated error plus 1e-5·|F| + 1e-6.

use super::thread_frame::ThreadGeometry;
use super::{Plane, quadrilinear_corners};
use glam::DVec3;

/// Weight quantisation of hardware filtering (8-bit fractions).
pub const FILTER_WEIGHT_STEP: f64 = 1.0 / 256.0;
/// f32 coordinate error, in texels, per axis.
pub const COORDINATE_ERROR: f64 = 1e-4;
/// Relative and absolute floor of every bound (f32 sums).
pub const RELATIVE: f64 = 1e-5;
pub const ABSOLUTE: f64 = 1e-6;
/// |u| (radians) below which f32 may fold a pair to the other side of u = 0.
pub const FOLD_EPSILON: f64 = 1e-5;
/// Relative error of F from the f32 sample kernel of split_frame's point masses (point 4).
pub const KERNEL_RELATIVE: f64 = 1e-3;

/// A bound on |GPU − CPU| of one pair, per RGB channel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GpuErrorBound {
    pub per_channel: DVec3,
    /// The pair lies on a fold (point 3) where f32 may read the table's other side.
    pub on_fold: bool,
}

/// The bound's floor for a value `cpu`: 1e-5·|F| + 1e-6.
pub fn floor(cpu: DVec3) -> DVec3 {
    cpu.abs() * RELATIVE + ABSOLUTE
}

/// Largest minus smallest of `values`.
pub fn range(values: impl IntoIterator<Item = f64>) -> f64 {
    let (lo, hi) = values
        .into_iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    hi - lo
}

/// A thread's 4D table (`data`, two channels) interpolated at table coordinates, as the
/// thread layouts' lookups do.
fn interpolate(thread: &ThreadGeometry, data: &[f32], coordinates: [f64; 4]) -> [f64; 2] {
    let axes = std::array::from_fn(|a| thread.axes[a].locate(coordinates[a]));
    let mut sum = [0.0; 2];
    for (index, weight) in quadrilinear_corners(axes) {
        let k = thread.texel_index(index) * 2;
        sum[0] += weight * data[k] as f64;
        sum[1] += weight * data[k + 1] as f64;
    }
    sum
}

/// The interpolation errors of one thread table (4D plane `table`, masking plane
/// `masking`) at a pair: `[reflection, transmission, ⟨P⟩]` from filtering and f32
/// coordinates (points 1 and 2), and the fold differences `[reflection, transmission]`
/// (point 3; at least a tiny value when the pair is on the fold u = 0, else 0).
pub fn thread_errors(
    thread: &ThreadGeometry,
    table: &Plane,
    masking: &Plane,
    wi: DVec3,
    wo: DVec3,
) -> ([f64; 3], [f64; 2]) {
    let coordinates = thread.coordinates(wi, wo);
    let axes = std::array::from_fn(|a| thread.axes[a].locate(coordinates[a]));
    let texels: Vec<usize> = quadrilinear_corners(axes)
        .map(|(i, _)| thread.texel_index(i) * 2)
        .collect();
    let data = &table.data;
    let scale = 3.0 * FILTER_WEIGHT_STEP + 4.0 * COORDINATE_ERROR;
    let mut errors = [0.0; 3];
    errors[0] = scale * range(texels.iter().map(|&k| data[k] as f64));
    errors[1] = scale * range(texels.iter().map(|&k| data[k + 1] as f64));
    let m = thread.masking_axis;
    let ((x0, x1, _), (y0, y1, _)) = (m.locate(thread.beta(wi)), m.locate(thread.beta(wo)));
    let p_range =
        range([(x0, y0), (x1, y0), (x0, y1), (x1, y1)].map(|(x, y)| masking.texel(x, y)[0] as f64));
    errors[2] = (2.0 * FILTER_WEIGHT_STEP + 2.0 * COORDINATE_ERROR) * p_range;
    let mut fold = [0.0; 2];
    // On the fold u = 0, f32 may land on the other side, (u, v) → (−u, −v).
    if coordinates[2] < FOLD_EPSILON {
        let [u, v] = [coordinates[2], coordinates[3]];
        let other = interpolate(thread, data, [coordinates[0], coordinates[1], u, -v]);
        let here = interpolate(thread, data, coordinates);
        fold = [
            (other[0] - here[0]).abs().max(f64::MIN_POSITIVE),
            (other[1] - here[1]).abs(),
        ];
    }
    (errors, fold)
}
