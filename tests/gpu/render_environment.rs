//! The environment light of the renderer (shaders/render/renderer.wgsl, `render_environment_light`):
//! the white furnace (radiance 1 everywhere, lights off: each pixel is the fabric's
//! directional albedo at its wo), the studio environment and the generated sky (with and
//! without its sun lit as a light) against the CPU reference, for
//! every built-in fabric, on the device wgpu finds (lavapipe in CI; printed).
//!
//! Needs a wgpu adapter; without a GPU, Mesa's lavapipe (`apt-get install -y
//! mesa-vulkan-drivers libvulkan1`). No adapter is a failure, not a skip.

use crate::common::*;

use clothbake::bake::bake;
use clothbake::evaluator::table::gpu::GpuTable;
use clothbake::gpu::{GpuContext, GpuSampleTaps};
use clothbake::lighting::bright_sources::MAX_SOURCES;
use clothbake::lighting::{Environment, GeneratedEnvironment, disk_above_horizon};
use clothbake::measure::accuracy::lookup_f32;
use clothbake::render::image::{LinearImage, image_error};

use clothbake::render::reference::{self, ReferenceEnvironment};
use clothbake::render::{FrameSettings, GBuffer, GpuEnvironment, Headless};
use clothbake::sampling::{SampleTaps, Sampler};
use clothbake::scene::mesh::Mesh;
use clothbake::scene::{DEFAULT_ENVIRONMENT_SAMPLES, Scene};
use clothbake::table::{Layout, Table};
use glam::DVec3;
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64;
use std::f64::consts::PI;

/// thread_frame resolution of the tables baked here: the tests compare the GPU with the CPU
/// using the same table, so its accuracy does not matter.
const RESOLUTION: u32 = 16;
/// Image side: small, so that the CPU side is fast.
const SIDE: u32 = 96;

fn scene() -> Scene {
    let mut scene = Scene::builtin();
    scene.mesh.resolution = 64;
    scene
}

/// Environment-only settings with `samples` per pixel.
fn settings(samples: u32) -> FrameSettings {
    FrameSettings {
        lights: Vec::new(),
        environment_samples: samples,
        ..FrameSettings::from_scene(&scene())
    }
}

struct Render {
    table: Table,
    sampler: Sampler,
    image: LinearImage,
    gbuffer: GBuffer,
}

/// `fabric`'s table baked here, its sampler, and the view of `settings` rendered under `map`
/// with at most `sources` of its bright sources lit as lights, through the table's sample
/// taps for the settings' K.
fn render(
    context: &GpuContext,
    fabric: &clothbake::model::Fabric,
    map: &Environment,
    settings: &FrameSettings,
    sources: usize,
) -> Render {
    let table = bake(fabric, Layout::THREAD_FRAME, RESOLUTION, &|| {}).unwrap();
    let sampler = Sampler::for_table(&table);
    let brdf = GpuTable::new(context, &table).unwrap();
    let mesh = Mesh::from_spec(&scene().mesh).unwrap();
    let mut headless = Headless::new(context, &mesh, &brdf, SIDE, SIDE).unwrap();
    let environment = GpuEnvironment::split(context, &map.split_bright_sources(sources)).unwrap();
    let taps = SampleTaps::for_table(&table, &sampler, settings.environment_samples);
    let gpu_taps = GpuSampleTaps::new(context, &taps).unwrap();
    headless
        .renderer
        .set_environment(context, &environment, &gpu_taps)
        .unwrap();
    let image = headless.render(context, settings, 1).unwrap().linear;
    let gbuffer = headless.gbuffer(context, settings).unwrap();
    Render {
        table,
        sampler,
        image,
        gbuffer,
    }
}

/// The CPU reference of `r`'s view under `map`: F by the same table's f32 lookup, so that
/// only the light's integration differs; the residual by 256 MIS pairs per pixel.
fn reference_of(r: &Render, map: &Environment, settings: &FrameSettings) -> LinearImage {
    let environment = ReferenceEnvironment {
        map,
        sampler: &r.sampler,
        samples: 256,
    };
    reference::shade_with(
        &r.gbuffer,
        settings,
        |wi, wo| lookup_f32(&r.table, wi, wo),
        Some(&environment),
    )
}

/// wo in each covered pixel's thread frame (as the reference builds it), by pixel index.
fn outgoing(gbuffer: &GBuffer, eye: DVec3) -> Vec<(usize, DVec3)> {
    let v = |a: [f32; 4]| DVec3::new(a[0] as f64, a[1] as f64, a[2] as f64);
    (0..gbuffer.position.len())
        .filter(|&i| gbuffer.position[i][3] > 0.5)
        .map(|i| {
            let n = v(gbuffer.normal[i]).normalize();
            let t = (v(gbuffer.tangent[i]) - n * n.dot(v(gbuffer.tangent[i]))).normalize();
            let b = n.cross(t);
            let w = (eye - v(gbuffer.position[i])).normalize();
            (i, DVec3::new(w.dot(t), w.dot(b), w.dot(n)))
        })
        .collect()
}

#[test]
fn white_furnace_gives_the_directional_albedo() {
    // Under radiance 1 the shader's estimate of one pixel is the mean of the K weights of
    // its sample taps, the strata's K·∫F dwi blended over the tap nodes around its wo: the
    // albedo ∫F dwi at wo, to the taps' quadrature (under 1%) and the blend over nodes a
    // fraction of a degree to a few degrees away. Here the albedo is estimated on the CPU at each pixel's
    // wo by DRAWS random pairs of c = F(w_f)/(p_f + p_e) + F(w_e)/(p_e + p_f(w_e)), w_f from
    // the fabric's sampler, w_e uniform on the sphere (p_e = 1/4π; below the horizon it adds
    // 0; E[c] is the albedo); c's spread σ sets the CPU estimate's own error, σ/√DRAWS, which
    // dominates the difference (2.2–2.5% RMS); the 2/K term, from when the taps were draws,
    // only makes the bound looser. The mip chain plays no part (every
    // level is 1). Bound: |z| ≤ 6 for every pixel and RMS z ≤ 1.5,
    // z = (GPU − mean)/(σ·√(2/K + 1/DRAWS)).
    const DRAWS: usize = 256;
    let context = gpu_context();
    let map = Environment::uniform(1.0);
    let samples = DEFAULT_ENVIRONMENT_SAMPLES;
    let eye = scene().camera;
    let eye = clothbake::render::Camera::orbit(&eye).eye.as_dvec3();
    let p_e = 1.0 / (4.0 * PI);
    for fabric in builtin() {
        let r = render(&context, &fabric, &map, &settings(samples), 0);
        let mut rng = Pcg64::seed_from_u64(0xf0_7ace);
        let (mut worst, mut sum_z2, mut count, mut mean_albedo) = (0.0f64, 0.0, 0usize, 0.0);
        let mut rel2 = 0.0;
        for (i, wo) in outgoing(&r.gbuffer, eye) {
            if wo.z <= 1e-3 {
                continue;
            }
            let f = |wi: DVec3| {
                let v = lookup_f32(&r.table, wi, wo);
                (v.x + v.y + v.z) / 3.0
            };
            let values: Vec<f64> = (0..DRAWS)
                .map(|_| {
                    let u = [rng.random(), rng.random(), rng.random()];
                    let mut c = 0.0;
                    if let Some(s) = r.sampler.sample(wo, u) {
                        c += f(s.wi) / (s.pdf + p_e);
                    }
                    let z: f64 = 2.0 * rng.random::<f64>() - 1.0;
                    let a = 2.0 * PI * rng.random::<f64>();
                    let w = DVec3::new(
                        (1.0 - z * z).sqrt() * a.cos(),
                        (1.0 - z * z).sqrt() * a.sin(),
                        z,
                    );
                    if w.z > 0.0 {
                        c += f(w) / (p_e + r.sampler.pdf(wo, w));
                    }
                    c
                })
                .collect();
            let mean = values.iter().sum::<f64>() / DRAWS as f64;
            let sigma = (values.iter().map(|v| (v - mean).powi(2)).sum::<f64>()
                / (DRAWS - 1) as f64)
                .sqrt();
            let p = r.image.pixels[i];
            let gpu = (p[0] as f64 + p[1] as f64 + p[2] as f64) / 3.0;
            let scale = sigma * (2.0 / samples as f64 + 1.0 / DRAWS as f64).sqrt();
            let z = (gpu - mean) / scale.max(1e-4 * mean);
            rel2 += ((gpu - mean) / mean).powi(2);
            worst = worst.max(z.abs());
            sum_z2 += z * z;
            count += 1;
            mean_albedo += mean;
        }
        let rms = (sum_z2 / count as f64).sqrt();
        println!(
            "{:<28} white furnace, K = {samples}: {count} pixels, mean albedo {:.4}, \
             |z| ≤ {worst:.2}, RMS z {rms:.2}; RMS relative error {:.2}%",
            fabric.name,
            mean_albedo / count as f64,
            100.0 * (rel2 / count as f64).sqrt()
        );
        assert!(
            worst <= 6.0 && rms <= 1.5,
            "{}: |z| {worst:.2}, RMS {rms:.2}",
            fabric.name
        );
    }
}

/// Measured relative L2 of the studio render at the default K against the CPU reference
/// (same table, 256 MIS samples per pixel), per fabric, on lavapipe; the bound of
/// `studio_render_approaches_the_cpu_reference` is each plus a quarter (the GPU side is
/// deterministic on one device; the reference's own noise, ~0.8%, is fixed by its seeds).
const STUDIO_ERROR: [(&str, f64); 6] = [
    ("linen_plain", 0.0161),
    ("silk_crepe_de_chine", 0.0184),
    ("polyester_satin_charmeuse", 0.0195),
    ("polyester_satin_charmeuse_back", 0.0196),
    ("silk_shot", 0.0202),
    ("velvet", 0.0212),
];

#[test]
fn studio_render_approaches_the_cpu_reference() {
    let context = gpu_context();
    let map = Environment::studio();
    let settings = settings(DEFAULT_ENVIRONMENT_SAMPLES);
    let mut failures = Vec::new();
    for fabric in builtin() {
        let r = render(&context, &fabric, &map, &settings, 0);
        let cpu = reference_of(&r, &map, &settings);
        let error = image_error(&r.image, &cpu, settings.exposure).unwrap();
        let measured = STUDIO_ERROR
            .iter()
            .find(|(name, _)| *name == fabric.name)
            .map_or(0.0, |e| e.1);
        println!(
            "{:<28} studio, K = {DEFAULT_ENVIRONMENT_SAMPLES}: relative L2 {:.2}% against the \
             CPU reference (recorded {:.2}%), PSNR {:.1} dB",
            fabric.name,
            100.0 * error.relative_l2,
            100.0 * measured,
            error.psnr_db
        );
        assert_eq!(error.coverage_mismatch, 0);
        if error.relative_l2 > 1.25 * measured {
            failures.push(format!(
                "{}: {:.2}%",
                fabric.name,
                100.0 * error.relative_l2
            ));
        }
    }
    assert!(
        failures.is_empty(),
        "above the recorded error + 25%: {failures:?}"
    );
}

/// Measured relative L2 under the generated sky at the default K against the CPU reference
/// (same table, 256 MIS samples per pixel on the residual, the sun by its texel blocks), per
/// fabric on lavapipe: with the sun lit as a light, and with the whole map sampled. The bound
/// of `the_sun_as_a_light_brings_the_sky_to_the_reference` is the first plus a quarter, and
/// the sun as a light must keep at least a factor 4 over sampling it (measured 21–23). The
/// sun is set by the horizon over its disk; lit at its centre alone, velvet read 3.26%.
const SKY_ERROR: [(&str, f64, f64); 6] = [
    ("linen_plain", 0.0093, 0.1983),
    ("silk_crepe_de_chine", 0.0111, 0.2555),
    ("polyester_satin_charmeuse", 0.0113, 0.2482),
    ("polyester_satin_charmeuse_back", 0.0110, 0.2402),
    ("silk_shot", 0.0110, 0.2558),
    ("velvet", 0.0142, 0.3061),
];

#[test]
fn the_sun_as_a_light_brings_the_sky_to_the_reference() {
    let context = gpu_context();
    let map = GeneratedEnvironment::Sky.environment();
    let settings = settings(DEFAULT_ENVIRONMENT_SAMPLES);
    let mut failures = Vec::new();
    for fabric in builtin() {
        let errors = [MAX_SOURCES, 0].map(|sources| {
            let r = render(&context, &fabric, &map, &settings, sources);
            let cpu = reference_of(&r, &map, &settings);
            image_error(&r.image, &cpu, settings.exposure)
                .unwrap()
                .relative_l2
        });
        let (_, with_sun, without) = SKY_ERROR
            .iter()
            .find(|(name, ..)| *name == fabric.name)
            .copied()
            .unwrap_or_default();
        println!(
            "{:<28} sky, K = {DEFAULT_ENVIRONMENT_SAMPLES}: relative L2 {:.2}% with the sun as a \
             light (recorded {:.2}%), {:.2}% with the whole map sampled (recorded {:.2}%)",
            fabric.name,
            100.0 * errors[0],
            100.0 * with_sun,
            100.0 * errors[1],
            100.0 * without
        );
        if errors[0] > 1.25 * with_sun || errors[1] < 4.0 * errors[0] {
            failures.push(format!(
                "{}: {:.2}% with the sun as a light, {:.2}% without",
                fabric.name,
                100.0 * errors[0],
                100.0 * errors[1]
            ));
        }
    }
    assert!(
        failures.is_empty(),
        "above the recorded error + 25%, or the sun's light no longer pays: {failures:?}"
    );
}

#[test]
fn a_turned_sky_lights_the_cloth_as_the_reference_turns_it() {
    // The environment's rotation enters the shader's map lookups, the sources' directions
    // (turned on the CPU) and the reference's draws: turned by 100°, the sun comes from
    // behind-left and the render must still match the reference turned alike, as closely as
    // unturned (velvet, the worst fabric under the sky: 1.4% unturned). Measured on
    // lavapipe: 1.01% against the turned reference, 120% against the unturned one; the bound
    // is the first plus a quarter, as the other environment tests'.
    const TURNED_ERROR: f64 = 0.0101;
    let context = gpu_context();
    let map = GeneratedEnvironment::Sky.environment();
    let fabric = builtin()
        .into_iter()
        .find(|f| f.name == "velvet")
        .expect("velvet is built in");
    let settings = FrameSettings {
        environment_rotation: 100f32.to_radians(),
        ..settings(DEFAULT_ENVIRONMENT_SAMPLES)
    };
    let r = render(&context, &fabric, &map, &settings, MAX_SOURCES);
    let cpu = reference_of(&r, &map, &settings);
    let error = image_error(&r.image, &cpu, settings.exposure)
        .unwrap()
        .relative_l2;
    // The same reference without the turn is far: the test would see a rotation the shader
    // applied and the reference did not (or the other way round).
    let unturned = reference_of(
        &r,
        &map,
        &FrameSettings {
            environment_rotation: 0.0,
            ..settings.clone()
        },
    );
    let apart = image_error(&r.image, &unturned, settings.exposure)
        .unwrap()
        .relative_l2;
    println!(
        "velvet under the sky turned by 100°: relative L2 {:.2}% against the turned reference \
         (recorded {:.2}%), {:.1}% against the unturned one",
        100.0 * error,
        100.0 * TURNED_ERROR,
        100.0 * apart
    );
    assert!(error <= 1.25 * TURNED_ERROR, "{:.2}%", 100.0 * error);
    assert!(apart > 10.0 * error, "{:.2}%", 100.0 * apart);
}

#[test]
fn wgsl_source_disk_is_the_cpus() {
    // The sources' disks set by the horizon (shaders/lighting/source_disk.wgsl) against their
    // Rust twin, over elevations across the disk and beyond, radii from none to 3°, and
    // azimuths all round.
    let context = gpu_context();
    let mut requests = Vec::new();
    for radius_deg in [0.0f32, 0.265, 1.5, 3.0] {
        let radius = radius_deg.to_radians();
        for step in -15..=15 {
            let elevation = (step as f32 / 10.0) * radius.max(0.01);
            for azimuth_step in 0..7 {
                let azimuth = azimuth_step as f32 * 0.9;
                let wi = glam::Vec3::new(
                    elevation.cos() * azimuth.cos(),
                    elevation.cos() * azimuth.sin(),
                    elevation.sin(),
                );
                requests.push((wi, radius.sin()));
            }
        }
    }
    let gpu = clothbake::gpu::disks_above_horizon(&context, &requests).unwrap();
    let (mut direction, mut fraction) = (0.0f32, 0.0f32);
    for (&(wi, sin_radius), &(gpu_centroid, gpu_fraction)) in requests.iter().zip(&gpu) {
        let (centroid, share) = disk_above_horizon(wi, sin_radius);
        fraction = fraction.max((gpu_fraction - share).abs());
        if share > 0.0 {
            direction = direction.max((gpu_centroid - centroid).length());
        }
    }
    println!(
        "source disks: {} requests, largest difference {direction:.1e} in direction, \
         {fraction:.1e} in visible fraction",
        requests.len()
    );
    // Measured on lavapipe: 1.9e-5 in direction, 5.0e-5 in fraction (its asin and acos near
    // ±1, where they are steep); the bounds are ten times that.
    assert!(direction < 2e-4, "direction off by {direction}");
    assert!(fraction < 5e-4, "fraction off by {fraction}");
}
