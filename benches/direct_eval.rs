//! Nanoseconds per evaluation of F(wi, wo) for each built-in fabric: the converged direct
//! evaluation, paper mode at N = 8, 32, 128 and 1024 samples per thread, the resonant
//! quadrature at its default node counts (`resonant_default`, `ResonantNodes::DEFAULT`), and
//! the CPU lookups of every registered layout's default table (baked at the layout's default
//! resolution during setup): `lookup_f32_<layout>` is `Table::lookup_f32` (the fast path),
//! `lookup_batch_<layout>` `Table::lookup_batch` over the whole pair set, and
//! `lookup_f64_<layout>` the f64 reference lookup `Table::lookup`.
//!
//! `cargo bench --bench direct_eval`; each figure is the median time of one batch of
//! direction pairs divided by the batch size, reported by criterion per element. Sample
//! counts and times are set so that the whole run takes about two minutes.

use clothbake::bake::bake;
use clothbake::formats::fabric_toml::FabricSet;
use clothbake::model::{Integration, Patch, ResonantNodes};
use clothbake::table::{BATCH_LANES, BatchLanes, Layout, split_frame};
use criterion::{
    BenchmarkGroup, BenchmarkId, Criterion, SamplingMode, Throughput, criterion_group,
    criterion_main, measurement::WallTime,
};
use glam::{DVec3, Vec3};
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
    let pairs_f32: Vec<(Vec3, Vec3)> = pairs
        .iter()
        .map(|&(wi, wo)| (wi.as_vec3(), wo.as_vec3()))
        .collect();
    let mut out = vec![Vec3::ZERO; pairs.len()];
    let mut group = c.benchmark_group("eval");
    configure(&mut group);
    group.throughput(Throughput::Elements(pairs.len() as u64));
    for &layout in Layout::ALL {
        for fabric in FabricSet::builtin().fabrics() {
            let table = bake(fabric, layout, layout.default_resolution(), &|| {}).expect("bake");
            let id = |kind: &str| BenchmarkId::new(format!("lookup_{kind}_{layout}"), &fabric.name);
            group.bench_function(id("f32"), |b| {
                b.iter(|| {
                    pairs_f32
                        .iter()
                        .map(|&(wi, wo)| table.lookup_f32(black_box(wi), black_box(wo)))
                        .sum::<Vec3>()
                })
            });
            group.bench_function(id("batch"), |b| {
                b.iter(|| table.lookup_batch(black_box(&pairs_f32), &mut out))
            });
            group.bench_function(id("f64"), |b| {
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

/// What split_frame's batch lookup spends on its point masses (the flat segments it
/// evaluates by the sample kernel instead of tabulating): `point_masses` is both threads'
/// `PointSamples::sums` over the same pairs, eight lanes at a time, as `lookup_batch` runs it.
/// Beside `lookup_batch_split_frame` and `lookup_batch_thread_frame` of the same run it
/// splits split_frame's cost into its table part and its point masses.
fn bench_point_masses(c: &mut Criterion) {
    let pairs: Vec<(Vec3, Vec3)> = direction_pairs(256)
        .iter()
        .map(|&(wi, wo)| (wi.as_vec3(), wo.as_vec3()))
        .collect();
    let mut group = c.benchmark_group("eval");
    configure(&mut group);
    group.throughput(Throughput::Elements(pairs.len() as u64));
    for fabric in FabricSet::builtin().fabrics() {
        let geometry = split_frame::Geometry::new(fabric, Layout::SPLIT_FRAME.default_resolution());
        if geometry.threads.iter().all(|t| t.points.is_empty()) {
            continue;
        }
        group.bench_function(BenchmarkId::new("point_masses", &fabric.name), |b| {
            b.iter(|| {
                let mut total = BatchLanes::splat(0.0);
                for chunk in pairs.chunks_exact(BATCH_LANES) {
                    let wi: [Vec3; BATCH_LANES] = std::array::from_fn(|k| black_box(chunk[k].0));
                    let wo: [Vec3; BATCH_LANES] = std::array::from_fn(|k| black_box(chunk[k].1));
                    for thread in &geometry.threads {
                        let [r, t, p] = thread.samples.sums::<BatchLanes>(&wi, &wo);
                        total += r + t + p;
                    }
                }
                total
            })
        });
    }
    group.finish();
}

criterion_group!(benches, bench_direct_eval, bench_lookup, bench_point_masses);
criterion_main!(benches);
