//! The WGSL fabric sampler (shaders/sampling/fabric_sampler.wgsl) on the device wgpu finds (lavapipe in
//! CI): its draws follow the CPU sampler's density (chi-square, every built-in fabric, the
//! eight outgoing directions of the CPU test), and the density it returns is the CPU's.
//!
//! Needs a wgpu adapter; without a GPU, Mesa's lavapipe (`apt-get install -y
//! mesa-vulkan-drivers libvulkan1`). No adapter is a failure, not a skip.

use crate::chi2;

use crate::common::{builtin, dir, gpu_context};
use clothbake::gpu::GpuSampler;
use clothbake::sampling::{COLUMNS, ROWS, Sampler};
use glam::{DVec3, Vec3};
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64;

/// Draws per outgoing direction.
const DRAWS: usize = 200_000;
/// Overall significance of all GPU chi-square tests together.
const ALPHA: f64 = 0.01;
/// Largest relative difference of the GPU's density from the CPU's away from cell edges:
/// f32 CDF differences are exact on both sides, so what is left is f32 rounding in the
/// bilinear weights and the cell's solid angle, whose z_{r+1} − z_r cancels next to the
/// normal: sin's ~6e-8 over 1 − cos(90°/32) ≈ 1.2e-3 is 5e-5 (measured 6.2e-5 on
/// lavapipe).
const PDF_RELATIVE: f64 = 1e-4;

/// Whether `w` is within 1e-5 rad (about a hundred f32 roundings of the angles) of an
/// edge of the sampler's cells, where the f32 and f64 sides may pick neighbouring cells
/// (about 6 draws in 10⁴: the band is 2e-5 rad of every 0.05 rad row and 0.1 rad sector).
fn near_cell_edge(w: DVec3) -> bool {
    use std::f64::consts::{FRAC_PI_2, TAU};
    let near = |angle: f64, step: f64| {
        let x = angle / step;
        (x - x.round()).abs() * step < 1e-5
    };
    near(w.z.atan2(w.x.hypot(w.y)), FRAC_PI_2 / ROWS as f64)
        || near(w.y.atan2(w.x), TAU / COLUMNS as f64)
}

/// Whether the CPU density jumps within 1e-5 of `wi` (moved along each axis and
/// renormalised): the edge of F's support for `wo`, where it drops to 0 or the cosine share
/// changes its count of lunes, which the f32 and f64 sides may place differently, as at a
/// cell's edge.
fn near_support_edge(sampler: &Sampler, wo: DVec3, wi: DVec3) -> bool {
    let here = sampler.pdf(wo, wi);
    [DVec3::X, DVec3::Y, DVec3::Z]
        .into_iter()
        .flat_map(|axis| [axis, -axis])
        .any(|step| {
            let there = sampler.pdf(wo, (wi + 1e-5 * step).normalize());
            (there - here).abs() > PDF_RELATIVE * here.max(there)
        })
}

/// Bound on the error of the expected mass's total (`chi2::expected_mass`), as in the CPU
/// test (tests/sampling/sampler.rs).
const INTEGRATION: f64 = 1e-5;

#[test]
fn wgsl_draws_follow_the_cpu_density() {
    let context = gpu_context();
    let fabrics = builtin();
    let threshold = chi2::sidak(ALPHA, fabrics.len() * chi2::OUTGOING.len());
    let mut failures = Vec::new();
    let (mut worst_pdf, mut off_cell) = (0.0f64, 0usize);
    for fabric in &fabrics {
        let sampler = Sampler::for_fabric(fabric);
        let gpu = GpuSampler::new(&context, &sampler).unwrap();
        let mut rng = Pcg64::seed_from_u64(0x6b0_5a3e);
        for &(elevation, azimuth) in &chi2::OUTGOING {
            let wo = dir(elevation, azimuth);
            let requests: Vec<(Vec3, Vec3)> = (0..DRAWS)
                .map(|_| {
                    let u = Vec3::new(rng.random(), rng.random(), rng.random());
                    (wo.as_vec3(), u)
                })
                .collect();
            let draws = gpu.draw(&context, &requests).unwrap();
            let mass = chi2::expected_mass(|wi| sampler.pdf(wo, wi));
            let mut observed = vec![0u64; mass.len()];
            let mut rejected = 0usize;
            for d in &draws {
                if d[3] <= 0.0 {
                    rejected += 1;
                    continue;
                }
                let wi = DVec3::new(d[0] as f64, d[1] as f64, d[2] as f64);
                observed[chi2::bin_of(wi)] += 1;
                // The f32 density against the CPU's at the same direction. Draws within
                // f32 rounding of a cell edge may be placed in the neighbouring cell by one
                // side and not the other; those are counted, not compared.
                let cpu = sampler.pdf(wo, wi.normalize());
                if near_cell_edge(wi) || near_support_edge(&sampler, wo, wi.normalize()) {
                    off_cell += 1;
                } else {
                    worst_pdf = worst_pdf.max((d[3] as f64 - cpu).abs() / cpu);
                }
            }
            // The accepted fraction is the CPU's ∫pdf (tests/sampling/sampler.rs): binomial,
            // five standard errors, plus the integration's error.
            let total: f64 = mass.iter().sum();
            let accepted = 1.0 - rejected as f64 / DRAWS as f64;
            if total < 1.0 - INTEGRATION {
                println!(
                    "{} at {elevation}°/{azimuth}°: GPU accepted {accepted:.6}, ∫pdf {total:.6}",
                    fabric.name
                );
            }
            // The variance p(1 − p)/N with p held at least 1/N: at ∫pdf = 1 the binomial
            // estimate would allow no rejected draw at all (a draw that f32 rounds onto the
            // horizon is one).
            let variance = (total * (1.0 - total.min(1.0))).max(1.0 / DRAWS as f64);
            let standard_error = (variance / DRAWS as f64).sqrt();
            assert!(
                (accepted - total).abs() < 5.0 * standard_error + INTEGRATION,
                "{} at {elevation}°: {rejected} of {DRAWS} GPU draws rejected, ∫pdf {total}",
                fabric.name
            );
            let label = format!("{:<28} wo {elevation:>4}°/{azimuth:>3}°", fabric.name);
            failures.extend(chi2::test(&label, &observed, &mass, DRAWS, threshold));
        }
    }
    let total = fabrics.len() * chi2::OUTGOING.len() * DRAWS;
    println!(
        "GPU pdf against CPU pdf: worst relative difference {worst_pdf:.2e}; \
         {off_cell} of {total} draws within 1e-5 rad of a cell's or the support's edge"
    );
    assert!(worst_pdf < PDF_RELATIVE, "GPU pdf off by {worst_pdf:.2e}");
    assert!(
        failures.is_empty(),
        "chi-square rejects (threshold p {threshold:.2e}): {failures:#?}"
    );
}

#[test]
fn wgsl_pdf_is_the_cpu_pdf() {
    let context = gpu_context();
    let fabric = builtin().into_iter().find(|f| f.name == "velvet").unwrap();
    let sampler = Sampler::for_fabric(&fabric);
    let gpu = GpuSampler::new(&context, &sampler).unwrap();
    let pairs = clothbake::measure::direction_sets::uniform_pairs(20_000, 0x9df);
    let gpu_pdf = gpu
        .pdf(
            &context,
            &pairs
                .iter()
                .map(|(wo, wi)| (wo.as_vec3(), wi.as_vec3()))
                .collect::<Vec<_>>(),
        )
        .unwrap();
    let mut close = 0;
    for ((wo, wi), g) in pairs.iter().zip(&gpu_pdf) {
        let cpu = sampler.pdf(
            wo.as_vec3().as_dvec3().normalize(),
            wi.as_vec3().as_dvec3().normalize(),
        );
        if (*g as f64 - cpu).abs() <= PDF_RELATIVE * cpu {
            close += 1;
        }
    }
    // Random pairs land within f32 rounding of a cell edge about 1 time in 10^5.
    assert!(
        close * 1000 >= pairs.len() * 999,
        "{close} of {} pdfs agree",
        pairs.len()
    );
}

/// The WGSL tap (`sampling_tap`, shaders/sampling/sample_taps.wgsl) is the CPU's
/// `SampleTaps::pick`, for random wo above the horizon and every k: the same four nodes,
/// their packed taps decoded alike and blended by the same bilinear weights. The weights
/// come from an f32 atan2 and pow on the GPU and f64 on the CPU, and the blend is
/// continuous in them, so the two differ by that rounding times the difference between
/// neighbouring nodes' taps: measured on lavapipe at most 4.8e-5 in the direction, 1.9e-6
/// (relative) in the weight and 2.8e-4 in log2 of the solid angle (neighbouring strata can
/// differ several-fold in size); the bounds are ten times those.
#[test]
fn wgsl_tap_picks_are_the_cpus() {
    use clothbake::gpu::GpuSampleTaps;
    use clothbake::sampling::SampleTaps;
    const CAPACITY: u32 = 16;
    let context = gpu_context();
    let fabric = &builtin()[2];
    let sampler = Sampler::for_fabric(fabric);
    // F need not be the fabric's for the twins to agree: the fabric's sampler density
    // itself, cheap to evaluate at the taps' 8.5 million points.
    let taps = SampleTaps::build(&sampler, CAPACITY, |pairs, out| {
        for (o, &(wi, wo)) in out.iter_mut().zip(pairs) {
            *o = glam::DVec3::splat(sampler.pdf(wo, wi));
        }
    });
    let gpu = GpuSampleTaps::new(&context, &taps).unwrap();
    let mut rng = Pcg64::seed_from_u64(0x7a95);
    let requests: Vec<(Vec3, u32)> = (0..4000)
        .flat_map(|_| {
            let z: f32 = rng.random_range(0.001..1.0);
            let a: f32 = rng.random_range(0.0..std::f32::consts::TAU);
            let r = (1.0 - z * z).sqrt();
            let wo = Vec3::new(r * a.cos(), r * a.sin(), z);
            (0..CAPACITY).map(move |k| (wo, k))
        })
        .collect();
    let picked = gpu.pick(&context, &requests).unwrap();
    // Weights are compared against the taps' largest (the header's scale): the blend of four
    // nodes in f32 errs by a few ulps of its largest term, and the weights matched to F's
    // moments can differ a thousandfold between neighbouring nodes, so an error relative to
    // a small blended weight measures the nodes' contrast rather than the twins. Measured
    // 4.5e-5 on lavapipe (satin); bound 1e-4.
    let scale = f32::from_bits(taps.words()[1]);
    let (mut direction, mut weight, mut size) = (0.0f32, 0.0f32, 0.0f32);
    for (&(wo, k), [draw, w]) in requests.iter().zip(&picked) {
        let cpu = taps.pick(wo.as_dvec3(), k);
        direction = direction.max((Vec3::new(draw[0], draw[1], draw[2]) - cpu.wi).length());
        size = size.max((draw[3] - cpu.log2_solid_angle).abs());
        let relative = (Vec3::new(w[0], w[1], w[2]) - cpu.weight).abs() / scale;
        weight = weight.max(relative.max_element());
    }
    println!(
        "{}: {} taps on {}, largest differences from the CPU's: direction {direction:.1e}, \
         weight {weight:.1e} (of the largest), log2 solid angle {size:.1e}",
        fabric.name,
        requests.len(),
        context.adapter
    );
    assert!(direction < 5e-4 && weight < 1e-4 && size < 2.8e-3);
}
