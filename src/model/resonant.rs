//! The resonant quadrature: the curve means `⟨s⟩_j`, `⟨P⟩_j` of
//! docs/model.md#coverage-and-normalisation from a few dozen tangent samples per light, placed
//! where each term of the integrand lives.
//!
//! Over a curve segment the density of tangent offsets α is constant, and the integrand
//! splits (see `SampleTerms`) into a surface part that follows `g(γs, θh(α))`, a volume part
//! that follows `g(γv, θh(α))`, and a lobe-free part (`⟨P⟩` and the kd term of
//! transmission). Inside the facing window (both `wi·n(α) > 0` and `wo·n(α) > 0`, where
//! the integrand lives) θh is monotone in α with slope `dθh/dα = (cos φi + cos φo)/2 > 0`
//! (since `d sin θ/dα = w·n` and `cos θ = |w⊥|`), and it vanishes at the resonant offset
//! `α* = −atan2(h·t0, h·z)`, h = wi + wo (h·t(α*) = 0 means θi = −θo).
//!
//! Per segment, clipped to the facing window:
//! - **Lobe nodes.** θh is linearised at the point `αc` of the segment nearest to α*
//!   (where the lobe is largest): `z(α) = (θh(αc) + k (α − αc)) / σ`. Substituting
//!   `t = Φ(z)` (Φ the standard normal CDF) turns the Gaussian factor into a near-constant,
//!   `g(θh) dα = (σ/k) g(θh) / φ(z) dt` with `g(θh)/φ(z) ≈ 1/σ`, and Gauss–Legendre nodes
//!   in t over `[Φ(z(lo)), Φ(z(hi))]` integrate what is left, a smooth function, with no
//!   truncation of the lobe at the segment's ends. θh's curvature only makes the ratio
//!   deviate from 1, smoothly. A lobe that is at most `FLAT_LOBE_SPAN` standard
//!   deviations across the segment is smooth there and is integrated on the base nodes,
//!   with as many of them as the lobe would have had; one whose nearest point is more than
//!   `NEGLIGIBLE_LOBE_Z` deviations away is dropped (`g` there is below 1e-8 of its peak).
//! - **Base nodes.** Gauss–Legendre in α over the clipped segment for `P` and the kd term.
//! - **Kinks.** The reweighted products `(1 − u)·a·b + u·min(a, b)` of M and P have kinks
//!   where their two factors cross (see `kinks`); both node sets are split there, each
//!   part getting its share of the nodes (at least [`MIN_NODES_PER_PART`]). Where a
//!   direction is near the horizon the facing window is a sliver a few degrees wide, the
//!   lobes are flat across it and the kinks decide the integral: unsplit, one such pair
//!   carried most of satin back's squared error.
//! - A flat segment (all of its share at one α, e.g. satin's floats) is one node for every
//!   term.

use super::curve::{CurvePiece, ResonantNodes};
use super::sample::{PairInThreadFrame, SampleTerms, ThreadMeans, half_angle_and_difference};
use std::f64::consts::{FRAC_1_SQRT_2, PI};

/// A lobe that spans at most this many standard deviations across a (clipped) segment is
/// integrated on the base nodes, their count raised to the lobe's: over so short a stretch
/// the Gaussian is a smooth, low-order function of α, and one node set serves every term.
/// Only lobes that are narrow against the segment get nodes of their own in t = Φ(z).
/// Larger values save evaluations per light and lose nothing up to about 5; beyond that
/// crepe and silk_shot lose accuracy (the surface lobe on too few nodes).
pub const FLAT_LOBE_SPAN: f64 = 4.0;
/// A lobe whose value within a segment is nowhere above `g` at this many standard
/// deviations (e^−18 ≈ 1.5e-8 of its peak) contributes nothing measurable there.
pub const NEGLIGIBLE_LOBE_Z: f64 = 6.0;

/// Fewest nodes a part of a lobe's or the base's interval gets when kinks split it (or all
/// of the count, if smaller). With one node, crepe's and silk_shot's
/// highlight errors grow; two cost one to two more evaluations per light.
pub const MIN_NODES_PER_PART: u32 = 2;

/// How far above a whole number a part's share of nodes must be to get one more (see
/// `split_counts`); far above f32 rounding, far below any share that matters.
pub const SPLIT_TOLERANCE: f64 = 1e-3;

/// Lobe nodes stay within this many standard deviations of the peak: beyond it the Gaussian
/// holds 1e-15 of its mass, and in f64 Φ and φ underflow further out (φ(38) = 0), which
/// would turn the weights into 0/0.
pub const LOBE_Z_RANGE: f64 = 8.0;

/// A segment holding less than this share of a lobe's Gaussian mass (the lobe's tail, or a
/// sliver of it) gets half of the lobe's nodes, and one holding less than an eighth of it a
/// quarter: its error weighs in proportion to its mass. The share is the largest that
/// leaves every built-in fabric's error where it was.
pub const TAIL_MASS: f64 = 0.15;

/// Gauss–Legendre nodes and weights on [0, 1] (weights sum to 1).
#[derive(Clone, Debug, PartialEq)]
pub struct GaussLegendre {
    pub nodes: Vec<f64>,
    pub weights: Vec<f64>,
}

impl GaussLegendre {
    /// The n-point rule: the roots of the Legendre polynomial P_n by Newton's method from
    /// the asymptotic guesses `cos(π(i + 3/4)/(n + 1/2))`, weights `2/((1 − x²) P_n'(x)²)`,
    /// both mapped from [−1, 1] to [0, 1].
    pub fn new(n: usize) -> Self {
        let mut nodes = Vec::with_capacity(n);
        let mut weights = Vec::with_capacity(n);
        for i in 0..n {
            let mut x = (PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
            let mut derivative = 1.0;
            for _ in 0..100 {
                // P_n(x) and P_{n-1}(x) by the three-term recurrence.
                let (mut p_prev, mut p) = (1.0, x);
                for k in 2..=n {
                    let k = k as f64;
                    (p_prev, p) = (p, ((2.0 * k - 1.0) * x * p - (k - 1.0) * p_prev) / k);
                }
                if n == 1 {
                    (p_prev, p) = (1.0, x);
                }
                derivative = n as f64 * (x * p - p_prev) / (x * x - 1.0);
                let step = p / derivative;
                x -= step;
                if step.abs() < 1e-16 {
                    break;
                }
            }
            nodes.push(0.5 * (1.0 - x));
            weights.push(1.0 / ((1.0 - x * x) * derivative * derivative));
        }
        Self { nodes, weights }
    }
}

/// The standard normal density φ(z).
fn normal_pdf(z: f64) -> f64 {
    (-0.5 * z * z).exp() / (2.0 * PI).sqrt()
}

/// The standard normal CDF Φ(z), accurate in relative terms in the lower tail.
fn normal_cdf(z: f64) -> f64 {
    0.5 * libm::erfc(-z * FRAC_1_SQRT_2)
}

/// Φ⁻¹(p) for p in (0, 1): Acklam's rational approximation, relative error below 1.2e-9.
/// The quadrature only needs nodes and weights that agree with each other: a node moved by
/// that much, weighted by φ at the node, changes a lobe integral by about as little.
fn normal_quantile(p: f64) -> f64 {
    const A: [f64; 6] = [
        -3.969_683_028_665_376e1,
        2.209_460_984_245_205e2,
        -2.759_285_104_469_687e2,
        1.383_577_518_672_69e2,
        -3.066_479_806_614_716e1,
        2.506_628_277_459_239,
    ];
    const B: [f64; 5] = [
        -5.447_609_879_822_406e1,
        1.615_858_368_580_409e2,
        -1.556_989_798_598_866e2,
        6.680_131_188_771_972e1,
        -1.328_068_155_288_572e1,
    ];
    const C: [f64; 6] = [
        -7.784_894_002_430_293e-3,
        -3.223_964_580_411_365e-1,
        -2.400_758_277_161_838,
        -2.549_732_539_343_734,
        4.374_664_141_464_968,
        2.938_163_982_698_783,
    ];
    const D: [f64; 4] = [
        7.784_695_709_041_462e-3,
        3.224_671_290_700_398e-1,
        2.445_134_137_142_996,
        3.754_408_661_907_416,
    ];
    const P_LOW: f64 = 0.02425;
    let tail = |q: f64| {
        let r = (-2.0 * q.ln()).sqrt();
        (((((C[0] * r + C[1]) * r + C[2]) * r + C[3]) * r + C[4]) * r + C[5])
            / ((((D[0] * r + D[1]) * r + D[2]) * r + D[3]) * r + 1.0)
    };
    if p < P_LOW {
        tail(p)
    } else if p > 1.0 - P_LOW {
        -tail(1.0 - p)
    } else {
        let q = p - 0.5;
        let r = q * q;
        (((((A[0] * r + A[1]) * r + A[2]) * r + A[3]) * r + A[4]) * r + A[5]) * q
            / (((((B[0] * r + B[1]) * r + B[2]) * r + B[3]) * r + B[4]) * r + 1.0)
    }
}

/// θh at tangent offset α (given by its cosine and sine) and its slope dθh/dα =
/// (cos φi + cos φo)/2, without the rest of the sample.
fn theta_h_and_slope(pair: &PairInThreadFrame, cos_a: f64, sin_a: f64) -> (f64, f64) {
    // (|w⊥|, w·t(α)) and cos φ of one direction.
    let frame = |t0: f64, z: f64, b: f64| {
        let n = z * cos_a - t0 * sin_a;
        let s = t0 * cos_a + z * sin_a;
        let perp = (n * n + b * b).sqrt();
        let cos_phi = if perp > 0.0 { n / perp } else { 0.0 };
        ((perp, s), cos_phi)
    };
    let (i, cos_phi_i) = frame(pair.ti0, pair.zi, pair.bi);
    let (o, cos_phi_o) = frame(pair.to0, pair.zo, pair.bo);
    let (theta_h, _) = half_angle_and_difference(i, o);
    (theta_h, 0.5 * (cos_phi_i + cos_phi_o))
}

/// Which terms a node adds to the means.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Terms {
    reflection: bool,
    volume: bool,
    base: bool,
}

/// What one resonant evaluation of a thread cost: its kernel evaluations (tangent samples
/// whose terms were computed). Placing the nodes costs besides, per clipped segment, θh and
/// its slope at one point (two atan2), and per lobe node Φ⁻¹ and φ; the report's timings
/// include all of it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ResonantCost {
    pub samples: usize,
}

/// The resonant rule of one thread, prepared once: its Gauss–Legendre rules and lobe widths.
#[derive(Clone, Debug, PartialEq)]
pub struct ResonantRule {
    nodes: ResonantNodes,
    /// `gauss_legendre[n - 1]` is the n-point rule, n = 1..=[`ResonantNodes::MAX`].
    gauss_legendre: Vec<GaussLegendre>,
    /// Lobe standard deviations in radians (surface, volume).
    sigma: [f64; 2],
}

/// The nodes a part holding `fraction` of an interval gets out of the interval's `n`: its
/// share rounded up, so the density never drops, and at least [`MIN_NODES_PER_PART`].
/// A share within [`SPLIT_TOLERANCE`] of a whole number is not rounded up: on highlight and
/// mirrored pairs a kink sits at the lobe's median, the share is n/2 exactly, and rounding
/// noise (f64 here, f32 in the shader) would otherwise pick the count.
fn split_counts(n: u32, fraction: f64) -> usize {
    ((n as f64 * fraction - SPLIT_TOLERANCE).ceil() as usize)
        .clamp(MIN_NODES_PER_PART.min(n) as usize, n as usize)
}

impl ResonantRule {
    pub fn new(nodes: ResonantNodes, sigma_s: f64, sigma_v: f64) -> Self {
        Self {
            nodes,
            gauss_legendre: (1..=ResonantNodes::MAX as usize)
                .map(GaussLegendre::new)
                .collect(),
            sigma: [sigma_s, sigma_v],
        }
    }

    fn rule(&self, n: usize) -> &GaussLegendre {
        &self.gauss_legendre[n - 1]
    }

    /// The curve means of a thread for `pair`, whose facing window is `facing` (α interval
    /// where both directions face the tangent sample), and what they cost: the thread's
    /// quadrature `pieces` (with (cos, sin) of their start), and `sample`, its terms at the
    /// tangent sample of (cos α, sin α).
    pub(crate) fn means(
        &self,
        pieces: &[(CurvePiece, f64, f64)],
        sample: impl Fn(f64, f64) -> Option<SampleTerms>,
        pair: &PairInThreadFrame,
        facing: (f64, f64),
    ) -> (ThreadMeans, ResonantCost) {
        let mut sums = ThreadMeans::default();
        let mut cost = ResonantCost::default();
        let mut add = |alpha: f64, weight: f64, terms: Terms| {
            cost.samples += 1;
            let (sin_a, cos_a) = alpha.sin_cos();
            if let Some(s) = sample(cos_a, sin_a) {
                add_terms(&mut sums, &s, weight, terms);
            }
        };
        let resonant = -(pair.ti0 + pair.to0).atan2(pair.zi + pair.zo);
        let kinks = kinks(pair, facing);
        for &(piece, _, _) in pieces {
            if piece.start == piece.end {
                if piece.start > facing.0 && piece.start < facing.1 {
                    add(piece.start, piece.weight, Terms::ALL);
                }
                continue;
            }
            let (lo, hi) = (piece.start.max(facing.0), piece.end.min(facing.1));
            if lo >= hi {
                continue;
            }
            let segment = Segment {
                lo,
                hi,
                density: piece.weight / (piece.end - piece.start),
                cuts: &kinks,
            };
            self.segment(&segment, resonant, pair, &mut add);
        }
        (sums, cost)
    }

    /// Places the nodes of one clipped segment.
    fn segment(
        &self,
        segment: &Segment,
        resonant: f64,
        pair: &PairInThreadFrame,
        add: &mut impl FnMut(f64, f64, Terms),
    ) {
        let &Segment {
            lo, hi, density, ..
        } = segment;
        let centre = resonant.clamp(lo, hi);
        let (sin_c, cos_c) = centre.sin_cos();
        let (theta_c, slope) = theta_h_and_slope(pair, cos_c, sin_c);
        // Per lobe: on the base nodes (smooth over the segment), dropped, or its own nodes.
        let mut on_base = [false; 2];
        for (lobe, n) in [self.nodes.surface, self.nodes.volume]
            .into_iter()
            .enumerate()
        {
            let sigma = self.sigma[lobe];
            let z = |alpha: f64| (theta_c + slope * (alpha - centre)) / sigma;
            let (z_lo, z_hi) = (z(lo), z(hi));
            if slope <= 0.0 || z_hi - z_lo <= FLAT_LOBE_SPAN {
                on_base[lobe] = true;
                continue;
            }
            if theta_c.abs() / sigma > NEGLIGIBLE_LOBE_Z {
                continue;
            }
            let terms = Terms {
                reflection: lobe == 0,
                volume: lobe == 1,
                base: false,
            };
            // Work in the lower tail, where Φ keeps its relative accuracy: reflect the
            // segment when it lies wholly above the peak.
            let sign = if z_lo > 0.0 { -1.0 } else { 1.0 };
            let t = |alpha: f64| normal_cdf((sign * z(alpha)).clamp(-LOBE_Z_RANGE, LOBE_Z_RANGE));
            let (t_lo, t_hi) = if sign > 0.0 {
                (t(lo), t(hi))
            } else {
                (t(hi), t(lo))
            };
            let mass = t_hi - t_lo;
            // The lobe's mass in the segment sets how many of its nodes the segment gets.
            let n = if mass < TAIL_MASS / 8.0 {
                n.div_ceil(4)
            } else if mass < TAIL_MASS {
                n.div_ceil(2)
            } else {
                n
            };
            let mut cuts_t = Cuts::default();
            for cut in segment.inner_cuts() {
                cuts_t.push(t(cut));
            }
            cuts_t.sort();
            for (a, b) in parts(t_lo, t_hi, cuts_t.as_slice()) {
                if b <= a {
                    continue;
                }
                let rule = self.rule(split_counts(n, (b - a) / mass));
                for (&x, &w) in rule.nodes.iter().zip(&rule.weights) {
                    let zn = sign * normal_quantile(a + (b - a) * x);
                    let alpha = centre + (sigma * zn - theta_c) / slope;
                    // dα = (σ/k) dz and dz = dt/φ(z).
                    let weight = density * w * (b - a) * sigma / (slope * normal_pdf(zn));
                    add(alpha, weight, terms);
                }
            }
        }
        let terms = Terms {
            reflection: on_base[0],
            volume: on_base[1],
            base: true,
        };
        let mut cuts = Cuts::default();
        for cut in segment.inner_cuts() {
            cuts.push(cut);
        }
        // A lobe riding on the base nodes brings its node count with it.
        let mut count = self.nodes.base;
        if on_base[0] {
            count = count.max(self.nodes.surface);
        }
        if on_base[1] {
            count = count.max(self.nodes.volume);
        }
        for (a, b) in parts(lo, hi, cuts.as_slice()) {
            let rule = self.rule(split_counts(count, (b - a) / (hi - lo)));
            for (&x, &w) in rule.nodes.iter().zip(&rule.weights) {
                add(a + (b - a) * x, density * (b - a) * w, terms);
            }
        }
    }
}

/// A curve segment clipped to the facing window `[lo, hi]`, the density of the curve over
/// it, and where the integrand has kinks.
struct Segment<'a> {
    lo: f64,
    hi: f64,
    density: f64,
    cuts: &'a Cuts,
}

impl Segment<'_> {
    /// The kinks strictly inside the segment, in increasing α.
    fn inner_cuts(&self) -> impl Iterator<Item = f64> + '_ {
        self.cuts
            .as_slice()
            .iter()
            .copied()
            .filter(|&c| c > self.lo && c < self.hi)
    }
}

/// `[start, end]` cut at the increasing `cuts` (all inside it).
fn parts(start: f64, end: f64, cuts: &[f64]) -> impl Iterator<Item = (f64, f64)> + '_ {
    let ends = std::iter::once(start)
        .chain(cuts.iter().copied())
        .chain(std::iter::once(end));
    ends.clone().zip(ends.skip(1))
}

/// Where the reweighted products have the kinks of their `min`, in increasing α within the
/// facing window. Quadrature across a kink converges slowly; where the window is a sliver
/// (a direction near the horizon) these kinks decide the integral.
///
/// - P: `P(w) = w·n/|w∥| = cos(α + δ)`, so `P(wi) = P(wo)` at the window's centre
///   `α = −(δi + δo)/2`.
/// - M: `M(w) = w·n/|w⊥|` with `|w⊥|² = (w·n)² + (w·b)²` is increasing in `(w·n)/|w·b|`, so
///   `M(wi) = M(wo)` where `|wo·b| (wi·n) = |wi·b| (wo·n)`. With `w·n = (w·z) cos α − (w·t0)
///   sin α` that is `tan α = (|bo| zi − |bi| zo) / (|bo| ti0 − |bi| to0)`.
fn kinks(pair: &PairInThreadFrame, facing: (f64, f64)) -> Cuts {
    let centre = 0.5 * (facing.0 + facing.1);
    let (bi, bo) = (pair.bi.abs(), pair.bo.abs());
    let m = ((bo * pair.zi - bi * pair.zo) / (bo * pair.ti0 - bi * pair.to0)).atan();
    let mut kinks = Cuts::default();
    kinks.push(centre);
    // The facing window is narrower than π, so at most one of these lies inside it.
    for a in [m - PI, m, m + PI] {
        if a > facing.0 && a < facing.1 && a != centre {
            kinks.push(a);
        }
    }
    kinks.sort();
    kinks
}

/// At most [`Cuts::CAPACITY`] increasing cut points, without allocating.
#[derive(Clone, Copy, Debug, Default)]
struct Cuts {
    values: [f64; Cuts::CAPACITY],
    len: usize,
}

impl Cuts {
    const CAPACITY: usize = 2;

    fn push(&mut self, value: f64) {
        self.values[self.len] = value;
        self.len += 1;
    }

    fn sort(&mut self) {
        self.values[..self.len].sort_by(f64::total_cmp);
    }

    fn as_slice(&self) -> &[f64] {
        &self.values[..self.len]
    }
}

impl Terms {
    const ALL: Self = Self {
        reflection: true,
        volume: true,
        base: true,
    };
}

fn add_terms(sums: &mut ThreadMeans, s: &SampleTerms, weight: f64, terms: Terms) {
    if terms.reflection {
        sums.reflection += weight * s.reflection;
    }
    if terms.volume {
        sums.transmission += weight * s.volume;
    }
    if terms.base {
        sums.masking += weight * s.masking;
        sums.transmission += weight * s.diffuse;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gauss_legendre_integrates_polynomials_of_degree_2n_minus_1() {
        for n in 1..=12 {
            let rule = GaussLegendre::new(n);
            let total: f64 = rule.weights.iter().sum();
            assert!((total - 1.0).abs() < 1e-14, "n = {n}: {total}");
            let degree = 2 * n - 1;
            let integral: f64 = rule
                .nodes
                .iter()
                .zip(&rule.weights)
                .map(|(x, w)| w * x.powi(degree as i32))
                .sum();
            let exact = 1.0 / (degree as f64 + 1.0);
            assert!((integral - exact).abs() < 1e-13, "n = {n}: {integral}");
        }
    }

    #[test]
    fn normal_quantile_inverts_the_cdf() {
        for &z in &[-8.0, -5.0, -2.5, -1.0, -0.3, 0.0, 0.4, 1.7, 3.0] {
            let back = normal_quantile(normal_cdf(z));
            assert!(
                (back - z).abs() < 2e-9 * z.abs().max(1.0),
                "z = {z}: {back}"
            );
        }
    }
}
