//! Table layouts and their lookup: which direction pairs each texel holds, and how a lookup
//! interpolates. The WGSL lookup of each layout follows exactly its module's description.
//!
//! Every layout stores albedo-free quantities, so that the RGB value is
//! `reflection + A1·transmission1 + A2·transmission2` with the thread albedos A1, A2 of the
//! fabric the table records: albedo stays editable after baking. A table is a list of
//! planes (one EXR layer each) of f16 channels.
//!
//! A layout is one unit: a module implementing [`LayoutUnit`] (planes and axes, bake, the
//! CPU lookups in f64 and f32, the GPU textures and the generated WGSL constants), its WGSL
//! file under `shaders/`, and one line in [`Layout::ALL`]. `bake`, `check`, `eval`, `wgsl`,
//! `render`, `view` and `report` handle every registered layout through that trait.
//!
//! - [`thread_frame`]: per thread, coordinates aligned with its specular resonance (the
//!   default).
//! - [`split_frame`]: each thread's point masses evaluated exactly, its sloped segments
//!   tabulated as thread_frame tabulates a thread.
//! - [`grid4d`]: the baseline, octahedral(wi) × octahedral(wo).

pub mod axis;
pub mod bindings;
pub mod fast_math;
pub mod gpu_bound;
pub mod grid4d;
pub mod octahedral;
pub mod point_samples;
pub mod prefilter;
pub mod progress;
pub mod shader_language;
pub mod split_frame;
pub mod thread;
pub mod thread_frame;
pub mod wgsl;

use crate::model::Fabric;
use glam::{DVec3, Vec3};
use half::f16;
use progress::BakeProgress;
use serde::{Deserialize, Deserializer, Serialize, Serializer};
use std::any::Any;
use std::fmt;
use std::sync::Arc;

/// One table layout: everything that depends on how texels are arranged.
pub trait LayoutUnit: Sync {
    /// The name used by `--layout`, in files and in reports.
    fn name(&self) -> &'static str;
    /// The resolution `bake` uses when none is given.
    fn default_resolution(&self) -> u32;
    /// Largest resolution accepted: bounds what a table file can make a reader allocate.
    fn max_resolution(&self) -> u32;
    /// The resolutions `--max-error`, memory budgets and the full report choose among,
    /// ascending.
    fn resolution_ladder(&self) -> &'static [u32];
    /// The resolutions the report measures (`quick`: its quick preset).
    fn report_resolutions(&self, quick: bool) -> &'static [u32];
    /// How the texels are integrated, as recorded in the table file.
    fn integration(&self) -> &'static str;
    /// The planes of a table of `fabric` at `resolution`.
    fn plane_specs(&self, fabric: &Fabric, resolution: u32) -> Vec<PlaneSpec>;
    /// Rows of work a bake reports through [`BakeProgress::row_done`].
    fn bake_rows(&self, fabric: &Fabric, resolution: u32) -> u64;
    /// The values of every plane in the order of [`Self::plane_specs`] (channel-interleaved,
    /// row by row, before rounding to f16). `progress` hears of each finished row; once it
    /// says the bake is cancelled, the remaining rows are skipped and the values are not
    /// a table's (the caller discards them).
    fn bake(&self, fabric: &Fabric, resolution: u32, progress: &dyn BakeProgress) -> Vec<Vec<f64>>;
    /// The lookup of a table of `fabric` at `resolution` (its geometry; texels stay in the
    /// planes).
    fn lookup(&self, fabric: &Fabric, resolution: u32) -> Arc<dyn TableLookup>;
    /// The layout's WGSL file, `shaders/table/<name>.wgsl` under the module name
    /// `table/<name>`: it defines `cloth_<name>_brdf(wi, wo)` over the shared lookup files
    /// and the generated constants, and the lookup's composer adds it
    /// ([`crate::shader::Composer::unit_file`]).
    fn wgsl_file(&self) -> &'static crate::shader::ShaderFile;
}

/// The lanes of a batch lookup's coordinates ([`fast_math::Lanes`]): eight f32, one AVX
/// register (two SSE ones).
pub type BatchLanes = wide::f32x8;

/// Pairs per unit of work of [`Table::lookup_batch`], one per lane of [`BatchLanes`].
pub const BATCH_LANES: usize = <BatchLanes as fast_math::Lanes>::WIDTH;

/// The lookup of one table: the geometry its layout derives from fabric and resolution.
/// Every method takes the table's planes.
pub trait TableLookup: Send + Sync + fmt::Debug + Any {
    /// The interpolated terms (reflection, transmission1, transmission2), divided by Q, for
    /// unit `wi`, `wo` above the horizon, in f64: the reference that the f32 and GPU
    /// lookups follow.
    fn terms(&self, planes: &[Plane], wi: DVec3, wo: DVec3) -> [f64; 3];
    /// The same terms in f32 with fast approximations of the transcendental functions (see
    /// [`fast_math`] for their error bounds): the lookup to use on a CPU.
    fn terms_f32(&self, planes: &[Plane], wi: Vec3, wo: Vec3) -> [f32; 3];
    /// [`Self::terms_f32`] of [`BATCH_LANES`] pairs, bit for bit the same values: the batch
    /// entry point's unit of work, which a layout overrides where computing the pairs'
    /// coordinates together pays (the default takes them one by one).
    fn terms_f32_lanes(
        &self,
        planes: &[Plane],
        wi: &[Vec3; BATCH_LANES],
        wo: &[Vec3; BATCH_LANES],
    ) -> [[f32; 3]; BATCH_LANES] {
        std::array::from_fn(|k| self.terms_f32(planes, wi[k], wo[k]))
    }
    /// The layout's part of the generated module `table_constants`: the constants and
    /// functions its WGSL file expects, as literals.
    fn wgsl_constants(&self) -> String;
    /// The textures the WGSL file binds, built from the planes.
    fn textures(&self, planes: &[Plane]) -> Vec<TextureData>;
    /// How far the layout's WGSL lookup may be from the f64 lookup `cpu` (= F by
    /// [`Self::terms`] and the thread albedos `albedo`) at a pair above the horizon, per
    /// channel ([`gpu_bound`] derives the sources). Every layout declares its own; the GPU
    /// test of every registered layout asserts it.
    fn gpu_error_bound(
        &self,
        planes: &[Plane],
        albedo: [DVec3; 2],
        wi: DVec3,
        wo: DVec3,
        cpu: DVec3,
    ) -> gpu_bound::GpuErrorBound;
    /// Whether [`Self::terms_f32`] cannot follow [`Self::terms`] at `wi`, `wo` (above the
    /// horizon) because the lookup divides there by a quantity that f32 cannot resolve: a
    /// normalisation Q positive but below 1e-6 (F a 0/0 limit that f32 weights round to the
    /// model's value for Q = 0), or a tabulated reflection divided by a cos²θd' below its
    /// 1e-8 floor (rounding of the stored value amplified 1e8 times). At such pairs the f32
    /// lookup is held only to finite, non-negative values; the test of every registered
    /// layout holds it to the f64 lookup everywhere else. Every layout declares its own.
    fn f32_exempt(&self, planes: &[Plane], wi: DVec3, wo: DVec3) -> bool;
    fn as_any(&self) -> &dyn Any;
}

/// A texture's contents before upload: its binding (one of [`bindings::TEXTURE_SLOTS`], as
/// the layout's WGSL file declares it), dimension (the slot's), size in texels (width, height,
/// depth or layers) and f16 texels, channel-interleaved, x fastest, then y, then z.
#[derive(Clone, Debug, PartialEq)]
pub struct TextureData {
    pub name: String,
    pub binding: u32,
    /// A 3D texture (else a 2D array texture over the depth).
    pub three_d: bool,
    pub size: [u32; 3],
    pub channels: u32,
    pub texels: Vec<f16>,
}

/// A registered table layout, selectable with `--layout`; compared, hashed and serialised
/// by name.
#[derive(Clone, Copy)]
pub struct Layout(&'static dyn LayoutUnit);

impl Layout {
    pub const THREAD_FRAME: Layout = Layout(&thread_frame::ThreadFrame);
    pub const GRID4D: Layout = Layout(&grid4d::Grid4d);
    pub const SPLIT_FRAME: Layout = Layout(&split_frame::SplitFrame);
    /// The registry: every layout, the default first.
    pub const ALL: &'static [Layout] = &[Layout::SPLIT_FRAME, Layout::THREAD_FRAME, Layout::GRID4D];
    /// The layout `bake` uses when none is given.
    pub const DEFAULT: Layout = Layout::SPLIT_FRAME;

    pub fn unit(self) -> &'static dyn LayoutUnit {
        self.0
    }

    pub fn name(self) -> &'static str {
        self.0.name()
    }

    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.iter().copied().find(|l| l.name() == name)
    }

    pub fn default_resolution(self) -> u32 {
        self.0.default_resolution()
    }

    pub fn max_resolution(self) -> u32 {
        self.0.max_resolution()
    }

    pub fn resolution_ladder(self) -> Vec<u32> {
        self.0.resolution_ladder().to_vec()
    }

    pub fn plane_specs(self, fabric: &Fabric, resolution: u32) -> Vec<PlaneSpec> {
        self.0.plane_specs(fabric, resolution)
    }

    /// Bytes of f16 texel data of a table of `fabric` at `resolution`.
    pub fn byte_size(self, fabric: &Fabric, resolution: u32) -> usize {
        self.plane_specs(fabric, resolution)
            .iter()
            .map(PlaneSpec::byte_size)
            .sum()
    }
}

impl PartialEq for Layout {
    fn eq(&self, other: &Self) -> bool {
        self.name() == other.name()
    }
}

impl Eq for Layout {}

impl std::hash::Hash for Layout {
    fn hash<H: std::hash::Hasher>(&self, state: &mut H) {
        self.name().hash(state)
    }
}

impl fmt::Display for Layout {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl fmt::Debug for Layout {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl Serialize for Layout {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.serialize_str(self.name())
    }
}

impl<'de> Deserialize<'de> for Layout {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let name = String::deserialize(deserializer)?;
        Layout::from_name(&name).ok_or_else(|| {
            let known: Vec<&str> = Layout::ALL.iter().map(|l| l.name()).collect();
            serde::de::Error::custom(format!(
                "unknown layout '{name}' (known: {})",
                known.join(", ")
            ))
        })
    }
}

/// The 16 corners of a 4D multilinear interpolation: for each axis `(i0, i1, weight of
/// i1)`, yields the corner's indices and its weight (the product over axes).
pub fn quadrilinear_corners(
    axes: [(usize, usize, f64); 4],
) -> impl Iterator<Item = ([usize; 4], f64)> {
    (0..16).map(move |corner| {
        let mut weight = 1.0;
        let index = std::array::from_fn(|a| {
            let upper = corner >> a & 1 == 1;
            weight *= if upper { axes[a].2 } else { 1.0 - axes[a].2 };
            if upper { axes[a].1 } else { axes[a].0 }
        });
        (index, weight)
    })
}

/// The shape of one plane: its name (the EXR layer name), size and channel names.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PlaneSpec {
    pub name: String,
    pub width: usize,
    pub height: usize,
    pub channels: Vec<&'static str>,
}

impl PlaneSpec {
    pub fn new(name: String, width: usize, height: usize, channels: &[&'static str]) -> Self {
        Self {
            name,
            width,
            height,
            channels: channels.to_vec(),
        }
    }

    pub fn texel_count(&self) -> usize {
        self.width * self.height
    }

    pub fn byte_size(&self) -> usize {
        self.texel_count() * self.channels.len() * 2
    }
}

/// One plane's texels: channel-interleaved, row by row, values exactly representable in f16.
#[derive(Clone, Debug, PartialEq)]
pub struct Plane {
    pub spec: PlaneSpec,
    pub data: Vec<f32>,
}

impl Plane {
    /// The channels of texel (x, y).
    pub fn texel(&self, x: usize, y: usize) -> &[f32] {
        let c = self.spec.channels.len();
        let start = (y * self.spec.width + x) * c;
        &self.data[start..start + c]
    }

    /// Asks the CPU to start loading the cache line that holds `data[at]`, so that a batch
    /// lookup can request every corner of its pairs before it interpolates any of them.
    /// A table of a few MiB is read at random places that miss the core's caches; a pair's
    /// interpolation waits on them one dependent step at a time, while prefetches for a
    /// whole batch overlap their waits. Only a hint: no effect on any value, and nothing
    /// where `at` is out of range or the target has no stable prefetch instruction.
    #[inline(always)]
    pub fn prefetch(&self, at: usize) {
        #[cfg(target_arch = "x86_64")]
        if let Some(value) = self.data.get(at) {
            use std::arch::x86_64::{_MM_HINT_T0, _mm_prefetch};
            // SAFETY: PREFETCHT0 (SSE, part of the x86_64 baseline) never faults and writes
            // nothing; the pointer is a live element of `data`.
            unsafe { _mm_prefetch::<_MM_HINT_T0>(std::ptr::from_ref(value).cast()) }
        }
        #[cfg(not(target_arch = "x86_64"))]
        let _ = at;
    }
}

/// A baked table: layout, resolution, the fabric it was baked from, and its planes.
#[derive(Clone)]
pub struct Table {
    pub layout: Layout,
    pub resolution: u32,
    pub fabric: Fabric,
    planes: Vec<Plane>,
    lookup: Arc<dyn TableLookup>,
    albedo: [DVec3; 2],
}

impl fmt::Debug for Table {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Table")
            .field("layout", &self.layout)
            .field("resolution", &self.resolution)
            .field("fabric", &self.fabric.name)
            .field("bytes", &self.byte_size())
            .finish()
    }
}

/// Tables are equal when layout, resolution, fabric and every texel are (the lookup
/// geometry follows from these).
impl PartialEq for Table {
    fn eq(&self, other: &Self) -> bool {
        self.layout == other.layout
            && self.resolution == other.resolution
            && self.fabric == other.fabric
            && self.planes == other.planes
    }
}

/// Planes that are not the ones a layout's table holds.
#[derive(Debug, thiserror::Error)]
pub enum PlaneShapeError {
    #[error("planes {found:?} do not match the layout's {expected:?}")]
    Shapes {
        found: Vec<PlaneSpec>,
        expected: Vec<PlaneSpec>,
    },
    #[error("plane {plane} holds {found} values, expected {expected}")]
    Values {
        plane: String,
        found: usize,
        expected: usize,
    },
}

impl Table {
    /// Assembles a table, checking that the planes have exactly the layout's shapes.
    pub fn new(
        layout: Layout,
        resolution: u32,
        fabric: &Fabric,
        planes: Vec<Plane>,
    ) -> Result<Self, PlaneShapeError> {
        let expected = layout.plane_specs(fabric, resolution);
        if !planes.iter().map(|p| &p.spec).eq(expected.iter()) {
            return Err(PlaneShapeError::Shapes {
                found: planes.iter().map(|p| p.spec.clone()).collect(),
                expected,
            });
        }
        if let Some(p) = planes
            .iter()
            .find(|p| p.data.len() != p.spec.texel_count() * p.spec.channels.len())
        {
            return Err(PlaneShapeError::Values {
                plane: p.spec.name.clone(),
                found: p.data.len(),
                expected: p.spec.texel_count() * p.spec.channels.len(),
            });
        }
        let albedo = fabric.threads().map(|t| DVec3::from_array(t.albedo_rgb()));
        Ok(Self {
            layout,
            resolution,
            fabric: fabric.clone(),
            planes,
            lookup: layout.unit().lookup(fabric, resolution),
            albedo,
        })
    }

    pub fn planes(&self) -> &[Plane] {
        &self.planes
    }

    /// The layout's lookup geometry of this table.
    pub fn geometry(&self) -> &dyn TableLookup {
        self.lookup.as_ref()
    }

    /// The lookup geometry as the layout's own type `G`, if it is one.
    pub fn geometry_as<G: TableLookup>(&self) -> Option<&G> {
        self.lookup.as_any().downcast_ref()
    }

    /// How far this table's WGSL lookup may be from [`Table::lookup`]'s `cpu` at a pair
    /// ([`TableLookup::gpu_error_bound`]; below the horizon, where both are 0, the floor).
    pub fn gpu_error_bound(&self, wi: DVec3, wo: DVec3, cpu: DVec3) -> gpu_bound::GpuErrorBound {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return gpu_bound::GpuErrorBound {
                per_channel: gpu_bound::floor(cpu),
                on_fold: false,
            };
        }
        self.lookup
            .gpu_error_bound(&self.planes, self.albedo, wi, wo, cpu)
    }

    /// Whether the f32 lookup is exempt from following the f64 lookup at a pair
    /// ([`TableLookup::f32_exempt`]; never below the horizon, where both are 0).
    pub fn f32_exempt(&self, wi: DVec3, wo: DVec3) -> bool {
        wi.z > 0.0 && wo.z > 0.0 && self.lookup.f32_exempt(&self.planes, wi, wo)
    }

    /// Bytes of texel data as stored (f16 channels).
    pub fn byte_size(&self) -> usize {
        self.planes.iter().map(|p| p.spec.byte_size()).sum()
    }

    /// The interpolated terms (reflection, transmission1, transmission2), divided by Q, for
    /// unit `wi`, `wo`, in f64 (the reference the f32 and GPU lookups follow). 0 below the
    /// horizon.
    pub fn lookup_terms(&self, wi: DVec3, wo: DVec3) -> [f64; 3] {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return [0.0; 3];
        }
        self.lookup.terms(&self.planes, wi, wo)
    }

    /// The table's estimate of `F(wi, wo)` (RGB), in f64.
    pub fn lookup(&self, wi: DVec3, wo: DVec3) -> DVec3 {
        let [r, t1, t2] = self.lookup_terms(wi, wo);
        DVec3::splat(r) + self.albedo[0] * t1 + self.albedo[1] * t2
    }

    /// The table's estimate of `F(wi, wo)` (RGB) by the f32 lookup
    /// ([`TableLookup::terms_f32`]): the fast CPU path.
    #[inline]
    pub fn lookup_f32(&self, wi: Vec3, wo: Vec3) -> Vec3 {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return Vec3::ZERO;
        }
        self.combine_f32(self.lookup.terms_f32(&self.planes, wi, wo))
    }

    /// [`Self::lookup_f32`] of every pair of `pairs`, into `out` (same length), bit for bit
    /// the same values: the batch entry point for callers shading many pairs, which computes
    /// [`BATCH_LANES`] pairs' table coordinates together (in SIMD registers where the
    /// layout supports it, see [`TableLookup::terms_f32_lanes`]).
    pub fn lookup_batch(&self, pairs: &[(Vec3, Vec3)], out: &mut [Vec3]) {
        assert_eq!(pairs.len(), out.len(), "one output per pair");
        let mut chunks = pairs.chunks_exact(BATCH_LANES);
        let mut outs = out.chunks_exact_mut(BATCH_LANES);
        for (chunk, f) in (&mut chunks).zip(&mut outs) {
            let (mut wi, mut wo) = ([Vec3::ZERO; BATCH_LANES], [Vec3::ZERO; BATCH_LANES]);
            for (k, &(i, o)) in chunk.iter().enumerate() {
                (wi[k], wo[k]) = (i, o);
            }
            let terms = self.lookup.terms_f32_lanes(&self.planes, &wi, &wo);
            for k in 0..BATCH_LANES {
                f[k] = if wi[k].z <= 0.0 || wo[k].z <= 0.0 {
                    Vec3::ZERO
                } else {
                    self.combine_f32(terms[k])
                };
            }
        }
        for (&(wi, wo), f) in chunks.remainder().iter().zip(outs.into_remainder()) {
            *f = self.lookup_f32(wi, wo);
        }
    }

    /// F from the terms (reflection, transmission1, transmission2) with the albedos.
    #[inline]
    fn combine_f32(&self, [r, t1, t2]: [f32; 3]) -> Vec3 {
        Vec3::splat(r) + self.albedo[0].as_vec3() * t1 + self.albedo[1].as_vec3() * t2
    }
}

/// A table of `fabric` with zero texels at `resolution`, for tests of what depends on the
/// geometry only (the generated WGSL, its bindings).
#[cfg(test)]
pub(crate) fn zero_table(fabric: &Fabric, layout: Layout, resolution: u32) -> Table {
    let planes = layout
        .plane_specs(fabric, resolution)
        .into_iter()
        .map(|spec| Plane {
            data: vec![0.0; spec.texel_count() * spec.channels.len()],
            spec,
        })
        .collect();
    Table::new(layout, resolution, fabric, planes).expect("table")
}
