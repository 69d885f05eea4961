//! Where `F(wi, wo)` can be non-zero for a given `wo`: the sampler's support
//! (docs/sampling.md#support).
//!
//! A tangent sample at offset α of thread j contributes only where both directions face it,
//! `w·n(α) > 0` with `n(α) = −sin α t0 + cos α z` (`ThreadModel::means`), and every term it
//! then adds is positive. Write `δ(w) = atan2(w·t0, w·z)`, so `w·n(α) = |w∥| cos(α + δ)`:
//! `wo` faces α for α in its window `W = (−π/2 − δo, π/2 − δo)`, and the thread adds to F
//! exactly when some α of its curve S_j lies in W and satisfies `δi ∈ (−π/2 − α, π/2 − α)`.
//! With `a = inf(S_j ∩ W)` and `A = sup(S_j ∩ W)`, the union of those intervals is
//! `δi ∈ (−π/2 − A, π/2 − a)` (intervals of length π whose offsets lie in a window of length
//! π overlap, so the union has no gap). Above the horizon δi ∈ (−π/2, π/2), so the thread's
//! set is the lune `L < δi < U`, `L = max(−π/2, −π/2 − A)`, `U = min(π/2, π/2 − a)`,
//! bounded by great circles through ±b; F's support is the union of the threads' lunes
//! (threads of zero coverage add nothing). Since W always holds α = 0, a thread whose curve
//! reaches 0 covers the whole hemisphere for every wo, which is every built-in fabric but
//! velvet.
//!
//! The cosine density restricted to a lune, `cos θ/π / m` on it: projected onto the disk
//! (Malley), `p = w·t0 = |w∥| sin δ` with `|w∥| = √(1 − q²)`, `q = w·b`, so the lune's
//! shadow is `p/√(1 − q²) ∈ (sin L, sin U)` and its area is `(sin U − sin L)·π/2`: the mass
//! is `m = (sin U − sin L)/2`. Uniform points of that shadow are uniform points of the disk
//! with `p/√(1 − q²)`, uniform on (−1, 1) given q, mapped affinely onto (sin L, sin U).

use super::direction_at_z;
use crate::model::curve::curve_pieces;
use crate::model::{Fabric, Integration, thread_axes};
use glam::DVec3;
use std::f64::consts::{FRAC_PI_2, PI, TAU};

/// The α intervals (radians, `start ≤ end`, a point where equal) of each thread's curve
/// that add to F; `None` where every wo's support is the whole hemisphere.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Support {
    curves: Option<[Vec<(f64, f64)>; 2]>,
}

/// One thread's lune `L < δ(w) < U` about its axis b, with (cos, sin) of both bounds and its
/// cosine-weighted mass.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Lune {
    pub thread: usize,
    pub lower: (f64, f64),
    pub upper: (f64, f64),
    pub mass: f64,
}

impl Lune {
    /// The whole hemisphere, L = −π/2 and U = π/2 (its thread does not matter).
    const WHOLE: Lune = Lune {
        thread: 0,
        lower: (0.0, -1.0),
        upper: (0.0, 1.0),
        mass: 1.0,
    };

    /// Whether `w` (w.z > 0) lies strictly inside: `sin(δ − L) > 0` and `sin(U − δ) > 0`.
    pub fn contains(&self, w: DVec3) -> bool {
        let p = w.dot(thread_axes(self.thread).0);
        p * self.lower.0 - w.z * self.lower.1 > 0.0 && w.z * self.upper.1 - p * self.upper.0 > 0.0
    }
}

/// F's support for one wo.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Lunes {
    /// The whole upper hemisphere.
    Everywhere,
    /// The union of these lunes (one or two; none: F is 0 for every wi).
    Some([Option<Lune>; 2]),
}

impl Lunes {
    /// Whether `w` (w.z > 0) is in the support.
    pub fn contains(&self, w: DVec3) -> bool {
        match self {
            Lunes::Everywhere => true,
            Lunes::Some(lunes) => lunes.iter().flatten().any(|l| l.contains(w)),
        }
    }

    /// The cosine density restricted to the support: cos θ/π times the number of lunes
    /// holding w over their total mass (a mixture of each lune's restricted cosine density,
    /// each picked with its mass).
    pub fn cosine_pdf(&self, w: DVec3) -> f64 {
        match self {
            Lunes::Everywhere => w.z / PI,
            Lunes::Some(lunes) => {
                let total: f64 = lunes.iter().flatten().map(|l| l.mass).sum();
                let holding = lunes.iter().flatten().filter(|l| l.contains(w)).count();
                if total > 0.0 && holding > 0 {
                    w.z / PI * holding as f64 / total
                } else {
                    0.0
                }
            }
        }
    }

    /// A draw of [`Self::cosine_pdf`] from `u` (u[0], u[1] place the point, `pick` in [0, 1)
    /// the lune); `None` where the support is empty.
    pub fn sample_cosine(&self, u: [f64; 2], pick: f64) -> Option<DVec3> {
        // Malley's method: z² uniform, the azimuth uniform.
        let disk = direction_at_z((1.0 - u[0]).sqrt(), u[1] * TAU);
        let lunes = match self {
            Lunes::Everywhere => return Some(disk),
            Lunes::Some(lunes) => lunes,
        };
        let total: f64 = lunes.iter().flatten().map(|l| l.mass).sum();
        let mut chosen = None;
        let mut pick = pick * total;
        for lune in lunes.iter().flatten() {
            chosen = Some(lune);
            if pick < lune.mass {
                break;
            }
            pick -= lune.mass;
        }
        let lune = chosen.filter(|_| total > 0.0)?;
        let (t0, b) = thread_axes(lune.thread);
        let (p, q) = (disk.dot(t0), disk.dot(b));
        let h = (1.0 - q * q).max(0.0).sqrt();
        let s = if h > 0.0 {
            (p / h).clamp(-1.0, 1.0)
        } else {
            0.0
        };
        let p = h * (lune.lower.1 + 0.5 * (s + 1.0) * (lune.upper.1 - lune.lower.1));
        let z = (1.0 - p * p - q * q).max(0.0).sqrt();
        Some(t0 * p + b * q + DVec3::Z * z)
    }
}

impl Support {
    /// No restriction: the sampler of an F known only by its values.
    pub fn everywhere() -> Self {
        Self { curves: None }
    }

    /// The support of `fabric`'s F: its threads' curves as the model integrates them (the
    /// direct rule's intervals, which the resonant and baking rules share and the paper
    /// rule's points lie in).
    pub fn of_fabric(fabric: &Fabric) -> Self {
        let curves = [0, 1].map(|j| {
            let thread = fabric.threads()[j];
            if thread.coverage <= 0.0 {
                return Vec::new();
            }
            curve_pieces(thread, &fabric.options, Integration::Direct)
                .iter()
                .filter(|p| p.weight > 0.0)
                .map(|p| (p.start, p.end))
                .collect::<Vec<_>>()
        });
        let reaches_zero =
            |curve: &Vec<(f64, f64)>| curve.iter().any(|&(s, e)| s <= 0.0 && 0.0 <= e);
        if curves.iter().any(reaches_zero) {
            return Self::everywhere();
        }
        Self {
            curves: Some(curves),
        }
    }

    /// The intervals of thread `j` (for the GPU's copy), empty when unrestricted.
    pub fn curve(&self, j: usize) -> &[(f64, f64)] {
        self.curves.as_ref().map_or(&[], |c| &c[j])
    }

    /// Whether every wo's support is the whole hemisphere.
    pub fn is_everywhere(&self) -> bool {
        self.curves.is_none()
    }

    /// F's support for `wo` (wo.z > 0).
    pub fn lunes(&self, wo: DVec3) -> Lunes {
        let Some(curves) = &self.curves else {
            return Lunes::Everywhere;
        };
        let lunes = [0, 1].map(|j| {
            let t0 = thread_axes(j).0;
            let delta = wo.dot(t0).atan2(wo.z);
            let (window_lo, window_hi) = (-FRAC_PI_2 - delta, FRAC_PI_2 - delta);
            let (mut a, mut big_a) = (f64::INFINITY, f64::NEG_INFINITY);
            for &(s, e) in &curves[j] {
                let (lo, hi) = (s.max(window_lo), e.min(window_hi));
                let meets = if s == e {
                    window_lo < s && s < window_hi
                } else {
                    lo < hi
                };
                if meets {
                    a = a.min(lo);
                    big_a = big_a.max(hi);
                }
            }
            if a > big_a {
                return None;
            }
            if a <= 0.0 && big_a >= 0.0 {
                return Some(Lune::WHOLE);
            }
            let lower = (-FRAC_PI_2 - big_a).max(-FRAC_PI_2);
            let upper = (FRAC_PI_2 - a).min(FRAC_PI_2);
            let (sin_l, cos_l) = lower.sin_cos();
            let (sin_u, cos_u) = upper.sin_cos();
            Some(Lune {
                thread: j,
                lower: (cos_l, sin_l),
                upper: (cos_u, sin_u),
                mass: 0.5 * (sin_u - sin_l),
            })
        });
        if lunes.contains(&Some(Lune::WHOLE)) {
            Lunes::Everywhere
        } else {
            Lunes::Some(lunes)
        }
    }
}
