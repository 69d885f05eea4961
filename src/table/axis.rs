//! Table axes: how a texel index maps to a coordinate value and back, including warps that
//! put texels where the function needs them.
//!
//! Texel convention: a clamped axis of N texels holds the function at `x_i = i/(N−1)`, both
//! ends included (ends are evaluated at their limits); a GPU samples it at texture
//! coordinate `(x·(N−1) + ½)/N` with clamp-to-edge. A periodic axis holds `x_i = i/N`
//! (GPU: `(x·N + ½)/N`, repeat addressing). `x ∈ [0, 1]` is the warped coordinate of the
//! value `v` (see [`Warp`]).

use super::fast_math::Lanes;

/// The map between an axis value v and its unit coordinate x ∈ [0, 1].
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Warp {
    /// `v = lo + (hi − lo)·x`.
    Linear { lo: f64, hi: f64 },
    /// Piecewise linear through four knots `(x_k, v_k)`, increasing, `x_0 = 0`, `x_3 = 1`.
    Knots { xs: [f64; 4], vs: [f64; 4] },
    /// `v = hi·sin(k(2x − 1))/sin k`, symmetric on [−hi, hi], denser towards ±hi as k grows
    /// (k → 0 is linear).
    SinEnds { hi: f64, k: f64 },
}

impl Warp {
    pub fn value(&self, x: f64) -> f64 {
        match *self {
            Warp::Linear { lo, hi } => lo + (hi - lo) * x,
            Warp::Knots { xs, vs } => {
                let k = (0..2).find(|&k| x <= xs[k + 1]).unwrap_or(2);
                vs[k] + (vs[k + 1] - vs[k]) * (x - xs[k]) / (xs[k + 1] - xs[k])
            }
            Warp::SinEnds { hi, k } => hi * (k * (2.0 * x - 1.0)).sin() / k.sin(),
        }
    }

    pub fn unit(&self, v: f64) -> f64 {
        match *self {
            Warp::Linear { lo, hi } => (v - lo) / (hi - lo),
            Warp::Knots { xs, vs } => {
                let k = (0..2).find(|&k| v <= vs[k + 1]).unwrap_or(2);
                xs[k] + (xs[k + 1] - xs[k]) * (v - vs[k]) / (vs[k + 1] - vs[k])
            }
            Warp::SinEnds { hi, k } => {
                let s = (v / hi * k.sin()).clamp(-1.0, 1.0);
                0.5 * (s.asin() / k + 1.0)
            }
        }
    }
}

/// One table axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Axis {
    pub texels: usize,
    pub periodic: bool,
    pub warp: Warp,
}

impl Axis {
    pub fn clamped(texels: usize, warp: Warp) -> Self {
        Self {
            texels,
            periodic: false,
            warp,
        }
    }

    pub fn periodic(texels: usize, lo: f64, hi: f64) -> Self {
        Self {
            texels,
            periodic: true,
            warp: Warp::Linear { lo, hi },
        }
    }

    /// The value texel `i` holds.
    pub fn texel_value(&self, i: usize) -> f64 {
        let x = if self.periodic {
            i as f64 / self.texels as f64
        } else {
            i as f64 / (self.texels - 1) as f64
        };
        self.warp.value(x)
    }

    /// The two texels around value `v` and the weight of the second, as linear filtering
    /// with this axis's addressing computes them.
    #[inline]
    pub fn locate(&self, v: f64) -> (usize, usize, f64) {
        let x = self.warp.unit(v);
        let n = self.texels;
        if self.periodic {
            let g = x * n as f64;
            let f = g.floor();
            let i0 = (f as i64).rem_euclid(n as i64) as usize;
            (i0, (i0 + 1) % n, g - f)
        } else {
            let g = (x * (n - 1) as f64).clamp(0.0, (n - 1) as f64);
            let i0 = (g.floor() as usize).min(n.saturating_sub(2));
            (i0, (i0 + 1).min(n - 1), g - i0 as f64)
        }
    }
}

/// An [`Axis`] prepared for f32 lookups: the warp's constant factors folded as the WGSL
/// warp functions fold them (`shaders/table/thread_geometry.wgsl`), so that a lookup is a few
/// multiplications (and one fast asin for `SinEnds`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AxisF32 {
    warp: WarpF32,
    /// N − 1.
    last: f32,
    /// The largest first index of a pair, N − 2 (0 for a single texel).
    last_pair: usize,
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum WarpF32 {
    /// g = (v − lo)·scale.
    Linear { lo: f32, scale: f32 },
    /// Piece k: g = gs[k] + (v − vs[k])·slopes[k].
    Knots {
        vs: [f32; 4],
        gs: [f32; 3],
        slopes: [f32; 3],
    },
    /// g = (asin(v·c)/k + 1)·½(N − 1), folded as asin(v·c)·scale + ½(N − 1).
    SinEnds { c: f32, scale: f32 },
}

impl AxisF32 {
    /// The clamped `axis` in f32 (periodic axes have no f32 lookup).
    pub fn new(axis: &Axis) -> Self {
        assert!(!axis.periodic, "f32 lookups use clamped axes");
        let last = (axis.texels - 1) as f64;
        let warp = match axis.warp {
            Warp::Linear { lo, hi } => WarpF32::Linear {
                lo: lo as f32,
                scale: (last / (hi - lo)) as f32,
            },
            Warp::Knots { xs, vs } => WarpF32::Knots {
                vs: vs.map(|v| v as f32),
                gs: std::array::from_fn(|k| (xs[k] * last) as f32),
                slopes: std::array::from_fn(|k| {
                    ((xs[k + 1] - xs[k]) * last / (vs[k + 1] - vs[k])) as f32
                }),
            },
            Warp::SinEnds { hi, k } => WarpF32::SinEnds {
                c: (k.sin() / hi) as f32,
                scale: (0.5 * last / k) as f32,
            },
        };
        Self {
            warp,
            last: last as f32,
            last_pair: axis.texels.saturating_sub(2),
        }
    }

    /// [`Axis::locate`] in f32, lane by lane: the first texel of the interpolated pair and
    /// the fraction towards the next.
    #[inline(always)]
    pub fn locate<L: Lanes>(&self, v: L) -> (L::Indices, L::Values) {
        let splat = L::splat;
        let g = match self.warp {
            WarpF32::Linear { lo, scale } => (v - splat(lo)) * splat(scale),
            WarpF32::Knots { vs, gs, slopes } => {
                let (first, second) = (v.le(splat(vs[1])), v.le(splat(vs[2])));
                let pick = |a: [f32; 3]| {
                    L::select(
                        first,
                        splat(a[0]),
                        L::select(second, splat(a[1]), splat(a[2])),
                    )
                };
                pick(gs) + (v - pick([vs[0], vs[1], vs[2]])) * pick(slopes)
            }
            WarpF32::SinEnds { c, scale } => {
                super::fast_math::asin(v * splat(c)) * splat(scale) + splat(0.5 * self.last)
            }
        };
        // g ≥ 0 after the clamp: truncation is the floor.
        g.max(splat(0.0))
            .min(splat(self.last))
            .split_floor(self.last_pair as i32)
    }

    /// The WGSL value of `axis` as `cloth_axis_texel` of `shaders/table/thread_geometry.wgsl`
    /// takes it (a `ClothAxis`: its warp's kind and folded constants, N − 1), and a comment
    /// describing the axis.
    pub fn wgsl_axis(axis: &Axis) -> (String, String) {
        use super::wgsl::{wgsl_f32, wgsl_vec};
        let folded = Self::new(axis);
        let zero = || wgsl_vec(&[0.0f32; 3]);
        let (kind, p, gs, slopes, about) = match (axis.warp, folded.warp) {
            (Warp::Linear { lo, hi }, WarpF32::Linear { scale, .. }) => (
                0,
                wgsl_vec(&[lo as f32, scale, 0.0]),
                zero(),
                zero(),
                format!("Linear [{lo:.6}, {hi:.6}], {} texels", axis.texels),
            ),
            (Warp::Knots { xs, vs }, WarpF32::Knots { gs, slopes, .. }) => (
                1,
                wgsl_vec(&vs[..3]),
                wgsl_vec(&gs),
                wgsl_vec(&slopes),
                format!("Knots xs {:.6?}, vs {:.6?}, {} texels", xs, vs, axis.texels),
            ),
            (Warp::SinEnds { hi, k }, WarpF32::SinEnds { c, scale }) => (
                2,
                wgsl_vec(&[c, scale, 0.0]),
                zero(),
                zero(),
                format!("SinEnds hi {hi:.6}, k {k}, {} texels", axis.texels),
            ),
            _ => unreachable!("the f32 warp follows the warp"),
        };
        (
            format!(
                "ClothAxis({kind}u, {p}, {gs}, {slopes}, {})",
                wgsl_f32(folded.last)
            ),
            about,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn warps_invert() {
        let warps = [
            Warp::Linear { lo: -1.0, hi: 2.0 },
            Warp::Knots {
                xs: [0.0, 0.2, 0.9, 1.0],
                vs: [-1.5, -0.5, 0.3, 1.5],
            },
            Warp::SinEnds { hi: 1.5, k: 1.4 },
        ];
        for w in warps {
            for i in 0..=20 {
                let x = i as f64 / 20.0;
                assert!((w.unit(w.value(x)) - x).abs() < 1e-12, "{w:?} at {x}");
            }
        }
    }

    #[test]
    fn locate_hits_texel_values() {
        let axis = Axis::clamped(7, Warp::SinEnds { hi: 1.5, k: 1.4 });
        for i in 0..7 {
            let (i0, i1, f) = axis.locate(axis.texel_value(i));
            assert!((i0 as f64 + f - i as f64).abs() < 1e-9 && i1 == (i0 + 1).min(6));
        }
        let ring = Axis::periodic(8, -4.0, 4.0);
        assert_eq!(ring.locate(3.5), (7, 0, 0.5));
    }
}
