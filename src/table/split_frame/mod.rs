//! Layout `split_frame`: each thread's curve split into its point masses, evaluated exactly
//! at lookup, and its sloped segments, tabulated in the thread's resonant frame as
//! [`super::thread_frame`] tabulates a whole thread.
//!
//! # Why
//! A flat segment of a tangent curve is a point mass of the curve's density of tangent
//! offsets. In a table over (βH, θd', u, v) it makes a ridge as narrow as the surface lobe,
//! and its masking factors M and P have kinks along the great circles w·n(α_k) = 0 (for a
//! float at α_k = 0, the horizon itself) that cut through texels; a 4D table of the whole
//! curve converges slowly near them (for the fabrics with floats, most of a table's error
//! came from such pairs). One tangent sample is cheap to evaluate
//! exactly, so the point masses are taken out of the table and evaluated at lookup: a thread
//! that is a single point (the straight weft of crepe, both satins and shot silk) needs no
//! table at all. What remains tabulated is the smooth convolution of the sloped segments.
//!
//! # Planes and lookup
//! For thread j let the curve's density of tangent offsets be
//! `Σ_k w_k δ(α − α_k) + w_c D_c`: point masses α_k with their shares w_k of the arc length
//! (its flat segments, or every control point with `tangent_sampling = "control_points"`)
//! and the sloped segments with share `w_c = 1 − Σ w_k`, `D_c` their own normalised density.
//! For every thread with sloped segments the table holds the planes of a
//! [`super::thread_frame`] thread baked from `D_c` alone (`threadJ`: channels
//! `reflection` = R_c·cos²θd'/⟨P⟩_c and `transmission` = T_c/⟨P⟩_c over (βH, θd', u, v);
//! `maskingJ`: ⟨P⟩_c over (βi, βo), 129²), with the axes of [`PLAN`]: 1.2 βH texels per σs
//! on the band of the sloped segments' ridges (1.8 on the zone around the inner edge of a
//! band that reaches an end of the axis), θd' R texels (`SinEnds`, k = 1.2), u 0.56R,
//! v the odd count nearest 0.84R; texels hold the least-squares fit of
//! [`super::prefilter`]. Thread planes come first, then masking planes, both in thread
//! order.
//!
//! Texels whose directions fall below the horizon hold the function continued past it with
//! its one-sided slope: with w⁺ = normalize(w.x, w.y, max(w.z, 10⁻⁶)) and
//! wᵐ = normalize(w.x, w.y, |w.z|), the stored ratios ρ are `max(2ρ(w⁺) − ρ(wᵐ), 0)`
//! (each ρ with its own pair's cos²θd'), where baking the model there instead would carry
//! the kinks of the samples that stop facing the directions into the last texel inside.
//!
//! A lookup for thread j sums, over its point masses, the single-sample terms
//! (`ThreadModel::point_sums`: w_k·R_k, w_k·T_k, w_k·P_k, exactly as the direct evaluation
//! weighs a flat segment; the f32 lookup runs the same kernel in f32,
//! [`super::point_samples::PointSamples`], eight pairs at once in a batch), and for the
//! sloped part `w_c⟨P⟩_c` times the interpolated ratios (reflection divided by cos²θd' as
//! in thread_frame); then
//! `Q = Σ_j a_j (Σ_k w_k P_k + w_c⟨P⟩_c) + (1 − a1 − a2)·wo.z` and `F = Σ_j a_j ⟨s⟩_j / Q`.
//!
//! # The horizon
//! Nothing in a lookup integrates the curve; pairs near the horizon are no special case.
//! The texels below the horizon hold the continuation above, so a pair a fraction of a
//! degree up interpolates between a texel inside and one continued outside as any other
//! pair interpolates, and v = 0, where min(M(wi), M(wo)) kinks, is a texel line. Every
//! built-in fabric meets the default's goal, horizon included
//! (docs/tables.md#the-horizon-inside-the-table).
//!
//! # GPU textures
//! The sloped tables as thread_frame arranges them (bindings 4 and 5, 3D, only for threads
//! that have one) and their masking planes in one array texture (binding 6, layer = the
//! thread's position among those with a table). Per light: two filtered fetches per sloped
//! table and one per masking plane (0–6 in all: linen and velvet 6, crepe, satin and shot
//! silk 3), plus one evaluation of the shared sample kernel (`shaders/model/tangent_sample.wgsl`) per
//! point mass (linen and velvet 0, crepe 3, satin 4, satin back 5, shot silk 3). The same
//! shader on every adapter.

use super::axis::AxisF32;
use super::fast_math::Lanes;
use super::point_samples::{PointSamples, PointSums};
use super::progress::BakeProgress;
use super::thread::{self, AxisPlan, LocatedPairs, ThreadGeometry};
use super::wgsl::{wgsl_f32, wgsl_vec};
use super::{LayoutUnit, Plane, PlaneSpec, TableLookup};
use crate::model::curve::{Integration, curve_pieces};
use crate::model::fabric::TangentSampling;
use crate::model::patch::ThreadModel;
use crate::model::{Fabric, Thread};
use crate::shader::ShaderFile;
use glam::{DVec3, Vec3};
use std::fmt::Write;
use std::sync::Arc;

mod lookup;

/// The axes of the sloped tables (see the module doc): βH needs fewer texels once the point
/// masses' sharp ridges are gone, and u more; the edge zone's denser texels are what
/// velvet's image error needed (docs/notebook/2026-12-07-tables.md#what-was-tried).
pub const PLAN: AxisPlan = AxisPlan {
    beta_texels_per_sigma: 1.2,
    beta_focus: 0.7,
    beta_edge_density: 1.5,
    inner_per_resolution: [1.0, 0.56, 0.84],
    theta_warp_k: 1.2,
};

/// The layout unit `split_frame`.
pub struct SplitFrame;

/// The layout's WGSL file: the lookup `cloth_split_frame_brdf(wi, wo)`.
const WGSL_FILE: ShaderFile = ShaderFile {
    name: "table/split_frame",
    path: "shaders/table/split_frame.wgsl",
    source: include_str!("../../../shaders/table/split_frame.wgsl"),
};

impl LayoutUnit for SplitFrame {
    fn name(&self) -> &'static str {
        "split_frame"
    }

    fn wgsl_file(&self) -> &'static ShaderFile {
        &WGSL_FILE
    }

    /// The smallest resolution at which every built-in fabric meets the default's goal
    /// (docs/tables.md#goals); sizes and bake times in report/REPORT.md.
    fn default_resolution(&self) -> u32 {
        31
    }

    /// At 64: 64 × 36 × 53 texels per βH slice, at most ~130 slices: 64 MiB.
    fn max_resolution(&self) -> u32 {
        64
    }

    fn resolution_ladder(&self) -> &'static [u32] {
        &[16, 20, 24, 31, 40, 48]
    }

    fn report_resolutions(&self, quick: bool) -> &'static [u32] {
        if quick {
            &[16, 31]
        } else {
            &[16, 20, 24, 31, 40]
        }
    }

    fn integration(&self) -> &'static str {
        "baking: per-segment midpoint rule over the sloped segments, alpha spacing <= min(2 deg, sigma/6); point masses evaluated at lookup"
    }

    fn plane_specs(&self, fabric: &Fabric, resolution: u32) -> Vec<PlaneSpec> {
        let geometry = Geometry::new(fabric, resolution);
        let mut specs: Vec<PlaneSpec> = geometry
            .tabulated()
            .map(|(j, t)| t.geometry.spec(j))
            .collect();
        specs.extend(geometry.tabulated().map(|(j, _)| {
            PlaneSpec::new(
                format!("masking{}", j + 1),
                thread::MASKING_TEXELS,
                thread::MASKING_TEXELS,
                &["masking"],
            )
        }));
        specs
    }

    fn bake_rows(&self, fabric: &Fabric, resolution: u32) -> u64 {
        let geometry = Geometry::new(fabric, resolution);
        geometry
            .tabulated()
            .map(|(j, t)| t.geometry.spec(j).height as u64)
            .sum()
    }

    fn bake(&self, fabric: &Fabric, resolution: u32, progress: &dyn BakeProgress) -> Vec<Vec<f64>> {
        let geometry = Geometry::new(fabric, resolution);
        let mut tables = Vec::new();
        let mut masking = Vec::new();
        for (j, slopes) in geometry.tabulated() {
            tables.push(bake_slopes(&slopes.fabric, &slopes.geometry, j, progress));
            if !progress.cancelled() {
                masking.push(thread::bake_masking(&slopes.fabric, &slopes.geometry, j));
            }
        }
        tables.extend(masking);
        tables
    }

    fn lookup(&self, fabric: &Fabric, resolution: u32) -> Arc<dyn TableLookup> {
        Arc::new(Geometry::new(fabric, resolution))
    }
}

/// The sloped segments of one thread, tabulated.
#[derive(Clone, Debug)]
pub struct Slopes {
    /// The fabric with this thread's curve replaced by its sloped segments alone.
    pub fabric: Fabric,
    pub geometry: ThreadGeometry,
    fast_axes: [AxisF32; 5],
    /// w_c, their share of the curve's arc length.
    pub weight: f64,
}

/// One thread of a split_frame table.
#[derive(Clone, Debug)]
pub struct SplitThread {
    /// Point masses as (cos α_k, sin α_k, w_k).
    pub points: Vec<(f64, f64, f64)>,
    pub slopes: Option<Slopes>,
    /// Evaluates single tangent samples of this thread in f64 (its curve is not used).
    model: ThreadModel,
    /// The same in f32 for the CPU lookup, with the constants of the WGSL sample kernel.
    pub samples: PointSamples,
}

/// The lookup geometry of a split_frame table.
#[derive(Clone, Debug)]
pub struct Geometry {
    pub threads: [SplitThread; 2],
    pub coverage: [f64; 2],
    pub gap: f64,
    /// Per thread, the indices of its 4D and masking planes, if it has sloped segments.
    planes: [Option<(usize, usize)>; 2],
}

/// A thread's sloped segments as a thread of their own (zero-length jumps between them),
/// or `None` when the curve has none (a single point, only flat segments, or control-point
/// sampling).
fn sloped_part(thread: &Thread, sampling: TangentSampling) -> Option<Thread> {
    let offsets = &thread.offsets_deg;
    if sampling == TangentSampling::ControlPoints || offsets.len() < 2 {
        return None;
    }
    let single = offsets.len() == 2;
    let (mut part_offsets, mut part_lengths) = (Vec::new(), Vec::new());
    for k in 0..offsets.len() - 1 {
        let length = if single { 1.0 } else { thread.lengths[k] };
        if offsets[k] == offsets[k + 1] || length <= 0.0 {
            continue;
        }
        if !part_offsets.is_empty() {
            part_lengths.push(0.0);
        }
        part_offsets.extend([offsets[k], offsets[k + 1]]);
        part_lengths.push(length);
    }
    (!part_offsets.is_empty()).then(|| Thread {
        offsets_deg: part_offsets,
        lengths: part_lengths,
        ..thread.clone()
    })
}

/// A thread's sloped table as one batch of lookups reads it: its geometry, planes and share
/// w_c, and where the pairs fall.
struct SlopedLookup<'a, L: Lanes> {
    geometry: &'a ThreadGeometry,
    table: &'a Plane,
    masking: &'a Plane,
    weight: f32,
    located: LocatedPairs<L>,
}

impl Geometry {
    pub fn new(fabric: &Fabric, resolution: u32) -> Self {
        let threads = [0, 1].map(|j| {
            let thread = fabric.threads()[j];
            let points: Vec<(f64, f64, f64)> =
                curve_pieces(thread, &fabric.options, Integration::Direct)
                    .into_iter()
                    .filter(|p| p.start == p.end)
                    .map(|p| (p.start.cos(), p.start.sin(), p.weight))
                    .collect();
            let weight = 1.0 - points.iter().map(|p| p.2).sum::<f64>();
            let slopes = sloped_part(thread, fabric.options.tangent_sampling)
                .filter(|_| weight > 1e-12)
                .map(|part| {
                    let mut sub = fabric.clone();
                    *(if j == 0 {
                        &mut sub.thread1
                    } else {
                        &mut sub.thread2
                    }) = part;
                    let n_beta = PLAN.beta_texels(&sub, j);
                    let geometry = ThreadGeometry::planned(&sub, j, resolution, n_beta, &PLAN);
                    Slopes {
                        fast_axes: geometry.fast_axes(),
                        geometry,
                        fabric: sub,
                        weight,
                    }
                });
            let options = &fabric.options;
            let sigmas = [thread.gamma_s_deg, thread.gamma_v_deg]
                .map(|gamma| options.lobe_sigma_deg(gamma).to_radians());
            let sigmas = [sigmas[0], sigmas[1], options.sigma_u_deg.to_radians()];
            SplitThread {
                samples: PointSamples::new(j, sigmas, thread.eta, thread.kd, &points),
                points,
                slopes,
                model: ThreadModel::new(fabric, j, Integration::Direct),
            }
        });
        let tabulated: Vec<usize> = (0..2).filter(|&j| threads[j].slopes.is_some()).collect();
        let planes = [0, 1].map(|j| {
            tabulated
                .iter()
                .position(|&k| k == j)
                .map(|at| (at, tabulated.len() + at))
        });
        Self {
            threads,
            coverage: [fabric.thread1.coverage, fabric.thread2.coverage],
            gap: (1.0 - fabric.thread1.coverage - fabric.thread2.coverage).max(0.0),
            planes,
        }
    }

    /// The threads with sloped segments, in order.
    pub fn tabulated(&self) -> impl Iterator<Item = (usize, &Slopes)> {
        (0..2).filter_map(|j| self.threads[j].slopes.as_ref().map(|s| (j, s)))
    }

    /// The indices of thread `j`'s 4D plane and masking plane, if it has sloped segments.
    pub fn plane_indices(&self, j: usize) -> Option<(usize, usize)> {
        self.planes[j]
    }

    /// Thread `j`'s curve sums (reflection, transmission, ⟨P⟩), reflection divided by
    /// cos²θd' where it comes from the table (see the module doc).
    pub fn thread_sums(&self, planes: &[Plane], j: usize, wi: DVec3, wo: DVec3) -> [f64; 3] {
        let thread = &self.threads[j];
        let mut sums = [0.0; 3];
        if !thread.points.is_empty() {
            let points = thread.model.point_sums(wi, wo, &thread.points);
            sums = [points.reflection, points.transmission, points.masking];
        }
        if let (Some(slopes), Some((table, masking))) = (&thread.slopes, self.planes[j]) {
            let [r, t, p, cos2_d] =
                slopes
                    .geometry
                    .sample(&planes[table], &planes[masking], wi, wo);
            let p = slopes.weight * p;
            sums[0] += r * p / cos2_d.max(thread::COS2_D_FLOOR);
            sums[1] += t * p;
            sums[2] += p;
        }
        sums
    }

    /// [`Self::thread_sums`] in f32 for pair `k` of the `L::WIDTH` pairs whose point masses
    /// sum to `points`, with the thread's sloped table where it has one.
    #[inline(always)]
    fn thread_sums_f32<L: Lanes>(
        points: &PointSums<L>,
        sloped: Option<&SlopedLookup<L>>,
        k: usize,
    ) -> [f32; 3] {
        let mut sums = [
            points[0].values()[k],
            points[1].values()[k],
            points[2].values()[k],
        ];
        if let Some(sloped) = sloped {
            let [r, t, p, cos2_d] =
                sloped
                    .geometry
                    .sample_located(sloped.table, sloped.masking, &sloped.located, k);
            let p = sloped.weight * p;
            sums[0] += r * p / cos2_d.max(thread::COS2_D_FLOOR as f32);
            sums[1] += t * p;
            sums[2] += p;
        }
        sums
    }

    /// Thread j's sloped table and where the `L::WIDTH` pairs fall in it, if it has one.
    #[inline(always)]
    fn locate_slopes<'a, L: Lanes>(
        &'a self,
        planes: &'a [Plane],
        j: usize,
        wi: &[Vec3],
        wo: &[Vec3],
    ) -> Option<SlopedLookup<'a, L>> {
        let (slopes, (table, masking)) = (self.threads[j].slopes.as_ref()?, self.planes[j]?);
        Some(SlopedLookup {
            geometry: &slopes.geometry,
            table: &planes[table],
            masking: &planes[masking],
            weight: slopes.weight as f32,
            located: slopes.geometry.locate_f32::<L>(&slopes.fast_axes, wi, wo),
        })
    }

    /// [`TableLookup::terms_f32`] of the `L::WIDTH` pairs `wi`, `wo` into `terms` (one per
    /// pair, left as they are where Q = 0, so the caller passes zeros), the sloped tables'
    /// coordinates located for all lanes together.
    #[inline(always)]
    fn terms_lanes<L: Lanes>(
        &self,
        planes: &[Plane],
        wi: &[Vec3],
        wo: &[Vec3],
        terms: &mut [[f32; 3]],
    ) {
        // Each thread's steps are written out, and its planes found once per batch: closures
        // called twice were not inlined, and the calls, with the planes looked up per pair,
        // cost a fifth of a batch.
        let sloped = [
            self.locate_slopes::<L>(planes, 0, wi, wo),
            self.locate_slopes::<L>(planes, 1, wi, wo),
        ];
        // A batch requests every pair's table rows before interpolating any (one pair alone
        // gains nothing from it).
        if L::WIDTH > 1 {
            for s in sloped.iter().flatten() {
                s.geometry.prefetch_located(s.table, s.masking, &s.located);
            }
        }
        let points = [
            self.threads[0].samples.sums::<L>(wi, wo),
            self.threads[1].samples.sums::<L>(wi, wo),
        ];
        let a = [self.coverage[0] as f32, self.coverage[1] as f32];
        for (k, terms) in terms.iter_mut().enumerate() {
            let sums = [
                Self::thread_sums_f32(&points[0], sloped[0].as_ref(), k),
                Self::thread_sums_f32(&points[1], sloped[1].as_ref(), k),
            ];
            let q = self.gap as f32 * wo[k].z + a[0] * sums[0][2] + a[1] * sums[1][2];
            if q > 0.0 {
                *terms = [
                    (a[0] * sums[0][0] + a[1] * sums[1][0]) / q,
                    a[0] * sums[0][1] / q,
                    a[1] * sums[1][1] / q,
                ];
            }
        }
    }

    /// The constants of thread j that `cloth_split_threadJ` of `shaders/table/split_frame.wgsl`
    /// reads: its point masses (their count, and their sum at a pair over the (cos α_k,
    /// sin α_k, w_k) as literals), its sample material and axes, and its sloped table
    /// (whether it has one, its share w_c and its `ClothThreadTable`).
    fn thread_wgsl(&self, j: usize) -> String {
        let k = j + 1;
        let thread = &self.threads[j];
        let sloped = thread.slopes.as_ref().zip(self.planes[j]);
        let mut f = format!(
            "\n// Thread {k}: {} point masses, sloped share {}.\n",
            thread.points.len(),
            sloped.map_or(0.0, |(s, _)| s.weight)
        );
        // The point masses' sum written out: HLSL through naga and glslang takes no array
        // of constants, neither a module-scope one (two of one type read as a recursion) nor a
        // local one (zero-initialised by a constructor glslang refuses).
        let masses: Vec<String> = thread
            .points
            .iter()
            .map(|&(cos_a, sin_a, weight)| {
                format!(
                    "cloth_split_point(pair, material, {})",
                    wgsl_vec(&[cos_a, sin_a, weight])
                )
            })
            .collect();
        let masses = if masses.is_empty() {
            "vec3<f32>(0.0)".to_string()
        } else {
            masses.join("\n        + ")
        };
        let (t0, b) = crate::model::thread_axes(j);
        let _ = write!(
            f,
            "const CLOTH_SPLIT_POINT_COUNT{k} = {}u;\n\
             fn cloth_split_point_masses{k}(pair: ClothSamplePair, material: ClothSampleMaterial) \
             -> vec3<f32> {{\n    return {};\n}}\n\
             fn cloth_split_material{k}() -> ClothSampleMaterial {{\n    return {};\n}}\n\
             const CLOTH_SPLIT_T0_{k} = {};\n\
             const CLOTH_SPLIT_B{k} = {};\n\
             const CLOTH_SPLIT_SLOPED{k} = {};\n\
             const CLOTH_SPLIT_SLOPED_SHARE{k} = {};\n",
            thread.points.len(),
            masses,
            self.material_wgsl(j),
            wgsl_vec(&t0.to_array()),
            wgsl_vec(&b.to_array()),
            sloped.is_some(),
            wgsl_f32(sloped.map_or(0.0, |(s, _)| s.weight)),
        );
        match sloped {
            Some((slopes, (table, _))) => {
                f += &slopes
                    .geometry
                    .wgsl_constant(&format!("cloth_split_slopes{k}"), table);
            }
            None => {
                let _ = writeln!(
                    f,
                    "fn cloth_split_slopes{k}() -> ClothThreadTable {{\n    \
                     return cloth_split_no_table();\n}}"
                );
            }
        }
        f
    }

    /// The `ClothSampleMaterial` of thread `j` as a WGSL literal.
    fn material_wgsl(&self, j: usize) -> String {
        let samples = &self.threads[j].samples;
        format!(
            "ClothSampleMaterial({}, {}, {}, {}, {}, {})",
            wgsl_vec(&samples.lobes),
            wgsl_f32(samples.eta),
            wgsl_f32(samples.kd),
            if samples.no_interface { "1.0" } else { "0.0" },
            wgsl_f32(samples.k_u),
            wgsl_f32(samples.threshold),
        )
    }
}

/// The stored ratios of every texel of thread `index`'s sloped table (`fabric` holds only
/// its sloped segments), with the horizon rule of the module doc, in plane order.
fn bake_slopes(
    fabric: &Fabric,
    geometry: &ThreadGeometry,
    index: usize,
    progress: &dyn BakeProgress,
) -> Vec<f64> {
    let model = ThreadModel::new(fabric, index, Integration::Baking);
    // The ratios of a pair that is not a texel's own, at its own θd'.
    let ratios = |wi: DVec3, wo: DVec3| {
        thread::stored_ratios(&model, wi, wo, geometry.coordinates(wi, wo)[1])
    };
    let lift = |w: DVec3, z: f64| DVec3::new(w.x, w.y, z).normalize();
    thread::bake_thread_plane(geometry, progress, |wi, wo, theta_d| {
        if wi.z >= 0.0 && wo.z >= 0.0 {
            return thread::stored_ratios(&model, wi, wo, theta_d);
        }
        let above = ratios(lift(wi, wi.z.max(1e-6)), lift(wo, wo.z.max(1e-6)));
        let mirror = ratios(lift(wi, wi.z.abs()), lift(wo, wo.z.abs()));
        [0, 1].map(|c| (2.0 * above[c] - mirror[c]).max(0.0))
    })
}
