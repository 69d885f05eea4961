//! Paper mode on the GPU (`src/evaluator/paper/paper.wgsl` through `GpuPaper`, f32)
//! against the CPU's `Patch::new(fabric, Integration::Paper(N)).eval` (f64), for the six
//! built-in fabrics, N ∈ {1, 8, 32}, on uniform pairs, highlight pairs and the curated hard
//! cases of tests/common (which add the stressed fabric variants).
//!
//! Needs a wgpu adapter; without a GPU, Mesa's lavapipe (`apt-get install -y
//! mesa-vulkan-drivers libvulkan1`). No adapter is a failure, not a skip.
//!
//! Both sides get the same input: the pairs rounded to f32 (the CPU evaluates those f32
//! directions in f64).
//!
//! # The bound
//! Per pair and channel, |GPU − CPU| ≤ R·|F| + A, from an error analysis of the f32 shader
//! with one measured input, the device's `atan2` error δ:
//! - Every term the shader sums (the per-sample reflection and transmission parts of ⟨s⟩,
//!   ⟨P⟩, Q) is ≥ 0, and the shader forms them without cancellation (bounded products,
//!   cos²θd = (di + do − di·do + ĉi·ĉo)/2 near θd → ±π/2, 1 − Fr from the transmission
//!   coefficients, half-angle forms of φd and ψd), so F's relative error is at most the
//!   largest relative error of a term: about 40 f32 operations per term and ≤ 34 summed
//!   terms at ε = 6e-8, and the device's `exp` (lavapipe: 1.1e-6 relative at arguments up to
//!   20): [`BASE_RELATIVE`] = 2e-5 covers them with margin.
//! - The lobes amplify the error of θh = (θi + θo)/2, whose θi, θo come from `atan2` (error
//!   δ, measured on the device by [`atan2_error`]: 3.4e-6 on lavapipe, far above f32
//!   rounding) plus 1.2e-7 of rounding in its arguments: g(θh) = peak·e^{−θh²/(2σ²)} has
//!   relative error (θh/σ)·δθh/σ. A sample beyond [`LOBE_REACH`] = 6σ weighs e^{−18} ≈ 1.5e-8
//!   of its lobe's peak and cannot dominate F next to the samples nearer the peak or the
//!   wider volume term, so R = BASE_RELATIVE + 6·δθh/σ_min, σ_min the narrowest lobe of the
//!   fabric (satin, σ = 2.5°: R ≈ 5e-4 on lavapipe; the stressed γ = 0.01° variant: ≈ 0.1).
//! - Where F is near 0 because every facing sample barely faces the directions (w·n(α) →
//!   0), w·n(α) = z cos α − (w·t0) sin α cancels and keeps an absolute error of ε·|w∥|, so
//!   the absolute floor A scales with the largest contributions, not with F:
//!   A = [`FLOOR`]·max |F| over the set (1e-7, about 2ε).
//!
//! Measured on lavapipe (llvmpipe, LLVM 15): the largest relative difference where
//! |F| > 1e-4 is 7.1e-5 (satin highlights, N = 1; R = 5.1e-4 there), the largest absolute
//! difference where |F| ≤ 1e-4 is 4.3e-9, and the largest diff/bound over all sets is 0.2
//! (velvet, R = 2.2e-4).

use crate::common;
use crate::common::*;

use clothbake::evaluator::paper::gpu::GpuPaper;
use clothbake::gpu::{GpuBrdf, GpuContext, GpuError, evaluate_pairs};
use clothbake::model::{Fabric, Integration, Patch};
use glam::Vec3;

/// Relative error of the f32 arithmetic and `exp` (module doc).
const BASE_RELATIVE: f64 = 2e-5;
/// θh/σ beyond which a sample's lobe cannot dominate F (module doc).
const LOBE_REACH: f64 = 6.0;
/// Rounding error of the θ that `atan2` receives through its f32 arguments (≈ 1 ulp of π/2).
const ATAN2_ARGUMENT_ERROR: f64 = 1.2e-7;
/// Absolute floor relative to the largest |F| of the set (module doc).
const FLOOR: f64 = 1e-7;

/// A `GpuBrdf` that returns the device's `atan2(wi.x, wi.y)`: for measuring its accuracy.
struct Atan2Probe {
    layout: wgpu::BindGroupLayout,
    group: wgpu::BindGroup,
}

impl GpuBrdf for Atan2Probe {
    fn wgsl(&self) -> String {
        "fn cloth_brdf(wi: vec3<f32>, wo: vec3<f32>) -> vec3<f32> {\n\
         return vec3<f32>(atan2(wi.x, wi.y), 0.0, 0.0);\n}\n"
            .into()
    }
    fn bind_group_layout(&self) -> &wgpu::BindGroupLayout {
        &self.layout
    }
    fn bind_group(&self) -> &wgpu::BindGroup {
        &self.group
    }
    fn label(&self) -> String {
        "atan2 probe".into()
    }
}

/// The largest absolute error of the device's f32 `atan2` over the angles in [−π, π] (the
/// shader's θ lie in [−π/2, π/2]), at several radii, against f64 on the same f32 arguments.
fn atan2_error(context: &GpuContext) -> f64 {
    let (layout, group) = clothbake::gpu::empty_bind_group(context, "atan2 probe");
    let probe = Atan2Probe { layout, group };
    let count = 100_000;
    let pairs: Vec<(Vec3, Vec3)> = (0..count)
        .map(|k| {
            let angle = std::f64::consts::PI * (2.0 * (k as f64 + 0.5) / count as f64 - 1.0);
            let radius = [1.0, 0.3, 1e-3, 7.0][k % 4];
            let (s, c) = angle.sin_cos();
            let w = Vec3::new((radius * s) as f32, (radius * c) as f32, 0.0);
            (w, Vec3::ZERO)
        })
        .collect();
    let values = evaluate_pairs(context, &probe, &pairs).expect("atan2 probe");
    pairs
        .iter()
        .zip(&values)
        .map(|((w, _), v)| (v[0] as f64 - (w.x as f64).atan2(w.y as f64)).abs())
        .fold(0.0, f64::max)
}

/// Compares the paper-mode shader with the CPU's paper mode at N = `samples` on `pairs`
/// (named by `names`), within the bound of the module doc.
fn compare(
    context: &GpuContext,
    atan2_error: f64,
    fabric: &Fabric,
    samples: u32,
    pairs: &[(Vec3, Vec3)],
    names: &[String],
    label: &str,
) -> (GpuCpuStats, Vec<String>) {
    let brdf = GpuPaper::new(context, fabric, samples).expect("GpuPaper");
    let patch = Patch::new(fabric, Integration::Paper(samples));
    let relative =
        BASE_RELATIVE + LOBE_REACH * (atan2_error + ATAN2_ARGUMENT_ERROR) / sigma_min(fabric);
    let bound = |scale| (relative, FLOOR * scale);
    compare_gpu_cpu(context, &brdf, &patch, pairs, names, bound, label)
}

/// A GPU context and the device's measured `atan2` error, printed.
fn setup() -> (GpuContext, f64) {
    let context = gpu_context();
    let error = atan2_error(&context);
    println!("device atan2: max absolute error {error:.2e}");
    (context, error)
}

#[test]
fn builtin_fabrics_match_cpu_paper_mode() {
    let (context, atan2_error) = setup();
    let mut failures = Vec::new();
    for (f, fabric) in common::builtin().iter().enumerate() {
        let (pairs, names) = f32_validation_pairs(fabric, 1500, 100 + 10 * f as u64);
        for samples in [1, 8, 32] {
            let label = format!("{} N={samples}", fabric.name);
            let (stats, failed) = compare(
                &context,
                atan2_error,
                fabric,
                samples,
                &pairs,
                &names,
                &label,
            );
            assert!(
                stats.nonzero > stats.count / 2,
                "{label}: most pairs should see F > 0"
            );
            failures.extend(failed);
        }
    }
    assert!(
        failures.is_empty(),
        "GPU and CPU paper mode differ beyond the bound:\n{}",
        failures.join("\n")
    );
}

#[test]
fn hard_cases_match_cpu_paper_mode() {
    let (context, atan2_error) = setup();
    let mut failures = Vec::new();
    for (fabric, pairs, names) in &f32_hard_cases_by_fabric() {
        for samples in [1, 8, 32] {
            let label = format!("hard cases {} N={samples}", fabric.name);
            let (_, failed) = compare(&context, atan2_error, fabric, samples, pairs, names, &label);
            failures.extend(failed);
        }
    }
    assert!(
        failures.is_empty(),
        "GPU and CPU paper mode differ beyond the bound on hard cases:\n{}",
        failures.join("\n")
    );
}

#[test]
fn sample_count_is_validated() {
    let context = gpu_context();
    let fabric = common::fabric("velvet");
    for samples in [0, gpu_max_samples() + 1] {
        match GpuPaper::new(&context, &fabric, samples) {
            Err(GpuError::Invalid { name, message }) => {
                assert!(name.contains("samples"), "{name}: {message}");
                assert!(message.contains(&samples.to_string()), "{message}");
            }
            Err(e) => panic!("N = {samples}: unexpected error {e}"),
            Ok(_) => panic!("N = {samples} was accepted"),
        }
    }
    let paper = GpuPaper::new(&context, &fabric, gpu_max_samples()).expect("max N");
    assert_eq!(paper.label(), format!("paper N={}", gpu_max_samples()));
}

fn gpu_max_samples() -> u32 {
    clothbake::evaluator::paper::MAX_SHADER_SAMPLES
}
