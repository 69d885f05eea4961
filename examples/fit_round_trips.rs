//! The fit's round trip on the six built-in fabrics (issue 46): each fabric's parameters
//! moved by up to ±30% (own seeds), 2,000 samples of the moved fabric's F (1,600 uniform
//! pairs, 400 highlight pairs) with 3% multiplicative noise, fitted `--like` the unmoved
//! fabric; the fitted fabric's relative RMS against the moved one on 1,000 fresh uniform and
//! 1,000 fresh highlight pairs (direct evaluation), and the fit's wall time.
//!
//! With `--by-weave`, each of the paper's five woven fabrics is itself the truth, fitted from
//! its weave and fibre alone (`fit --weave DRAFT --fibre FIBRE`): the price of describing a
//! fabric by its weave.
//!
//! `cargo run --profile ci --example fit_round_trips [-- FABRIC... ] [--by-weave] [--absolute] [--starts N]`

use clothbake::fit::cases::{CASE_SAMPLES, CaseKind, fit_case};
use clothbake::fit::fit;
use clothbake::fit::samples::synthetic_samples;
use clothbake::fit::solve::{FitOptions, ResidualScale, relative_rms};
use clothbake::formats::fabric_toml::FabricSet;
use clothbake::measure::direction_sets::{highlight_pairs, uniform_pairs};
use std::time::Instant;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mut options = FitOptions::default();
    let mut names = Vec::new();
    let mut verbose = false;
    let mut by_weave = false;
    let mut it = args.iter();
    let mut sample_count = CASE_SAMPLES;
    while let Some(a) = it.next() {
        match a.as_str() {
            "--absolute" => options.residual = ResidualScale::Absolute,
            "--floor" => {
                let floor = it.next().unwrap().parse().unwrap();
                options.residual = ResidualScale::Relative { floor };
            }
            "--starts" => options.starts = Some(it.next().unwrap().parse().unwrap()),
            "--evaluations" => options.max_evaluations = it.next().unwrap().parse().unwrap(),
            "--broaden" => {
                // Schedules separated by '/', stages by ',': 20,10,5,2,0/10,5,2,0.
                let schedules: Vec<&'static [f64]> = it
                    .next()
                    .unwrap()
                    .split('/')
                    .map(|s| -> &'static [f64] {
                        Vec::leak(s.split(',').map(|b| b.parse().unwrap()).collect())
                    })
                    .collect();
                options.broadening_deg = Vec::leak(schedules);
            }
            "--coarse" => options.coarse_samples = it.next().unwrap().parse().unwrap(),
            "--step" => options.step = it.next().unwrap().parse().unwrap(),
            "--samples" => sample_count = it.next().unwrap().parse().unwrap(),
            "--verbose" => verbose = true,
            "--by-weave" => by_weave = true,
            name => names.push(name.to_string()),
        }
    }
    let set = FabricSet::builtin();
    let fabrics = set.select(&names).expect("known fabric names");
    println!("options: {options:?}");
    println!(
        "| fabric | params | fit rel. RMS | held-out (own) | uniform | highlight | start | time |"
    );
    println!("|---|---|---|---|---|---|---|---|");
    let kind = if by_weave {
        CaseKind::ByWeave
    } else {
        CaseKind::RoundTrip
    };
    for fabric in &fabrics {
        let Some(case) = fit_case(&fabric.name, kind, sample_count) else {
            continue;
        };
        let (parametrisation, moved_values, moved, samples, seed) = (
            case.parametrisation.as_ref(),
            &case.truth_values,
            &case.truth,
            &case.samples,
            case.seed,
        );
        moved.validate().expect("moved fabric valid");
        let start = Instant::now();
        let stage_log = std::cell::RefCell::new(Vec::<(usize, usize, usize, f64, f64)>::new());
        let report = fit(parametrisation, samples, &options, &|p| {
            let mut log = stage_log.borrow_mut();
            let t = start.elapsed().as_secs_f64();
            match log.last_mut() {
                Some(last) if last.0 == p.start && last.1 == p.stage => {
                    last.2 = p.evaluations;
                    last.3 = t;
                    last.4 = p.objective;
                }
                _ => log.push((p.start, p.stage, p.evaluations, t, p.objective)),
            }
        })
        .expect("fit");
        let seconds = start.elapsed().as_secs_f64();
        let truth = |pairs: Vec<_>| synthetic_samples(moved, &pairs, 0.0, 0);
        let uniform = relative_rms(&report.fabric, &truth(uniform_pairs(1000, seed + 4)));
        let highlight = relative_rms(
            &report.fabric,
            &truth(highlight_pairs(moved, 1000, seed + 5)),
        );
        println!(
            "| {} | {} | {:.2}% | {:.2}% | {:.2}% | {:.2}% | {}/{} ({} evals, {}) | {:.1} s |",
            fabric.name,
            parametrisation.parameters().len(),
            100.0 * report.fit_relative_rms,
            100.0 * report.holdout_relative_rms.unwrap_or(f64::NAN),
            100.0 * uniform,
            100.0 * highlight,
            report.best_start + 1,
            report.start_objectives.len(),
            report.evaluations,
            report.termination,
            seconds
        );
        if verbose {
            for (start, stage, evals, t, objective) in stage_log.borrow().iter() {
                println!(
                    "    start {start} stage {stage}: {evals} evaluations, until {t:.1} s, objective {objective:.3e}"
                );
            }
            for ((p, m), f) in parametrisation
                .parameters()
                .iter()
                .zip(moved_values)
                .zip(&report.values)
            {
                println!(
                    "    {:40} start {:9.4} moved {:9.4} fitted {:9.4}",
                    p.name, p.start, m, f
                );
            }
            println!("    objectives {:?}", report.start_objectives);
        }
        for d in &report.flat_directions {
            println!("    unconstrained: {d}");
        }
    }
}
