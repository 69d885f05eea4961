//! A thread's tables read at a pair: in f64 ([`ThreadGeometry::sample`]), in f32 one pair or
//! eight at a time ([`ThreadGeometry::locate_f32`], [`ThreadGeometry::sample_located`]), and
//! how far the GPU's reading may be from the f64 one ([`thread_errors`]).

use super::geometry::{MASKING_TEXELS, ThreadGeometry, lanes_in_thread_axes};
use crate::table::axis::{Axis, AxisF32};
use crate::table::fast_math::{self, Lanes};
use crate::table::{Plane, gpu_bound, quadrilinear_corners};
use glam::{DVec3, Vec3, Vec4, Vec4Swizzles};

impl ThreadGeometry {
    /// This thread's interpolated stored channels, masking and cos²θd' at (wi, wo), from its
    /// 4D plane `table` and its masking plane: `[reflection, transmission, ⟨P⟩, cos²θd']`.
    pub fn sample(&self, table: &Plane, masking: &Plane, wi: DVec3, wo: DVec3) -> [f64; 4] {
        let coordinates = self.coordinates(wi, wo);
        let axes: [(usize, usize, f64); 4] =
            std::array::from_fn(|a| self.axes[a].locate(coordinates[a]));
        let (mut r, mut t) = (0.0, 0.0);
        for (index, weight) in quadrilinear_corners(axes) {
            let texel = self.texel_index(index) * 2;
            r += weight * table.data[texel] as f64;
            t += weight * table.data[texel + 1] as f64;
        }
        let masking = bilinear(masking, self.masking_axis, self.beta(wi), self.beta(wo)).max(0.0);
        let sin_d = coordinates[1].sin();
        [r, t, masking, 1.0 - sin_d * sin_d]
    }

    /// Where `L::WIDTH` pairs (`wi`, `wo` of that length) fall in this thread's tables: the
    /// first half of [`Self::sample`] in f32 (the arithmetic of
    /// `shaders/table/thread_geometry.wgsl`, with [`fast_math`] for atan2 and asin; `fast` are
    /// this thread's axes in f32, the 4D axes, then the masking axis), lane by lane the
    /// same operations: one pair in `f32`, or eight in SIMD registers (`wide::f32x8`), which
    /// pays because the angles of a lookup are chains of dependent divisions and
    /// polynomials that one pair alone cannot keep the floating-point units busy with.
    /// [`Self::sample_located`] is the second half.
    #[inline(always)]
    pub fn locate_f32<L: Lanes>(
        &self,
        fast: &[AxisF32; 5],
        wi: &[Vec3],
        wo: &[Vec3],
    ) -> LocatedPairs<L> {
        let thread2 = self.t0 != DVec3::X;
        let [wi_t, wi_b, wi_z] = lanes_in_thread_axes::<L>(thread2, wi);
        let [wo_t, wo_b, wo_z] = lanes_in_thread_axes::<L>(thread2, wo);
        let (half, one) = (L::splat(0.5), L::splat(1.0));
        let (h_t, h_z) = (wi_t + wo_t, wi_z + wo_z);
        let r = one / (h_t * h_t + h_z * h_z).max(L::splat(1e-37)).sqrt();
        let (sin_b, cos_b) = (h_t * r, h_z * r);
        let s = (half * ((wi_t - wo_t) * cos_b - (wi_z - wo_z) * sin_b))
            .max(-one)
            .min(one);
        let wi_n = wi_t * sin_b + wi_z * cos_b;
        let wo_n = wo_t * sin_b + wo_z * cos_b;
        let phi_i = fast_math::atan2(wi_b, wi_n);
        let phi_o = fast_math::atan2(wo_b, wo_n);
        let cos2_d = wi_n * wi_n + wi_b * wi_b;
        // u, v folded by b → −b to u ≥ 0.
        let (u, v) = (half * (phi_i + phi_o), half * (phi_i - phi_o));
        let flip = u.lt(L::splat(0.0));
        LocatedPairs {
            axes: [
                fast[0].locate(fast_math::atan2(h_t, h_z)),
                fast[1].locate(fast_math::atan2(s, cos2_d.sqrt())),
                fast[2].locate(L::select(flip, -u, u)),
                fast[3].locate(L::select(flip, -v, v)),
                fast[4].locate(fast_math::atan2(wi_t, wi_z)),
                fast[4].locate(fast_math::atan2(wo_t, wo_z)),
            ],
            cos2_d: cos2_d.values(),
        }
    }

    /// This thread's `[reflection, transmission, ⟨P⟩, cos²θd']` at pair `k` of `at`
    /// (quadrilinear in the 4D table, bilinear in the masking table).
    #[inline(always)]
    pub fn sample_located(
        &self,
        table: &Plane,
        masking: &Plane,
        at: &LocatedPairs<impl Lanes>,
        k: usize,
    ) -> [f32; 4] {
        let lane = |a: usize| (at.axes[a].0[k] as usize, at.axes[a].1[k]);
        let [reflection, transmission] =
            interpolate_f32(self, table, [lane(0), lane(1), lane(2), lane(3)]);
        [
            reflection,
            transmission,
            masking_f32(masking, [lane(4), lane(5)]),
            at.cos2_d[k],
        ]
    }

    /// Prefetches ([`Plane::prefetch`]) the rows that [`Self::sample_located`] reads for
    /// every pair of `at`: per pair the 4D table's eight (two per corner block) and the
    /// masking table's two.
    #[inline(always)]
    pub fn prefetch_located<L: Lanes>(&self, table: &Plane, masking: &Plane, at: &LocatedPairs<L>) {
        for k in 0..L::WIDTH {
            let lower = |a: usize| at.axes[a].0[k] as usize;
            let (starts, s1) = corner_blocks(self, [lower(0), lower(1), lower(2), lower(3)]);
            for start in starts {
                table.prefetch(start);
                table.prefetch(start + s1);
            }
            let masking_row = lower(5) * MASKING_TEXELS + lower(4);
            masking.prefetch(masking_row);
            masking.prefetch(masking_row + MASKING_TEXELS);
        }
    }
}

/// Where `L::WIDTH` pairs fall in one thread's tables for the f32 lookup, lane by lane:
/// the located texels (first index, fraction) of the 4D axes (βH, θd', u, v) and of the
/// masking axes (βi, βo), and cos²θd'.
#[derive(Clone, Copy, Debug)]
pub struct LocatedPairs<L: Lanes> {
    pub axes: [(L::Indices, L::Values); 6],
    pub cos2_d: L::Values,
}

/// A thread's ⟨P⟩ at located (βi, βo) from its masking plane, bilinearly, in f32.
#[inline(always)]
fn masking_f32(plane: &Plane, [(x0, fx), (y0, fy)]: [(usize, f32); 2]) -> f32 {
    let at = |x: usize, y: usize| plane.data[y * MASKING_TEXELS + x];
    ((1.0 - fy) * ((1.0 - fx) * at(x0, y0) + fx * at(x0 + 1, y0))
        + fy * ((1.0 - fx) * at(x0, y0 + 1) + fx * at(x0 + 1, y0 + 1)))
    .max(0.0)
}

/// Where the 16 corners of a quadrilinear lookup lie in a thread's 4D plane (f32 units),
/// given the lower texel of each axis (βH, θd', u, v): the starts of the four corner blocks
/// (lower and upper v, lower and upper u) and the step `s1` along axis 1. Each block is two
/// rows along axis 1 (at `start` and `start + s1`), each four consecutive floats:
/// reflection and transmission at i0 and i0 + 1.
#[inline(always)]
fn corner_blocks(thread: &ThreadGeometry, [i0, i1, i2, i3]: [usize; 4]) -> ([usize; 4], usize) {
    // Arrays written out, here and in `prefetch_located`: `array::map` with a closure was
    // left as a call once both layouts used this, which slowed every lookup.
    let a = &thread.axes;
    let n = [a[0].texels, a[1].texels, a[2].texels, a[3].texels];
    // Plane row (i2·N3 + i3)·N1 + i1, column i0, two channels per texel: in f32 units
    // the corners along axis 0 are 2 apart, along axis 1 s1, along v s3, along u s2.
    let (s1, s3) = (2 * n[0], 2 * n[0] * n[1]);
    let s2 = s3 * n[3];
    let base = 2 * (((i2 * n[3] + i3) * n[1] + i1) * n[0] + i0);
    ([base, base + s3, base + s2, base + s2 + s3], s1)
}

/// A thread's stored channels (reflection, transmission) from its 4D plane at the located
/// texel pairs of its four axes (βH, θd', u, v), quadrilinearly, in f32.
#[inline(always)]
fn interpolate_f32(thread: &ThreadGeometry, table: &Plane, located: [(usize, f32); 4]) -> [f32; 2] {
    let [(i0, f0), (i1, f1), (i2, f2), (i3, f3)] = located;
    let (starts, s1) = corner_blocks(thread, [i0, i1, i2, i3]);
    let data = &table.data;
    // A corner block's two rows blended along axis 1 in one SIMD register.
    let block = |at: usize| {
        let p = &data[at..at + s1 + 4];
        Vec4::from_slice(&p[..4]).lerp(Vec4::from_slice(&p[s1..]), f1)
    };
    let lower_u = block(starts[0]).lerp(block(starts[1]), f3);
    let upper_u = block(starts[2]).lerp(block(starts[3]), f3);
    let blended = lower_u.lerp(upper_u, f2);
    // Last, axis 0: (x, y) at i0, (z, w) at i0 + 1.
    let [reflection, transmission, _, _] = blended.lerp(blended.zwxy(), f0).to_array();
    [reflection, transmission]
}

/// Bilinear interpolation of a one-channel square plane over the same axis in x and y.
fn bilinear(plane: &Plane, axis: Axis, x: f64, y: f64) -> f64 {
    let (x0, x1, fx) = axis.locate(x);
    let (y0, y1, fy) = axis.locate(y);
    let width = plane.spec.width;
    let at = |i: usize, j: usize| plane.data[j * width + i] as f64;
    (1.0 - fy) * ((1.0 - fx) * at(x0, y0) + fx * at(x1, y0))
        + fy * ((1.0 - fx) * at(x0, y1) + fx * at(x1, y1))
}

/// A thread's 4D table (`data`, two channels) interpolated at table coordinates, as the
/// thread layouts' lookups do.
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
/// `masking`) at a pair: `[reflection, transmission, ⟨P⟩]` from filtering and f32
/// coordinates (points 1 and 2), and the fold differences `[reflection, transmission]`
/// (point 3 of [`gpu_bound`]; at least a tiny value when the pair is on the fold u = 0, else 0).
pub fn thread_errors(
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
    let scale = 3.0 * gpu_bound::FILTER_WEIGHT_STEP + 4.0 * gpu_bound::COORDINATE_ERROR;
    let mut errors = [0.0; 3];
    errors[0] = scale * gpu_bound::range(texels.iter().map(|&k| data[k] as f64));
    errors[1] = scale * gpu_bound::range(texels.iter().map(|&k| data[k + 1] as f64));
    let m = thread.masking_axis;
    let ((x0, x1, _), (y0, y1, _)) = (m.locate(thread.beta(wi)), m.locate(thread.beta(wo)));
    let p_range = gpu_bound::range(
        [(x0, y0), (x1, y0), (x0, y1), (x1, y1)].map(|(x, y)| masking.texel(x, y)[0] as f64),
    );
    errors[2] = (2.0 * gpu_bound::FILTER_WEIGHT_STEP + 2.0 * gpu_bound::COORDINATE_ERROR) * p_range;
    let mut fold = [0.0; 2];
    // On the fold u = 0, f32 may land on the other side, (u, v) → (−u, −v).
    if coordinates[2] < gpu_bound::FOLD_EPSILON {
        let [u, v] = [coordinates[2], coordinates[3]];
        let other = interpolate(thread, data, [coordinates[0], coordinates[1], u, -v]);
        let here = interpolate(thread, data, coordinates);
        fold = [
            (other[0] - here[0]).abs().max(f64::MIN_POSITIVE),
            (other[1] - here[1]).abs(),
        ];
    }
    (errors, fold)
}

/// [`crate::table::TableLookup::f32_exempt`] for the layouts that tabulate threads, from the
/// pair's normalisation `q` and the cos²θd' of each thread table it read: Q positive but
/// below 1e-6, or any cos²θd' below the floor that the reflection is divided by.
pub fn f32_exempt(q: f64, cos2_d: impl IntoIterator<Item = f64>) -> bool {
    (q > 0.0 && q < 1e-6) || cos2_d.into_iter().any(|c| c < super::COS2_D_FLOOR)
}
