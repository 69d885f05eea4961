//! The editor's background bake, stage by stage: for each built-in fabric (or the ones
//! named), the seconds of its bake (to the table file's bytes), of the error's measurement
//! and of the sample taps for the built-in scene's environment samples, at the default
//! layout and resolution, and their sums over the fabrics: what the progress bar's stage
//! shares follow (`STAGE_SHARES` in src/editor/background.rs).
//!
//! `cargo run --profile ci --example background_bake_stages [-- FABRIC...] [--threads N]`

use clothbake::editor::background::{BackgroundBake, default_threads};
use clothbake::formats::fabric_toml::FabricSet;
use clothbake::scene::Scene;
use clothbake::table::Layout;

fn main() {
    let mut names = Vec::new();
    let mut threads = default_threads();
    let mut args = std::env::args().skip(1);
    while let Some(arg) = args.next() {
        match arg.as_str() {
            "--threads" => {
                threads = args
                    .next()
                    .and_then(|n| n.parse().ok())
                    .expect("--threads N");
            }
            name => names.push(name.to_string()),
        }
    }
    let set = FabricSet::builtin();
    let fabrics = set.select(&names).expect("built-in fabric names");
    let samples = Scene::builtin().environment.samples;
    let layout = Layout::DEFAULT;
    println!(
        "{layout} at resolution {}, taps for {samples} samples, {threads} threads",
        layout.default_resolution()
    );
    let mut sums = [0.0; 3];
    for fabric in fabrics {
        let name = fabric.name.clone();
        let baked = BackgroundBake::start_with_threads(
            fabric,
            layout,
            layout.default_resolution(),
            Some(samples),
            threads,
        )
        .wait()
        .expect("the bake finishes");
        let stages = [
            baked.bake_seconds,
            baked.measure_seconds,
            baked.taps_seconds,
        ];
        println!(
            "{name}: bake {:.2} s, error {:.2} s, taps {:.2} s",
            stages[0], stages[1], stages[2]
        );
        for (sum, s) in sums.iter_mut().zip(stages) {
            *sum += s;
        }
    }
    let total: f64 = sums.iter().sum();
    println!(
        "sum: bake {:.2} s, error {:.2} s, taps {:.2} s; shares {:.3} / {:.3} / {:.3}",
        sums[0],
        sums[1],
        sums[2],
        sums[0] / total,
        sums[1] / total,
        sums[2] / total
    );
}
