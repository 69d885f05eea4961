//! The environment light's measured front: image error against the CPU reference and GPU
//! frame time, per fabric and environment, for K filtered importance samples per pixel with
//! and without the map's compact bright sources lit as lights (docs/sampling.md#measured).
//!
//! ```sh
//! cargo run --profile ci --example environment_front -- [SIZE] [REFERENCE_SAMPLES] [TIME_SIZE] [ENVS] [FABRICS] [lights]
//! ```
//!
//! Defaults: 128, 2048, 0, every built-in environment, every fabric of the built-in scene
//! (ENVS and FABRICS comma-separated). Each fabric's table from `tables/` (bake first), the
//! environment alone (with the scene's two lights as well when the last argument is `lights`),
//! the built-in scene's camera and drape. One CPU reference per fabric and environment
//! (direct evaluation's resonant quadrature, the map by multiple importance sampling), and a
//! second at a quarter of its samples, whose distance from the first gives the reference's own
//! noise: with independent errors of variance σ² / N, ‖r_N/4 − r_N‖ ≈ σ·√(4/N + 1/N), so the
//! noise of r_N is that distance over √5. Frame times at TIME_SIZE² (0: none) are the median
//! of 5 frames on whatever adapter wgpu finds, of the built-in scene (its lights) with the sky.
//!
//! With `ENVIRONMENT_FRONT_REFERENCES=DIR` the references are read from DIR when there
//! (EXR, named by environment, fabric, size, samples and lights) and written there when not,
//! so that a change to the GPU side is measured again in minutes. They depend on the model,
//! the scene and the sampler: empty DIR when any of those changes.

use clothbake::evaluator::table::BakedTable;
use clothbake::evaluator::{EvaluationContext, Evaluator};
use clothbake::formats::fabric_toml::FabricSet;
use clothbake::gpu::{GpuContext, GpuSampleTaps};
use clothbake::lighting::GeneratedEnvironment;
use clothbake::lighting::bright_sources::MAX_SOURCES;
use clothbake::model::{Integration, Patch, ResonantNodes};
use clothbake::render::image::{image_error, read_linear_exr, write_linear_exr};
use clothbake::render::reference::{self, ReferenceEnvironment};
use clothbake::render::{FrameSettings, GpuEnvironment, Headless};
use clothbake::scene::Scene;
use clothbake::scene::mesh::Mesh;

const SAMPLE_COUNTS: [u32; 5] = [16, 32, 64, 96, 128];

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let arg = |i: usize, default: u32| -> u32 {
        std::env::args()
            .nth(i)
            .map_or(default, |a| a.parse().expect("a number"))
    };
    let (size, reference_samples, time_size) = (arg(1, 128), arg(2, 2048), arg(3, 0));
    let list = |i: usize| {
        std::env::args()
            .nth(i)
            .map(|a| a.split(',').map(String::from).collect::<Vec<_>>())
    };
    let environments = list(4);
    let fabrics = list(5);
    let with_lights = std::env::args().nth(6).is_some_and(|a| a == "lights");
    let mut scene = Scene::builtin();
    if !with_lights {
        scene.lights.clear();
    }
    let set = FabricSet::load_or_builtin(None)?;
    let mesh = Mesh::from_spec(&scene.mesh)?;
    let context = GpuContext::new()?;
    println!("adapter: {}", context.adapter);
    println!(
        "{size}² image, reference of {reference_samples} MIS pairs per pixel; error: relative \
         L2 of linear radiance, {}",
        if with_lights {
            "environment and the scene's lights"
        } else {
            "environment alone"
        }
    );
    let evaluator = BakedTable { path: None };
    let settings = FrameSettings::from_scene(&scene);
    // SIZE 0: frame times only.
    let chosen = |g: &GeneratedEnvironment| {
        size > 0
            && environments
                .as_ref()
                .is_none_or(|e| e.iter().any(|n| n == g.name()))
    };
    for generated in GeneratedEnvironment::ALL.into_iter().filter(chosen) {
        let map = generated.environment();
        let start = std::time::Instant::now();
        let splits = [0, MAX_SOURCES].map(|n| map.split_bright_sources(n));
        println!(
            "\n## {}: {} (split in {:.2} s)",
            generated.name(),
            splits[1],
            start.elapsed().as_secs_f64() / 2.0
        );
        let gpu_maps = splits
            .iter()
            .map(|split| GpuEnvironment::split(&context, split))
            .collect::<Result<Vec<_>, _>>()?;
        for name in fabrics.as_ref().unwrap_or(&scene.fabrics) {
            let fabric = set.require(name)?;
            let evaluation = evaluator.prepare(fabric, &EvaluationContext::default())?;
            let brdf = evaluation.gpu(&context)?;
            let sampler = evaluation.sampler();
            let taps = SAMPLE_COUNTS
                .iter()
                .map(|&k| GpuSampleTaps::new(&context, &evaluation.sample_taps(&sampler, k)))
                .collect::<Result<Vec<_>, _>>()?;
            let mut headless = Headless::new(&context, &mesh, brdf.as_ref(), size, size)?;
            let gbuffer = headless.gbuffer(&context, &settings)?;
            let patch = Patch::new(fabric, Integration::Resonant(ResonantNodes::DEFAULT));
            let reference_with = |samples: u32| -> Result<_, Box<dyn std::error::Error>> {
                let cached = std::env::var_os("ENVIRONMENT_FRONT_REFERENCES").map(|dir| {
                    std::path::PathBuf::from(dir).join(format!(
                        "{}-{name}-{size}-{samples}{}.exr",
                        generated.name(),
                        if with_lights { "-lights" } else { "" }
                    ))
                });
                if let Some(path) = cached.as_ref().filter(|p| p.exists()) {
                    return Ok(read_linear_exr(path)?);
                }
                let environment = ReferenceEnvironment {
                    map: &map,
                    sampler: &sampler,
                    samples,
                };
                let image = reference::shade(&gbuffer, &settings, &patch, Some(&environment));
                if let Some(path) = cached {
                    write_linear_exr(&path, &image)?;
                }
                Ok(image)
            };
            let start = std::time::Instant::now();
            let reference = reference_with(reference_samples)?;
            let seconds = start.elapsed().as_secs_f64();
            let quarter = reference_with((reference_samples / 4).max(1))?;
            let noise = image_error(&quarter, &reference, 1.0)?.relative_l2 / 5f64.sqrt();
            print!(
                "{name}: reference {seconds:.1} s, its noise {:.2}%;",
                100.0 * noise
            );
            // A map without sources is measured once.
            let kinds = if splits[1].sources.is_empty() { 1 } else { 2 };
            for (split, gpu_map) in splits.iter().zip(&gpu_maps).take(kinds) {
                print!(" {} sources:", split.sources.len());
                for (k, taps) in SAMPLE_COUNTS.into_iter().zip(&taps) {
                    headless.renderer.set_environment(&context, gpu_map, taps)?;
                    let mut settings = settings.clone();
                    settings.environment_samples = k;
                    let output = headless.render(&context, &settings, 1)?;
                    let error = image_error(&output.linear, &reference, 1.0)?;
                    print!(" K={k} {:.2}%", 100.0 * error.relative_l2);
                }
                print!(";");
            }
            println!();
        }
    }
    if time_size > 0 {
        // The frame a user sees: the scene's lights and the sky, whose sun is a source.
        let full = Scene::builtin();
        let settings = FrameSettings::from_scene(&full);
        let map = GeneratedEnvironment::Sky.environment();
        let fabric = set.require(&full.fabrics[0])?;
        let evaluation = evaluator.prepare(fabric, &EvaluationContext::default())?;
        let brdf = evaluation.gpu(&context)?;
        let sampler = evaluation.sampler();
        let taps = SAMPLE_COUNTS
            .iter()
            .map(|&k| GpuSampleTaps::new(&context, &evaluation.sample_taps(&sampler, k)))
            .collect::<Result<Vec<_>, _>>()?;
        let mut headless = Headless::new(&context, &mesh, brdf.as_ref(), time_size, time_size)?;
        let time = |headless: &Headless,
                    label: &str,
                    samples: u32|
         -> Result<(), Box<dyn std::error::Error>> {
            let mut settings = settings.clone();
            settings.environment_samples = samples;
            let output = headless.render(&context, &settings, 5)?;
            println!("| {label} | {:.1} ms |", output.timing.median_ms());
            Ok(())
        };
        println!(
            "\n{time_size}² frames of the built-in scene (its lights and the sky), {}, median of 5:\n",
            full.fabrics[0]
        );
        println!("| frame | median |\n|---|---:|");
        time(&headless, "lights only", 0)?;
        for sources in [MAX_SOURCES, 0] {
            let gpu_map = GpuEnvironment::split(&context, &map.split_bright_sources(sources))?;
            for (k, taps) in SAMPLE_COUNTS.into_iter().zip(&taps) {
                headless
                    .renderer
                    .set_environment(&context, &gpu_map, taps)?;
                time(&headless, &format!("+ sky, sources {sources}, K = {k}"), k)?;
            }
        }
    }
    Ok(())
}
