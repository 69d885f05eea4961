//! The split_frame lookup ([`TableLookup`] for its [`Geometry`]): the point masses summed
//! exactly and the sloped tables interpolated, in f64 and in f32, the WGSL constants and
//! textures, and the bound on the GPU's difference.

use super::Geometry;
use crate::table::bindings::{ARRAY_SLOTS, VOLUME_SLOTS, stand_in_texture};
use crate::table::gpu_bound::{self, GpuErrorBound};
use crate::table::thread;
use crate::table::{BATCH_LANES, BatchLanes, Plane, TableLookup, TextureData};
use glam::{DVec3, Vec3};
use std::any::Any;

impl TableLookup for Geometry {
    fn terms(&self, planes: &[Plane], wi: DVec3, wo: DVec3) -> [f64; 3] {
        let sums = [0, 1].map(|j| self.thread_sums(planes, j, wi, wo));
        let q = self.gap * wo.z + self.coverage[0] * sums[0][2] + self.coverage[1] * sums[1][2];
        if q <= 0.0 {
            return [0.0; 3];
        }
        [
            (self.coverage[0] * sums[0][0] + self.coverage[1] * sums[1][0]) / q,
            self.coverage[0] * sums[0][1] / q,
            self.coverage[1] * sums[1][1] / q,
        ]
    }

    fn terms_f32(&self, planes: &[Plane], wi: Vec3, wo: Vec3) -> [f32; 3] {
        let mut terms = [[0.0; 3]];
        self.terms_lanes::<f32>(planes, &[wi], &[wo], &mut terms);
        terms[0]
    }

    fn terms_f32_lanes(
        &self,
        planes: &[Plane],
        wi: &[Vec3; BATCH_LANES],
        wo: &[Vec3; BATCH_LANES],
    ) -> [[f32; 3]; BATCH_LANES] {
        let mut terms = [[0.0; 3]; BATCH_LANES];
        self.terms_lanes::<BatchLanes>(planes, wi, wo, &mut terms);
        terms
    }

    fn wgsl_constants(&self) -> String {
        let mut out = thread::layout_wgsl(self.coverage, self.gap);
        for j in 0..2 {
            out += &self.thread_wgsl(j);
        }
        out
    }

    /// The sloped tables and their masking planes; the WGSL declares a table for each thread
    /// and the masking texture, so a thread without sloped segments (or a table without any)
    /// gets a one-texel stand-in there, which the lookup never reads.
    fn textures(&self, planes: &[Plane]) -> Vec<TextureData> {
        let mut textures: Vec<TextureData> = (0..2)
            .map(|j| match (&self.threads[j].slopes, self.planes[j]) {
                (Some(slopes), Some((table, _))) => {
                    thread::thread_texture(&planes[table], &slopes.geometry, j)
                }
                _ => stand_in_texture(VOLUME_SLOTS[j]),
            })
            .collect();
        let masking: Vec<Plane> = self
            .tabulated()
            .map(|(j, _)| planes[self.planes[j].expect("planes").1].clone())
            .collect();
        textures.push(if masking.is_empty() {
            stand_in_texture(ARRAY_SLOTS[0])
        } else {
            thread::masking_texture(&masking)
        });
        textures
    }

    /// The sloped tables' interpolation errors propagated to F as for thread_frame (their
    /// ⟨P⟩ weighted by the sloped share), plus the f32 sample kernel's relative error for
    /// the point masses ([`gpu_bound`] point 4).
    fn gpu_error_bound(
        &self,
        planes: &[Plane],
        albedo: [DVec3; 2],
        wi: DVec3,
        wo: DVec3,
        cpu: DVec3,
    ) -> GpuErrorBound {
        let floor = gpu_bound::floor(cpu);
        let sums = [0, 1].map(|j| self.thread_sums(planes, j, wi, wo));
        let q = self.gap * wo.z + (0..2).map(|j| self.coverage[j] * sums[j][2]).sum::<f64>();
        let mut total = floor;
        if q <= 0.0 {
            return GpuErrorBound {
                per_channel: total,
                on_fold: false,
            };
        }
        total += cpu.abs() * gpu_bound::KERNEL_RELATIVE;
        let mut folded = false;
        for (j, slopes) in self.tabulated() {
            let (t, m) = self
                .plane_indices(j)
                .expect("a tabulated thread has planes");
            let [r, tr, p, c2] = slopes.geometry.sample(&planes[t], &planes[m], wi, wo);
            let (errors, fold) =
                thread::thread_errors(&slopes.geometry, &planes[t], &planes[m], wi, wo);
            folded |= fold != [0.0; 2];
            let a = self.coverage[j] * slopes.weight;
            let c = c2.max(thread::COS2_D_FLOOR);
            let d_r = a * p / (c * q);
            let d_t = albedo[j] * (a * p / q);
            let d_p = (DVec3::splat(r / c) + albedo[j] * tr - cpu) * (a / q);
            total += DVec3::splat(d_r * (errors[0] + fold[0]))
                + d_t.abs() * (errors[1] + fold[1])
                + d_p.abs() * errors[2];
        }
        GpuErrorBound {
            per_channel: total,
            on_fold: folded,
        }
    }

    /// Q from every thread's sums, and cos²θd' of the sloped tables only (the point masses
    /// divide by nothing).
    fn f32_exempt(&self, planes: &[Plane], wi: DVec3, wo: DVec3) -> bool {
        let q = self.gap * wo.z
            + (0..2)
                .map(|j| self.coverage[j] * self.thread_sums(planes, j, wi, wo)[2])
                .sum::<f64>();
        let cos2_d = self.tabulated().map(|(j, slopes)| {
            let (t, m) = self
                .plane_indices(j)
                .expect("a tabulated thread has planes");
            slopes.geometry.sample(&planes[t], &planes[m], wi, wo)[3]
        });
        thread::f32_exempt(q, cos2_d)
    }

    fn as_any(&self) -> &dyn Any {
        self
    }
}
