//! Layout `thread_frame`: per thread, a 4D table in coordinates aligned with the thread's
//! specular resonance, plus a 2D table of the thread's masking mean ⟨P⟩.
//!
//! # Why these coordinates
//! For thread j (base tangent t0, rotation axis b) let h = wi + wo and
//! `βH = atan2(h·t0, h·z)`. Then `h·t(α) = |h∥| sin(βH + α)`, so the tangent sample
//! `α' = −βH` is exactly the one whose surface lobe peaks (θh = 0), and a sample α near it
//! has `θh ≈ k(α + βH)` with `k = (cos φi' + cos φo')/2`. A point of the curve's α density
//! becomes a ridge `βH = −α` of width γs/|k|; everything else varies smoothly in the other
//! three coordinates, measured in the resonant sample's frame t' = t(α'), n' = n(α'):
//!
//! | axis | value | range | texels |
//! |---|---|---|---|
//! | 0 | βH | [−90°, 90°], piecewise linear: 70% of the texels on the band [−α_max − 4σs, −α_min + 4σs] where the curve's ridges lie (a curve that jumps, as velvet's thread 2 does, has two bands at the ends of the axis, and the gap between them gets 0.3 of their density; `RidgeBands`) | 3 per σs over the bands (at least 16), both threads scaled down together to keep the table within 16 MiB |
//! | 1 | θd' = asin s, s = ½(wi·t' − wo·t') | [−L, L], L = 90° − 1e-4 rad, `Warp::SinEnds` k = 1.4 (denser towards grazing) | R |
//! | 2 | u = (φi' + φo')/2 | [0°, 90°], linear | 0.29·R |
//! | 3 | v = (φi' − φo')/2 | [−90°, 90°], linear | the odd count nearest 0.83·R (v = 0 a texel line) |
//!
//! with φi' = atan2(wi·b, wi·n'), φo' = atan2(wo·b, wo·n'). R is the table's `resolution`.
//! Since n' is the direction of h's projection, cos φi' + cos φo' = 2 cos u cos v ≥ 0, so
//! every pair lies in the square |u|, |v| ≤ 90°; the exact symmetry b → −b of each sample
//! (u, v) → (−u, −v) folds it to u ≥ 0. Texel centres follow [`super::axis`]. Texels whose
//! directions fall below the horizon are baked with the same formula, so the stored
//! function continues smoothly past the domain edge instead of dropping to 0. The texels
//! hold the node values of the least-squares quadrilinear fit of these samples
//! ([`super::prefilter`]), which takes out linear interpolation's bias towards the chord.
//!
//! # Channels and lookup
//! The 4D table of thread j stores `reflection = R_j·cos²θd'/⟨P⟩_j` and
//! `transmission = T_j/⟨P⟩_j`, where R_j, T_j, ⟨P⟩_j are the thread's curve means
//! ([`crate::model::ThreadMeans`]). Dividing by ⟨P⟩ makes F a ⟨P⟩-weighted mean of bounded
//! ratios where Q → 0 near the horizon; R/⟨P⟩ alone grows like 1/cos²θd' at grazing forward
//! scattering, which the cos²θd' factor (exactly `1 − s²`, known at lookup) takes out.
//! Where ⟨P⟩ vanishes (no tangent sample faces both directions) the texel holds 0, the
//! ratios' limit there (see [`MASKING_FLOOR`](super::thread::MASKING_FLOOR)).
//!
//! ⟨P⟩_j depends only on the angles `β = atan2(w·t0, w·z)` of wi and wo in the t0–z plane,
//! and is stored in a 129×129 table over (βi, βo) ∈ [−90°, 90°]², clamped, texel i at
//! `−90° + 180°·i/128`, bilinear.
//!
//! A lookup for thread j: the four coordinates, a quadrilinear interpolation of the 4D table
//! (on a GPU: axes 0, 1, 3 by hardware filtering of a 3D texture, axis 2 by a manual blend of
//! two layers), and ⟨P⟩_j bilinearly from its 2D table; then
//! `R_j = reflection·⟨P⟩_j / max(1 − s², floor)` ([`thread::COS2_D_FLOOR`]), `T_j = transmission·⟨P⟩_j`,
//! `Q = a1⟨P⟩_1 + a2⟨P⟩_2 + (1 − a1 − a2)·wo.z` and `F = Σ_j a_j (R_j + A_j T_j) / Q`.
//!
//! # Planes (EXR layers)
//! `thread1`, `thread2`: channels `reflection`, `transmission`; width = axis-0 texels,
//! height = (axis 2 × axis 3 × axis 1) texels: row `(i2·N3 + i3)·N1 + i1`, column `i0`.
//! `masking1`, `masking2`: channel `masking`, 129×129, column βi, row βo.
//!
//! # GPU textures
//! Per thread one `Rg16Float` 3D texture (bindings 4, 5; channels reflection, transmission)
//! of width N0 (βH), height N1 (θd') and depth N2·(N3 + 2): for each texel i2 of axis 2 (u)
//! a block of N3 + 2 depth slices holding axis 3 (v), texel i3 at slice
//! `i2·(N3 + 2) + 1 + i3`, with one duplicated edge slice before and after the block.
//! Hardware filtering interpolates βH, θd' and v; the shader blends the two u blocks by
//! hand, and the duplicated slices make sure that a sample at a block's edge can only ever
//! blend with a copy of that edge, never with the neighbouring u block (the axes are
//! clamped, so a copy is exactly clamp-to-edge). This is the plane's own row order
//! `(i2·N3 + i3)·N1 + i1` regrouped as depth `i2·N3 + i3`, plus the padding slices. Both
//! masking planes go into one `R16Float` 2D array texture (binding 6, layer j), 129×129,
//! column βi, row βo. Six filtered fetches per light: two per thread's 4D table, one per
//! thread's ⟨P⟩.

use super::BatchLanes;
use super::axis::AxisF32;
use super::fast_math::Lanes;
use super::gpu_bound::{self, GpuErrorBound};
use super::progress::BakeProgress;
use super::thread::{
    self, AxisPlan, LocatedPairs, MASKING_TEXELS, MIN_BETA_TEXELS, ThreadGeometry, bake_masking,
    bake_thread_plane, f32_exempt, masking_texture, stored_ratios, thread_errors, thread_texture,
};
use super::{BATCH_LANES, LayoutUnit, Plane, PlaneSpec, TableLookup, TextureData};
use crate::model::{Fabric, Integration, patch::ThreadModel};
use crate::shader::ShaderFile;
use glam::{DVec3, Vec3};
use std::any::Any;
use std::sync::Arc;

/// The layout unit `thread_frame`.
pub struct ThreadFrame;

/// The layout's WGSL file: the lookup `cloth_thread_frame_brdf(wi, wo)`.
const WGSL_FILE: ShaderFile = ShaderFile {
    name: "table/thread_frame",
    path: "shaders/table/thread_frame.wgsl",
    source: include_str!("../../shaders/table/thread_frame.wgsl"),
};

impl LayoutUnit for ThreadFrame {
    fn name(&self) -> &'static str {
        "thread_frame"
    }

    fn wgsl_file(&self) -> &'static ShaderFile {
        &WGSL_FILE
    }

    fn default_resolution(&self) -> u32 {
        48
    }

    /// At 96: at most 32 βH slices of 96 × 28 × 79 texels, 26 MiB.
    fn max_resolution(&self) -> u32 {
        96
    }

    fn resolution_ladder(&self) -> &'static [u32] {
        &[16, 24, 32, 40, 48]
    }

    fn report_resolutions(&self, quick: bool) -> &'static [u32] {
        if quick {
            &[16, 24, 48]
        } else {
            self.resolution_ladder()
        }
    }

    fn integration(&self) -> &'static str {
        "baking: per-segment midpoint rule, alpha spacing <= min(2 deg, sigma/6), masking planes included"
    }

    fn plane_specs(&self, fabric: &Fabric, resolution: u32) -> Vec<PlaneSpec> {
        Geometry::new(fabric, resolution).specs()
    }

    /// The rows of both 4D tables (the masking planes are quick and not reported).
    fn bake_rows(&self, fabric: &Fabric, resolution: u32) -> u64 {
        self.plane_specs(fabric, resolution)[..2]
            .iter()
            .map(|s| s.height as u64)
            .sum()
    }

    /// The curve means of every texel of both threads, encoded as "Channels and lookup"
    /// describes, then the masking planes.
    fn bake(&self, fabric: &Fabric, resolution: u32, progress: &dyn BakeProgress) -> Vec<Vec<f64>> {
        let geometry = Geometry::new(fabric, resolution);
        let mut planes = Vec::with_capacity(4);
        for (j, thread) in geometry.threads.iter().enumerate() {
            let model = ThreadModel::new(fabric, j, Integration::Baking);
            planes.push(bake_thread_plane(thread, progress, |wi, wo, theta_d| {
                stored_ratios(&model, wi, wo, theta_d)
            }));
        }
        if progress.cancelled() {
            return planes;
        }
        for (j, thread) in geometry.threads.iter().enumerate() {
            planes.push(bake_masking(fabric, thread, j));
        }
        planes
    }

    fn lookup(&self, fabric: &Fabric, resolution: u32) -> Arc<dyn TableLookup> {
        Arc::new(Geometry::new(fabric, resolution))
    }
}

/// Bytes of texel data a table may use: the βH axes of both threads shrink together to fit.
pub const BYTE_BUDGET: usize = 16 << 20;
const BETA_FOCUS: f64 = 0.7;
const BETA_TEXELS_PER_SIGMA: f64 = 3.0;
const THETA_WARP_K: f64 = 1.4;

/// How this layout sizes a thread's axes: 3 βH texels per σs on the ridge bands, 70% of the
/// axis on them, and θd', u, v at 1, 0.29 and 0.83 times the resolution.
pub const PLAN: AxisPlan = AxisPlan {
    beta_texels_per_sigma: BETA_TEXELS_PER_SIGMA,
    beta_focus: BETA_FOCUS,
    beta_edge_density: 1.0,
    inner_per_resolution: [1.0, 0.29, 0.83],
    theta_warp_k: THETA_WARP_K,
};

/// βH texels of both threads: 3 per σs on each ridge band, scaled down together (to at
/// least 16 each) when the table would exceed [`BYTE_BUDGET`].
fn beta_texels(fabric: &Fabric, resolution: u32) -> [usize; 2] {
    let plan = PLAN;
    let wanted = [0, 1].map(|j| plan.beta_texels(fabric, j));
    let slice_bytes: usize = plan.inner_texels(resolution).iter().product::<usize>() * 2 * 2;
    let masking_bytes = 2 * MASKING_TEXELS * MASKING_TEXELS * 2;
    let available = BYTE_BUDGET.saturating_sub(masking_bytes) / slice_bytes;
    let total = wanted[0] + wanted[1];
    if total <= available {
        return wanted;
    }
    let scale = available as f64 / total as f64;
    wanted.map(|n| ((n as f64 * scale).floor() as usize).max(MIN_BETA_TEXELS))
}

/// The axes of thread `index` of `fabric` at `resolution` in this layout.
pub fn thread_geometry(fabric: &Fabric, index: usize, resolution: u32) -> ThreadGeometry {
    let n_beta = beta_texels(fabric, resolution)[index];
    ThreadGeometry::planned(fabric, index, resolution, n_beta, &PLAN)
}

/// The lookup geometry of a whole table.
#[derive(Clone, Debug, PartialEq)]
pub struct Geometry {
    pub threads: [ThreadGeometry; 2],
    pub coverage: [f64; 2],
    pub gap: f64,
    /// Per thread, the 4D axes and the masking axis for the f32 lookup.
    fast_axes: [[AxisF32; 5]; 2],
}

impl Geometry {
    pub fn new(fabric: &Fabric, resolution: u32) -> Self {
        let threads = [0, 1].map(|j| thread_geometry(fabric, j, resolution));
        let fast_axes = threads.each_ref().map(ThreadGeometry::fast_axes);
        Self {
            threads,
            coverage: [fabric.thread1.coverage, fabric.thread2.coverage],
            gap: (1.0 - fabric.thread1.coverage - fabric.thread2.coverage).max(0.0),
            fast_axes,
        }
    }

    pub fn specs(&self) -> Vec<PlaneSpec> {
        let mut specs: Vec<PlaneSpec> = self
            .threads
            .iter()
            .enumerate()
            .map(|(j, t)| t.spec(j))
            .collect();
        for j in 0..2 {
            specs.push(PlaneSpec::new(
                format!("masking{}", j + 1),
                MASKING_TEXELS,
                MASKING_TEXELS,
                &["masking"],
            ));
        }
        specs
    }

    /// Thread `j`'s interpolated stored channels, masking and cos²θd' at (wi, wo):
    /// `[reflection, transmission, ⟨P⟩, cos²θd']` (channels as the planes hold them).
    pub fn sample_thread(&self, planes: &[Plane], j: usize, wi: DVec3, wo: DVec3) -> [f64; 4] {
        self.threads[j].sample(&planes[j], &planes[2 + j], wi, wo)
    }

    /// The interpolated terms (reflection, transmission1, transmission2), already divided
    /// by Q, from `planes` in the order of [`Self::specs`].
    pub fn lookup_terms(&self, planes: &[Plane], wi: DVec3, wo: DVec3) -> [f64; 3] {
        let mut reflection = 0.0;
        let mut transmission = [0.0; 2];
        let mut q = self.gap * wo.z;
        for (j, share) in transmission.iter_mut().enumerate() {
            let [r, t, masking, cos2_d] = self.sample_thread(planes, j, wi, wo);
            reflection += self.coverage[j] * r * masking / cos2_d.max(thread::COS2_D_FLOOR);
            *share = self.coverage[j] * t * masking;
            q += self.coverage[j] * masking;
        }
        if q <= 0.0 {
            return [0.0; 3];
        }
        [reflection / q, transmission[0] / q, transmission[1] / q]
    }
}

impl Geometry {
    /// The terms of pair `k` of `located` (each thread's located pairs), as
    /// [`TableLookup::terms_f32`] describes them; `wo_z` is that pair's wo.z.
    #[inline(always)]
    fn terms_located<L: Lanes>(
        &self,
        planes: &[Plane],
        located: &[LocatedPairs<L>; 2],
        k: usize,
        wo_z: f32,
    ) -> [f32; 3] {
        let mut reflection = 0.0;
        let mut transmission = [0.0; 2];
        let mut q = self.gap as f32 * wo_z;
        for (j, share) in transmission.iter_mut().enumerate() {
            let [r, t, masking, cos2_d] =
                self.threads[j].sample_located(&planes[j], &planes[2 + j], &located[j], k);
            let a = self.coverage[j] as f32;
            reflection += a * r * masking / cos2_d.max(thread::COS2_D_FLOOR as f32);
            *share = a * t * masking;
            q += a * masking;
        }
        if q <= 0.0 {
            return [0.0; 3];
        }
        [reflection / q, transmission[0] / q, transmission[1] / q]
    }

    /// Both threads' located pairs for `L::WIDTH` pairs.
    #[inline(always)]
    fn locate<L: Lanes>(&self, wi: &[Vec3], wo: &[Vec3]) -> [LocatedPairs<L>; 2] {
        let thread = |j: usize| self.threads[j].locate_f32::<L>(&self.fast_axes[j], wi, wo);
        [thread(0), thread(1)]
    }
}

impl TableLookup for Geometry {
    fn terms(&self, planes: &[Plane], wi: DVec3, wo: DVec3) -> [f64; 3] {
        self.lookup_terms(planes, wi, wo)
    }

    #[inline]
    fn terms_f32(&self, planes: &[Plane], wi: Vec3, wo: Vec3) -> [f32; 3] {
        let located = self.locate::<f32>(&[wi], &[wo]);
        self.terms_located(planes, &located, 0, wo.z)
    }

    fn terms_f32_lanes(
        &self,
        planes: &[Plane],
        wi: &[Vec3; BATCH_LANES],
        wo: &[Vec3; BATCH_LANES],
    ) -> [[f32; 3]; BATCH_LANES] {
        let located = self.locate::<BatchLanes>(wi, wo);
        for (j, thread) in self.threads.iter().enumerate() {
            thread.prefetch_located(&planes[j], &planes[2 + j], &located[j]);
        }
        let mut terms = [[0.0; 3]; BATCH_LANES];
        for (k, terms) in terms.iter_mut().enumerate() {
            *terms = self.terms_located(planes, &located, k, wo[k].z);
        }
        terms
    }

    fn wgsl_constants(&self) -> String {
        // The u blend reads blocks i0 and i0 + 1 (i0 ≤ N2 − 2).
        assert!(
            self.threads.iter().all(|t| t.axes[2].texels >= 2),
            "thread_frame has at least 2 u texels"
        );
        let mut out = thread::layout_wgsl(self.coverage, self.gap);
        for (j, thread) in self.threads.iter().enumerate() {
            out += &thread.wgsl_constant(&format!("cloth_thread{}_axes", j + 1), j);
        }
        out
    }

    fn textures(&self, planes: &[Plane]) -> Vec<TextureData> {
        let mut textures: Vec<TextureData> = (0..2)
            .map(|j| thread_texture(&planes[j], &self.threads[j], j))
            .collect();
        textures.push(masking_texture(&planes[2..4]));
        textures
    }

    /// Per thread: 3 filtered axes of the 4D table and 2 of ⟨P⟩, f32 coordinates, the fold
    /// u = 0, and cos²θd' in f32, propagated to F ([`gpu_bound`] points 1 to 3).
    fn gpu_error_bound(
        &self,
        planes: &[Plane],
        albedo: [DVec3; 2],
        wi: DVec3,
        wo: DVec3,
        cpu: DVec3,
    ) -> GpuErrorBound {
        let floor = gpu_bound::floor(cpu);
        let mut samples = [[0.0f64; 4]; 2];
        let mut errors = [[0.0; 3]; 2];
        let mut fold = [[0.0; 2]; 2];
        for (j, thread) in self.threads.iter().enumerate() {
            samples[j] = self.sample_thread(planes, j, wi, wo);
            (errors[j], fold[j]) = thread_errors(thread, &planes[j], &planes[2 + j], wi, wo);
        }
        let q: f64 = self.gap * wo.z
            + (0..2)
                .map(|j| self.coverage[j] * samples[j][2])
                .sum::<f64>();
        if q <= 0.0 {
            return GpuErrorBound {
                per_channel: floor,
                on_fold: false,
            };
        }
        let mut total = floor;
        for j in 0..2 {
            let [r, t, p, c2] = samples[j];
            let a = self.coverage[j];
            let c = c2.max(thread::COS2_D_FLOOR);
            let d_r = a * p / (c * q);
            let d_t = albedo[j] * (a * p / q);
            let d_p = (DVec3::splat(r / c) + albedo[j] * t - cpu) * (a / q);
            // f32 error of 1 − s² (absolute ~1e-7) in reflection/cos²θd'.
            let c2_error = a * p * r / (c * q) * (1e-7 / c);
            total += DVec3::splat(d_r * (errors[j][0] + fold[j][0]) + c2_error)
                + d_t.abs() * (errors[j][1] + fold[j][1])
                + d_p.abs() * errors[j][2];
        }
        GpuErrorBound {
            per_channel: total,
            on_fold: fold != [[0.0; 2]; 2],
        }
    }

    fn f32_exempt(&self, planes: &[Plane], wi: DVec3, wo: DVec3) -> bool {
        let samples = [0, 1].map(|j| self.sample_thread(planes, j, wi, wo));
        let q = self.gap * wo.z
            + (0..2)
                .map(|j| self.coverage[j] * samples[j][2])
                .sum::<f64>();
        f32_exempt(q, samples.map(|s| s[3]))
    }

    fn as_any(&self) -> &dyn Any {
        self
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bake::bake;
    use crate::table::Layout;

    fn builtin(name: &str) -> Fabric {
        let set = crate::formats::fabric_toml::FabricSet::builtin();
        set.get(name).expect("built-in fabric").clone()
    }

    /// At a texel's own coordinates the thread_frame lookup returns that texel's stored
    /// channels, and halfway between two texels along an axis their mean.
    #[test]
    fn thread_frame_lookup_reproduces_texels_at_their_coordinates() {
        let table = bake(&builtin("linen_plain"), Layout::THREAD_FRAME, 8, &|| {}).unwrap();
        let Some(geometry) = table.geometry_as::<Geometry>() else {
            panic!("not thread_frame")
        };
        let planes = table.planes();
        for j in 0..2 {
            let thread = &geometry.threads[j];
            let n = thread.axes.map(|a| a.texels);
            let mut checked = 0;
            let all = (0..n[0]).flat_map(|i0| {
                (0..n[1]).flat_map(move |i1| {
                    (0..n[2]).flat_map(move |i2| (0..n[3]).map(move |i3| [i0, i1, i2, i3]))
                })
            });
            for index in all {
                let coordinates = [0, 1, 2, 3].map(|a| thread.axes[a].texel_value(index[a]));
                let (wi, wo) = thread.directions(coordinates);
                // Texels below the horizon extend the function; only pairs above it are
                // looked up (and only there is the coordinate map invertible).
                if wi.z <= 1e-3 || wo.z <= 1e-3 {
                    continue;
                }
                let stored = &planes[j].data[thread.texel_index(index) * 2..][..2];
                let [r, t, _, _] = geometry.sample_thread(planes, j, wi, wo);
                for (got, want) in [(r, stored[0]), (t, stored[1])] {
                    assert!(
                        (got - want as f64).abs() <= 1e-6 * (want as f64).abs().max(1e-3),
                        "thread {j} {index:?}: {got} vs {want}"
                    );
                }
                // Halfway along v (a linear axis) between this texel and the next.
                if index[3] + 1 == n[3] {
                    continue;
                }
                let next = [index[0], index[1], index[2], index[3] + 1];
                let mut halfway = coordinates;
                halfway[3] = 0.5 * (coordinates[3] + thread.axes[3].texel_value(index[3] + 1));
                let (wi, wo) = thread.directions(halfway);
                if wi.z <= 1e-3 || wo.z <= 1e-3 {
                    continue;
                }
                let following = &planes[j].data[thread.texel_index(next) * 2..][..2];
                let [r, t, _, _] = geometry.sample_thread(planes, j, wi, wo);
                for (got, a, b) in [(r, stored[0], following[0]), (t, stored[1], following[1])] {
                    let want = 0.5 * (a as f64 + b as f64);
                    assert!(
                        (got - want).abs() <= 1e-6 * want.abs().max(1e-3),
                        "thread {j} {index:?} halfway: {got} vs {want}"
                    );
                }
                checked += 1;
            }
            assert!(
                checked > 100,
                "thread {j}: only {checked} texels above the horizon"
            );
        }
    }

    /// The fold (u, v) → (−u, −v) (the exact b → −b symmetry of every tangent sample) glues the
    /// table's u = 0 slice to itself with v → −v: a lookup just below u = 0 reads the slice at −v.
    /// The slice must therefore be symmetric in v, or F jumps across the fold. Baked texels are
    /// symmetric up to rounding; the filled ones (⟨P⟩ below the floor) must be too.
    #[test]
    fn thread_frame_u0_slice_is_symmetric_in_v() {
        for name in ["polyester_satin_charmeuse", "linen_plain"] {
            let table = bake(&builtin(name), Layout::THREAD_FRAME, 12, &|| {}).unwrap();
            let Some(geometry) = table.geometry_as::<Geometry>() else {
                panic!("not thread_frame")
            };
            for j in 0..2 {
                let thread = &geometry.threads[j];
                let n = thread.axes.map(|a| a.texels);
                let data = &table.planes()[j].data;
                let mut worst = 0.0f64;
                for i0 in 0..n[0] {
                    for i1 in 0..n[1] {
                        for i3 in 0..n[3] {
                            let a = thread.texel_index([i0, i1, 0, i3]) * 2;
                            let b = thread.texel_index([i0, i1, 0, n[3] - 1 - i3]) * 2;
                            for c in 0..2 {
                                let (x, y) = (data[a + c] as f64, data[b + c] as f64);
                                worst = worst.max((x - y).abs() / x.abs().max(y.abs()).max(1e-3));
                            }
                        }
                    }
                }
                // f16 storage: symmetric values round identically, so any difference beyond
                // one f16 step (2^-11 relative) is a real asymmetry.
                assert!(
                    worst <= 1e-3,
                    "{name} thread {j}: u = 0 slice asymmetric by {worst:.2e}"
                );
                eprintln!("{name} thread {j}: u = 0 slice symmetric to {worst:.1e}");
            }
        }
    }
}
