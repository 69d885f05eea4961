//! The CPU side of the GPU layout: how a [`Table`]'s planes are arranged into textures, and
//! the uniform block (axes, frames, fabric constants) that `shaders/lookup.wgsl` reads.
//! Pure data, no device: testable without a GPU.
//!
//! # Textures
//! - `thread_frame` (see [`crate::table::thread_frame`], "Channels and lookup"): per thread
//!   one `Rg16Float` 3D texture (channels reflection, transmission) of width N0 (βH), height
//!   N1 (θd') and depth N2·(N3 + 2): for each texel i2 of axis 2 (u) a block of N3 + 2 depth
//!   slices holding axis 3 (v), texel i3 at slice `i2·(N3 + 2) + 1 + i3`, with one duplicated
//!   edge slice before and after the block. Hardware filtering interpolates βH, θd' and v;
//!   the shader blends the two u blocks by hand, and the duplicated slices make sure that a
//!   sample at a block's edge can only ever blend with a copy of that edge, never with the
//!   neighbouring u block (the axes are clamped, so a copy is exactly clamp-to-edge). This
//!   is the plane's own row order `(i2·N3 + i3)·N1 + i1` regrouped as depth `i2·N3 + i3`,
//!   plus the padding slices. Both masking planes go into one `R16Float` 2D array texture
//!   (layer j), 129×129, column βi, row βo.
//! - `grid4d` (see [`crate::table::grid4d`]): one `Rgba16Float` 2D array texture of N²
//!   layers of N×N texels, layer `x + N·y` for wi's octahedral texel (x, y), each layer the
//!   N×N image over wo; channels reflection, transmission1, transmission2, 0. (Plus one
//!   unused layer when N² is a multiple of 6: wgpu's GL backend would otherwise make the
//!   texture a cube map array.)
//!
//! Texel values are the planes' f32 values, exactly representable in f16, so the upload is
//! lossless.

use crate::table::axis::{Axis, Warp};
use crate::table::thread_frame::{self, ThreadGeometry};
use crate::table::{Geometry, Plane, Table};
use bytemuck::{Pod, Zeroable};
use half::f16;

/// Warp kinds as the shader's `Axis.info.x` names them.
pub const WARP_LINEAR: u32 = 0;
pub const WARP_KNOTS: u32 = 1;
pub const WARP_SIN_ENDS: u32 = 2;

/// One axis (WGSL `Axis`): `a`, `b` the warp parameters, `info` = (warp kind, texels,
/// periodic, 0). Linear: `a = (lo, hi, ·, ·)`; Knots: `a = xs`, `b = vs`; SinEnds:
/// `a = (hi, k, sin k, ·)`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct AxisUniform {
    pub a: [f32; 4],
    pub b: [f32; 4],
    pub info: [u32; 4],
}

impl AxisUniform {
    pub fn new(axis: &Axis) -> Self {
        let (kind, a, b) = match axis.warp {
            Warp::Linear { lo, hi } => (WARP_LINEAR, [lo, hi, 0.0, 0.0], [0.0; 4]),
            Warp::Knots { xs, vs } => (WARP_KNOTS, xs, vs),
            Warp::SinEnds { hi, k } => (WARP_SIN_ENDS, [hi, k, k.sin(), 0.0], [0.0; 4]),
        };
        Self {
            a: a.map(|v| v as f32),
            b: b.map(|v| v as f32),
            info: [kind, axis.texels as u32, axis.periodic as u32, 0],
        }
    }
}

/// One thread of a `thread_frame` table (WGSL `Thread`): its frame, its four 4D-table axes,
/// the masking axis, and `depth` = (N3 + 2, total depth, 0, 0).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct ThreadUniform {
    pub t0: [f32; 4],
    pub b: [f32; 4],
    pub axes: [AxisUniform; 4],
    pub masking: AxisUniform,
    pub depth: [u32; 4],
}

impl ThreadUniform {
    pub fn new(thread: &ThreadGeometry) -> Self {
        let v4 = |v: glam::DVec3| [v.x as f32, v.y as f32, v.z as f32, 0.0];
        let [_, _, n2, n3] = thread.axes.map(|a| a.texels as u32);
        Self {
            t0: v4(thread.t0),
            b: v4(thread.b),
            axes: thread.axes.each_ref().map(AxisUniform::new),
            masking: AxisUniform::new(&thread.masking_axis),
            depth: [n3 + 2, n2 * (n3 + 2), 0, 0],
        }
    }
}

/// The whole uniform block (WGSL `Params`). `coverage` = (a1, a2, gap, 0); `albedo[j]` the
/// RGB albedo of thread j (albedo_scale applied), as [`Table::lookup`] combines them;
/// `grid` = (N of grid4d, layout: 0 grid4d / 1 thread_frame, 0, 0).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct Params {
    pub threads: [ThreadUniform; 2],
    pub coverage: [f32; 4],
    pub albedo: [[f32; 4]; 2],
    pub grid: [u32; 4],
}

impl Params {
    pub fn new(table: &Table) -> Self {
        let albedo = table
            .fabric
            .threads()
            .map(|t| t.albedo_rgb())
            .map(|[r, g, b]| [r as f32, g as f32, b as f32, 0.0]);
        match table.geometry() {
            Geometry::Grid4d => Self {
                albedo,
                grid: [table.resolution, 0, 0, 0],
                ..Self::default()
            },
            Geometry::ThreadFrame(geometry) => Self {
                threads: geometry.threads.each_ref().map(ThreadUniform::new),
                coverage: [
                    geometry.coverage[0] as f32,
                    geometry.coverage[1] as f32,
                    geometry.gap as f32,
                    0.0,
                ],
                albedo,
                grid: [table.resolution, 1, 0, 0],
            },
        }
    }
}

/// A texture's contents before upload: size in texels (width, height, depth or layers) and
/// f16 texels, channel-interleaved, x fastest, then y, then z.
#[derive(Clone, Debug, PartialEq)]
pub struct TextureData {
    pub size: [u32; 3],
    pub channels: u32,
    pub texels: Vec<f16>,
}

/// The 3D texture of thread `j` (see the module doc): 2 channels, depth N2·(N3 + 2).
pub fn thread_texture(plane: &Plane, thread: &ThreadGeometry) -> TextureData {
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
        size: [n0 as u32, n1 as u32, (n2 * block) as u32],
        channels: 2,
        texels,
    }
}

/// Both masking planes as the 2 layers of one one-channel array texture.
pub fn masking_texture(planes: &[Plane]) -> TextureData {
    let n = thread_frame::MASKING_TEXELS as u32;
    TextureData {
        size: [n, n, 2],
        channels: 1,
        texels: planes
            .iter()
            .flat_map(|p| p.data.iter().map(|&v| f16::from_f32(v)))
            .collect(),
    }
}

/// The grid4d plane as N² layers of N×N RGBA texels (alpha 0).
pub fn grid4d_texture(plane: &Plane, resolution: u32) -> TextureData {
    let n = resolution as usize;
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
    let mut layers = resolution * resolution;
    if layers % 6 == 0 {
        layers += 1;
        texels.resize(texels.len() + n * n * 4, f16::ZERO);
    }
    TextureData {
        size: [resolution, resolution, layers],
        channels: 4,
        texels,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uniform_sizes_match_wgsl() {
        // WGSL uniform layout: vec4 members, arrays of 16-byte-multiple structs.
        assert_eq!(std::mem::size_of::<AxisUniform>(), 48);
        assert_eq!(std::mem::size_of::<ThreadUniform>(), 2 * 16 + 5 * 48 + 16);
        assert_eq!(
            std::mem::size_of::<Params>(),
            2 * std::mem::size_of::<ThreadUniform>() + 4 * 16
        );
    }

    #[test]
    fn thread_texture_pads_u_blocks_with_edge_copies() {
        use crate::table::{Layout, PlaneSpec};
        let fabric = crate::fabric_file::FabricSet::builtin().fabrics()[0].clone();
        let geometry = thread_frame::Geometry::new(&fabric, 4);
        let thread = &geometry.threads[0];
        let spec: PlaneSpec = Layout::ThreadFrame.plane_specs(&fabric, 4)[0].clone();
        let values = spec.texel_count() * 2;
        // Values 0, 1, 2, … up to 2048 are exact in f16; stay below by taking them mod 2048.
        let plane = Plane {
            spec,
            data: (0..values).map(|k| (k % 2048) as f32).collect(),
        };
        let texture = thread_texture(&plane, thread);
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

    #[test]
    fn grid4d_texture_puts_wi_in_layers() {
        for n in [4usize, 6] {
            let spec = crate::table::grid4d::spec(n as u32);
            let data = (0..spec.texel_count() * 3)
                .map(|k| (k % 2048) as f32)
                .collect();
            let plane = Plane { spec, data };
            let texture = grid4d_texture(&plane, n as u32);
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
