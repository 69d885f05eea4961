//! Layout `grid4d` (the baseline): a 4D grid over (wi, wo), each direction through the
//! hemi-octahedral map of [`super::octahedral`] at N×N, N = `resolution`.
//!
//! One plane, `grid4d`, of N²×N² texels with channels `reflection`, `transmission1`,
//! `transmission2` (the albedo-free terms of F, already divided by Q): texel (x, y) holds wo
//! at octahedral texel (x mod N, y mod N) and wi at (x div N, y div N), i.e. N×N tiles over
//! wi, each an N×N image over wo. Texel centres are at `(i + ½)/N`, so no texel lies on the
//! horizon. A lookup takes the octahedral coordinates `uv` of wi and wo, the continuous
//! texel coordinates `uv·N − ½`, and interpolates multilinearly between the 16 surrounding
//! texels, clamping indices to [0, N−1] (clamp-to-edge) on every axis. On a GPU: a 2D array
//! texture of N² layers (layer = wi texel x + N·y), bilinear filtering within each layer
//! over wo, and a manual bilinear blend of the 4 layers around wi.
//!
//! # GPU texture
//! One `Rgba16Float` 2D array texture (binding 7) of N² layers of N×N texels, layer
//! `x + N·y` for wi's octahedral texel (x, y), each layer the N×N image over wo; channels
//! reflection, transmission1, transmission2, 0. (Plus one unused layer when N² is a
//! multiple of 6: wgpu's GL backend would otherwise make the texture a cube map array.)

use super::bindings::ARRAY_SLOTS;
use super::gpu_bound::{COORDINATE_ERROR, FILTER_WEIGHT_STEP, GpuErrorBound, floor, range};
use super::progress::{BakeProgress, row_unless_cancelled};
use super::{
    LayoutUnit, Plane, PlaneSpec, TableLookup, TextureData, octahedral, quadrilinear_corners,
};
use crate::model::{Fabric, Integration, Patch};
use crate::shader::ShaderFile;
use glam::{DVec2, DVec3, Vec2, Vec3};
use half::f16;
use rayon::prelude::*;
use std::any::Any;
use std::sync::Arc;

/// The layout unit `grid4d`.
pub struct Grid4d;

/// The layout's WGSL file: the lookup `cloth_grid4d_brdf(wi, wo)`.
const WGSL_FILE: ShaderFile = ShaderFile {
    name: "table/grid4d",
    path: "shaders/table/grid4d.wgsl",
    source: include_str!("../../shaders/table/grid4d.wgsl"),
};

impl LayoutUnit for Grid4d {
    fn name(&self) -> &'static str {
        "grid4d"
    }

    fn wgsl_file(&self) -> &'static ShaderFile {
        &WGSL_FILE
    }

    fn default_resolution(&self) -> u32 {
        16
    }

    /// 64⁴ texels × 3 channels × 2 bytes = 96 MiB.
    fn max_resolution(&self) -> u32 {
        64
    }

    fn resolution_ladder(&self) -> &'static [u32] {
        &[8, 12, 16, 24, 32, 48, 64]
    }

    /// Up to the size of the smaller thread_frame tables.
    fn report_resolutions(&self, quick: bool) -> &'static [u32] {
        if quick { &[8, 12] } else { &[8, 12, 16, 24] }
    }

    fn integration(&self) -> &'static str {
        "direct: per-segment midpoint rule, alpha spacing <= min(0.05 deg, sigma/16)"
    }

    fn plane_specs(&self, _fabric: &Fabric, resolution: u32) -> Vec<PlaneSpec> {
        vec![spec(resolution)]
    }

    fn bake_rows(&self, _fabric: &Fabric, resolution: u32) -> u64 {
        spec(resolution).height as u64
    }

    fn bake(&self, fabric: &Fabric, resolution: u32, progress: &dyn BakeProgress) -> Vec<Vec<f64>> {
        vec![bake(fabric, resolution, progress)]
    }

    fn lookup(&self, _fabric: &Fabric, resolution: u32) -> Arc<dyn TableLookup> {
        Arc::new(Grid4dLookup {
            n: resolution as usize,
        })
    }
}

/// The lookup of a grid4d table of N×N octahedral texels per direction.
#[derive(Clone, Debug, PartialEq)]
pub struct Grid4dLookup {
    pub n: usize,
}

impl TableLookup for Grid4dLookup {
    fn terms(&self, planes: &[Plane], wi: DVec3, wo: DVec3) -> [f64; 3] {
        lookup_terms(&planes[0], self.n as u32, wi, wo)
    }

    fn terms_f32(&self, planes: &[Plane], wi: Vec3, wo: Vec3) -> [f32; 3] {
        let n = self.n;
        let encode = |w: Vec3| {
            let p = Vec2::new(w.x, w.y) / (w.x.abs() + w.y.abs() + w.z.abs());
            (Vec2::new(p.x + p.y, p.x - p.y) + 1.0) * (0.5 * n as f32) - 0.5
        };
        let (ci, co) = (encode(wi), encode(wo));
        let axes = [ci.x, ci.y, co.x, co.y].map(|x| axis_f32(x, n));
        let data = &planes[0].data;
        let width = n * n;
        let mut sum = [0.0f32; 3];
        for corner in 0..16 {
            let mut weight = 1.0;
            let index: [usize; 4] = std::array::from_fn(|a| {
                let (i0, i1, f) = axes[a];
                if corner >> a & 1 == 1 {
                    weight *= f;
                    i1
                } else {
                    weight *= 1.0 - f;
                    i0
                }
            });
            let texel = ((index[1] * n + index[3]) * width + index[0] * n + index[2]) * 3;
            for c in 0..3 {
                sum[c] += weight * data[texel + c];
            }
        }
        sum
    }

    fn wgsl_constants(&self) -> String {
        format!(
            "// Octahedral texels per axis of the grid.\nconst CLOTH_GRID_N: u32 = {}u;\n",
            self.n
        )
    }

    fn textures(&self, planes: &[Plane]) -> Vec<TextureData> {
        vec![texture(&planes[0], self.n)]
    }

    /// The wo blend is filtered in hardware (2 axes, 8-bit weights); the wi blend is in
    /// f32; every coordinate carries f32 error ([`super::gpu_bound`] points 1 and 2).
    fn gpu_error_bound(
        &self,
        planes: &[Plane],
        albedo: [DVec3; 2],
        wi: DVec3,
        wo: DVec3,
        cpu: DVec3,
    ) -> GpuErrorBound {
        let n = self.n;
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
        let ranges: [f64; 3] = std::array::from_fn(|c| range(corners.iter().map(|t| t[c] as f64)));
        let scale = 2.0 * FILTER_WEIGHT_STEP + 4.0 * COORDINATE_ERROR;
        let per_channel = (DVec3::splat(ranges[0]) + albedo[0] * ranges[1] + albedo[1] * ranges[2])
            * scale
            + floor(cpu);
        GpuErrorBound {
            per_channel,
            on_fold: false,
        }
    }

    /// Never: the texels hold the terms already divided by Q, and the lookup divides by
    /// nothing.
    fn f32_exempt(&self, _planes: &[Plane], _wi: DVec3, _wo: DVec3) -> bool {
        false
    }

    fn as_any(&self) -> &dyn Any {
        self
    }
}

/// [`axis`] in f32.
#[inline(always)]
fn axis_f32(x: f32, n: usize) -> (usize, usize, f32) {
    let floor = x.floor();
    let last = n as i32 - 1;
    let i0 = (floor as i32).clamp(0, last) as usize;
    let i1 = (floor as i32 + 1).clamp(0, last) as usize;
    (i0, i1, x - floor)
}

/// The grid4d plane as the GPU texture of the module doc.
pub fn texture(plane: &Plane, n: usize) -> TextureData {
    let mut texels = Vec::with_capacity(n.pow(4) * 4);
    for (wi_y, wi_x) in (0..n).flat_map(|y| (0..n).map(move |x| (y, x))) {
        for wo_y in 0..n {
            for wo_x in 0..n {
                let t = plane.texel(wi_x * n + wo_x, wi_y * n + wo_y);
                texels.extend([t[0], t[1], t[2], 0.0].map(f16::from_f32));
            }
        }
    }
    // wgpu's GL backend creates square 2D textures whose layer count is a multiple of 6 as
    // cube map arrays, which a D2Array view then misreads: one unused zero layer avoids it.
    let mut layers = n * n;
    if layers.is_multiple_of(6) {
        layers += 1;
        texels.resize(texels.len() + n * n * 4, f16::ZERO);
    }
    TextureData {
        name: "grid4d".into(),
        binding: ARRAY_SLOTS[1].binding,
        three_d: ARRAY_SLOTS[1].three_d(),
        size: [n as u32, n as u32, layers as u32],
        channels: 4,
        texels,
    }
}

pub fn spec(resolution: u32) -> PlaneSpec {
    let side = resolution as usize * resolution as usize;
    PlaneSpec::new(
        "grid4d".into(),
        side,
        side,
        &["reflection", "transmission1", "transmission2"],
    )
}

/// The direction pair whose value texel (x, y) stores.
pub fn texel_directions(resolution: u32, x: usize, y: usize) -> (DVec3, DVec3) {
    let n = resolution as usize;
    let centre = |i: usize, j: usize| {
        octahedral::decode(DVec2::new(i as f64 + 0.5, j as f64 + 0.5) / n as f64)
    };
    (centre(x / n, y / n), centre(x % n, y % n))
}

/// The terms of every texel, row by row, from the direct evaluation (zeros for the rows
/// left once `progress` says the bake is cancelled).
pub fn bake(fabric: &Fabric, resolution: u32, progress: &dyn BakeProgress) -> Vec<f64> {
    let patch = Patch::new(fabric, Integration::Direct);
    let spec = spec(resolution);
    (0..spec.height)
        .into_par_iter()
        .flat_map_iter(|y| {
            row_unless_cancelled(progress, 3 * spec.width, || {
                (0..spec.width)
                    .flat_map(|x| {
                        let (wi, wo) = texel_directions(resolution, x, y);
                        let terms = patch.terms(wi, wo);
                        [
                            terms.reflection,
                            terms.transmission[0],
                            terms.transmission[1],
                        ]
                    })
                    .collect()
            })
        })
        .collect()
}

/// One axis of a linear interpolation with clamp-to-edge: the two texel indices and the
/// weight of the second, for continuous texel coordinate `x` (texel i's centre at i).
#[inline]
fn axis(x: f64, n: usize) -> (usize, usize, f64) {
    let floor = x.floor();
    let last = n as i64 - 1;
    let i0 = (floor as i64).clamp(0, last) as usize;
    let i1 = (floor as i64 + 1).clamp(0, last) as usize;
    (i0, i1, x - floor)
}

/// The interpolated terms at (wi, wo).
pub fn lookup_terms(plane: &Plane, resolution: u32, wi: DVec3, wo: DVec3) -> [f64; 3] {
    let n = resolution as usize;
    let ci = octahedral::encode(wi) * n as f64 - 0.5;
    let co = octahedral::encode(wo) * n as f64 - 0.5;
    let axes = [axis(ci.x, n), axis(ci.y, n), axis(co.x, n), axis(co.y, n)];
    let mut sum = [0.0f64; 3];
    for (index, weight) in quadrilinear_corners(axes) {
        let texel = plane.texel(index[0] * n + index[2], index[1] * n + index[3]);
        for c in 0..3 {
            sum[c] += weight * texel[c] as f64;
        }
    }
    sum
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::table::Layout;

    fn builtin(name: &str) -> Fabric {
        let set = crate::formats::fabric_toml::FabricSet::builtin();
        set.get(name).expect("built-in fabric").clone()
    }

    #[test]
    fn grid4d_lookup_reproduces_texels_at_centres_and_interpolates_between() {
        let table = crate::bake::bake(&builtin("silk_shot"), Layout::GRID4D, 6, &|| {}).unwrap();
        let plane = &table.planes()[0];
        for y in 0..plane.spec.height {
            for x in 0..plane.spec.width {
                let (wi, wo) = texel_directions(6, x, y);
                let got = table.lookup_terms(wi, wo);
                let stored = plane.texel(x, y);
                for c in 0..3 {
                    // Centres map back to themselves up to the octahedral round trip (1e-15).
                    assert!(
                        (got[c] - stored[c] as f64).abs() <= 1e-9 * (stored[c] as f64).max(1e-6),
                        "({x},{y}) {got:?} {stored:?}"
                    );
                }
            }
        }
        // Halfway between two wo texel centres along one axis, the lookup is their mean.
        let (wi, wo_a) = texel_directions(6, 2 * 6 + 1, 3 * 6 + 4);
        let (_, wo_b) = texel_directions(6, 2 * 6 + 2, 3 * 6 + 4);
        let uv = (octahedral::encode(wo_a) + octahedral::encode(wo_b)) * 0.5;
        let mid = table.lookup_terms(wi, octahedral::decode(uv));
        let (a, b) = (plane.texel(13, 22), plane.texel(14, 22));
        for c in 0..3 {
            let expected = 0.5 * (a[c] as f64 + b[c] as f64);
            assert!(
                (mid[c] - expected).abs() <= 1e-9 * expected.max(1e-6),
                "{mid:?} vs {a:?} {b:?}"
            );
        }
    }

    #[test]
    fn grid4d_texture_puts_wi_in_layers() {
        for n in [4usize, 6] {
            let spec = spec(n as u32);
            let data = (0..spec.texel_count() * 3)
                .map(|k| (k % 2048) as f32)
                .collect();
            let plane = Plane { spec, data };
            let texture = texture(&plane, n);
            let layers = if n * n % 6 == 0 { n * n + 1 } else { n * n };
            assert_eq!(texture.size, [n as u32, n as u32, layers as u32]);
            let (wi, wo) = ((1, n - 1), (n - 2, 2));
            let at = (((wi.0 + n * wi.1) * n + wo.1) * n + wo.0) * 4;
            let want = plane.texel(wi.0 * n + wo.0, wi.1 * n + wo.1);
            let got: Vec<f32> = texture.texels[at..at + 3]
                .iter()
                .map(|t| t.to_f32())
                .collect();
            assert_eq!(got, want);
        }
    }
}
