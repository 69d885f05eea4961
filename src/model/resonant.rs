//! The resonant quadrature: the curve means `⟨s⟩_j`, `⟨P⟩_j` of MODEL.md from a few dozen
//! tangent samples per light, placed where each term of the integrand lives.
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
//!   deviate from 1, smoothly. A lobe that is less than `FLAT_LOBE_SPAN` standard
//!   deviations across the segment is smooth there and is integrated on the base nodes; one
//!   whose nearest point is more than `NEGLIGIBLE_LOBE_Z` deviations away is dropped
//!   (`g` there is below 1e-8 of its peak).
//! - **Base nodes.** Gauss–Legendre in α over the clipped segment for `P` and the kd term.
//! - A flat segment (all of its share at one α, e.g. satin's floats) is one node for every
//!   term.

use super::curve::CurvePiece;
use super::patch::{PairInThreadFrame, SampleTerms, ThreadMeans, ThreadModel};
use std::f64::consts::{FRAC_1_SQRT_2, PI};

/// Node counts of the resonant quadrature, per curve segment: Gauss–Legendre nodes for the
/// surface lobe, for the volume lobe, and for the lobe-free terms.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub struct ResonantNodes {
    pub surface: u32,
    pub volume: u32,
    pub base: u32,
}

impl ResonantNodes {
    /// Most nodes of one kind per segment.
    pub const MAX: u32 = 16;

    /// The default counts: the measured point of the report where every built-in fabric is
    /// within 0.25% relative RMS (see README "Which evaluation to pick").
    pub const DEFAULT: Self = Self {
        surface: 7,
        volume: 5,
        base: 3,
    };

    /// Checks every count is in 1..=[`Self::MAX`], naming the one that is not.
    pub fn validate(&self) -> Result<(), String> {
        for (name, n) in [
            ("surface", self.surface),
            ("volume", self.volume),
            ("base", self.base),
        ] {
            if !(1..=Self::MAX).contains(&n) {
                return Err(format!(
                    "resonant {name} nodes must be in 1..={}, got {n}",
                    Self::MAX
                ));
            }
        }
        Ok(())
    }
}

impl Default for ResonantNodes {
    fn default() -> Self {
        Self::DEFAULT
    }
}

impl std::fmt::Display for ResonantNodes {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}/{}", self.surface, self.volume, self.base)
    }
}

/// A lobe narrower than this many standard deviations across a segment is integrated on the
/// base nodes: over so short a stretch the Gaussian is close to a low-order polynomial.
pub const FLAT_LOBE_SPAN: f64 = 0.5;
/// A lobe whose value within a segment is nowhere above `g` at this many standard
/// deviations (e^−18 ≈ 1.5e-8 of its peak) contributes nothing measurable there.
pub const NEGLIGIBLE_LOBE_Z: f64 = 6.0;

/// A segment holding less than this share of a lobe's Gaussian mass (the lobe's tail, or a
/// sliver of it) gets half of the lobe's nodes, and one holding less than an eighth of it a
/// quarter: its error weighs in proportion to its mass. Measured on the six fabrics at
/// 7/5/3 (4,000 pairs per set): 0.15 cuts satin's samples per light from 41.0 to 37.5 on
/// highlight pairs and changes no fabric's relative RMS by more than 0.01%; 0.3 costs
/// silk_shot 0.2% on uniform pairs.
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

    pub fn len(&self) -> usize {
        self.nodes.len()
    }

    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
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

/// Φ⁻¹(p) for p in (0, 1): Acklam's rational approximation (relative error 1.2e-9), refined
/// by one Halley step on Φ(z) − p, which brings it to f64 rounding.
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
    let z = if p < P_LOW {
        tail(p)
    } else if p > 1.0 - P_LOW {
        -tail(1.0 - p)
    } else {
        let q = p - 0.5;
        let r = q * q;
        (((((A[0] * r + A[1]) * r + A[2]) * r + A[3]) * r + A[4]) * r + A[5]) * q
            / (((((B[0] * r + B[1]) * r + B[2]) * r + B[3]) * r + B[4]) * r + 1.0)
    };
    let e = normal_cdf(z) - p;
    let u = e / normal_pdf(z);
    z - u / (1.0 + 0.5 * z * u)
}

/// θh at tangent offset α (given by its cosine and sine) and its slope dθh/dα =
/// (cos φi + cos φo)/2, without the rest of the sample.
fn theta_h_and_slope(pair: &PairInThreadFrame, cos_a: f64, sin_a: f64) -> (f64, f64) {
    let half = |t0: f64, z: f64, b: f64| {
        let n = z * cos_a - t0 * sin_a;
        let s = t0 * cos_a + z * sin_a;
        let perp = (n * n + b * b).sqrt();
        let cos_phi = if perp > 0.0 { n / perp } else { 0.0 };
        (0.5 * s.atan2(perp), 0.5 * cos_phi)
    };
    let (hi, ki) = half(pair.ti0, pair.zi, pair.bi);
    let (ho, ko) = half(pair.to0, pair.zo, pair.bo);
    (hi + ho, ki + ko)
}

/// Which terms a node adds to the means.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Terms {
    reflection: bool,
    volume: bool,
    base: bool,
}

/// What one resonant evaluation of a thread cost.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ResonantCost {
    /// Full kernel evaluations (tangent samples whose terms were computed).
    pub samples: usize,
    /// Segments that needed θh and its slope at one point to place lobe nodes.
    pub probes: usize,
}

/// The resonant rule of one thread, prepared once: its Gauss–Legendre rules and lobe widths.
#[derive(Clone, Debug, PartialEq)]
pub struct ResonantRule {
    surface: GaussLegendre,
    volume: GaussLegendre,
    base: GaussLegendre,
    /// Lobe standard deviations in radians (surface, volume).
    sigma: [f64; 2],
    /// Lobe rules with half and a quarter of the nodes (rounded up), for segments that hold
    /// less than [`TAIL_MASS`] and `TAIL_MASS/8` of a lobe.
    tail: [GaussLegendre; 2],
    far_tail: [GaussLegendre; 2],
}

impl ResonantRule {
    pub fn new(nodes: ResonantNodes, sigma_s: f64, sigma_v: f64) -> Self {
        Self {
            surface: GaussLegendre::new(nodes.surface as usize),
            volume: GaussLegendre::new(nodes.volume as usize),
            base: GaussLegendre::new(nodes.base as usize),
            sigma: [sigma_s, sigma_v],
            tail: [nodes.surface, nodes.volume].map(|n| GaussLegendre::new(n.div_ceil(2) as usize)),
            far_tail: [nodes.surface, nodes.volume]
                .map(|n| GaussLegendre::new(n.div_ceil(4) as usize)),
        }
    }

    /// The curve means of `model`'s thread for `pair`, whose facing window is `facing`
    /// (α interval where both directions face the tangent sample), and what they cost.
    pub(crate) fn means(
        &self,
        model: &ThreadModel,
        pair: &PairInThreadFrame,
        facing: (f64, f64),
    ) -> (ThreadMeans, ResonantCost) {
        let mut sums = ThreadMeans::default();
        let mut cost = ResonantCost::default();
        let mut add = |alpha: f64, weight: f64, terms: Terms, cost: &mut ResonantCost| {
            cost.samples += 1;
            if let Some(s) = model.sample(pair, alpha.cos(), alpha.sin()) {
                add_terms(&mut sums, &s, weight, terms);
            }
        };
        let resonant = -(pair.ti0 + pair.to0).atan2(pair.zi + pair.zo);
        for &(piece, _, _) in model.pieces() {
            if piece.start == piece.end {
                if piece.start > facing.0 && piece.start < facing.1 {
                    let all = Terms {
                        reflection: true,
                        volume: true,
                        base: true,
                    };
                    add(piece.start, piece.weight, all, &mut cost);
                }
                continue;
            }
            let (lo, hi) = (piece.start.max(facing.0), piece.end.min(facing.1));
            if lo >= hi {
                continue;
            }
            self.segment(&piece, lo, hi, resonant, pair, &mut cost, &mut add);
        }
        (sums, cost)
    }

    /// Places the nodes of one segment clipped to `[lo, hi]`.
    #[allow(clippy::too_many_arguments)]
    fn segment(
        &self,
        piece: &CurvePiece,
        lo: f64,
        hi: f64,
        resonant: f64,
        pair: &PairInThreadFrame,
        cost: &mut ResonantCost,
        add: &mut impl FnMut(f64, f64, Terms, &mut ResonantCost),
    ) {
        let density = piece.weight / (piece.end - piece.start);
        cost.probes += 1;
        let centre = resonant.clamp(lo, hi);
        let (theta_c, slope) = theta_h_and_slope(pair, centre.cos(), centre.sin());
        // Per lobe: on the base nodes (smooth over the segment), dropped, or its own nodes.
        let mut on_base = [false; 2];
        for (lobe, rule) in [&self.surface, &self.volume].into_iter().enumerate() {
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
            let (a, b) = if sign > 0.0 {
                (z_lo, z_hi)
            } else {
                (-z_hi, -z_lo)
            };
            let (t_lo, t_hi) = (normal_cdf(a), normal_cdf(b));
            let span = t_hi - t_lo;
            // The lobe's mass in the segment sets how many of its nodes the segment gets.
            let rule = if span < TAIL_MASS / 8.0 {
                &self.far_tail[lobe]
            } else if span < TAIL_MASS {
                &self.tail[lobe]
            } else {
                rule
            };
            for (&x, &w) in rule.nodes.iter().zip(&rule.weights) {
                let zn = sign * normal_quantile(t_lo + span * x);
                let alpha = centre + (sigma * zn - theta_c) / slope;
                // dα = (σ/k) dz and dz = dt/φ(z).
                let weight = density * w * span * sigma / (slope * normal_pdf(zn));
                add(alpha, weight, terms, cost);
            }
        }
        let terms = Terms {
            reflection: on_base[0],
            volume: on_base[1],
            base: true,
        };
        let width = hi - lo;
        for (&x, &w) in self.base.nodes.iter().zip(&self.base.weights) {
            add(lo + width * x, density * width * w, terms, cost);
        }
    }
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
            assert!((back - z).abs() < 1e-9, "z = {z}: {back}");
        }
    }
}
