//! The GPU lookup (`shaders/table/lookup.wgsl` specialised for each table by
//! `clothbake::table::wgsl::lookup_wgsl`, as a `GpuBrdf`, through
//! `clothbake::gpu::evaluate_pairs`) against the CPU lookup `Table::lookup`, on small baked
//! tables of every layout and seeded direction pairs.
//!
//! Needs a wgpu adapter; without a GPU, Mesa's lavapipe (`apt-get install -y
//! mesa-vulkan-drivers libvulkan1`). No adapter is a failure, not a skip.
//!
//! # The bound
//! Both sides read the same f16 texels (the upload is lossless) and interpolate the same
//! corners with the same weights, so the differences come from two sources:
//! 1. Hardware filtering quantises each filter weight: lavapipe (like most GPUs) computes
//!    them in 8-bit fixed point, so a weight is off by at most δ = 1/256. On one filtered
//!    axis this moves the result by at most δ·|difference across that axis| ≤ δ·(range of
//!    the corners); over k filtered axes by k·δ·range. thread_frame filters 3 axes of the 4D
//!    table (βH, θd', v; u is blended in f32 by the shader) and 2 of ⟨P⟩; grid4d filters
//!    the 2 wo axes (the wi blend is in f32).
//! 2. f32 arithmetic: the coordinates (atan2, asin, sin βH and cos βH as h.x/|h∥|, h.z/|h∥|,
//!    the warps with their constant factors folded in f64 and rounded once to f32) carry
//!    errors of a few ulp, which shift every interpolation weight by far less than ε = 1e-4
//!    of a texel (so
//!    ≤ ε·range per axis, 4 axes), cos²θd' = 1 − s² carries ~1e-7 absolute error (relative
//!    1e-7/cos²θd' in reflection/cos²θd'), and the final sums ~1e-6 relative.
//!
//! For thread_frame, F = Σ_j a_j ⟨P⟩_j (r_j / c_j + A_j t_j) / Q with Q = Σ_j a_j ⟨P⟩_j +
//! gap·wo.z is nonlinear in the interpolated r_j, t_j, ⟨P⟩_j, so the interpolation errors
//! above are propagated to F with its partial derivatives (first order, evaluated at the
//! CPU's values).
//! 3. The fold u → |u| of `thread_frame` (u = (φi' + φo')/2, see its module doc): pairs with
//!    u within f32 error of 0 (highlight pairs produce them) may be folded to the other side
//!    on the GPU, reading the table at (|u|, −v) instead of (|u|, v). The model is symmetric
//!    there, but the baked table need not be exactly (measured: up to ~4% on satin's
//!    grazing texels at R = 16), so for |u| < 1e-5 the difference between the two
//!    interpolations is added, propagated like the filtering error.
//!
//! 4. split_frame evaluates its point masses with the shared f32 sample kernel
//!    (`shaders/model/tangent_sample.wgsl`) where the CPU uses the f64 model. tests/gpu_direct.rs bounds
//!    that kernel's relative error by R = 2e-5 + 6·δθh/σ_min, δθh the device's atan2 error
//!    (3.4e-6 on lavapipe): 5e-4 for satin's σs = 2.5°, the narrowest lobe here. The point
//!    sums enter both ⟨s⟩ and Q, so F moves by at most 2R relative: 1e-3·|F| is added.
//!    In the horizon band (a direction below 1°) the sloped segments come from the resonant
//!    quadrature instead of the table, in f32 on the GPU (`shaders/model/resonant_quadrature.wgsl`, the same
//!    sample kernel) and f64 on the CPU: no interpolation error, and the same 1e-3·|F|
//!    covers the kernel (tests/gpu_resonant.rs measures at most 1.4e-4 relative where
//!    |F| > 1e-4).
//!
//! The bound per pair and channel is that propagated error plus 1e-5·|F| +
//! 1e-6. The test asserts |GPU − CPU| ≤ bound everywhere, and prints the largest absolute
//! and relative differences and the largest ratio difference/bound.
#![cfg(feature = "runtime")] // the wgpu runtime: not in `--no-default-features` builds

mod common;
use common::*;

use clothbake::bake::bake;
use clothbake::direction_sets::{highlight_pairs, uniform_pairs};
use clothbake::fabric_file::FabricSet;
use clothbake::gpu::{GpuBrdf, GpuTable, evaluate_pairs};
use clothbake::table::thread_frame::ThreadGeometry;
use clothbake::table::{
    Layout, Plane, Table, octahedral, quadrilinear_corners, split_frame, thread_frame,
};
use glam::{DVec3, Vec3};
use std::time::Instant;

/// Weight quantisation of hardware filtering (8-bit fractions).
const DELTA: f64 = 1.0 / 256.0;
/// f32 coordinate error, in texels, per axis.
const EPSILON: f64 = 1e-4;
const RELATIVE: f64 = 1e-5;
const ABSOLUTE: f64 = 1e-6;
/// |u| (radians) below which f32 may fold a pair to the other side of u = 0.
const FOLD_EPSILON: f64 = 1e-5;
/// Relative error of F from the f32 sample kernel of split_frame's point masses (module
/// doc, point 4).
const KERNEL_RELATIVE: f64 = 1e-3;

/// 2000 uniform and 2000 highlight pairs, rounded to f32 (both sides see the same input).
fn pairs(table: &Table, seed: u64) -> Vec<(Vec3, Vec3)> {
    let mut pairs = uniform_pairs(2000, seed);
    pairs.extend(highlight_pairs(&table.fabric, 2000, seed + 1));
    pairs
        .into_iter()
        .map(|(wi, wo)| (wi.as_vec3(), wo.as_vec3()))
        .collect()
}

fn range(values: impl IntoIterator<Item = f64>) -> f64 {
    let (lo, hi) = values
        .into_iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    hi - lo
}

/// Thread `thread`'s 4D table (`data`, two channels) interpolated at table coordinates, as
/// `Geometry::sample_thread` does.
fn interpolate(thread: &ThreadGeometry, data: &[f32], coordinates: [f64; 4]) -> [f64; 2] {
    let axes = std::array::from_fn(|a| thread.axes[a].locate(coordinates[a]));
    let mut sum = [0.0; 2];
    for (index, weight) in quadrilinear_corners(axes) {
        let k = thread.texel_index(index) * 2;
        sum[0] += weight * data[k] as f64;
        sum[1] += weight * data[k + 1] as f64;
    }
    sum
}

/// The interpolation errors of one thread table (4D plane `table`, masking plane
/// `masking`) at a pair, per the module doc: `[reflection, transmission, ⟨P⟩]` from
/// filtering and f32 coordinates, and the fold differences `[reflection, transmission]`
/// (at least a tiny value when the pair is on the fold u = 0, else 0).
fn thread_errors(
    thread: &ThreadGeometry,
    table: &Plane,
    masking: &Plane,
    wi: DVec3,
    wo: DVec3,
) -> ([f64; 3], [f64; 2]) {
    let coordinates = thread.coordinates(wi, wo);
    let axes = std::array::from_fn(|a| thread.axes[a].locate(coordinates[a]));
    let texels: Vec<usize> = quadrilinear_corners(axes)
        .map(|(i, _)| thread.texel_index(i) * 2)
        .collect();
    let data = &table.data;
    let scale = 3.0 * DELTA + 4.0 * EPSILON;
    let mut errors = [0.0; 3];
    errors[0] = scale * range(texels.iter().map(|&k| data[k] as f64));
    errors[1] = scale * range(texels.iter().map(|&k| data[k + 1] as f64));
    let m = thread.masking_axis;
    let ((x0, x1, _), (y0, y1, _)) = (m.locate(thread.beta(wi)), m.locate(thread.beta(wo)));
    let p_range =
        range([(x0, y0), (x1, y0), (x0, y1), (x1, y1)].map(|(x, y)| masking.texel(x, y)[0] as f64));
    errors[2] = (2.0 * DELTA + 2.0 * EPSILON) * p_range;
    let mut fold = [0.0; 2];
    // On the fold u = 0, f32 may land on the other side, (u, v) → (−u, −v).
    if coordinates[2] < FOLD_EPSILON {
        let [u, v] = [coordinates[2], coordinates[3]];
        let other = interpolate(thread, data, [coordinates[0], coordinates[1], u, -v]);
        let here = interpolate(thread, data, coordinates);
        // At least a tiny value, marking the pair as on the fold.
        fold = [
            (other[0] - here[0]).abs().max(f64::MIN_POSITIVE),
            (other[1] - here[1]).abs(),
        ];
    }
    (errors, fold)
}

/// The bound for a split_frame table: the sloped tables' interpolation errors propagated
/// to F as for thread_frame (their ⟨P⟩ weighted by the sloped share; none in the horizon
/// band), plus the f32 sample kernel's relative error for the point masses and the band's
/// resonant quadrature (module doc, point 4).
fn split_frame_bound(
    table: &Table,
    geometry: &split_frame::Geometry,
    wi: DVec3,
    wo: DVec3,
    cpu: DVec3,
    floor: DVec3,
) -> (DVec3, bool) {
    let planes = table.planes();
    let albedo = table
        .fabric
        .threads()
        .map(|t| DVec3::from_array(t.albedo_rgb()));
    let sums = [0, 1].map(|j| geometry.thread_sums(planes, j, wi, wo));
    let q = geometry.gap * wo.z
        + (0..2)
            .map(|j| geometry.coverage[j] * sums[j][2])
            .sum::<f64>();
    if q <= 0.0 {
        return (floor, false);
    }
    let mut total = floor + cpu.abs() * KERNEL_RELATIVE;
    let mut folded = false;
    if geometry.in_horizon_band(wi, wo) {
        return (total, false);
    }
    for (j, slopes) in geometry.tabulated() {
        let (t, m) = geometry
            .plane_indices(j)
            .expect("a tabulated thread has planes");
        let [r, tr, p, c2] = slopes.geometry.sample(&planes[t], &planes[m], wi, wo);
        let (errors, fold) = thread_errors(&slopes.geometry, &planes[t], &planes[m], wi, wo);
        folded |= fold != [0.0; 2];
        let a = geometry.coverage[j] * slopes.weight;
        let c = c2.max(1e-8);
        let d_r = a * p / (c * q);
        let d_t = albedo[j] * (a * p / q);
        let d_p = (DVec3::splat(r / c) + albedo[j] * tr - cpu) * (a / q);
        total += DVec3::splat(d_r * (errors[0] + fold[0]))
            + d_t.abs() * (errors[1] + fold[1])
            + d_p.abs() * errors[2];
    }
    (total, folded)
}

/// The error bound of the module doc for one pair, per RGB channel, and whether the pair
/// lies on the fold u = 0 of a thread (point 3).
fn bound(table: &Table, wi: DVec3, wo: DVec3, cpu: DVec3) -> (DVec3, bool) {
    let albedo = table
        .fabric
        .threads()
        .map(|t| DVec3::from_array(t.albedo_rgb()));
    let floor = cpu.abs() * RELATIVE + ABSOLUTE;
    if wi.z <= 0.0 || wo.z <= 0.0 {
        return (floor, false);
    }
    let planes = table.planes();
    if let Some(geometry) = table.geometry_as::<split_frame::Geometry>() {
        return split_frame_bound(table, geometry, wi, wo, cpu, floor);
    }
    match table.geometry_as::<thread_frame::Geometry>() {
        None => {
            let n = table.resolution as usize;
            let axis = |x: f64| {
                let f = x.floor();
                let last = n as i64 - 1;
                let i = |k: i64| k.clamp(0, last) as usize;
                (i(f as i64), i(f as i64 + 1), x - f)
            };
            let ci = octahedral::encode(wi) * n as f64 - 0.5;
            let co = octahedral::encode(wo) * n as f64 - 0.5;
            let axes = [axis(ci.x), axis(ci.y), axis(co.x), axis(co.y)];
            let corners: Vec<&[f32]> = quadrilinear_corners(axes)
                .map(|(i, _)| planes[0].texel(i[0] * n + i[2], i[1] * n + i[3]))
                .collect();
            let ranges: [f64; 3] =
                std::array::from_fn(|c| range(corners.iter().map(|t| t[c] as f64)));
            let scale = 2.0 * DELTA + 4.0 * EPSILON;
            let bound = (DVec3::splat(ranges[0]) + albedo[0] * ranges[1] + albedo[1] * ranges[2])
                * scale
                + floor;
            (bound, false)
        }
        Some(geometry) => {
            let mut samples = [[0.0f64; 4]; 2];
            let mut errors = [[0.0; 3]; 2];
            let mut fold = [[0.0; 2]; 2];
            for (j, thread) in geometry.threads.iter().enumerate() {
                samples[j] = geometry.sample_thread(planes, j, wi, wo);
                (errors[j], fold[j]) = thread_errors(thread, &planes[j], &planes[2 + j], wi, wo);
            }
            let q: f64 = geometry.gap * wo.z
                + (0..2)
                    .map(|j| geometry.coverage[j] * samples[j][2])
                    .sum::<f64>();
            if q <= 0.0 {
                return (floor, false);
            }
            let mut total = floor;
            for j in 0..2 {
                let [r, t, p, c2] = samples[j];
                let a = geometry.coverage[j];
                let c = c2.max(1e-8);
                let d_r = a * p / (c * q);
                let d_t = albedo[j] * (a * p / q);
                let d_p = (DVec3::splat(r / c) + albedo[j] * t - cpu) * (a / q);
                // f32 error of 1 − s² (absolute ~1e-7) in reflection/cos²θd'.
                let c2_error = a * p * r / (c * q) * (1e-7 / c);
                total += DVec3::splat(d_r * (errors[j][0] + fold[j][0]) + c2_error)
                    + d_t.abs() * (errors[j][1] + fold[j][1])
                    + d_p.abs() * errors[j][2];
            }
            (total, fold != [[0.0; 2]; 2])
        }
    }
}

/// Bakes `fabric_name` into `layout` at `resolution`, evaluates 4000 pairs on both sides,
/// prints the differences and asserts the bound.
fn compare(fabric_name: &str, layout: Layout, resolution: u32, seed: u64) {
    let start = Instant::now();
    let context = gpu_context();
    let fabric = FabricSet::builtin()
        .get(fabric_name)
        .expect("built-in fabric")
        .clone();
    let table = bake(&fabric, layout, resolution, &|| {}).expect("bake");
    let baked = start.elapsed();
    // The lookup that follows `Table::lookup`, horizon band included, whatever the adapter.
    let gpu_table =
        GpuTable::with_horizon_band(&context, &table, Some(true)).expect("upload table");
    let pairs = pairs(&table, seed);
    let gpu_start = Instant::now();
    let gpu = evaluate_pairs(&context, &gpu_table, &pairs).expect("GPU lookup");
    let gpu_time = gpu_start.elapsed();
    assert_eq!(gpu.len(), pairs.len());

    let (mut max_abs, mut max_rel, mut max_ratio) = (0.0f64, 0.0f64, 0.0f64);
    // The same, over the pairs off the fold u = 0.
    let (mut off_abs, mut off_rel, mut off_ratio, mut on_fold) = (0.0f64, 0.0f64, 0.0f64, 0);
    let mut failures = Vec::new();
    let mut nonzero = 0;
    for (k, (&(wi, wo), g)) in pairs.iter().zip(&gpu).enumerate() {
        let (wi, wo) = (wi.as_dvec3(), wo.as_dvec3());
        let cpu = table.lookup(wi, wo);
        let gpu = DVec3::new(g[0] as f64, g[1] as f64, g[2] as f64);
        let (bound, folded) = bound(&table, wi, wo, cpu);
        on_fold += folded as usize;
        if cpu.max_element() > 0.0 {
            nonzero += 1;
        }
        for c in 0..3 {
            let diff = (gpu[c] - cpu[c]).abs();
            max_abs = max_abs.max(diff);
            if !folded {
                off_abs = off_abs.max(diff);
                off_ratio = off_ratio.max(diff / bound[c]);
            }
            if cpu[c].abs() > 1e-3 {
                max_rel = max_rel.max(diff / cpu[c].abs());
                if !folded {
                    off_rel = off_rel.max(diff / cpu[c].abs());
                }
            }
            max_ratio = max_ratio.max(diff / bound[c]);
            // A NaN on the GPU fails too.
            let within = diff <= bound[c];
            if !within && failures.len() < 10 {
                failures.push(format!(
                    "pair {k} wi {wi} wo {wo}: channel {c} GPU {} CPU {} diff {diff:e} bound {:e}",
                    gpu[c], cpu[c], bound[c]
                ));
            }
        }
    }
    println!(
        "{} ({fabric_name}): {} pairs ({nonzero} with F > 0), \
         max |GPU−CPU| {max_abs:.3e}, max relative {max_rel:.3e} (where |F| > 1e-3), \
         max diff/bound {max_ratio:.3}; off the fold u = 0 ({on_fold} pairs on it): \
         max |GPU−CPU| {off_abs:.3e}, max relative {off_rel:.3e}, max diff/bound {off_ratio:.3}; bake {:.2} s, GPU lookup {:.1} ms, total {:.2} s",
        gpu_table.label(),
        pairs.len(),
        baked.as_secs_f64(),
        gpu_time.as_secs_f64() * 1e3,
        start.elapsed().as_secs_f64()
    );
    assert!(
        nonzero > pairs.len() / 2,
        "most pairs should see a nonzero F, got {nonzero}"
    );
    assert!(
        failures.is_empty(),
        "GPU and CPU lookups differ beyond the bound:\n{}",
        failures.join("\n")
    );
}

#[test]
fn thread_frame_satin_matches_cpu() {
    compare("polyester_satin_charmeuse", Layout::THREAD_FRAME, 16, 11);
}

#[test]
fn thread_frame_velvet_matches_cpu() {
    compare("velvet", Layout::THREAD_FRAME, 16, 23);
}

#[test]
fn split_frame_satin_back_matches_cpu() {
    compare(
        "polyester_satin_charmeuse_back",
        Layout::SPLIT_FRAME,
        12,
        41,
    );
}

#[test]
fn split_frame_linen_matches_cpu() {
    compare("linen_plain", Layout::SPLIT_FRAME, 12, 43);
}

#[test]
fn grid4d_matches_cpu() {
    compare("silk_shot", Layout::GRID4D, 12, 37);
}

/// split_frame's lookup without the horizon band (what `GpuTable::new` builds on a software
/// rasteriser) against the one with it, on the same device: pairs outside the band must get
/// the same F (the same table code, compiled in another shader); pairs inside it read the
/// table instead of the resonant quadrature, so they differ by the table's error there,
/// which is printed.
#[test]
fn split_frame_without_horizon_band_changes_only_the_band() {
    let context = gpu_context();
    let fabric = FabricSet::builtin()
        .get("polyester_satin_charmeuse")
        .expect("built-in fabric")
        .clone();
    let table = bake(&fabric, Layout::SPLIT_FRAME, 12, &|| {}).expect("bake");
    let geometry = table
        .geometry_as::<split_frame::Geometry>()
        .expect("split_frame geometry");
    let pairs = pairs(&table, 47);
    let evaluate = |horizon_band| {
        let gpu_table = GpuTable::with_horizon_band(&context, &table, Some(horizon_band))
            .expect("upload table");
        println!("{}", gpu_table.label());
        evaluate_pairs(&context, &gpu_table, &pairs).expect("GPU lookup")
    };
    let (with_band, without) = (evaluate(true), evaluate(false));
    let (mut in_band, mut outside_worst, mut band_squared, mut band_norm) = (0, 0.0f64, 0.0, 0.0);
    for ((&(wi, wo), a), b) in pairs.iter().zip(&with_band).zip(&without) {
        let (a, b) = (Vec3::from(*a).as_dvec3(), Vec3::from(*b).as_dvec3());
        if geometry.in_horizon_band(wi.as_dvec3(), wo.as_dvec3()) {
            in_band += 1;
            band_squared += (a - b).length_squared();
            band_norm += a.length_squared();
        } else {
            outside_worst =
                outside_worst.max((a - b).abs().max_element() / (a.max_element() + 1e-6));
        }
    }
    println!(
        "{} pairs, {in_band} in the horizon band: outside it the largest difference is \
         {outside_worst:.2e} of F (+1e-6); inside it the band-free lookup is {:.2}% off (relative \
         RMS against the band's resonant quadrature)",
        pairs.len(),
        100.0 * (band_squared / band_norm).sqrt()
    );
    assert!(in_band > 0, "the pairs must reach the band");
    // The same f32 operations in both shaders; 1e-5 leaves room for a compiler that fuses
    // them differently in the two pipelines.
    assert!(outside_worst <= 1e-5, "{outside_worst:e}");
    assert!(
        band_squared > 0.0,
        "without the band its pairs must read the table"
    );
}
