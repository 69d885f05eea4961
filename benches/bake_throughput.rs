//! Bake throughput, texels per second, for each built-in fabric and layout at a small
//! resolution (thread_frame at 16, grid4d at 8), on all cores of rayon's global pool.
//!
//! `cargo bench --bench bake_throughput`; criterion reports the median time of one bake and
//! the throughput in texels (of every plane, masking planes included) per second. Small
//! resolutions keep the run to about a minute; the bake time against resolution, and the
//! speed-up from one to two threads, are in `clothbake report`.

use clothbake::bake::bake;
use clothbake::formats::fabric_toml::FabricSet;
use clothbake::table::Layout;
use criterion::{
    BenchmarkId, Criterion, SamplingMode, Throughput, criterion_group, criterion_main,
};
use std::hint::black_box;
use std::time::Duration;

fn bench_bake(c: &mut Criterion) {
    let mut group = c.benchmark_group("bake");
    // A bake takes 0.1-1 s here: flat sampling with few samples bounds the run time while
    // the median stays stable to a few percent.
    group.sampling_mode(SamplingMode::Flat);
    group.sample_size(10);
    group.warm_up_time(Duration::from_millis(500));
    group.measurement_time(Duration::from_secs(3));
    for (layout, resolution) in [(Layout::THREAD_FRAME, 16), (Layout::GRID4D, 8)] {
        for fabric in FabricSet::builtin().fabrics() {
            let texels: usize = layout
                .plane_specs(fabric, resolution)
                .iter()
                .map(|s| s.texel_count())
                .sum();
            group.throughput(Throughput::Elements(texels as u64));
            let id = BenchmarkId::new(format!("{layout}_{resolution}"), &fabric.name);
            group.bench_function(id, |b| {
                b.iter(|| bake(black_box(fabric), layout, resolution, &|| {}).expect("bake"))
            });
        }
    }
    group.finish();
}

criterion_group!(benches, bench_bake);
criterion_main!(benches);
