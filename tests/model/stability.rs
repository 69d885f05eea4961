//! Stability on the model's hard cases (docs/model.md#hard-numerical-cases): the curated list of tests/common and a dense sweep
//! of the hemisphere pair. Every value must be finite and non-negative.

use crate::common::*;
use clothbake::model::{Integration, Patch};
use rayon::prelude::*;

fn assert_sane(name: &str, integration: Integration, f: glam::DVec3) {
    assert!(
        f.is_finite() && f.min_element() >= 0.0,
        "{name} ({integration:?}): F = {f}"
    );
}

#[test]
fn hard_cases_are_finite_and_non_negative() {
    let cases = hard_cases();
    assert!(
        cases.len() > 1000,
        "the curated list lost its cases: {}",
        cases.len()
    );
    let mut patches = std::collections::HashMap::new();
    for case in &cases {
        for integration in [
            Integration::Direct,
            Integration::Paper(1),
            Integration::Paper(8),
        ] {
            let patch = patches
                .entry((case.fabric.name.clone(), format!("{integration:?}")))
                .or_insert_with(|| Patch::new(&case.fabric, integration));
            assert_sane(&case.name, integration, patch.eval(case.wi, case.wo));
        }
    }
    println!("{} hard cases finite and non-negative", cases.len());
}

#[test]
fn below_or_on_the_horizon_gives_zero() {
    for fabric in builtin().iter().chain(&stressed_fabrics()) {
        let patch = Patch::new(fabric, Integration::Paper(16));
        for (wi, wo) in [
            (dir(-10.0, 30.0), dir(40.0, 10.0)),
            (dir(40.0, 10.0), dir(-10.0, 30.0)),
            (dir(0.0, 30.0), dir(40.0, 10.0)),
            (dir(40.0, 10.0), dir(0.0, 0.0)),
            (-glam::DVec3::Z, glam::DVec3::Z),
        ] {
            assert_eq!(
                patch.eval(wi, wo),
                glam::DVec3::ZERO,
                "{}: {wi} {wo}",
                fabric.name
            );
        }
    }
}

#[test]
fn dense_hemisphere_sweep_is_finite_and_non_negative() {
    let directions = hemisphere_sweep();
    for fabric in builtin() {
        let patch = Patch::new(&fabric, Integration::Direct);
        let worst = directions
            .par_iter()
            .map(|&wi| {
                directions.iter().fold(0.0_f64, |worst, &wo| {
                    let f = patch.eval(wi, wo);
                    assert_sane(&fabric.name, Integration::Direct, f);
                    worst.max(f.max_element())
                })
            })
            .reduce(|| 0.0, f64::max);
        println!(
            "{}: {} pairs, largest F component {worst:.4e}",
            fabric.name,
            directions.len().pow(2)
        );
    }
}
