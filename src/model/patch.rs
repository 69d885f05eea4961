//! The cosine-weighted patch transfer `F(wi, wo)` of docs/model.md#the-patch-transfer-f: two thread
//! families, each a curve of tangent samples with shadowing/masking and reweighting, normalised by
//! `Q`.

use super::curve::{CurvePiece, Integration, curve_pieces};
use super::fabric::{Fabric, Thread};
use super::lobes::{ThreadLobes, UnitHeightGaussian, fresnel_dielectric};
use super::resonant::{ResonantCost, ResonantRule};
use super::sample::{
    PairInThreadFrame, SampleTerms, ThreadMeans, half_angle_and_difference, thread_axes,
};
use glam::DVec3;

/// Below this length a projection of a unit direction counts as degenerate (the direction is
/// parallel to the tangent or to the rotation axis). Rounding alone leaves ~1e-16 residues in
/// the components, so a residual length of 1e-9 carries no direction; the sample then
/// contributes 0 to s and to P, as docs/model.md#degenerate-projections prescribes.
pub const DEGENERATE_PROJECTION: f64 = 1e-9;

/// `F` split into a grey surface term and one volume term per thread:
/// `F = reflection + A1 · transmission[0] + A2 · transmission[1]`, every term already
/// weighted by its coverage and divided by `Q`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PatchTerms {
    pub reflection: f64,
    pub transmission: [f64; 2],
}

/// One thread family prepared for evaluation: its frame, lobes and quadrature nodes.
#[derive(Clone, Debug)]
pub struct ThreadModel {
    /// Base tangent t0 (x for thread 1, y for thread 2).
    t0: DVec3,
    /// Rotation axis b (y for thread 1, x for thread 2).
    b: DVec3,
    /// Quadrature pieces with (cos, sin) of their start precomputed.
    pieces: Vec<(CurvePiece, f64, f64)>,
    eta: f64,
    kd: f64,
    albedo: DVec3,
    coverage: f64,
    lobes: ThreadLobes,
    reweight: UnitHeightGaussian,
    /// Set for `Integration::Resonant`: the rule that places nodes per pair.
    resonant: Option<ResonantRule>,
}

/// `(1 − u)·a·b + u·min(a, b)`: the reweighted product of M and P (docs/model.md#reweighting).
#[inline]
fn reweighted(u: f64, a: f64, b: f64) -> f64 {
    (1.0 - u) * a * b + u * a.min(b)
}

impl ThreadModel {
    /// Prepares `thread` as family `index` (0: thread 1 along x, 1: thread 2 along y).
    pub fn new(fabric: &Fabric, index: usize, integration: Integration) -> Self {
        let thread: &Thread = fabric.threads()[index];
        let options = fabric.options;
        let (t0, b) = thread_axes(index);
        let sigma_s = options.lobe_sigma_deg(thread.gamma_s_deg);
        let sigma_v = options.lobe_sigma_deg(thread.gamma_v_deg);
        let pieces = curve_pieces(thread, &options, integration)
            .into_iter()
            .map(|p| (p, p.start.cos(), p.start.sin()))
            .collect();
        Self {
            t0,
            b,
            pieces,
            eta: thread.eta,
            kd: thread.kd,
            albedo: DVec3::from_array(thread.albedo_rgb()),
            coverage: thread.coverage,
            lobes: ThreadLobes::new(sigma_s.to_radians(), sigma_v.to_radians()),
            reweight: UnitHeightGaussian::new(options.sigma_u_deg.to_radians()),
            resonant: match integration {
                Integration::Resonant(nodes) => Some(ResonantRule::new(
                    nodes,
                    sigma_s.to_radians(),
                    sigma_v.to_radians(),
                )),
                _ => None,
            },
        }
    }

    /// Most tangent samples one evaluation visits, for the direct, baking and paper rules
    /// (the resonant rule places its nodes per pair: [`Self::resonant_means`] counts them).
    pub fn node_count(&self) -> usize {
        self.pieces.iter().map(|(p, _, _)| p.count).sum()
    }

    /// The curve means of s and P for unit directions `wi`, `wo` in the patch frame.
    ///
    /// Everything is expressed through the components of w in the sample's orthonormal frame
    /// {t, n, b}, with t = cos α t0 + sin α z and n = −sin α t0 + cos α z:
    /// - `w⊥ = w − (w·t)t = (w·n)n + (w·b)b`, so `cos θ = |w⊥| = √((w·n)² + (w·b)²)`
    ///   (no cancellation near w ∥ t), `cos φ = (w·n)/|w⊥|` and
    ///   `wi⊥·wo⊥ = (wi·n)(wo·n) + (wi·b)(wo·b)`.
    /// - `w∥ = w − (w·b)b` does not depend on α: `|w∥| = √((w·t0)² + (w·z)²)`,
    ///   `cos ψ = (w·n)/|w∥|`, and ψd is one angle per evaluation.
    ///
    /// M(w) and P(w) both have the sign of w·n, and the reweighted products vanish when
    /// either factor does, so a sample with `wi·n ≤ 0` or `wo·n ≤ 0` contributes exactly 0
    /// to s and P and is skipped.
    ///
    /// The factors 1/cos²θd and 1/(cos θi + cos θo) diverge as both directions approach ±t;
    /// the code forms `cos θi/(cos θi + cos θo)` (≤ 1) and takes θi, θo from atan2 of
    /// accurate sines and cosines, so cos θd keeps its relative accuracy down to the
    /// degenerate threshold, where M·P·cos θi vanishes faster than cos²θd.
    ///
    /// Both M and P vanish unless `wi·n(α) > 0` and `wo·n(α) > 0`. With
    /// `w·n(α) = |w∥| cos(α + δ)`, `δ = atan2(w·t0, w·z)`, that is the α interval
    /// `(−π/2 − δ, π/2 − δ)` for each direction. An integration interval is first clipped to
    /// the intersection and its midpoints placed inside it: the integrand vanishes at the
    /// clipped ends like a product of cosines, so no midpoint straddles a kink, and a sliver
    /// where both directions barely face the sample is resolved rather than hit or missed.
    pub fn means(&self, wi: DVec3, wo: DVec3) -> ThreadMeans {
        let Some(pair) = self.pair_frame(wi, wo) else {
            return ThreadMeans::default();
        };
        if let Some(rule) = &self.resonant {
            return self.resonant_rule_means(rule, &pair).0;
        }
        let facing = pair.facing();
        let mut sums = ThreadMeans::default();
        for &(piece, cos_start, sin_start) in &self.pieces {
            if piece.start == piece.end {
                self.accumulate(&pair, cos_start, sin_start, piece.weight, &mut sums);
                continue;
            }
            let (lo, hi) = (piece.start.max(facing.0), piece.end.min(facing.1));
            if lo >= hi {
                continue;
            }
            let length = piece.end - piece.start;
            let count =
                ((piece.count as f64 * (hi - lo) / length).ceil() as usize).max(piece.min_count);
            let step = (hi - lo) / count as f64;
            let weight = piece.weight * step / length;
            // Midpoints by rotation: (cos, sin) advance by the angle `step` each node.
            let (mut cos_a, mut sin_a) = ((lo + 0.5 * step).cos(), (lo + 0.5 * step).sin());
            let (cos_step, sin_step) = (step.cos(), step.sin());
            for _ in 0..count {
                self.accumulate(&pair, cos_a, sin_a, weight, &mut sums);
                (cos_a, sin_a) = (
                    cos_a * cos_step - sin_a * sin_step,
                    sin_a * cos_step + cos_a * sin_step,
                );
            }
        }
        sums
    }

    /// The weighted sums of single tangent samples at the offsets `points` (α, given as
    /// (cos α, sin α, weight)): a curve's point masses (flat segments) alone, whatever this
    /// model's own curve. Each sample as [`Self::means`] weighs a point piece.
    pub fn point_sums(&self, wi: DVec3, wo: DVec3, points: &[(f64, f64, f64)]) -> ThreadMeans {
        let mut sums = ThreadMeans::default();
        if let Some(pair) = self.pair_frame(wi, wo) {
            for &(cos_a, sin_a, weight) in points {
                self.accumulate(&pair, cos_a, sin_a, weight, &mut sums);
            }
        }
        sums
    }

    /// For the resonant rule, the means together with what they cost; `None` for other rules.
    pub fn resonant_means(&self, wi: DVec3, wo: DVec3) -> Option<(ThreadMeans, ResonantCost)> {
        let rule = self.resonant.as_ref()?;
        Some(match self.pair_frame(wi, wo) {
            Some(pair) => self.resonant_rule_means(rule, &pair),
            None => Default::default(),
        })
    }

    /// `rule`'s means of this thread's curve for `pair`, and what they cost.
    fn resonant_rule_means(
        &self,
        rule: &ResonantRule,
        pair: &PairInThreadFrame,
    ) -> (ThreadMeans, ResonantCost) {
        let sample = |cos_a: f64, sin_a: f64| self.sample(pair, cos_a, sin_a);
        rule.means(&self.pieces, sample, pair, pair.facing())
    }

    /// The pair in this thread's fixed axes; `None` where a direction is parallel to b.
    fn pair_frame(&self, wi: DVec3, wo: DVec3) -> Option<PairInThreadFrame> {
        let (ti0, zi, bi) = (wi.dot(self.t0), wi.z, wi.dot(self.b));
        let (to0, zo, bo) = (wo.dot(self.t0), wo.z, wo.dot(self.b));
        let par_i = (ti0 * ti0 + zi * zi).sqrt();
        let par_o = (to0 * to0 + zo * zo).sqrt();
        if par_i < DEGENERATE_PROJECTION || par_o < DEGENERATE_PROJECTION {
            return None;
        }
        let cos_psi_d = ((ti0 * to0 + zi * zo) / (par_i * par_o)).clamp(-1.0, 1.0);
        let pair = PairInThreadFrame {
            ti0,
            zi,
            bi,
            to0,
            zo,
            bo,
            par_i,
            par_o,
            u_psi: self.reweight.eval(cos_psi_d.acos()),
        };
        Some(pair)
    }

    /// Adds one tangent sample at α (given by its cosine and sine) with `weight`.
    #[inline]
    fn accumulate(
        &self,
        pair: &PairInThreadFrame,
        cos_a: f64,
        sin_a: f64,
        weight: f64,
        sums: &mut ThreadMeans,
    ) {
        if let Some(s) = self.sample(pair, cos_a, sin_a) {
            sums.masking += weight * s.masking;
            sums.reflection += weight * s.reflection;
            sums.transmission += weight * (s.volume + s.diffuse);
        }
    }

    /// The terms of one tangent sample at α (given by its cosine and sine), or `None` where
    /// it contributes nothing (either direction faces away, or a projection is degenerate).
    #[inline]
    pub(crate) fn sample(
        &self,
        pair: &PairInThreadFrame,
        cos_a: f64,
        sin_a: f64,
    ) -> Option<SampleTerms> {
        let &PairInThreadFrame {
            ti0,
            zi,
            bi,
            to0,
            zo,
            bo,
            par_i,
            par_o,
            u_psi,
        } = pair;
        let ni = zi * cos_a - ti0 * sin_a;
        let no = zo * cos_a - to0 * sin_a;
        if ni <= 0.0 || no <= 0.0 {
            return None;
        }
        let perp_i = (ni * ni + bi * bi).sqrt();
        let perp_o = (no * no + bo * bo).sqrt();
        if perp_i < DEGENERATE_PROJECTION || perp_o < DEGENERATE_PROJECTION {
            return None;
        }
        let masking_p = reweighted(u_psi, ni / par_i, no / par_o);

        let cos_phi_d = ((ni * no + bi * bo) / (perp_i * perp_o)).clamp(-1.0, 1.0);
        let u_phi = self.reweight.eval(cos_phi_d.acos());
        let shadowing_m = reweighted(u_phi, ni / perp_i, no / perp_o);

        let si = ti0 * cos_a + zi * sin_a;
        let so = to0 * cos_a + zo * sin_a;
        let (theta_h, cos_theta_d) = half_angle_and_difference((perp_i, si), (perp_o, so));
        // cos(φd/2) from cos φd by the half-angle formula; φd/2 ∈ [0, π/2].
        let cos_half_phi_d = (0.5 * (1.0 + cos_phi_d)).sqrt();
        let fr = fresnel_dielectric(self.eta, cos_theta_d * cos_half_phi_d);
        let ft = (1.0 - fr) * (1.0 - fr);

        let common = shadowing_m * masking_p / (cos_theta_d * cos_theta_d);
        let transmission = common * ft * (perp_i / (perp_i + perp_o));
        let (surface, volume) = self.lobes.eval(theta_h);
        Some(SampleTerms {
            masking: masking_p,
            reflection: common * fr * cos_half_phi_d * surface * perp_i,
            volume: transmission * (1.0 - self.kd) * volume,
            diffuse: transmission * self.kd,
        })
    }
}

/// A fabric prepared for evaluating `F(wi, wo)` with one integration rule.
#[derive(Clone, Debug)]
pub struct Patch {
    threads: [ThreadModel; 2],
    gap: f64,
}

impl Patch {
    /// Prepares `fabric` (assumed valid, see [`Fabric::validate`]).
    pub fn new(fabric: &Fabric, integration: Integration) -> Self {
        let threads = [0, 1].map(|i| ThreadModel::new(fabric, i, integration));
        let gap = (1.0 - fabric.thread1.coverage - fabric.thread2.coverage).max(0.0);
        Self { threads, gap }
    }

    /// The two prepared thread families.
    pub fn threads(&self) -> &[ThreadModel; 2] {
        &self.threads
    }

    /// For the resonant rule, the mean and the largest number of kernel evaluations per light
    /// (tangent samples of both threads) over `pairs`; `None` for the other rules.
    pub fn resonant_evaluations(&self, pairs: &[(DVec3, DVec3)]) -> Option<(f64, usize)> {
        let mut counts = Vec::with_capacity(pairs.len());
        for &(wi, wo) in pairs {
            let mut count = 0;
            for thread in &self.threads {
                count += thread.resonant_means(wi, wo)?.1.samples;
            }
            counts.push(count);
        }
        let mean = counts.iter().sum::<usize>() as f64 / counts.len().max(1) as f64;
        Some((mean, counts.into_iter().max().unwrap_or(0)))
    }

    /// `F` in the factored form [`PatchTerms`], for unit `wi`, `wo` in the patch frame.
    /// Zero below the horizon (one-sided cloth) and where `Q = 0`.
    pub fn terms(&self, wi: DVec3, wo: DVec3) -> PatchTerms {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return PatchTerms::default();
        }
        let means = self.threads.each_ref().map(|t| t.means(wi, wo));
        let coverage = self.threads.each_ref().map(|t| t.coverage);
        let q = coverage[0] * means[0].masking + coverage[1] * means[1].masking + self.gap * wo.z;
        if q <= 0.0 {
            return PatchTerms::default();
        }
        PatchTerms {
            reflection: (coverage[0] * means[0].reflection + coverage[1] * means[1].reflection) / q,
            transmission: [0, 1].map(|j| coverage[j] * means[j].transmission / q),
        }
    }

    /// Combines factored terms into RGB with this fabric's albedos.
    pub fn combine(&self, terms: &PatchTerms) -> DVec3 {
        DVec3::splat(terms.reflection)
            + self.threads[0].albedo * terms.transmission[0]
            + self.threads[1].albedo * terms.transmission[1]
    }

    /// The cosine-weighted patch transfer `F(wi, wo)` (RGB) for unit directions in the
    /// patch frame: outgoing radiance per unit perpendicular irradiance.
    pub fn eval(&self, wi: DVec3, wo: DVec3) -> DVec3 {
        self.combine(&self.terms(wi, wo))
    }
}
