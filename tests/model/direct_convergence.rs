//! The direct evaluation is the ground truth of every accuracy claim: show it has converged
//! to better than 1e-4 relative, by comparing it with an independent rule, paper mode's
//! arc-length strata at N = 2^17 (its error is O(1/N) ≈ 1e-5 at curve jumps, smaller
//! elsewhere).

use crate::common::*;
use clothbake::measure::direction_sets::{highlight_pairs, uniform_pairs};
use clothbake::model::{Integration, Patch};
use rayon::prelude::*;

#[test]
fn direct_evaluation_is_converged_to_1e_4() {
    for fabric in builtin() {
        let direct = Patch::new(&fabric, Integration::Direct);
        let fine = Patch::new(&fabric, Integration::Paper(1 << 17));
        let mut pairs = uniform_pairs(40, 21);
        pairs.extend(highlight_pairs(&fabric, 40, 22));
        let worst = pairs
            .par_iter()
            .map(|&(wi, wo)| {
                let (a, b) = (direct.eval(wi, wo), fine.eval(wi, wo));
                // Relative to the pair's brightest channel, so a dark channel of a bright
                // pair is not judged on its own tiny scale.
                (a - b).abs().max_element() / b.max_element().max(1e-12)
            })
            .reduce(|| 0.0, f64::max);
        let nodes: Vec<usize> = direct.threads().iter().map(|t| t.node_count()).collect();
        println!(
            "{}: direct ({nodes:?} nodes) vs paper 2^17: max relative difference {worst:.2e}",
            fabric.name
        );
        assert!(worst < 1e-4, "{}: {worst:e}", fabric.name);
    }
}

/// The baker's coarser rule stays within 1e-3 relative RMS of the direct evaluation, a
/// small fraction of any table's interpolation error (percent level).
#[test]
fn baking_rule_is_within_1e_3_of_direct() {
    for fabric in builtin() {
        let direct = Patch::new(&fabric, Integration::Direct);
        let baking = Patch::new(&fabric, Integration::Baking);
        let mut pairs = uniform_pairs(200, 31);
        pairs.extend(highlight_pairs(&fabric, 200, 32));
        let (a, b): (Vec<_>, Vec<_>) = pairs
            .par_iter()
            .map(|&(wi, wo)| (baking.eval(wi, wo), direct.eval(wi, wo)))
            .unzip();
        let rms = relative_rms(&a, &b);
        let nodes: Vec<usize> = baking.threads().iter().map(|t| t.node_count()).collect();
        println!(
            "{}: baking rule ({nodes:?} nodes) vs direct: relative RMS {rms:.2e}",
            fabric.name
        );
        assert!(rms < 1e-3, "{}: {rms:e}", fabric.name);
    }
}
