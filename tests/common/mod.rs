//! Helpers shared by the integration tests, and the curated list of the model's numerically
//! hard cases that every stability test runs.
#![allow(dead_code)] // each test binary uses a different subset

use clothbake::formats::fabric_toml::FabricSet;
#[cfg(feature = "runtime")]
use clothbake::gpu::{GpuBrdf, GpuContext, evaluate_pairs};
use clothbake::measure::direction_sets::{highlight_pairs, uniform_pairs};
#[cfg(feature = "runtime")]
use clothbake::model::Patch;
use clothbake::model::{Fabric, Thread};
use glam::{DVec3, Vec3};
use std::path::Path;
use std::process::Output;

/// A device on whatever adapter wgpu finds, which the test prints; a test that needs one
/// fails without it (CI installs lavapipe through scripts/setup.sh).
#[cfg(feature = "runtime")]
pub fn gpu_context() -> GpuContext {
    match GpuContext::new() {
        Ok(context) => {
            println!("GPU adapter: {}", context.adapter);
            context
        }
        Err(e) => panic!(
            "this test needs a wgpu adapter and found none: {e}\n\
             (CI installs lavapipe: apt-get install -y mesa-vulkan-drivers libvulkan1)"
        ),
    }
}

/// A fresh, empty directory `clothbake-LABEL-XXXXXX` under the system's temporary
/// directory, removed with everything in it when dropped (also when the test fails).
pub fn temp_dir(label: &str) -> ScratchDir {
    ScratchDir(
        tempfile::Builder::new()
            .prefix(&format!("clothbake-{label}-"))
            .tempdir()
            .unwrap(),
    )
}

/// A temporary directory that reads as its path (`dir.join(..)`, `&dir`).
pub struct ScratchDir(tempfile::TempDir);

impl std::ops::Deref for ScratchDir {
    type Target = Path;
    fn deref(&self) -> &Path {
        self.0.path()
    }
}

impl AsRef<Path> for ScratchDir {
    fn as_ref(&self) -> &Path {
        self.0.path()
    }
}

/// A command's standard output followed by its standard error.
pub fn output_text(output: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    )
}

pub fn path_str(p: &Path) -> &str {
    p.to_str().unwrap()
}

pub fn builtin() -> Vec<Fabric> {
    FabricSet::builtin().fabrics().to_vec()
}

pub fn fabric(name: &str) -> Fabric {
    FabricSet::builtin()
        .get(name)
        .expect("built-in fabric")
        .clone()
}

/// A unit direction from elevation above the horizon and azimuth from +x, in degrees.
pub fn dir(elevation_deg: f64, azimuth_deg: f64) -> DVec3 {
    let (e, a) = (elevation_deg.to_radians(), azimuth_deg.to_radians());
    DVec3::new(e.cos() * a.cos(), e.cos() * a.sin(), e.sin())
}

/// The tangent t(α) of thread `index` (0: along x, 1: along y).
pub fn tangent(index: usize, alpha_deg: f64) -> DVec3 {
    let t0 = if index == 0 { DVec3::X } else { DVec3::Y };
    let a = alpha_deg.to_radians();
    a.cos() * t0 + a.sin() * DVec3::Z
}

/// Relative RMS error of `values` against `reference`, over all RGB components.
pub fn relative_rms(values: &[DVec3], reference: &[DVec3]) -> f64 {
    let err: f64 = values
        .iter()
        .zip(reference)
        .map(|(v, r)| (*v - *r).length_squared())
        .sum();
    let norm: f64 = reference.iter().map(|r| r.length_squared()).sum();
    (err / norm).sqrt()
}

/// The narrowest lobe standard deviation of `fabric` (surface or volume, either thread), in
/// radians: where an error in θh weighs most.
pub fn sigma_min(fabric: &Fabric) -> f64 {
    fabric
        .threads()
        .iter()
        .flat_map(|t| [t.gamma_s_deg, t.gamma_v_deg])
        .map(|g| fabric.options.lobe_sigma_deg(g).to_radians())
        .fold(f64::INFINITY, f64::min)
}

/// `count` uniform then `count` highlight pairs of `fabric` rounded to f32 as a shader
/// receives them, and their set names.
pub fn f32_validation_pairs(
    fabric: &Fabric,
    count: usize,
    seed: u64,
) -> (Vec<(Vec3, Vec3)>, Vec<String>) {
    let to_f32 = |(wi, wo): (DVec3, DVec3)| (wi.as_vec3(), wo.as_vec3());
    let mut pairs: Vec<(Vec3, Vec3)> = uniform_pairs(count, seed).into_iter().map(to_f32).collect();
    pairs.extend(
        highlight_pairs(fabric, count, seed + 1)
            .into_iter()
            .map(to_f32),
    );
    let names = (0..pairs.len())
        .map(|k| if k < count { "uniform" } else { "highlight" }.to_string())
        .collect();
    (pairs, names)
}

/// A fabric with direction pairs rounded to f32, as a shader receives them, and their names.
pub type F32Cases = (Fabric, Vec<(Vec3, Vec3)>, Vec<String>);

/// The curated hard cases grouped by fabric, pairs rounded to f32.
pub fn f32_hard_cases_by_fabric() -> Vec<F32Cases> {
    let mut groups: Vec<F32Cases> = Vec::new();
    for case in hard_cases() {
        let pair = (case.wi.as_vec3(), case.wo.as_vec3());
        match groups
            .iter_mut()
            .find(|(f, _, _)| f.name == case.fabric.name)
        {
            Some((_, pairs, names)) => {
                pairs.push(pair);
                names.push(case.name);
            }
            None => groups.push((case.fabric, vec![pair], vec![case.name])),
        }
    }
    groups
}

/// Largest differences of a GPU evaluation against the CPU's over a set of pairs.
#[derive(Default, Debug)]
pub struct GpuCpuStats {
    pub count: usize,
    /// Pairs where the CPU's F is not 0.
    pub nonzero: usize,
    pub max_abs: f64,
    /// Largest relative difference where |F| > 1e-4.
    pub max_rel: f64,
    /// Largest |GPU − CPU| where |F| ≤ 1e-4.
    pub max_abs_small: f64,
    /// Relative RMS of the GPU values against the CPU's.
    pub rms: f64,
    /// Largest difference over its bound.
    pub max_ratio: f64,
    pub worst: String,
}

#[cfg(feature = "runtime")]
/// Evaluates `pairs` (named by `names`) with `brdf` on the device and with `patch` on the CPU
/// (in f64, on the same f32 directions) and compares them pair by pair and channel by
/// channel: each GPU value must be finite, ≥ 0 and within R·|F| + A of the CPU's, where
/// `bound(max |F| of the set)` = (R, A). Prints one line headed `label` and returns the
/// statistics and up to ten failures.
pub fn compare_gpu_cpu(
    context: &GpuContext,
    brdf: &dyn GpuBrdf,
    patch: &Patch,
    pairs: &[(Vec3, Vec3)],
    names: &[String],
    bound: impl Fn(f64) -> (f64, f64),
    label: &str,
) -> (GpuCpuStats, Vec<String>) {
    let gpu = evaluate_pairs(context, brdf, pairs).expect("GPU evaluation");
    assert_eq!(gpu.len(), pairs.len());
    let cpu: Vec<DVec3> = pairs
        .iter()
        .map(|(wi, wo)| patch.eval(wi.as_dvec3(), wo.as_dvec3()))
        .collect();
    let scale = cpu
        .iter()
        .map(|f| f.abs().max_element())
        .fold(0.0, f64::max);
    let (relative, absolute) = bound(scale);
    let label = format!("{label} ({})", brdf.label());
    let cpu = &cpu[..];
    let gpu: Vec<DVec3> = gpu
        .iter()
        .map(|g| DVec3::new(g[0] as f64, g[1] as f64, g[2] as f64))
        .collect();
    let mut stats = GpuCpuStats {
        rms: relative_rms(&gpu, cpu),
        ..Default::default()
    };
    let mut failures = Vec::new();
    for (k, ((&(wi, wo), gpu), cpu)) in pairs.iter().zip(&gpu).zip(cpu).enumerate() {
        stats.count += 1;
        stats.nonzero += (cpu.max_element() > 0.0) as usize;
        for c in 0..3 {
            let diff = (gpu[c] - cpu[c]).abs();
            let bound = relative * cpu[c].abs() + absolute;
            stats.max_abs = stats.max_abs.max(diff);
            if cpu[c].abs() > 1e-4 {
                stats.max_rel = stats.max_rel.max(diff / cpu[c].abs());
            } else {
                stats.max_abs_small = stats.max_abs_small.max(diff);
            }
            let ratio = diff / bound;
            if ratio > stats.max_ratio || ratio.is_nan() || !gpu[c].is_finite() {
                stats.max_ratio = stats.max_ratio.max(ratio);
                stats.worst = format!(
                    "{} channel {c}: GPU {} CPU {} wi {wi} wo {wo}",
                    names[k], gpu[c], cpu[c]
                );
            }
            // A NaN on the GPU fails too (the comparison is false).
            let ok = gpu[c].is_finite() && gpu[c] >= 0.0 && diff <= bound;
            if !ok && failures.len() < 10 {
                failures.push(format!(
                    "{label}: {} wi {wi} wo {wo}: channel {c} GPU {} CPU {} diff {diff:e} \
                     bound {bound:e}",
                    names[k], gpu[c], cpu[c]
                ));
            }
        }
    }
    println!(
        "{label}: {} pairs ({} with F > 0), max |GPU−CPU| {:.3e}, max relative {:.3e} (where \
         |F| > 1e-4), max |GPU−CPU| {:.3e} where |F| ≤ 1e-4, relative RMS {:.3e}; bound R \
         {relative:.2e}, A {absolute:.2e}, max diff/bound {:.3}; worst: {}",
        stats.count,
        stats.nonzero,
        stats.max_abs,
        stats.max_rel,
        stats.max_abs_small,
        stats.rms,
        stats.max_ratio,
        stats.worst
    );
    (stats, failures)
}

/// One numerically hard evaluation: a fabric (built-in or a stressed variant) and a pair.
#[derive(Clone, Debug)]
pub struct HardCase {
    pub name: String,
    pub fabric: Fabric,
    pub wi: DVec3,
    pub wo: DVec3,
}

fn with_threads(base: &Fabric, name: &str, edit: impl Fn(&mut Thread)) -> Fabric {
    let mut f = base.clone();
    f.name = name.to_string();
    edit(&mut f.thread1);
    edit(&mut f.thread2);
    f.validate().expect("stressed variant is still valid");
    f
}

/// The stressed fabric variants of docs/model.md#hard-numerical-cases.
pub fn stressed_fabrics() -> Vec<Fabric> {
    let linen = fabric("linen_plain");
    let satin = fabric("polyester_satin_charmeuse");
    let mut full = with_threads(&linen, "full_coverage", |_| {});
    full.thread1.coverage = 0.5;
    full.thread2.coverage = 0.5;
    vec![
        with_threads(&linen, "eta_one", |t| t.eta = 1.0),
        with_threads(&satin, "gamma_0_01", |t| {
            t.gamma_s_deg = 0.01;
            t.gamma_v_deg = 0.01;
        }),
        full,
        with_threads(&linen, "single_point", |t| {
            t.offsets_deg = vec![10.0];
            t.lengths = vec![];
        }),
        with_threads(&linen, "zero_length_jumps", |t| {
            t.offsets_deg = vec![-40.0, -10.0, 20.0, 5.0, 5.0];
            t.lengths = vec![1.0, 0.0, 0.0, 2.0];
        }),
        with_threads(&linen, "vertical_tangents", |t| {
            t.offsets_deg = vec![-90.0, 90.0];
            t.lengths = vec![1.0];
        }),
    ]
}

/// Direction pairs that stress one fabric: grazing, parallel to every curve end's tangent,
/// parallel to each rotation axis, equal, mirrored.
fn hard_pairs(fabric: &Fabric) -> Vec<(String, DVec3, DVec3)> {
    let mut pairs = Vec::new();
    let generic = [dir(35.0, 20.0), dir(60.0, 200.0), dir(5.0, 95.0)];
    for (label, grazing) in [
        ("grazing exactly", 0.0),
        ("grazing 1e-12", 1e-12_f64.to_degrees()),
        ("grazing 1e-7", 1e-7_f64.to_degrees()),
    ] {
        for azimuth in [0.0, 45.0, 90.0, 180.0, 270.0] {
            let w = dir(grazing, azimuth);
            for g in generic {
                pairs.push((format!("{label} wi az {azimuth}"), w, g));
                pairs.push((format!("{label} wo az {azimuth}"), g, w));
            }
            pairs.push((format!("{label} both az {azimuth}"), w, w));
            pairs.push((
                format!("{label} opposite az {azimuth}"),
                w,
                dir(grazing, azimuth + 180.0),
            ));
        }
    }
    for (j, thread) in fabric.threads().into_iter().enumerate() {
        let ends = [thread.offsets_deg[0], *thread.offsets_deg.last().unwrap()];
        for alpha in ends.into_iter().chain(thread.offsets_deg.iter().copied()) {
            for sign in [1.0, -1.0] {
                let t = sign * tangent(j, alpha);
                // Keep the direction in the upper hemisphere; a horizontal t is lifted by 1e-9.
                let w = if t.z > 0.0 {
                    t
                } else {
                    DVec3::new(t.x, t.y, t.z.abs().max(1e-9)).normalize()
                };
                for g in generic
                    .iter()
                    .copied()
                    .chain([w, DVec3::new(-w.x, -w.y, w.z)])
                {
                    pairs.push((format!("thread {} t({alpha}) wi", j + 1), w, g));
                    pairs.push((format!("thread {} t({alpha}) wo", j + 1), g, w));
                }
            }
        }
    }
    for b in [DVec3::X, DVec3::Y, -DVec3::X, -DVec3::Y] {
        for lift in [0.0, 1e-15, 1e-9] {
            let w = (b + DVec3::Z * lift).normalize();
            for g in generic {
                pairs.push((format!("parallel to b {b} lift {lift}"), w, g));
                pairs.push((format!("parallel to b {b} lift {lift} (wo)"), g, w));
            }
        }
    }
    for w in generic
        .iter()
        .copied()
        .chain([DVec3::Z, dir(89.999, 0.0), dir(0.5, 30.0)])
    {
        pairs.push(("wi = wo".into(), w, w));
        pairs.push(("wi mirror of wo".into(), DVec3::new(-w.x, -w.y, w.z), w));
    }
    pairs
}

/// The curated hard cases: every built-in and stressed fabric with its hard pairs.
pub fn hard_cases() -> Vec<HardCase> {
    builtin()
        .into_iter()
        .chain(stressed_fabrics())
        .flat_map(|fabric| {
            hard_pairs(&fabric)
                .into_iter()
                .map(move |(label, wi, wo)| HardCase {
                    name: format!("{}: {label}", fabric.name),
                    fabric: fabric.clone(),
                    wi,
                    wo,
                })
        })
        .collect()
}

/// Upper-hemisphere directions on a grid dense in elevation near the horizon.
pub fn hemisphere_sweep() -> Vec<DVec3> {
    let elevations = [1e-6, 0.5, 2.0, 6.0, 15.0, 30.0, 50.0, 70.0, 89.9];
    elevations
        .iter()
        .flat_map(|&e| {
            (0..24).map(move |k| dir(e, 15.0 * k as f64 + 7.5 * (e > 45.0) as u8 as f64))
        })
        .collect()
}
