//! A thread's tables baked: the 4D table's stored ratios at every texel (prefiltered for
//! multilinear reading), the masking plane, and both as GPU textures.

use super::geometry::{MASKING_TEXELS, ThreadGeometry};
use crate::model::patch::ThreadModel;
use crate::model::{Fabric, Integration};
use crate::table::bindings::{ARRAY_SLOTS, VOLUME_SLOTS};
use crate::table::progress::{BakeProgress, row_unless_cancelled};
use crate::table::{Plane, TextureData};
use glam::DVec3;
use half::f16;

/// ⟨P⟩ at or below which a texel stores 0 instead of its ratios.
///
/// Why 0: a sample contributes to ⟨P⟩ only while it faces both directions, and M and P both
/// vanish at the edge of that window (w·n(α) = 0 for one of them). As the window closes,
/// ⟨s⟩ = ⟨f_s M P cos θi⟩ vanishes faster than ⟨P⟩, and the stored ratios, a ⟨P⟩-weighted
/// mean of f_s·M·cos θi, go to 0 with it. Near ⟨P⟩ = 10⁻³ the ratios are still as large as
/// anywhere, so the floor sits well below that; filling such texels from their neighbours
/// instead would continue the ratios flat across the edge where they drop to 0 (along
/// velvet's masking kinks). The figures behind the choice are in
/// docs/notebook/2026-12-07-figures-from-comments.md.
pub const MASKING_FLOOR: f64 = 1e-5;

/// The 3D texture of thread `j` (see "GPU textures"): 2 channels, depth N2·(N3 + 2).
pub fn thread_texture(plane: &Plane, thread: &ThreadGeometry, j: usize) -> TextureData {
    let [n0, n1, n2, n3] = thread.axes.map(|a| a.texels);
    let block = n3 + 2;
    let slice = n0 * n1 * 2;
    let mut texels = Vec::with_capacity(slice * n2 * block);
    for i2 in 0..n2 {
        for padded in 0..block {
            let i3 = padded.clamp(1, n3) - 1;
            let start = (i2 * n3 + i3) * slice;
            texels.extend(
                plane.data[start..start + slice]
                    .iter()
                    .map(|&v| f16::from_f32(v)),
            );
        }
    }
    TextureData {
        name: format!("thread{}", j + 1),
        binding: VOLUME_SLOTS[j].binding,
        three_d: VOLUME_SLOTS[j].three_d(),
        size: [n0 as u32, n1 as u32, (n2 * block) as u32],
        channels: 2,
        texels,
    }
}

/// Masking planes as the layers of one one-channel array texture (thread_frame: both).
pub fn masking_texture(planes: &[Plane]) -> TextureData {
    let n = MASKING_TEXELS as u32;
    TextureData {
        name: "masking".into(),
        binding: ARRAY_SLOTS[0].binding,
        three_d: ARRAY_SLOTS[0].three_d(),
        size: [n, n, planes.len() as u32],
        channels: 1,
        texels: planes
            .iter()
            .flat_map(|p| p.data.iter().map(|&v| f16::from_f32(v)))
            .collect(),
    }
}

/// The stored channels of every texel of one thread's 4D table, flattened in plane order:
/// `ratios(wi, wo, θd')` at each texel's direction pair and θd', then replaced by the node
/// values of their least-squares quadrilinear fit ([`super::prefilter`]). Rows in
/// parallel, each sample a pure function of its coordinates and the fit a pure function of
/// the samples, so the result is the same for any thread count.
/// Once `progress` says the bake is cancelled, the remaining rows hold zeros and the fit is
/// skipped.
pub fn bake_thread_plane(
    geometry: &ThreadGeometry,
    progress: &dyn BakeProgress,
    ratios: impl Fn(DVec3, DVec3, f64) -> [f64; 2] + Sync,
) -> Vec<f64> {
    use rayon::prelude::*;
    let n = geometry.axes.map(|a| a.texels);
    let values: [Vec<f64>; 4] =
        std::array::from_fn(|a| (0..n[a]).map(|i| geometry.axes[a].texel_value(i)).collect());
    let rows = n[1] * n[2] * n[3];
    let mut plane: Vec<f64> = (0..rows)
        .into_par_iter()
        .flat_map_iter(|row| {
            let (i1, i3, i2) = (row % n[1], (row / n[1]) % n[3], row / (n[1] * n[3]));
            let (values, ratios) = (&values, &ratios);
            row_unless_cancelled(progress, 2 * n[0], || {
                (0..n[0])
                    .flat_map(|i0| {
                        let theta_d = values[1][i1];
                        let (wi, wo) = geometry.directions([
                            values[0][i0],
                            theta_d,
                            values[2][i2],
                            values[3][i3],
                        ]);
                        ratios(wi, wo, theta_d)
                    })
                    .collect()
            })
        })
        .collect();
    if progress.cancelled() {
        return plane;
    }
    // Plane order, fastest first: βH, θd', v, u.
    crate::table::prefilter::fit_for_multilinear(&mut plane, 2, &[n[0], n[1], n[3], n[2]]);
    plane
}

/// The stored channels of "Channels and lookup" for a pair at θd' from the thread's curve
/// means: (R·cos²θd'/⟨P⟩, T/⟨P⟩), 0 where ⟨P⟩ ≤ [`MASKING_FLOOR`].
pub fn stored_ratios(model: &ThreadModel, wi: DVec3, wo: DVec3, theta_d: f64) -> [f64; 2] {
    let m = model.means(wi, wo);
    if m.masking <= MASKING_FLOOR {
        return [0.0; 2];
    }
    [
        m.reflection * theta_d.cos().powi(2) / m.masking,
        m.transmission / m.masking,
    ]
}

/// The masking plane of one thread: ⟨P⟩ at (βi, βo) for directions in the t0–z plane
/// (⟨P⟩ depends on nothing else), with the baking rule: ⟨P⟩ is smooth in α, and the rule's
/// 3e-4 bound on F holds for it too.
pub fn bake_masking(fabric: &Fabric, geometry: &ThreadGeometry, index: usize) -> Vec<f64> {
    use rayon::prelude::*;
    let model = ThreadModel::new(fabric, index, Integration::Baking);
    let axis = geometry.masking_axis;
    let in_plane = |beta: f64| beta.sin() * geometry.t0 + beta.cos() * DVec3::Z;
    (0..axis.texels * axis.texels)
        .into_par_iter()
        .map(|k| {
            let (i, j) = (k % axis.texels, k / axis.texels);
            model
                .means(in_plane(axis.texel_value(i)), in_plane(axis.texel_value(j)))
                .masking
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thread_texture_pads_u_blocks_with_edge_copies() {
        use crate::table::{Layout, PlaneSpec};
        let fabric = crate::formats::fabric_toml::FabricSet::builtin().fabrics()[0].clone();
        let geometry = crate::table::thread_frame::Geometry::new(&fabric, 4);
        let thread = &geometry.threads[0];
        let spec: PlaneSpec = Layout::THREAD_FRAME.plane_specs(&fabric, 4)[0].clone();
        let values = spec.texel_count() * 2;
        // Values 0, 1, 2, … up to 2048 are exact in f16; stay below by taking them mod 2048.
        let plane = Plane {
            spec,
            data: (0..values).map(|k| (k % 2048) as f32).collect(),
        };
        let texture = thread_texture(&plane, thread, 0);
        let [n0, n1, n2, n3] = thread.axes.map(|a| a.texels);
        assert_eq!(texture.size, [n0 as u32, n1 as u32, (n2 * (n3 + 2)) as u32]);
        for i2 in 0..n2 {
            for z in 0..n3 + 2 {
                let i3 = z.clamp(1, n3) - 1;
                for i1 in 0..n1 {
                    for i0 in 0..n0 {
                        let at = ((i2 * (n3 + 2) + z) * n1 + i1) * n0 + i0;
                        let want = thread.texel_index([i0, i1, i2, i3]) * 2;
                        assert_eq!(texture.texels[at * 2].to_f32(), plane.data[want]);
                        assert_eq!(texture.texels[at * 2 + 1].to_f32(), plane.data[want + 1]);
                    }
                }
            }
        }
    }
}
