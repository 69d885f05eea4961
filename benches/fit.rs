//! Seconds per fit (`clothbake::fit::fit`).
//!
//! `fit/…`: linen_plain and silk_shot moved by ±20%, 500 noisy samples, fitted like the
//! unmoved fabric with the default options but one broadened stage ([8°, 0°]); the figure to
//! watch when the fit's inner loop (the resonant quadrature, the finite-difference Jacobian)
//! changes.
//!
//! `fit_2000/…`: whole fits with the default options, as users run them, on 2,000 samples
//! (`clothbake::fit::cases`, the cases `examples/fit_round_trips.rs` measures the errors of):
//! the slowest of each kind there, the satin charmeuse's round trip and its back by weave.
//! About 40 s each, ten each: `cargo bench --profile ci --bench fit -- fit_2000`.
//!
//! `cargo bench --profile ci --bench fit`
use clothbake::fit::cases::{CASE_SAMPLES, CaseKind, fit_case};
use clothbake::fit::samples::synthetic_samples;
use clothbake::fit::solve::FitOptions;
use clothbake::fit::{LikeFabric, Parametrisation, Samples, fit, perturbed};
use clothbake::formats::fabric_toml::FabricSet;
use clothbake::measure::direction_sets::{highlight_pairs, uniform_pairs};
use criterion::{Criterion, SamplingMode, criterion_group, criterion_main};
use std::hint::black_box;
use std::time::Duration;

fn bench_fit(c: &mut Criterion) {
    let mut group = c.benchmark_group("fit");
    group.sample_size(10);
    group.warm_up_time(Duration::from_millis(100));
    group.measurement_time(Duration::from_secs(10));
    group.sampling_mode(SamplingMode::Flat);
    let options = FitOptions {
        broadening_deg: &[&[8.0, 0.0]],
        ..FitOptions::default()
    };
    let set = FabricSet::builtin();
    for name in ["linen_plain", "silk_shot"] {
        let fabric = set.get(name).unwrap();
        let like = LikeFabric::new(fabric, None);
        let moved = like.fabric(&perturbed(&like, 0.2, 1));
        let mut pairs = uniform_pairs(400, 2);
        pairs.extend(highlight_pairs(&moved, 100, 3));
        let samples = Samples {
            samples: synthetic_samples(&moved, &pairs, 0.03, 4),
            origin: "bench".into(),
            sha256: String::new(),
        };
        group.bench_function(name, |b| {
            b.iter(|| black_box(fit(&like, &samples, &options, &|_| {}).unwrap().values))
        });
    }
    group.finish();
}

fn bench_fit_2000(c: &mut Criterion) {
    let mut group = c.benchmark_group("fit_2000");
    group.sample_size(10);
    group.warm_up_time(Duration::from_millis(100));
    group.measurement_time(Duration::from_secs(60));
    group.sampling_mode(SamplingMode::Flat);
    for (name, kind, label) in [
        (
            "polyester_satin_charmeuse",
            CaseKind::RoundTrip,
            "round_trip_polyester_satin_charmeuse",
        ),
        (
            "polyester_satin_charmeuse_back",
            CaseKind::ByWeave,
            "by_weave_polyester_satin_charmeuse_back",
        ),
    ] {
        let case = fit_case(name, kind, CASE_SAMPLES).expect("a built-in woven fabric");
        let options = FitOptions::default();
        group.bench_function(label, |b| {
            b.iter(|| {
                black_box(
                    fit(
                        case.parametrisation.as_ref(),
                        &case.samples,
                        &options,
                        &|_| {},
                    )
                    .unwrap()
                    .values,
                )
            })
        });
    }
    group.finish();
}

criterion_group!(benches, bench_fit, bench_fit_2000);
criterion_main!(benches);
