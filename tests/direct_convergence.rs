//! The direct evaluation is the ground truth of every accuracy claim: show it has converged
//! to better than 1e-4 relative, by comparing it with an independent rule, paper mode's
//! arc-length strata at N = 2^17 (its error is O(1/N) ≈ 1e-5 at curve jumps, smaller
//! elsewhere).

mod common;

use clothbake::direction_sets::{highlight_pairs, uniform_pairs};
use clothbake::model::{Integration, Patch};
use common::*;
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
