//! The resonant quadrature (`Integration::Resonant`) against the converged direct rule: its
//! error and cost on every built-in fabric, its convergence as nodes are added, and its
//! behaviour on the model's hard cases (docs/model.md#hard-numerical-cases) and stressed fabrics.

use crate::common::*;
use clothbake::measure::accuracy::{HIGHLIGHT_SEED, Reference, UNIFORM_SEED};
use clothbake::measure::direction_sets::{highlight_pairs, uniform_pairs};
use clothbake::model::{Fabric, Integration, Patch, ResonantNodes};
use glam::DVec3;
use rayon::prelude::*;

const DEFAULT: Integration = Integration::Resonant(ResonantNodes::DEFAULT);

/// Mean and largest kernel evaluations per light (both threads) over `pairs`.
fn evaluations(fabric: &Fabric, nodes: ResonantNodes, pairs: &[(DVec3, DVec3)]) -> (f64, usize) {
    Patch::new(fabric, Integration::Resonant(nodes))
        .resonant_evaluations(pairs)
        .expect("resonant rule")
}

/// Issue 10's target, checked at the default node counts on `check`'s 4,000 + 4,000 pairs:
/// relative RMS ≤ 0.25% on uniform and on highlight pairs, and at most 40 kernel
/// evaluations per light on average on either set. Measured: 0.018–0.114% and 12–32
/// evaluations (satin's highlight pairs the most), so both bounds have room; on 20,000
/// pairs per set the worst is 0.20% (crepe highlight).
#[test]
fn within_a_quarter_percent_of_direct_in_at_most_40_evaluations_per_light() {
    for fabric in builtin() {
        let reference = Reference::new(&fabric, 4000);
        let patch = Patch::new(&fabric, DEFAULT);
        let error = reference.measure(|wi, wo| patch.eval(wi, wo));
        let nodes = ResonantNodes::DEFAULT;
        let uniform = evaluations(&fabric, nodes, &uniform_pairs(4000, UNIFORM_SEED));
        let highlight = evaluations(
            &fabric,
            nodes,
            &highlight_pairs(&fabric, 4000, HIGHLIGHT_SEED),
        );
        println!(
            "{} at {nodes}: relative RMS {:.3}% uniform, {:.3}% highlight; evaluations per \
             light {:.1} uniform, {:.1} highlight (max {} / {})",
            fabric.name,
            100.0 * error.uniform.relative_rms,
            100.0 * error.highlight.relative_rms,
            uniform.0,
            highlight.0,
            uniform.1,
            highlight.1
        );
        assert!(error.uniform.relative_rms <= 0.0025, "{}", fabric.name);
        assert!(error.highlight.relative_rms <= 0.0025, "{}", fabric.name);
        assert!(uniform.0 <= 40.0 && highlight.0 <= 40.0, "{}", fabric.name);
    }
}

/// More nodes, less error: at 16 nodes of each kind every fabric is within 0.05% (measured
/// 0.002–0.037% on 1,000 + 1,000 pairs) and closer than at the default. A rule that placed its nodes wrongly (a
/// wrong Jacobian, a lobe cut short) would stall instead.
#[test]
fn converges_as_nodes_are_added() {
    let many = ResonantNodes {
        surface: 16,
        volume: 16,
        base: 16,
    };
    for fabric in builtin() {
        let reference = Reference::new(&fabric, 1000);
        let error = |nodes| {
            let patch = Patch::new(&fabric, Integration::Resonant(nodes));
            let e = reference.measure(|wi, wo| patch.eval(wi, wo));
            e.uniform.relative_rms.max(e.highlight.relative_rms)
        };
        let (default, converged) = (error(ResonantNodes::DEFAULT), error(many));
        println!(
            "{}: {:.4}% at {}, {:.4}% at {many}",
            fabric.name,
            100.0 * default,
            ResonantNodes::DEFAULT,
            100.0 * converged
        );
        assert!(converged <= 5e-4 && converged < default, "{}", fabric.name);
    }
}

/// Every curated hard case is finite and non-negative, and within 5% of the direct value's
/// brightest channel. Measured worst: 0.62% (3.3% before lobes that span at most
/// `FLAT_LOBE_SPAN` deviations moved onto the base nodes), on dark pairs with a direction
/// along the tangent at a curve end, where the facing window ends inside the segment.
#[test]
fn hard_cases_are_finite_non_negative_and_close_to_direct() {
    let cases = hard_cases();
    let worst = cases
        .par_iter()
        .map(|case| {
            let direct = Patch::new(&case.fabric, Integration::Direct).eval(case.wi, case.wo);
            let resonant = Patch::new(&case.fabric, DEFAULT).eval(case.wi, case.wo);
            assert!(
                resonant.is_finite() && resonant.min_element() >= 0.0,
                "{}: {resonant}",
                case.name
            );
            let scale = direct.max_element();
            let error = (resonant - direct).abs().max_element();
            assert!(
                error <= 0.05 * scale,
                "{}: resonant {resonant}, direct {direct}",
                case.name
            );
            if scale > 0.0 { error / scale } else { 0.0 }
        })
        .reduce(|| 0.0, f64::max);
    println!(
        "{} hard cases: finite, non-negative, worst difference {:.2}% of the pair's brightest channel",
        cases.len(),
        100.0 * worst
    );
}

/// The stressed fabrics (η = 1, γ = 0.01°, full coverage, a single control point, zero-length
/// jumps with a flat segment as a point weight, vertical tangents) stay within 0.4% relative
/// RMS of the direct rule on 1,000 uniform and 1,000 highlight pairs. Measured: 0.000–0.14%,
/// vertical tangents (curve from −90° to 90°, where θh flattens at both ends) the worst.
#[test]
fn stressed_fabrics_stay_close_to_direct() {
    for fabric in stressed_fabrics() {
        let reference = Reference::new(&fabric, 1000);
        let patch = Patch::new(&fabric, DEFAULT);
        let error = reference.measure(|wi, wo| patch.eval(wi, wo));
        println!(
            "{}: {:.3}% uniform, {:.3}% highlight",
            fabric.name,
            100.0 * error.uniform.relative_rms,
            100.0 * error.highlight.relative_rms
        );
        assert!(
            error.uniform.relative_rms <= 0.004 && error.highlight.relative_rms <= 0.004,
            "{}",
            fabric.name
        );
    }
}

#[test]
fn below_or_on_the_horizon_gives_zero() {
    for fabric in builtin().iter().chain(&stressed_fabrics()) {
        let patch = Patch::new(fabric, DEFAULT);
        for (wi, wo) in [
            (dir(-10.0, 30.0), dir(40.0, 10.0)),
            (dir(40.0, 10.0), dir(0.0, 0.0)),
        ] {
            assert_eq!(patch.eval(wi, wo), DVec3::ZERO, "{}", fabric.name);
        }
    }
}
