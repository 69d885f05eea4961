//! Seconds per fit (`clothbake::fit::fit`): linen_plain and silk_shot moved by ±20%, 500
//! noisy samples, fitted like the unmoved fabric with the default options but one
//! broadened stage ([8°, 0°]); the figure to watch when the fit's inner loop (the resonant
//! quadrature, the finite-difference Jacobian) changes. The full round trip on all six
//! fabrics with 2,000 samples each is `cargo run --profile ci --example fit_round_trips`.
//!
//! `cargo bench --bench fit`

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

criterion_group!(benches, bench_fit);
criterion_main!(benches);
