//! Fast f32 approximations of the transcendental functions of the table lookups, with the
//! error bounds their tests measure. A texel of any layout spans at least 0.1° (1.7e-3
//! rad), so an angle error of 2e-5 rad moves a lookup by at most about 1% of a texel, far
//! below the interpolation error.
//!
//! They are written once for [`Lanes`], a number of f32 lanes: a plain `f32` for one
//! lookup, [`wide::f32x8`] for eight computed together in SIMD registers (the batch lookup,
//! see [`super::thread::ThreadGeometry::locate_f32`]). Every lane goes through the
//! same IEEE operations in the same order, so both give the same values bit for bit.

use std::f32::consts::{FRAC_PI_2, PI};
use std::ops::{Add, Div, Index, Mul, Neg, Sub};
use wide::{CmpGt, CmpLe, CmpLt};

/// A number of f32 lanes computed together, branch-free: comparisons give masks and
/// [`Lanes::select`] picks lane by lane.
pub trait Lanes:
    Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
{
    type Mask: Copy;
    /// The lanes' values as an array.
    type Values: Copy + Index<usize, Output = f32>;
    /// One i32 per lane, as an array.
    type Indices: Copy + Index<usize, Output = i32>;
    const WIDTH: usize;
    fn splat(x: f32) -> Self;
    /// Lane k = `f(k)`.
    fn from_fn(f: impl FnMut(usize) -> f32) -> Self;
    fn abs(self) -> Self;
    fn sqrt(self) -> Self;
    /// The larger of two non-NaN lanes.
    fn max(self, other: Self) -> Self;
    /// The smaller of two non-NaN lanes.
    fn min(self, other: Self) -> Self;
    fn gt(self, other: Self) -> Self::Mask;
    fn lt(self, other: Self) -> Self::Mask;
    fn le(self, other: Self) -> Self::Mask;
    /// Lane by lane `if mask { t } else { f }`.
    fn select(mask: Self::Mask, t: Self, f: Self) -> Self;
    /// |self| with the sign of `sign`.
    fn copysign(self, sign: Self) -> Self;
    /// For non-negative lanes: (min(⌊self⌋, limit), self − that).
    fn split_floor(self, limit: i32) -> (Self::Indices, Self::Values);
    fn values(self) -> Self::Values;
    /// 2ⁿ for lanes holding n + 1.5·2²³, n an integer in [−126, 127]: such a float's low
    /// mantissa bits are n in two's complement, so its bits shifted left by 23 are n's
    /// exponent field less the bias.
    fn pow2_of_shifted(self) -> Self;
    /// Lane by lane `a && b`.
    fn and(a: Self::Mask, b: Self::Mask) -> Self::Mask;
}

impl Lanes for f32 {
    type Mask = bool;
    type Values = [f32; 1];
    type Indices = [i32; 1];
    const WIDTH: usize = 1;
    #[inline(always)]
    fn splat(x: f32) -> Self {
        x
    }
    #[inline(always)]
    fn from_fn(mut f: impl FnMut(usize) -> f32) -> Self {
        f(0)
    }
    #[inline(always)]
    fn abs(self) -> Self {
        f32::abs(self)
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        f32::sqrt(self)
    }
    #[inline(always)]
    fn max(self, other: Self) -> Self {
        f32::max(self, other)
    }
    #[inline(always)]
    fn min(self, other: Self) -> Self {
        f32::min(self, other)
    }
    #[inline(always)]
    fn gt(self, other: Self) -> bool {
        self > other
    }
    #[inline(always)]
    fn lt(self, other: Self) -> bool {
        self < other
    }
    #[inline(always)]
    fn le(self, other: Self) -> bool {
        self <= other
    }
    #[inline(always)]
    fn select(mask: bool, t: Self, f: Self) -> Self {
        if mask { t } else { f }
    }
    #[inline(always)]
    fn copysign(self, sign: Self) -> Self {
        f32::copysign(self, sign)
    }
    #[inline(always)]
    fn split_floor(self, limit: i32) -> ([i32; 1], [f32; 1]) {
        // A plain i32 conversion (Rust's `as usize` from f32 saturates, which costs
        // branches in this hot path).
        let i = (self as i32).min(limit);
        ([i], [self - i as f32])
    }
    #[inline(always)]
    fn values(self) -> [f32; 1] {
        [self]
    }
    #[inline(always)]
    fn pow2_of_shifted(self) -> Self {
        f32::from_bits((self.to_bits() << 23).wrapping_add(127 << 23))
    }
    #[inline(always)]
    fn and(a: bool, b: bool) -> bool {
        a && b
    }
}

impl Lanes for wide::f32x8 {
    type Mask = wide::f32x8;
    type Values = [f32; 8];
    type Indices = [i32; 8];
    const WIDTH: usize = 8;
    #[inline(always)]
    fn splat(x: f32) -> Self {
        wide::f32x8::splat(x)
    }
    #[inline(always)]
    fn from_fn(mut f: impl FnMut(usize) -> f32) -> Self {
        let mut lanes = [0.0; 8];
        for (k, lane) in lanes.iter_mut().enumerate() {
            *lane = f(k);
        }
        wide::f32x8::new(lanes)
    }
    #[inline(always)]
    fn abs(self) -> Self {
        wide::f32x8::abs(self)
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        wide::f32x8::sqrt(self)
    }
    #[inline(always)]
    fn max(self, other: Self) -> Self {
        self.fast_max(other)
    }
    #[inline(always)]
    fn min(self, other: Self) -> Self {
        self.fast_min(other)
    }
    #[inline(always)]
    fn gt(self, other: Self) -> Self {
        self.cmp_gt(other)
    }
    #[inline(always)]
    fn lt(self, other: Self) -> Self {
        self.cmp_lt(other)
    }
    #[inline(always)]
    fn le(self, other: Self) -> Self {
        self.cmp_le(other)
    }
    #[inline(always)]
    fn select(mask: Self, t: Self, f: Self) -> Self {
        mask.blend(t, f)
    }
    #[inline(always)]
    fn copysign(self, sign: Self) -> Self {
        wide::f32x8::copysign(self, sign)
    }
    #[inline(always)]
    fn split_floor(self, limit: i32) -> ([i32; 8], [f32; 8]) {
        let i = self.fast_trunc_int().min(wide::i32x8::splat(limit));
        (i.to_array(), (self - wide::f32x8::from_i32x8(i)).to_array())
    }
    #[inline(always)]
    fn values(self) -> [f32; 8] {
        self.to_array()
    }
    #[inline(always)]
    fn pow2_of_shifted(self) -> Self {
        let bits: wide::i32x8 = bytemuck::cast(self);
        bytemuck::cast((bits << 23) + wide::i32x8::splat(127 << 23))
    }
    #[inline(always)]
    fn and(a: Self, b: Self) -> Self {
        a & b
    }
}

/// Coefficients of x, x³, …, x¹¹ of atan(x) for |x| ≤ 1: an odd polynomial fitted
/// near-minimax on [0, 1] (|error| 1.7e-6 rad in exact arithmetic).
const ATAN: [f32; 6] = [
    0.999_977_2,
    -0.332_622_8,
    0.193_540_3,
    -0.116_426_4,
    0.052_647_2,
    -0.011_719_1,
];

/// Coefficients of z, z³, …, z⁹ of asin(z) for |z| ≤ ½ (near-minimax, 2e-8 rad in exact
/// arithmetic).
const ASIN: [f32; 5] = [1.000_000_5, 0.166_631, 0.075_761_8, 0.038_137, 0.053_321_7];

#[inline(always)]
fn atan_unit<L: Lanes>(x: L) -> L {
    let x2 = x * x;
    let c = |i: usize| L::splat(ATAN[i]);
    x * (c(0) + x2 * (c(1) + x2 * (c(2) + x2 * (c(3) + x2 * (c(4) + x2 * c(5))))))
}

/// `y.atan2(x)` lane by lane within 2e-5 rad (`atan_unit` after reduction to
/// |ratio| ≤ 1); 0 at the origin. The reductions are selects, not branches.
#[inline(always)]
pub fn atan2<L: Lanes>(y: L, x: L) -> L {
    let (ax, ay) = (x.abs(), y.abs());
    let steep = ay.gt(ax);
    let (num, den) = (L::select(steep, ax, ay), L::select(steep, ay, ax));
    let ratio = num / den.max(L::splat(f32::MIN_POSITIVE));
    let a = atan_unit(ratio);
    let a = L::select(steep, L::splat(FRAC_PI_2) - a, a);
    let a = L::select(x.lt(L::splat(0.0)), L::splat(PI) - a, a);
    a.copysign(y)
}

/// `x.clamp(-1, 1).asin()` lane by lane within 2e-5 rad: asin x = π/2 − 2·asin(√((1 − x)/2))
/// for x > ½ folds the range to |x| ≤ ½, where the odd polynomial `ASIN` holds. Both
/// forms are computed and one selected.
#[inline(always)]
pub fn asin<L: Lanes>(x: L) -> L {
    let a = x.abs().min(L::splat(1.0));
    let small = |z: L| {
        let z2 = z * z;
        let c = |i: usize| L::splat(ASIN[i]);
        z * (c(0) + z2 * (c(1) + z2 * (c(2) + z2 * (c(3) + z2 * c(4)))))
    };
    let folded =
        L::splat(FRAC_PI_2) - L::splat(2.0) * small(((L::splat(1.0) - a) * L::splat(0.5)).sqrt());
    L::select(a.gt(L::splat(0.5)), folded, small(a)).copysign(x)
}

/// `x.exp()` lane by lane for x ≤ 0 (the Gaussians of the sample kernel), within 1e-6
/// relative for x ≥ −87 and below 2e-38 beneath. Reduction e^x = 2ⁿ·e^g with n the
/// integer nearest x·log2 e and g = x − n·ln 2 (ln 2 in two parts, so that g is exact to
/// f32 rounding), |g| ≤ ln 2 / 2, where the Taylor polynomial of degree 6 is within 1.7e-7
/// (the next term, 0.347⁷/7!). Adding 1.5·2²³ rounds x·log2 e to that integer in the
/// float's last place (SSE2 has no vector round), and the sum's bits give 2ⁿ.
#[inline(always)]
pub fn exp<L: Lanes>(x: L) -> L {
    const SHIFT: f32 = 12_582_912.0;
    let x = x.max(L::splat(-87.0));
    let shifted = x * L::splat(std::f32::consts::LOG2_E) + L::splat(SHIFT);
    let n = shifted - L::splat(SHIFT);
    let g = x - n * L::splat(0.693_359_4) - n * L::splat(-2.121_944_4e-4);
    let c = |k: usize| L::splat(EXP[k]);
    let p = c(0) + g * (c(1) + g * (c(2) + g * (c(3) + g * (c(4) + g * (c(5) + g * c(6))))));
    p * shifted.pow2_of_shifted()
}

/// 1/k! for k = 0 … 6.
const EXP: [f32; 7] = [
    1.0,
    1.0,
    0.5,
    1.0 / 6.0,
    1.0 / 24.0,
    1.0 / 120.0,
    1.0 / 720.0,
];

#[cfg(test)]
mod tests {
    use super::*;
    use wide::f32x8;

    /// The eight-lane result of `f` on lanes `inputs`, checked lane by lane against the
    /// one-lane result (the batch and single lookups rely on their being identical).
    fn both(
        inputs: [[f32; 2]; 8],
        f8: fn(f32x8, f32x8) -> f32x8,
        f1: fn(f32, f32) -> f32,
    ) -> [f32; 8] {
        let lanes = f8(
            f32x8::new(inputs.map(|p| p[0])),
            f32x8::new(inputs.map(|p| p[1])),
        )
        .to_array();
        for (k, p) in inputs.iter().enumerate() {
            assert_eq!(
                lanes[k].to_bits(),
                f1(p[0], p[1]).to_bits(),
                "lane {k} at {p:?}"
            );
        }
        lanes
    }

    #[test]
    fn atan2_within_bound_everywhere() {
        let mut worst = 0.0f64;
        for i in 0..20_000 {
            let angle = -std::f64::consts::PI + std::f64::consts::TAU * i as f64 / 20_000.0;
            let radii = [1e-6, 0.3, 1.0, 7.0, 1e-3, 2.0, 0.5, 1e3];
            let inputs = radii.map(|r| [(r * angle.sin()) as f32, (r * angle.cos()) as f32]);
            let fast = both(inputs, atan2, atan2);
            for (k, [y, x]) in inputs.into_iter().enumerate() {
                let exact = (y as f64).atan2(x as f64);
                worst = worst.max((fast[k] as f64 - exact).abs());
            }
        }
        assert!(worst < 2e-5, "atan2 error {worst:e}");
        assert_eq!(atan2(0.0, 0.0), 0.0);
    }

    #[test]
    fn exp_within_bound_for_non_positive_arguments() {
        let mut worst = 0.0f64;
        for i in 0..=20_000 {
            let inputs: [[f32; 2]; 8] =
                std::array::from_fn(|k| [(-87.0 * (8 * i + k) as f64 / 160_007.0) as f32, 0.0]);
            let fast = both(inputs, |x, _| exp(x), |x, _| exp(x));
            for (k, [x, _]) in inputs.into_iter().enumerate() {
                let exact = (x as f64).exp();
                worst = worst.max((fast[k] as f64 - exact).abs() / exact);
            }
        }
        assert!(worst < 1e-6, "exp relative error {worst:e}");
        assert!(exp(-200.0f32) < 2e-38 && exp(0.0f32) == 1.0);
    }

    #[test]
    fn asin_within_bound_everywhere() {
        let mut worst = 0.0f64;
        for i in 0..=5_000 {
            let inputs: [[f32; 2]; 8] =
                std::array::from_fn(|k| [(-1.0 + 2.0 * (8 * i + k) as f64 / 40_007.0) as f32, 0.0]);
            let fast = both(inputs, |x, _| asin(x), |x, _| asin(x));
            for (k, [x, _]) in inputs.into_iter().enumerate() {
                worst = worst.max((fast[k] as f64 - (x as f64).asin()).abs());
            }
        }
        assert!(worst < 2e-5, "asin error {worst:e}");
        assert_eq!(asin(1.5), std::f32::consts::FRAC_PI_2);
    }
}
