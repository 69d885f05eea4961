//! Rendering (`clothbake::render`, `clothbake render`): the image is not blank and follows
//! the light; the GPU shading equals the CPU shading of the same G-buffer; the table-lookup
//! render is close to the direct-evaluation reference; and a committed reference image per
//! fabric (tests/data/render/NAME.exr) still comes out.
//!
//! Needs a wgpu adapter; without a GPU, Mesa's lavapipe (`apt-get install -y
//! mesa-vulkan-drivers libvulkan1`). No adapter is a failure, not a skip.
//!
//! Tables are baked here, in-process, at a small thread_frame resolution ([`RESOLUTION`]);
//! baking is deterministic, so the committed reference images stay valid until the baker or
//! the renderer changes. To regenerate them (and say so in the commit):
//! `CLOTHBAKE_UPDATE_REFERENCE=1 cargo test --release --test gpu render:: -- --nocapture`; the
//! adapter that made them is recorded in tests/data/render/DEVICE.

use crate::common::*;

use clothbake::bake::bake;
use clothbake::evaluator::constant::gpu::GpuConstant;
use clothbake::evaluator::paper::gpu::GpuPaper;
use clothbake::evaluator::resonant::gpu::GpuResonant;
use clothbake::evaluator::table::gpu::GpuTable;
use clothbake::evaluator::{EVALUATORS, EvaluationContext, EvaluatorError};
use clothbake::formats::fabric_toml::FabricSet;
use clothbake::formats::table_exr::write_table;
use clothbake::gpu::{GpuBrdf, GpuContext};
use clothbake::model::{Fabric, Integration, Patch, ResonantNodes};
use clothbake::render::image::{LinearImage, image_error, read_linear_exr, write_linear_exr};
use clothbake::render::{FrameSettings, Headless, LightSource, reference};
use clothbake::scene::Scene;
use clothbake::scene::mesh::Mesh;
use clothbake::table::{Layout, Table};
use glam::{DVec3, Vec3};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

/// thread_frame resolution of the tables baked here (0.5–0.8 MiB, milliseconds to bake).
const RESOLUTION: u32 = 16;
/// Image side of the test renders: small, so that the CPU reference is fast.
const SIDE: u32 = 96;
/// Grid quads per side of the drape in the test scene.
const MESH_RESOLUTION: u32 = 64;

fn fabrics() -> Vec<Fabric> {
    FabricSet::builtin().fabrics().to_vec()
}

/// The six built-in fabrics baked once per test binary.
fn tables() -> &'static [Table] {
    static TABLES: OnceLock<Vec<Table>> = OnceLock::new();
    TABLES.get_or_init(|| {
        fabrics()
            .iter()
            .map(|f| bake(f, Layout::THREAD_FRAME, RESOLUTION, &|| {}).expect("bake"))
            .collect()
    })
}

fn table(name: &str) -> &'static Table {
    tables()
        .iter()
        .find(|t| t.fabric.name == name)
        .expect("baked table")
}

/// The built-in scene with a lighter mesh.
fn scene() -> Scene {
    let mut scene = Scene::builtin();
    scene.mesh.resolution = MESH_RESOLUTION;
    scene
}

fn mesh() -> Mesh {
    Mesh::from_spec(&scene().mesh).expect("procedural mesh")
}

fn settings() -> FrameSettings {
    FrameSettings::from_scene(&scene())
}

fn render(context: &GpuContext, brdf: &dyn GpuBrdf, settings: &FrameSettings) -> LinearImage {
    Headless::new(context, &mesh(), brdf, SIDE, SIDE)
        .expect("renderer")
        .render(context, settings, 1)
        .expect("render")
        .linear
}

fn luminance(p: &[f32; 4]) -> f64 {
    0.2126 * p[0] as f64 + 0.7152 * p[1] as f64 + 0.0722 * p[2] as f64
}

#[test]
fn render_is_not_blank_and_changes_when_the_light_moves() {
    let context = gpu_context();
    let brdf = GpuTable::new(&context, table("linen_plain")).unwrap();
    let lit = settings();
    let image = render(&context, &brdf, &lit);
    let covered: Vec<f64> = image
        .pixels
        .iter()
        .filter(|p| p[3] > 0.5)
        .map(luminance)
        .collect();
    let fraction = covered.len() as f64 / image.pixels.len() as f64;
    let mean = covered.iter().sum::<f64>() / covered.len().max(1) as f64;
    let sd = (covered.iter().map(|l| (l - mean).powi(2)).sum::<f64>()
        / covered.len().max(1) as f64)
        .sqrt();
    println!(
        "coverage {fraction:.3}, mean luminance {mean:.4}, relative spread {:.3}",
        sd / mean
    );
    // Measured with the built-in scene: coverage 0.23, mean luminance 0.096, relative
    // spread 0.39; a blank, black or flat image fails.
    assert!(fraction > 0.15, "the cloth covers {fraction} of the image");
    assert!(mean > 0.01, "the cloth is black: mean luminance {mean}");
    assert!(sd / mean > 0.1, "the shading is flat: spread {}", sd / mean);

    // Move the directional light to the other side: the image must change substantially.
    let mut moved = lit.clone();
    moved.lights[0] = LightSource::Directional {
        direction: Vec3::new(-0.7, 0.4, -0.6).normalize(),
        irradiance: Vec3::splat(2.0),
    };
    let other = render(&context, &brdf, &moved);
    let change = image_error(&other, &image, 1.0).unwrap();
    // Measured: 87%.
    println!(
        "moving the light changes the image by {:.1}% (relative L2)",
        100.0 * change.relative_l2
    );
    assert_eq!(
        change.coverage_mismatch, 0,
        "the light changed the coverage"
    );
    assert!(
        change.relative_l2 > 0.2,
        "moving the light changed the image by only {:.3}% (relative L2)",
        100.0 * change.relative_l2
    );
}

/// Renders `fabric` with `brdf` and shades the same G-buffer pixels on the CPU with
/// `integration`, the rule `brdf` evaluates; asserts the two agree (see the callers).
fn assert_render_matches_cpu(
    context: &GpuContext,
    fabric: &Fabric,
    brdf: &dyn GpuBrdf,
    integration: Integration,
) {
    let settings = settings();
    let mut headless = Headless::new(context, &mesh(), brdf, SIDE, SIDE).unwrap();
    let gpu = headless.render(context, &settings, 1).unwrap().linear;
    let gbuffer = headless.gbuffer(context, &settings).unwrap();
    let patch = Patch::new(fabric, integration);
    let cpu = reference::shade(&gbuffer, &settings, &patch, None);
    let error = image_error(&gpu, &cpu, settings.exposure).unwrap();
    let name = &fabric.name;
    println!(
        "{name}: {} on the GPU against the CPU: relative L2 {:.2e}, PSNR {:.1} dB, {} pixels, \
         {} differ in coverage",
        brdf.label(),
        error.relative_l2,
        error.psnr_db,
        error.covered,
        error.coverage_mismatch
    );
    assert!(error.covered > 1000);
    assert_eq!(error.coverage_mismatch, 0);
    // Measured on lavapipe: 3e-6 to 8e-6 for both shaders (f32 against f64); 1e-4 leaves
    // room for other devices' transcendental functions while catching any modelling
    // difference.
    assert!(
        error.relative_l2 < 1e-4,
        "{name}: GPU render ({}) differs from the CPU by {:.2e} (relative L2)",
        brdf.label(),
        error.relative_l2
    );
}

#[test]
fn every_registered_gpu_form_renders_what_its_cpu_evaluation_shades() {
    // The evaluator registry's GPU conformance: every unit at its default spelling, reached
    // only through `EVALUATORS`, on two fabrics; its GPU form's render against the CPU's
    // shading of the same G-buffer pixels with the same evaluation's `eval`. A unit without a
    // GPU form says so and is skipped; a unit added to the registry is tested here with no
    // other edit. The bound is the lookup's (below): texture filtering and f32 coordinates,
    // measured on lavapipe up to 1.8e-4, and the model's forms in f32 far within it; a wrong
    // frame, light or F gives percents.
    let context = gpu_context();
    let dir = temp_dir("render-evaluators");
    let names = ["polyester_satin_charmeuse", "velvet"];
    for name in names {
        let path = dir.join(format!("{name}.exr"));
        write_table(&path, table(name)).unwrap();
    }
    let files = EvaluationContext {
        tables: dir.to_path_buf(),
    };
    let settings = settings();
    for unit in EVALUATORS {
        let evaluator = (unit.parse)(None).unwrap();
        for name in names {
            let fabric = FabricSet::builtin().get(name).unwrap().clone();
            let evaluation = evaluator.prepare(&fabric, &files).unwrap();
            let brdf = match evaluation.gpu(&context) {
                Ok(brdf) => brdf,
                Err(error @ EvaluatorError::NoGpuForm { .. }) => {
                    println!("{}: {error}", evaluator.spelling());
                    break;
                }
                Err(error) => panic!("{}: {error}", evaluator.spelling()),
            };
            let mut headless = Headless::new(&context, &mesh(), brdf.as_ref(), SIDE, SIDE).unwrap();
            let gpu = headless.render(&context, &settings, 1).unwrap().linear;
            let gbuffer = headless.gbuffer(&context, &settings).unwrap();
            let cpu =
                reference::shade_with(&gbuffer, &settings, |wi, wo| evaluation.eval(wi, wo), None);
            let error = image_error(&gpu, &cpu, settings.exposure).unwrap();
            println!(
                "{name}: {} ({}) on {} against its CPU evaluation: relative L2 {:.2e}, {} pixels",
                evaluator.spelling(),
                brdf.label(),
                context.adapter,
                error.relative_l2,
                error.covered
            );
            assert!(error.covered > 1000);
            assert_eq!(error.coverage_mismatch, 0);
            assert!(
                error.relative_l2 < 1e-3,
                "{name}: {} renders {:.2e} (relative L2) off its CPU evaluation",
                evaluator.spelling(),
                error.relative_l2
            );
        }
    }
}

#[test]
fn paper_shader_render_equals_cpu_paper_mode_shading_of_the_same_pixels() {
    // The render pass and the CPU shade the same G-buffer pixels with the same paper-mode F,
    // so the difference is f32 arithmetic alone (frame, directions, irradiance, F): a wrong
    // frame, light or falloff shows up as percent-level differences.
    let context = gpu_context();
    for name in ["polyester_satin_charmeuse", "velvet"] {
        let fabric = FabricSet::builtin().get(name).unwrap().clone();
        let samples = 8;
        let brdf = GpuPaper::new(&context, &fabric, samples).unwrap();
        assert_render_matches_cpu(&context, &fabric, &brdf, Integration::Paper(samples));
    }
}

#[test]
fn resonant_shader_render_equals_cpu_resonant_shading_of_the_same_pixels() {
    // As for the paper-mode shader: the same G-buffer pixels shaded with the same resonant rule
    // on both sides, so the difference is f32 arithmetic (tests/gpu/resonant.rs bounds it per
    // pair: relative RMS ≤ 1e-5).
    let context = gpu_context();
    for name in ["polyester_satin_charmeuse", "velvet"] {
        let fabric = FabricSet::builtin().get(name).unwrap().clone();
        let nodes = ResonantNodes::DEFAULT;
        let brdf = GpuResonant::new(&context, &fabric, nodes).unwrap();
        assert_render_matches_cpu(&context, &fabric, &brdf, Integration::Resonant(nodes));
    }
}

#[test]
fn resonant_form_updated_in_place_renders_what_a_fresh_form_renders() {
    // The editor's path through the render pass: the renderer keeps its pipeline and the
    // form's bind group, the form's fabric buffer is rewritten (`GpuBrdf::update_fabric`),
    // and the next frame is the frame of a renderer made for the new fabric, to the bit.
    let context = gpu_context();
    let settings = settings();
    let nodes = ResonantNodes::DEFAULT;
    let velvet = FabricSet::builtin().get("velvet").unwrap().clone();
    let satin = FabricSet::builtin()
        .get("polyester_satin_charmeuse")
        .unwrap()
        .clone();
    let brdf = GpuResonant::new(&context, &velvet, nodes).unwrap();
    let headless = Headless::new(&context, &mesh(), &brdf, SIDE, SIDE).unwrap();
    let first = headless.render(&context, &settings, 1).unwrap().linear;
    assert!(brdf.update_fabric(&context, &satin).unwrap());
    let edited = headless.render(&context, &settings, 1).unwrap().linear;
    let fresh = render(
        &context,
        &GpuResonant::new(&context, &satin, nodes).unwrap(),
        &settings,
    );
    let bits = |image: &LinearImage| -> Vec<[u32; 4]> {
        image.pixels.iter().map(|p| p.map(f32::to_bits)).collect()
    };
    assert_ne!(bits(&edited), bits(&first), "the edit shows");
    assert_eq!(bits(&edited), bits(&fresh));
}

#[test]
fn constant_shader_render_equals_cpu_shading_with_f_one_over_pi() {
    // The cost-floor shader does the render pass's whole per-light work (frame, directions,
    // irradiance, horizon test) with F = 1/π: its image must be the CPU's shading of the
    // same G-buffer with that F, to f32 arithmetic.
    let context = gpu_context();
    let settings = settings();
    let brdf = GpuConstant::new(&context);
    let mut headless = Headless::new(&context, &mesh(), &brdf, SIDE, SIDE).unwrap();
    let gpu = headless.render(&context, &settings, 1).unwrap().linear;
    let gbuffer = headless.gbuffer(&context, &settings).unwrap();
    let cpu = reference::shade_with(
        &gbuffer,
        &settings,
        |_, _| DVec3::splat(std::f64::consts::FRAC_1_PI),
        None,
    );
    let error = image_error(&gpu, &cpu, settings.exposure).unwrap();
    println!(
        "constant F = 1/π on the GPU against the CPU: relative L2 {:.2e}, {} pixels",
        error.relative_l2, error.covered
    );
    assert!(error.covered > 1000);
    assert_eq!(error.coverage_mismatch, 0);
    // The same bound as the paper-mode shader's test above (f32 against f64 for the same
    // directions and irradiances).
    assert!(
        error.relative_l2 < 1e-4,
        "constant render differs from the CPU by {:.2e} (relative L2)",
        error.relative_l2
    );
}

/// Per fabric: (lookup render, CPU shading of the same G-buffer by `Table::lookup`, CPU
/// reference by direct evaluation).
fn lookup_and_references(
    context: &GpuContext,
) -> Vec<(String, LinearImage, LinearImage, LinearImage)> {
    let settings = settings();
    tables()
        .iter()
        .map(|table| {
            let brdf = GpuTable::new(context, table).unwrap();
            let mut headless = Headless::new(context, &mesh(), &brdf, SIDE, SIDE).unwrap();
            let gpu = headless.render(context, &settings, 1).unwrap().linear;
            let gbuffer = headless.gbuffer(context, &settings).unwrap();
            let cpu_lookup =
                reference::shade_with(&gbuffer, &settings, |wi, wo| table.lookup(wi, wo), None);
            let patch = Patch::new(&table.fabric, Integration::Direct);
            let direct = reference::shade(&gbuffer, &settings, &patch, None);
            (table.fabric.name.clone(), gpu, cpu_lookup, direct)
        })
        .collect()
}

#[test]
fn lookup_render_matches_the_cpu_lookup_and_approaches_the_direct_reference() {
    let context = gpu_context();
    let settings = settings();
    for (name, gpu, cpu_lookup, direct) in lookup_and_references(&context) {
        let device = image_error(&gpu, &cpu_lookup, settings.exposure).unwrap();
        let table = image_error(&gpu, &direct, settings.exposure).unwrap();
        let cpu_table = image_error(&cpu_lookup, &direct, settings.exposure).unwrap();
        println!(
            "{name}: GPU lookup vs CPU lookup {:.2e} ({:.1} dB); GPU lookup vs direct \
             {:.2}% ({:.1} dB); CPU lookup vs direct {:.2}%",
            device.relative_l2,
            device.psnr_db,
            100.0 * table.relative_l2,
            table.psnr_db,
            100.0 * cpu_table.relative_l2
        );
        // GPU against CPU lookup: hardware filtering (8-bit weights on lavapipe) and f32
        // coordinates, measured on lavapipe 1.4e-5 to 1.8e-4 over the six fabrics; 1e-3
        // leaves room for other devices' filtering while catching any lookup error (a wrong
        // texel or axis gives percents).
        assert!(
            device.relative_l2 < 1e-3,
            "{name}: GPU lookup differs from the CPU lookup by {:.2e}",
            device.relative_l2
        );
        // Against the direct evaluation: the R = 16 table's own error (the report: 2.7–6.2%
        // RMS over uniform pairs at R = 16, less on the directions a lit drape sees),
        // measured here 1.85% (linen_plain) to 3.82% (polyester_satin_charmeuse) at baker
        // revision 5;
        // 8% fails a broken lookup or frame, which give tens of percent.
        assert!(
            table.relative_l2 < 0.08,
            "{name}: lookup render is {:.2}% off the direct reference",
            100.0 * table.relative_l2
        );
    }
}

#[test]
fn default_tables_render_the_standard_scene_within_half_a_percent() {
    // The goal the default layout is held to (docs/tables.md#goals-and-where-they-stand):
    // the lookup render of the built-in scene (its full mesh, 256², the scene's lights)
    // within 0.5% relative L2 of the direct reference, every fabric. Measured on lavapipe
    // at baker revision 8: linen 0.48%, crepe 0.10%, satin 0.18%, satin back 0.12%,
    // silk_shot 0.18%, velvet 0.39% (0.51% before velvet's βH edge zone). The bound is the
    // goal itself, not a measurement plus margin: tables and renders are deterministic, and
    // a baker change that moves a fabric past it has missed the goal.
    let context = gpu_context();
    let scene = Scene::builtin();
    let mesh = Mesh::from_spec(&scene.mesh).expect("procedural mesh");
    let settings = FrameSettings::from_scene(&scene);
    let side = 256;
    for fabric in fabrics() {
        let name = &fabric.name;
        let layout = Layout::DEFAULT;
        let table = bake(&fabric, layout, layout.default_resolution(), &|| {}).unwrap();
        let brdf = GpuTable::new(&context, &table).unwrap();
        let mut headless = Headless::new(&context, &mesh, &brdf, side, side).unwrap();
        let gpu = headless.render(&context, &settings, 1).unwrap().linear;
        let gbuffer = headless.gbuffer(&context, &settings).unwrap();
        let patch = Patch::new(&fabric, Integration::Direct);
        let direct = reference::shade(&gbuffer, &settings, &patch, None);
        let error = image_error(&gpu, &direct, settings.exposure).unwrap();
        println!(
            "{name}: {} {} lookup render against the direct reference: {:.3}% ({} pixels, {})",
            layout.name(),
            layout.default_resolution(),
            100.0 * error.relative_l2,
            error.covered,
            context.adapter
        );
        assert!(error.covered > 10_000, "{name}: {} pixels", error.covered);
        assert!(
            error.relative_l2 <= 0.005,
            "{name}: the default table's render is {:.3}% off the direct reference",
            100.0 * error.relative_l2
        );
    }
}

/// Where the committed reference image of a fabric lies.
fn reference_path(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/render")
        .join(format!("{name}.exr"))
}

#[test]
fn committed_reference_images_still_come_out() {
    let context = gpu_context();
    let settings = settings();
    let device_file = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/render/DEVICE");
    if std::env::var_os("CLOTHBAKE_UPDATE_REFERENCE").is_some() {
        for table in tables() {
            let brdf = GpuTable::new(&context, table).unwrap();
            let image = render(&context, &brdf, &settings);
            write_linear_exr(&reference_path(&table.fabric.name), &image).unwrap();
        }
        std::fs::write(&device_file, format!("{}\n", context.adapter)).unwrap();
        println!("reference images rewritten on {}", context.adapter);
        return;
    }
    let device =
        std::fs::read_to_string(&device_file).unwrap_or_else(|_| "an unrecorded device".into());
    for table in tables() {
        let name = &table.fabric.name;
        let brdf = GpuTable::new(&context, table).unwrap();
        let image = render(&context, &brdf, &settings);
        let expected = read_linear_exr(&reference_path(name)).unwrap_or_else(|e| {
            panic!("{e} (regenerate with CLOTHBAKE_UPDATE_REFERENCE=1, see this file's doc)")
        });
        // Pixels on the cloth's silhouette may rasterise differently on another device (a
        // pixel's whole radiance against 0): count those, and measure the shading on the
        // pixels both images cover.
        let mask: Vec<bool> = (0..image.pixels.len())
            .map(|i| image.covered(i) && expected.covered(i))
            .collect();
        let both = |image: &LinearImage| LinearImage {
            pixels: image
                .pixels
                .iter()
                .zip(&mask)
                .map(|(p, &keep)| if keep { *p } else { [0.0; 4] })
                .collect(),
            ..image.clone()
        };
        let coverage = image_error(&image, &expected, settings.exposure)
            .unwrap()
            .coverage_mismatch;
        let error = image_error(&both(&image), &both(&expected), settings.exposure).unwrap();
        println!(
            "{name}: against the committed image (set on {}): relative L2 {:.2e}, PSNR {:.1} dB \
             on the pixels both cover; {coverage} pixels differ in coverage",
            device.trim(),
            error.relative_l2,
            error.psnr_db,
        );
        // Measured on the device that set the images: 2.0e-4 to 2.1e-4 (the f16 rounding of
        // the stored image, 2^-11 relative at most); on llvmpipe through wgpu's GL backend
        // (f16 linear target, other shader compiler): 5.0e-4 to 6.0e-4. Another device's
        // filtering and f32 arithmetic differ from lavapipe's by what the lookup test above
        // measures against the exact CPU lookup (at most 1.8e-4 on lavapipe): 2e-3 leaves a
        // factor of three to ten; a changed shading, frame or table gives percents.
        // Silhouette pixels: at most 1% of them.
        assert!(
            error.relative_l2 < 2e-3 && coverage <= (SIDE * SIDE / 100) as usize,
            "{name}: the render differs from tests/data/render/{name}.exr (set on {}) by {:.2e} \
             relative L2 and {coverage} coverage pixels; if the baker or renderer changed on \
             purpose, regenerate with CLOTHBAKE_UPDATE_REFERENCE=1",
            device.trim(),
            error.relative_l2,
        );
    }
}

fn clothbake(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_clothbake"))
        .args(args)
        .env("XDG_RUNTIME_DIR", std::env::temp_dir())
        .output()
        .expect("spawn clothbake")
}

#[test]
fn render_command_writes_frame_reference_and_error_map_or_explains_what_is_missing() {
    let dir = temp_dir("render-cli");
    let d = |name: &str| dir.join(name).to_str().unwrap().to_string();
    // No table yet: the message says to bake.
    let missing = clothbake(&[
        "render",
        "--fabric",
        "velvet",
        "--tables",
        &d("tables"),
        "--out",
        &d("frame.png"),
    ]);
    assert!(!missing.status.success());
    assert!(
        output_text(&missing).contains("clothbake bake"),
        "{}",
        output_text(&missing)
    );
    let baked = clothbake(&[
        "bake",
        "--fabric",
        "velvet",
        "--resolution",
        "16",
        "--out",
        &d("tables"),
    ]);
    assert!(baked.status.success(), "{}", output_text(&baked));
    let scene = dir.join("scene.toml");
    std::fs::write(&scene, "fabrics = [\"velvet\"]\n[mesh]\nresolution = 32\n").unwrap();
    let out = clothbake(&[
        "render",
        "--scene",
        &d("scene.toml"),
        "--tables",
        &d("tables"),
        "--out",
        &d("frame.png"),
        "--width",
        "48",
        "--height",
        "40",
        "--frames",
        "2",
        "--reference",
    ]);
    let report = output_text(&out);
    println!("{report}");
    assert!(out.status.success(), "{report}");
    assert!(
        report.contains("adapter:") && report.contains("ms per frame"),
        "{report}"
    );
    assert!(
        report.contains("relative L2") && report.contains("PSNR"),
        "{report}"
    );
    for file in ["frame.png", "frame-reference.png", "frame-error.png"] {
        let bytes = std::fs::read(dir.join(file)).unwrap_or_else(|e| panic!("{file}: {e}"));
        assert_eq!(&bytes[1..4], b"PNG", "{file}");
    }
    // Bad arguments fail with a message naming them.
    for (args, needle) in [
        (vec!["--shader", "lookup", "--samples", "8"], "--samples"),
        (
            vec!["--shader", "lookup", "--surface-nodes", "5"],
            "--surface-nodes",
        ),
        (
            vec!["--shader", "resonant", "--base-nodes", "0"],
            "base-nodes",
        ),
        (vec!["--width", "0"], "width"),
        (vec!["--mesh", "/nonexistent/cloth.obj"], "cloth.obj"),
    ] {
        let (scene_arg, tables_arg, frame) = (d("scene.toml"), d("tables"), d("bad.png"));
        let mut all = vec![
            "render",
            "--scene",
            &scene_arg,
            "--tables",
            &tables_arg,
            "--out",
            &frame,
        ];
        all.extend(args.iter().copied());
        let bad = clothbake(&all);
        assert!(!bad.status.success(), "{args:?}");
        assert!(
            output_text(&bad).contains(needle),
            "{args:?}: {}",
            output_text(&bad)
        );
    }
}
