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

use clothbake::fit::solve::{FitOptions, ResidualScale, relative_rms};
use clothbake::fit::weave::WeaveParameters;
use clothbake::fit::{
    LikeFabric, Parametrisation, Samples, fit, perturbed, samples::synthetic_samples,
};
use clothbake::formats::fabric_toml::FabricSet;
use clothbake::measure::direction_sets::{highlight_pairs, uniform_pairs};
use clothbake::weave::{Fibre, NamedWeave, Weave};
use std::time::Instant;

/// The weave and fibre of a built-in fabric (`--by-weave`): the paper's five woven fabrics.
/// Crepe de chine and shot silk are plain (taffeta) weaves; the back of a warp satin, its
/// weft floats along x (`--back --swap`), is again a warp satin.
fn woven_as(name: &str) -> Option<(&'static str, Fibre)> {
    match name {
        "linen_plain" => Some(("plain", Fibre::Linen)),
        "silk_crepe_de_chine" | "silk_shot" => Some(("plain", Fibre::Silk)),
        "polyester_satin_charmeuse" | "polyester_satin_charmeuse_back" => {
            Some(("satin:5", Fibre::Polyester))
        }
        _ => None,
    }
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mut options = FitOptions::default();
    let mut names = Vec::new();
    let mut verbose = false;
    let mut by_weave = false;
    let mut it = args.iter();
    let (mut uniform_count, mut highlight_count) = (1600, 400);
    while let Some(a) = it.next() {
        match a.as_str() {
            "--absolute" => options.residual = ResidualScale::Absolute,
            "--floor" => {
                let floor = it.next().unwrap().parse().unwrap();
                options.residual = ResidualScale::Relative { floor };
            }
            "--starts" => options.starts = it.next().unwrap().parse().unwrap(),
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
            "--samples" => {
                let total: usize = it.next().unwrap().parse().unwrap();
                uniform_count = total * 4 / 5;
                highlight_count = total - uniform_count;
            }
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
    for fabric in &fabrics {
        // Seeds by the fabric's place in the built-in set, whichever are run.
        let k = set
            .fabrics()
            .iter()
            .position(|f| f.name == fabric.name)
            .unwrap();
        let seed = 0x46_0000 + 16 * k as u64;
        let like = LikeFabric::new(fabric, None);
        let by_weave_parameters;
        let (parametrisation, moved_values, moved): (&dyn Parametrisation, _, _) = if by_weave {
            // The fabric itself, described by its weave and fibre alone.
            let Some((spelling, fibre)) = woven_as(&fabric.name) else {
                continue;
            };
            let draft = spelling.parse::<NamedWeave>().unwrap().draft();
            by_weave_parameters =
                WeaveParameters::new(&Weave::new(draft), &fabric.name, Some(fibre.eta()));
            let start = by_weave_parameters.start();
            (&by_weave_parameters, start, fabric.clone())
        } else {
            let moved_values = perturbed(&like, 0.3, seed);
            let moved = like.fabric(&moved_values);
            (&like, moved_values, moved)
        };
        moved.validate().expect("moved fabric valid");
        let mut pairs = uniform_pairs(uniform_count, seed + 1);
        pairs.extend(highlight_pairs(&moved, highlight_count, seed + 2));
        let samples = Samples {
            samples: synthetic_samples(&moved, &pairs, 0.03, seed + 3),
            origin: "synthetic".into(),
            sha256: String::new(),
        };
        let start = Instant::now();
        let stage_log = std::cell::RefCell::new(Vec::<(usize, usize, usize, f64, f64)>::new());
        let report = fit(parametrisation, &samples, &options, &|p| {
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
        let truth = |pairs: Vec<_>| synthetic_samples(&moved, &pairs, 0.0, 0);
        let uniform = relative_rms(&report.fabric, &truth(uniform_pairs(1000, seed + 4)));
        let highlight = relative_rms(
            &report.fabric,
            &truth(highlight_pairs(&moved, 1000, seed + 5)),
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
                .zip(&moved_values)
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
