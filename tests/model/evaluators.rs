//! The evaluator registry's conformance suite: every registered evaluator, reached only
//! through `clothbake::evaluator::EVALUATORS`, with its default spelling and on every built-in
//! fabric, keeps the interface's promises. A unit added to the registry is tested here with
//! no other edit.

use crate::common::{builtin, temp_dir};
use clothbake::bake::job::{BakeJob, Outcome, ResolutionChoice, run};
use clothbake::evaluator::{EVALUATORS, EvaluationContext, parse};
use clothbake::measure::direction_sets::{highlight_pairs, uniform_pairs};
use clothbake::model::Fabric;
use clothbake::table::Layout;
use glam::DVec3;

/// Pairs per fabric and evaluator: enough to cover both sets' shapes (grazing, highlight),
/// few enough that the direct rule's thousands of samples per pair stay cheap.
const PAIRS: usize = 64;

/// A tables directory holding a small thread_frame table of every built-in fabric, so that
/// the `table` evaluator's default (TABLES/FABRIC.exr) has something to read.
fn tables_with_every_fabric(dir: &std::path::Path) {
    let job = BakeJob {
        fabrics: builtin(),
        layout: Layout::ALL[0],
        resolution: ResolutionChoice::Fixed(Layout::ALL[0].resolution_ladder()[0]),
        out: dir.to_path_buf(),
        force: true,
        environment_samples: None,
    };
    let progress = |_: &str, _: u32, _: u64| -> Box<dyn Fn() + Sync> { Box::new(|| {}) };
    run(&job, &progress, &mut |_: &Fabric, _: &Outcome| {}).unwrap();
}

fn pairs() -> Vec<(DVec3, DVec3)> {
    let mut pairs = uniform_pairs(PAIRS / 2, 0x5eed_e001);
    pairs.extend(highlight_pairs(&builtin()[0], PAIRS / 2, 0x5eed_e002));
    pairs
}

#[test]
fn every_registered_evaluator_keeps_its_promises() {
    let tables = temp_dir("evaluators");
    tables_with_every_fabric(&tables);
    let context = EvaluationContext {
        tables: tables.to_path_buf(),
    };
    let pairs = pairs();
    for unit in EVALUATORS {
        let evaluator = (unit.parse)(None).unwrap();
        let spelling = evaluator.spelling();
        assert_eq!(parse(&spelling).unwrap().spelling(), spelling);
        for (k, fabric) in builtin().into_iter().enumerate() {
            let evaluation = evaluator.prepare(&fabric, &context).unwrap();
            let label = format!("{spelling} on {}", fabric.name);
            assert!(!evaluation.label().is_empty(), "{label}: empty label");
            let single: Vec<DVec3> = pairs
                .iter()
                .map(|&(wi, wo)| evaluation.eval(wi, wo))
                .collect();
            // Batches compute the same values as single pairs, bit for bit.
            assert_eq!(
                evaluation.eval_batch(&pairs),
                single,
                "{label}: batch differs"
            );
            for (&(wi, wo), f) in pairs.iter().zip(&single) {
                assert!(
                    f.is_finite() && f.min_element() >= 0.0,
                    "{label}: F({wi}, {wo}) = {f}"
                );
            }
            // Below the horizon F is 0 (the patch is one-sided).
            let (wi, wo) = pairs[0];
            let below = DVec3::new(wi.x, wi.y, -wi.z);
            assert_eq!(evaluation.eval(below, wo), DVec3::ZERO, "{label}: below");
            assert!(
                single.iter().any(|f| f.max_element() > 0.0),
                "{label}: all zero"
            );
            // The sampler that fits it draws directions with a positive density (on one
            // fabric: a fabric's sampler takes a resonant quadrature over a grid to build).
            if k > 0 {
                continue;
            }
            let sampler = evaluation.sampler();
            let drawn = (0..16)
                .filter_map(|k| sampler.sample(wo, [(k as f64 + 0.5) / 16.0, 0.37, 0.61]))
                .filter(|s| s.pdf > 0.0)
                .count();
            assert!(drawn > 0, "{label}: the sampler drew nothing");
        }
        println!(
            "{spelling}: {} fabrics × {} pairs",
            builtin().len(),
            pairs.len()
        );
    }
}

#[test]
fn the_table_evaluator_reports_a_missing_or_stale_table() {
    let tables = temp_dir("evaluators-missing");
    let context = EvaluationContext {
        tables: tables.to_path_buf(),
    };
    let fabric = builtin().remove(0);
    let message = parse("table")
        .unwrap()
        .prepare(&fabric, &context)
        .err()
        .expect("no table there")
        .to_string();
    assert!(message.contains("bake it first"), "{message}");
    tables_with_every_fabric(&tables);
    let mut changed = fabric.clone();
    changed.thread1.albedo[0] *= 0.5;
    let message = parse("table")
        .unwrap()
        .prepare(&changed, &context)
        .err()
        .expect("baked from other parameters")
        .to_string();
    assert!(message.contains("bake it again"), "{message}");
}
