//! Table layouts and their lookup: where each texel's directions come from, and how a
//! lookup interpolates. The WGSL lookup (`shaders/`) follows exactly this description.
//!
//! Every layout stores the albedo-free factors of F (see [`crate::model::PatchTerms`]) in
//! three channels, `reflection`, `transmission1`, `transmission2`, as f16; the RGB value is
//! `reflection + A1·transmission1 + A2·transmission2` with the thread albedos A1, A2 the
//! table carries. Albedo therefore stays editable after baking.
//!
//! # Layout `grid4d` (the baseline)
//!
//! A 4D grid over (wi, wo), each direction through the hemi-octahedral map of
//! [`octahedral`] at N×N, N = `resolution`. Stored as one 2D image of N²×N² texels: texel
//! (x, y) holds wo at octahedral texel (x mod N, y mod N) and wi at (x div N, y div N), i.e.
//! N×N tiles over wi, each an N×N image over wo. Texel centres are at `(i + ½)/N`, so no
//! texel lies on the horizon. A lookup takes the octahedral coordinates `uv` of wi and wo,
//! the continuous texel coordinates `uv·N − ½`, and interpolates multilinearly between the
//! 16 surrounding texels, clamping indices to [0, N−1] (clamp-to-edge) on every axis. On a
//! GPU: a 2D array texture of N² layers (layer = wi texel x + N·y), bilinear filtering
//! within each layer over wo, and a manual bilinear blend of the 4 layers around wi. F is 0
//! when wi.z ≤ 0 or wo.z ≤ 0.

pub mod octahedral;

use glam::{DVec2, DVec3};
use serde::{Deserialize, Serialize};
use std::fmt;

/// The channels every table stores, in this order.
pub const CHANNELS: [&str; 3] = ["reflection", "transmission1", "transmission2"];

/// A table layout, selectable with `--layout`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Layout {
    /// Octahedral(wi) × octahedral(wo), N⁴ texels: the baseline.
    Grid4d,
}

impl Layout {
    pub const ALL: [Layout; 1] = [Layout::Grid4d];

    pub fn name(self) -> &'static str {
        match self {
            Layout::Grid4d => "grid4d",
        }
    }

    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|l| l.name() == name)
    }

    /// The resolution `bake` uses when none is given.
    pub fn default_resolution(self) -> u32 {
        match self {
            Layout::Grid4d => 16,
        }
    }

    /// Largest resolution accepted: bounds what a table file can make a reader allocate
    /// (64⁴ texels × 3 channels × 2 bytes = 96 MiB).
    pub fn max_resolution(self) -> u32 {
        match self {
            Layout::Grid4d => 64,
        }
    }

    /// The resolutions `--max-error` and memory budgets choose among, ascending.
    pub fn resolution_ladder(self) -> Vec<u32> {
        match self {
            Layout::Grid4d => vec![8, 12, 16, 24, 32, 48, 64],
        }
    }

    /// Bytes of f16 texel data of a table at `resolution`.
    pub fn byte_size(self, resolution: u32) -> usize {
        let (width, height) = self.image_size(resolution);
        width * height * CHANNELS.len() * 2
    }

    /// Width and height of the stored image at `resolution`.
    pub fn image_size(self, resolution: u32) -> (usize, usize) {
        match self {
            Layout::Grid4d => {
                let side = resolution as usize * resolution as usize;
                (side, side)
            }
        }
    }

    /// The direction pair whose value texel (x, y) stores.
    pub fn texel_directions(self, resolution: u32, x: usize, y: usize) -> (DVec3, DVec3) {
        match self {
            Layout::Grid4d => {
                let n = resolution as usize;
                let centre = |i: usize, j: usize| {
                    octahedral::decode(DVec2::new(i as f64 + 0.5, j as f64 + 0.5) / n as f64)
                };
                (centre(x / n, y / n), centre(x % n, y % n))
            }
        }
    }
}

impl fmt::Display for Layout {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// One axis of a linear interpolation with clamp-to-edge: the two texel indices and the
/// weight of the second, for continuous texel coordinate `x` (texel i's centre at i).
#[inline]
fn axis(x: f64, n: usize) -> (usize, usize, f64) {
    let floor = x.floor();
    let frac = x - floor;
    let last = n as i64 - 1;
    let i0 = (floor as i64).clamp(0, last) as usize;
    let i1 = (floor as i64 + 1).clamp(0, last) as usize;
    (i0, i1, frac)
}

/// A baked table: the layout, its resolution, the thread albedos and the texels (values
/// exactly representable in f16, as stored).
#[derive(Clone, Debug, PartialEq)]
pub struct Table {
    pub layout: Layout,
    pub resolution: u32,
    /// RGB albedo A of thread 1 and thread 2.
    pub albedo: [[f32; 3]; 2],
    width: usize,
    texels: Vec<[f32; 3]>,
}

impl Table {
    /// Wraps texels laid out row by row as `layout` at `resolution` prescribes.
    ///
    /// # Panics
    /// If the texel count does not match the layout's image size (a programming error:
    /// file readers check sizes before calling this).
    pub fn new(
        layout: Layout,
        resolution: u32,
        albedo: [[f32; 3]; 2],
        texels: Vec<[f32; 3]>,
    ) -> Self {
        let (width, height) = layout.image_size(resolution);
        assert_eq!(
            texels.len(),
            width * height,
            "texel count does not match the layout"
        );
        Self {
            layout,
            resolution,
            albedo,
            width,
            texels,
        }
    }

    pub fn image_size(&self) -> (usize, usize) {
        self.layout.image_size(self.resolution)
    }

    /// The texels, row by row.
    pub fn texels(&self) -> &[[f32; 3]] {
        &self.texels
    }

    /// The stored terms at texel (x, y).
    pub fn texel(&self, x: usize, y: usize) -> [f32; 3] {
        self.texels[y * self.width + x]
    }

    /// Bytes of texel data as stored (f16 channels).
    pub fn byte_size(&self) -> usize {
        self.layout.byte_size(self.resolution)
    }

    /// The interpolated terms (reflection, transmission1, transmission2) for unit `wi`,
    /// `wo`, exactly as the GPU lookup computes them (see the module documentation).
    pub fn lookup_terms(&self, wi: DVec3, wo: DVec3) -> [f64; 3] {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return [0.0; 3];
        }
        match self.layout {
            Layout::Grid4d => {
                let n = self.resolution as usize;
                let ci = octahedral::encode(wi) * n as f64 - 0.5;
                let co = octahedral::encode(wo) * n as f64 - 0.5;
                let axes = [axis(ci.x, n), axis(ci.y, n), axis(co.x, n), axis(co.y, n)];
                let mut sum = [0.0f64; 3];
                for corner in 0..16 {
                    let mut weight = 1.0;
                    let mut index = [0usize; 4];
                    for (a, &(i0, i1, frac)) in axes.iter().enumerate() {
                        let upper = corner >> a & 1 == 1;
                        index[a] = if upper { i1 } else { i0 };
                        weight *= if upper { frac } else { 1.0 - frac };
                    }
                    let texel = self.texel(index[0] * n + index[2], index[1] * n + index[3]);
                    for c in 0..3 {
                        sum[c] += weight * texel[c] as f64;
                    }
                }
                sum
            }
        }
    }

    /// The table's estimate of `F(wi, wo)` (RGB).
    pub fn lookup(&self, wi: DVec3, wo: DVec3) -> DVec3 {
        let [r, t1, t2] = self.lookup_terms(wi, wo);
        let a1 = DVec3::from_array(self.albedo[0].map(f64::from));
        let a2 = DVec3::from_array(self.albedo[1].map(f64::from));
        DVec3::splat(r) + a1 * t1 + a2 * t2
    }
}
