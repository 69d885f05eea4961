//! The GPU lookup (`shaders/table/lookup.wgsl` specialised for each table by
//! `clothbake::table::wgsl::lookup_wgsl`, as a `GpuBrdf`, through
//! `clothbake::gpu::evaluate_pairs`) against the CPU lookup `Table::lookup`, on small baked
//! tables of every layout and seeded direction pairs.
//!
//! Needs a wgpu adapter; without a GPU, Mesa's lavapipe (`apt-get install -y
//! mesa-vulkan-drivers libvulkan1`). No adapter is a failure, not a skip.
//!
//! # The bound
//! Each layout declares how far its WGSL lookup may be from its CPU lookup
//! (`TableLookup::gpu_error_bound`; the sources of error are derived in
//! `clothbake::table::gpu_bound`: 8-bit filter weights, f32 coordinates, thread_frame's fold
//! u = 0, split_frame's f32 sample kernel). The test asserts |GPU − CPU| ≤ bound everywhere
//! through the table, whatever the layout, and prints the largest absolute and relative
//! differences and the largest ratio difference/bound.

use crate::common::*;

use clothbake::bake::bake;
use clothbake::evaluator::table::gpu::GpuTable;
use clothbake::formats::fabric_toml::FabricSet;
use clothbake::gpu::{GpuBrdf, evaluate_pairs};
use clothbake::measure::direction_sets::{highlight_pairs, uniform_pairs};
use clothbake::table::gpu_bound::GpuErrorBound;
use clothbake::table::{Layout, Table};
use glam::{DVec3, Vec3};
use std::time::Instant;

/// 2000 uniform and 2000 highlight pairs, rounded to f32 (both sides see the same input).
fn pairs(table: &Table, seed: u64) -> Vec<(Vec3, Vec3)> {
    let mut pairs = uniform_pairs(2000, seed);
    pairs.extend(highlight_pairs(&table.fabric, 2000, seed + 1));
    pairs
        .into_iter()
        .map(|(wi, wo)| (wi.as_vec3(), wo.as_vec3()))
        .collect()
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
    let gpu_table = GpuTable::new(&context, &table).expect("upload table");
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
        let GpuErrorBound {
            per_channel: bound,
            on_fold: folded,
        } = table.gpu_error_bound(wi, wo, cpu);
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

/// Every registered layout, at the smallest resolution of its ladder, on the fabric with the
/// narrowest lobes, within the bound the layout declares.
#[test]
fn every_registered_layout_matches_cpu_within_its_declared_bound() {
    for (k, &layout) in Layout::ALL.iter().enumerate() {
        let resolution = layout.resolution_ladder()[0];
        compare(
            "polyester_satin_charmeuse",
            layout,
            resolution,
            101 + 2 * k as u64,
        );
    }
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
