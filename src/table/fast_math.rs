//! Fast f32 approximations of the transcendental functions of the table lookups, with the
//! error bounds their tests measure. A texel of any layout spans at least 0.1° (1.7e-3
//! rad), so an angle error of 2e-5 rad moves a lookup by at most about 1% of a texel, far
//! below the interpolation error.

use std::f32::consts::{FRAC_PI_2, PI};

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

#[inline(always)]
fn atan_unit(x: f32) -> f32 {
    let x2 = x * x;
    x * (ATAN[0] + x2 * (ATAN[1] + x2 * (ATAN[2] + x2 * (ATAN[3] + x2 * (ATAN[4] + x2 * ATAN[5])))))
}

/// `y.atan2(x)` within 2e-5 rad (`atan_unit` after reduction to |ratio| ≤ 1); 0 at the
/// origin. Branch-free: the reductions are selects, so the compiler can interleave
/// several calls.
#[inline(always)]
pub fn atan2(y: f32, x: f32) -> f32 {
    let (ax, ay) = (x.abs(), y.abs());
    let steep = ay > ax;
    let (num, den) = if steep { (ax, ay) } else { (ay, ax) };
    let ratio = num / den.max(f32::MIN_POSITIVE);
    let a = atan_unit(ratio);
    let a = if steep { FRAC_PI_2 - a } else { a };
    let a = if x < 0.0 { PI - a } else { a };
    a.copysign(y)
}

/// `x.clamp(-1, 1).asin()` within 2e-5 rad: asin x = π/2 − 2·asin(√((1 − x)/2)) for
/// x > ½ folds the range to |x| ≤ ½, where an odd polynomial of degree 9 (fitted
/// near-minimax, 2e-8 rad in exact arithmetic) holds.
#[inline(always)]
pub fn asin(x: f32) -> f32 {
    let a = x.abs().min(1.0);
    let small = |z: f32| {
        let z2 = z * z;
        z * (1.000_000_5
            + z2 * (0.166_631 + z2 * (0.075_761_8 + z2 * (0.038_137 + z2 * 0.053_321_7))))
    };
    let r = if a > 0.5 {
        FRAC_PI_2 - 2.0 * small(((1.0 - a) * 0.5).sqrt())
    } else {
        small(a)
    };
    r.copysign(x)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn atan2_within_bound_everywhere() {
        let mut worst = 0.0f64;
        for i in 0..20_000 {
            let angle = -std::f64::consts::PI + std::f64::consts::TAU * i as f64 / 20_000.0;
            for r in [1e-6, 0.3, 1.0, 7.0] {
                let (y, x) = ((r * angle.sin()) as f32, (r * angle.cos()) as f32);
                let exact = (y as f64).atan2(x as f64);
                worst = worst.max((atan2(y, x) as f64 - exact).abs());
            }
        }
        assert!(worst < 2e-5, "atan2 error {worst:e}");
        assert_eq!(atan2(0.0, 0.0), 0.0);
    }

    #[test]
    fn asin_within_bound_everywhere() {
        let mut worst = 0.0f64;
        for i in 0..=40_000 {
            let x = -1.0 + 2.0 * i as f64 / 40_000.0;
            worst = worst.max((asin(x as f32) as f64 - (x as f32 as f64).asin()).abs());
        }
        assert!(worst < 2e-5, "asin error {worst:e}");
        assert_eq!(asin(1.5), std::f32::consts::FRAC_PI_2);
    }
}
