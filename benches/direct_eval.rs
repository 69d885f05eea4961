//! Nanoseconds per evaluation of F(wi, wo) for each built-in fabric: the converged direct
//! evaluation, paper mode at N = 8, 32, 128 and 1024 samples per thread, the resonant
//! quadrature at its default node counts (`resonant_default`, `ResonantNodes::DEFAULT`), and
//! the CPU lookup of each layout's default table (baked at the layout's default resolution during setup):
//! `table_lookup` is thread_frame, `table_lookup_grid4d` grid4d.
//!
//! `cargo bench --bench direct_eval`; each figure is the median time of one batch of
//! direction pairs divided by the batch size, reported by criterion per element. Sample
//! counts and times are set so that the whole run takes about two minutes.

use clothbake::bake::bake;
use clothbake::fabric_file::FabricSet;
use clothbake::model::{Integration, Patch, ResonantNodes};
use clothbake::table::Layout;
use criterion::{
    BenchmarkGroup, BenchmarkId, Criterion, SamplingMode, Throughput, criterion_group,
    criterion_main, measurement::WallTime,
};
use glam::DVec3;
use std::hint::black_box;
use std::time::Duration;

/// Short runs: 20 samples over 2 s after a 0.5 s warm-up. A batch of the direct evaluation
/// takes 15-50 ms, so flat sampling (the same iteration count per sample) keeps it within
/// that time; the medians move by a few percent between runs, less than the ratios
/// compared.
fn configure(group: &mut BenchmarkGroup<WallTime>) {
    group.sample_size(20);
    group.warm_up_time(Duration::from_millis(500));
    group.measurement_time(Duration::from_secs(2));
    group.sampling_mode(SamplingMode::Flat);
}

/// A fixed batch of upper-hemisphere direction pairs from a golden-ratio sequence, so every
/// run and every fabric times the same work.
fn direction_pairs(count: usize) -> Vec<(DVec3, DVec3)> {
    let direction = |u: f64, v: f64| {
        let z = 1.0 - u; // uniform in solid angle over the upper hemisphere
        let r = (1.0 - z * z).max(0.0).sqrt();
        let phi = std::f64::consts::TAU * v;
        DVec3::new(r * phi.cos(), r * phi.sin(), z.max(1e-3)).normalize()
    };
    let g = [
        0.754_877_666_246_692_7,
        0.569_840_290_998_053_3,
        0.438_289_107_045_047_3,
        0.342_979_643_571_025_6,
    ];
    (0..count)
        .map(|i| {
            let k = i as f64 + 0.5;
            let u = g.map(|a| (k * a).fract());
            (direction(u[0], u[1]), direction(u[2], u[3]))
        })
        .collect()
}

fn bench_direct_eval(c: &mut Criterion) {
    let pairs = direction_pairs(256);
    let mut group = c.benchmark_group("eval");
    configure(&mut group);
    group.throughput(Throughput::Elements(pairs.len() as u64));
    for fabric in FabricSet::builtin().fabrics() {
        for (label, integration) in [
            ("direct", Integration::Direct),
            ("paper_n8", Integration::Paper(8)),
            ("paper_n32", Integration::Paper(32)),
            // Where paper mode reaches the resonant rule's error (0.03–0.2%): N = 128 for
            // satin charmeuse, 1024 for satin back (report/REPORT.md).
            ("paper_n128", Integration::Paper(128)),
            ("paper_n1024", Integration::Paper(1024)),
            (
                "resonant_default",
                Integration::Resonant(ResonantNodes::DEFAULT),
            ),
        ] {
            let patch = Patch::new(fabric, integration);
            group.bench_function(BenchmarkId::new(label, &fabric.name), |b| {
                b.iter(|| {
                    pairs
                        .iter()
                        .map(|&(wi, wo)| patch.eval(black_box(wi), black_box(wo)))
                        .sum::<DVec3>()
                })
            });
        }
    }
    group.finish();
}

fn bench_lookup(c: &mut Criterion) {
    let pairs = direction_pairs(256);
    let mut group = c.benchmark_group("eval");
    configure(&mut group);
    group.throughput(Throughput::Elements(pairs.len() as u64));
    for (label, layout) in [
        ("table_lookup", Layout::THREAD_FRAME),
        ("table_lookup_grid4d", Layout::GRID4D),
    ] {
        for fabric in FabricSet::builtin().fabrics() {
            let table = bake(fabric, layout, layout.default_resolution(), &|| {}).expect("bake");
            group.bench_function(BenchmarkId::new(label, &fabric.name), |b| {
                b.iter(|| {
                    pairs
                        .iter()
                        .map(|&(wi, wo)| table.lookup(black_box(wi), black_box(wo)))
                        .sum::<DVec3>()
                })
            });
        }
    }
    group.finish();
}

criterion_group!(benches, bench_direct_eval, bench_lookup);
criterion_main!(benches);
