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
//!    there, but the baked table need not be exactly (satin's grazing texels at low
//!    resolutions differ most), so for |u| < 1e-5 the difference between the two
//!    interpolations is added, propagated like the filtering error.
//! 4. split_frame evaluates its point masses with the shared f32 sample kernel where the
//!    CPU uses the f64 model. The GPU test of that kernel bounds its relative error by
//!    R = 2e-5 + 6·δθh/σ_min, δθh the device's atan2 error (found on the device by that
//!    test), largest for the narrowest lobe of the built-in fabrics. The point sums enter
//!    both ⟨s⟩ and Q, so F moves by at most 2R relative: 1e-3·|F| is added, twice R at
//!    that lobe.
//!
//! The bound per pair and channel is that propagated error plus 1e-5·|F| + 1e-6.

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
