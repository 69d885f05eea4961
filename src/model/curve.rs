//! Tangent curves (docs/model.md#tangent-curves) and the quadrature rules that
//! turn the mean `⟨x⟩_j` over a curve into a weighted sum over tangent offsets α.
//!
//! A curve is piecewise linear in α over arc length: segment k runs from `o_k` to `o_{k+1}`
//! and holds the share `l_k / Σl` of the curve. A segment of length 0 is a jump (no samples);
//! a segment with `o_k = o_{k+1}` holds its whole share at one α.

use super::fabric::{ModelOptions, TangentSampling, Thread};

/// Finest α spacing, in degrees, of the direct rule. The integrand's narrowest feature in α
/// is the surface lobe: |dθh/dα| ≤ 1 (it is the mean of cos φi and cos φo), so a lobe of
/// standard deviation σ in θh is at least σ wide in α, and σ/16 spacing resolves it to far
/// below 1e-6. What remains are the O(h²) errors at the kinks of the reweighted min() terms
/// (the kinks of max(cos, 0) are removed by clipping, see `ThreadModel::means`). Against
/// an independent rule (tests/model/direct_convergence.rs) this spacing keeps the built-in
/// fabrics well under the 1e-4 that docs/model.md#direct-evaluation asks for (the figures:
/// docs/notebook/2026-12-07-figures-from-comments-issue-47.md).
pub const DIRECT_MAX_SPACING_DEG: f64 = 0.05;
/// Samples per standard deviation of the narrowest lobe in the direct rule.
pub const DIRECT_SAMPLES_PER_SIGMA: f64 = 16.0;
/// Bound on the direct rule's samples per thread, reached only for lobes narrower than
/// about 0.005° swept over a wide curve; beyond it the direct rule is no longer converged.
pub const DIRECT_MAX_SAMPLES: usize = 1 << 19;

/// Fewest midpoints placed in a clipped interval of the direct rule. Where both directions
/// barely face the tangent samples the clipped interval is a sliver a fraction of a degree
/// wide, across which M·P rises from and falls back to 0; its proportional share of the
/// segment's nodes can be 1 or 2. Measured on such a velvet pair (thread 2, ⟨P⟩ ≈ 3e-5)
/// against 2^18 strata: 1 node at least gives 2.7e-3 relative error, 64 give 7e-5 and 128
/// give 1.6e-5.
pub const DIRECT_MIN_NODES_PER_INTERVAL: usize = 128;

/// One quadrature node: a tangent offset α (radians) and its weight. Weights of a plan sum
/// to 1, so `Σ weight · x(α)` is the curve mean `⟨x⟩`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CurveNode {
    pub alpha: f64,
    pub weight: f64,
}

/// A piece of the quadrature: either a single node (`start == end`, `count == 1`), or an α
/// interval holding `weight` of the curve uniformly, integrated by `count` midpoints. The
/// evaluation may narrow an interval to where the integrand is non-zero before placing
/// its midpoints (see `ThreadModel::means`), so intervals are kept whole here.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CurvePiece {
    /// Interval ends in radians, `start ≤ end`.
    pub start: f64,
    pub end: f64,
    pub weight: f64,
    pub count: usize,
    /// Fewest midpoints the evaluation places in the interval after clipping it.
    pub min_count: usize,
}

impl CurvePiece {
    /// The piece's midpoint nodes over its whole interval.
    pub fn nodes(&self) -> impl Iterator<Item = CurveNode> + '_ {
        let n = self.count.max(1);
        (0..n).map(move |i| CurveNode {
            alpha: self.start + (self.end - self.start) * (i as f64 + 0.5) / n as f64,
            weight: self.weight / n as f64,
        })
    }
}

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

    /// The default counts: the cheapest that keep every built-in fabric within 0.25% relative
    /// RMS of the direct rule with a margin (tests/model/resonant.rs; the counts compared are in
    /// docs/notebook/2026-12-07-figures-from-comments.md).
    pub const DEFAULT: Self = Self {
        surface: 6,
        volume: 5,
        base: 2,
    };

    /// Checks every count is in 1..=[`Self::MAX`], naming the one that is not.
    pub fn validate(&self) -> Result<(), NodeCountError> {
        for (kind, count) in [
            ("surface", self.surface),
            ("volume", self.volume),
            ("base", self.base),
        ] {
            if !(1..=Self::MAX).contains(&count) {
                return Err(NodeCountError { kind, count });
            }
        }
        Ok(())
    }
}

/// A node count of [`ResonantNodes`] outside 1..=[`ResonantNodes::MAX`].
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("resonant {kind} nodes must be in 1..={max}, got {count}", max = ResonantNodes::MAX)]
pub struct NodeCountError {
    /// "surface", "volume" or "base".
    pub kind: &'static str,
    pub count: u32,
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

/// How the curve mean is computed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Integration {
    /// The converged mean (docs/model.md#direct-evaluation): per segment midpoints, spacing set
    /// by the thread's narrowest lobe (see [`DIRECT_MAX_SPACING_DEG`]).
    Direct,
    /// The paper's renderer: N stratified samples per thread, the midpoints of N equal
    /// arc-length strata of the whole curve.
    Paper(u32),
    /// The resonant quadrature (`super::resonant`): per segment, Gauss–Legendre nodes placed
    /// on each lobe in the variable that makes it flat, plus a few for the lobe-free terms.
    Resonant(ResonantNodes),
    /// The baker's rule: the direct rule at a coarser spacing, σ/6 of the narrowest lobe
    /// (and at most 2°), with fewer midpoints in clipped slivers. Measured within 3e-4
    /// relative RMS of the direct evaluation (tests/model/direct_convergence.rs), a small fraction
    /// of any table's error, at an eighth to a fortieth of the cost.
    Baking,
}

/// Paper mode's tangent samples per thread when none are given (`eval --integration paper`,
/// the direct shader).
pub const DEFAULT_PAPER_SAMPLES: u32 = 32;

/// Samples per standard deviation of the narrowest lobe in the baking rule.
pub const BAKING_SAMPLES_PER_SIGMA: f64 = 6.0;
/// Coarsest α spacing of the baking rule, in degrees.
pub const BAKING_MAX_SPACING_DEG: f64 = 2.0;
/// Fewest midpoints in a clipped interval of the baking rule.
pub const BAKING_MIN_NODES_PER_INTERVAL: usize = 8;

/// The share of the curve held by each segment, `l_k / Σl` (one segment ignores its length).
fn segment_shares(thread: &Thread) -> Vec<f64> {
    match thread.lengths.len() {
        0 => vec![],
        1 => vec![1.0],
        _ => {
            let total: f64 = thread.lengths.iter().sum();
            thread.lengths.iter().map(|l| l / total).collect()
        }
    }
}

/// Quadrature nodes for the mean over `thread`'s curve: the nodes of [`curve_pieces`].
pub fn curve_nodes(
    thread: &Thread,
    options: &ModelOptions,
    integration: Integration,
) -> Vec<CurveNode> {
    curve_pieces(thread, options, integration)
        .iter()
        .flat_map(|p| p.nodes().collect::<Vec<_>>())
        .collect()
}

/// The quadrature for the mean over `thread`'s curve. The direct rule gives one interval per
/// segment, its midpoint count set by the thread's narrowest lobe; paper mode and the
/// control-point option give single nodes. Equal consecutive nodes are merged, so a
/// constant segment costs one node.
pub fn curve_pieces(
    thread: &Thread,
    options: &ModelOptions,
    integration: Integration,
) -> Vec<CurvePiece> {
    let sigma_min_deg = options.lobe_sigma_deg(thread.gamma_s_deg.min(thread.gamma_v_deg));
    let offsets = &thread.offsets_deg;
    let mut nodes: Vec<CurvePiece> = Vec::new();
    let push = |nodes: &mut Vec<CurvePiece>, alpha_deg: f64, weight: f64| {
        let alpha = alpha_deg.to_radians();
        match nodes.last_mut() {
            Some(last) if last.count == 1 && last.start == alpha && last.end == alpha => {
                last.weight += weight
            }
            _ => nodes.push(CurvePiece {
                start: alpha,
                end: alpha,
                weight,
                count: 1,
                min_count: 1,
            }),
        }
    };
    if offsets.len() == 1 {
        push(&mut nodes, offsets[0], 1.0);
        return nodes;
    }
    if options.tangent_sampling == TangentSampling::ControlPoints {
        let w = 1.0 / offsets.len() as f64;
        for &o in offsets {
            push(&mut nodes, o, w);
        }
        return nodes;
    }
    let shares = segment_shares(thread);
    match integration {
        // The resonant rule places its nodes per pair, in the direct rule's intervals.
        Integration::Direct | Integration::Baking | Integration::Resonant(_) => {
            let (spacing, min_count) = if integration == Integration::Direct {
                (
                    DIRECT_MAX_SPACING_DEG.min(sigma_min_deg / DIRECT_SAMPLES_PER_SIGMA),
                    DIRECT_MIN_NODES_PER_INTERVAL,
                )
            } else {
                (
                    BAKING_MAX_SPACING_DEG.min(sigma_min_deg / BAKING_SAMPLES_PER_SIGMA),
                    BAKING_MIN_NODES_PER_INTERVAL,
                )
            };
            let span: f64 = offsets.windows(2).map(|w| (w[1] - w[0]).abs()).sum();
            // Keep the total under the cap by widening the spacing uniformly.
            let spacing = spacing.max(span / DIRECT_MAX_SAMPLES as f64);
            for (k, &share) in shares.iter().enumerate() {
                if share == 0.0 {
                    continue;
                }
                let (a, b) = (offsets[k], offsets[k + 1]);
                if a == b {
                    push(&mut nodes, a, share);
                    continue;
                }
                let count = (((b - a).abs() / spacing).ceil() as usize).max(1);
                let (start, end) = (a.min(b).to_radians(), a.max(b).to_radians());
                nodes.push(CurvePiece {
                    start,
                    end,
                    weight: share,
                    count,
                    min_count,
                });
            }
        }
        Integration::Paper(n) => {
            let n = n.max(1);
            // Walk the strata midpoints s = (i + ½)/n through the cumulative shares.
            let mut segment = 0;
            let mut start = 0.0;
            for i in 0..n {
                let s = (i as f64 + 0.5) / n as f64;
                while segment + 1 < shares.len() && s >= start + shares[segment] {
                    start += shares[segment];
                    segment += 1;
                }
                let share = shares[segment];
                let t = if share > 0.0 {
                    ((s - start) / share).clamp(0.0, 1.0)
                } else {
                    0.5
                };
                let (a, b) = (offsets[segment], offsets[segment + 1]);
                push(&mut nodes, a + (b - a) * t, 1.0 / n as f64);
            }
        }
    }
    nodes
}

#[cfg(test)]
mod tests {
    use super::*;

    fn nodes_of(
        t: &Thread,
        sampling: TangentSampling,
        integration: Integration,
        gamma: f64,
    ) -> Vec<CurveNode> {
        let t = Thread {
            gamma_s_deg: gamma,
            gamma_v_deg: 2.0 * gamma,
            ..t.clone()
        };
        let options = ModelOptions {
            tangent_sampling: sampling,
            ..ModelOptions::default()
        };
        curve_nodes(&t, &options, integration)
    }

    fn thread(offsets: &[f64], lengths: &[f64]) -> Thread {
        Thread {
            eta: 1.5,
            albedo: [1.0; 3],
            albedo_scale: 1.0,
            kd: 0.5,
            gamma_s_deg: 5.0,
            gamma_v_deg: 10.0,
            coverage: 0.5,
            offsets_deg: offsets.to_vec(),
            lengths: lengths.to_vec(),
        }
    }

    fn mean_alpha_deg(nodes: &[CurveNode]) -> f64 {
        nodes.iter().map(|n| n.weight * n.alpha.to_degrees()).sum()
    }

    #[test]
    fn weights_sum_to_one_and_zero_length_segments_hold_nothing() {
        // Satin back, thread 1: a jump (length 0) from 30° back to −5°.
        let t = thread(
            &[-30., -30., 30., 30., -5., -5., 5., 5.],
            &[1.33, 1.33, 1.33, 0., 0.67, 0.67, 0.67],
        );
        for integration in [Integration::Direct, Integration::Paper(7)] {
            let nodes = nodes_of(&t, TangentSampling::ArcLength, integration, 2.5);
            let total: f64 = nodes.iter().map(|n| n.weight).sum();
            assert!((total - 1.0).abs() < 1e-12, "{integration:?}: {total}");
        }
        // The constant segments collapse to one node each in the direct rule.
        let nodes = nodes_of(&t, TangentSampling::ArcLength, Integration::Direct, 2.5);
        let at_30 = nodes
            .iter()
            .filter(|n| n.alpha == 30f64.to_radians())
            .count();
        assert_eq!(at_30, 1);
    }

    #[test]
    fn paper_mode_uses_strata_midpoints_in_arc_length() {
        // Lengths 1 and 3: the first quarter of arc length covers 0°→10°, the rest 10°→40°.
        let t = thread(&[0., 10., 40.], &[1., 3.]);
        let nodes = nodes_of(&t, TangentSampling::ArcLength, Integration::Paper(4), 1.0);
        let alphas: Vec<f64> = nodes.iter().map(|n| n.alpha.to_degrees()).collect();
        let expected = [5.0, 15.0, 25.0, 35.0];
        for (a, e) in alphas.iter().zip(expected) {
            assert!((a - e).abs() < 1e-9, "{alphas:?}");
        }
    }

    #[test]
    fn single_segment_ignores_its_length_and_single_point_is_one_node() {
        let t = thread(&[-25., 25.], &[0.0]);
        let nodes = nodes_of(&t, TangentSampling::ArcLength, Integration::Direct, 12.);
        assert!(mean_alpha_deg(&nodes).abs() < 1e-9);
        let t = thread(&[17.], &[]);
        let nodes = nodes_of(&t, TangentSampling::ArcLength, Integration::Paper(8), 12.);
        assert_eq!(nodes.len(), 1);
        assert!((nodes[0].alpha.to_degrees() - 17.).abs() < 1e-12);
    }

    #[test]
    fn control_points_option_weights_points_equally() {
        let t = thread(&[-30., -30., 30.], &[5., 1.]);
        let nodes = nodes_of(&t, TangentSampling::ControlPoints, Integration::Direct, 1.);
        assert_eq!(nodes.len(), 2);
        assert!((nodes[0].weight - 2. / 3.).abs() < 1e-12);
        assert!((mean_alpha_deg(&nodes) - (-10.)).abs() < 1e-9);
    }
}
