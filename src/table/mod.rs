//! Table layouts and their lookup: which direction pairs each texel holds, and how a lookup
//! interpolates. The WGSL lookup follows exactly these descriptions.
//!
//! Every layout stores albedo-free quantities, so that the RGB value is
//! `reflection + A1·transmission1 + A2·transmission2` with the thread albedos A1, A2 of the
//! fabric the table records: albedo stays editable after baking. A table is a list of
//! planes (one EXR layer each) of f16 channels.
//!
//! - [`grid4d`]: the baseline, octahedral(wi) × octahedral(wo).
//! - [`thread_frame`]: per thread, coordinates aligned with its specular resonance (the
//!   default).

pub mod axis;
pub mod grid4d;
pub mod octahedral;
pub mod thread_frame;

use crate::model::Fabric;
use glam::DVec3;
use serde::{Deserialize, Serialize};
use std::fmt;

/// A table layout, selectable with `--layout`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Layout {
    /// Octahedral(wi) × octahedral(wo), N⁴ texels: the baseline.
    Grid4d,
    /// Per-thread resonant frame plus ⟨P⟩ tables.
    ThreadFrame,
}

impl Layout {
    pub const ALL: [Layout; 2] = [Layout::Grid4d, Layout::ThreadFrame];

    pub fn name(self) -> &'static str {
        match self {
            Layout::Grid4d => "grid4d",
            Layout::ThreadFrame => "thread_frame",
        }
    }

    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|l| l.name() == name)
    }

    /// The resolution `bake` uses when none is given.
    pub fn default_resolution(self) -> u32 {
        match self {
            Layout::Grid4d => 16,
            Layout::ThreadFrame => 48,
        }
    }

    /// Largest resolution accepted: bounds what a table file can make a reader allocate
    /// (grid4d: 64⁴ texels × 3 channels × 2 bytes = 96 MiB; thread_frame at 96: at most
    /// 32 βH slices of 96 × 28 × 80 texels, 26 MiB).
    pub fn max_resolution(self) -> u32 {
        match self {
            Layout::Grid4d => 64,
            Layout::ThreadFrame => 96,
        }
    }

    /// The resolutions `--max-error` and memory budgets choose among, ascending.
    pub fn resolution_ladder(self) -> Vec<u32> {
        match self {
            Layout::Grid4d => vec![8, 12, 16, 24, 32, 48, 64],
            Layout::ThreadFrame => vec![16, 24, 32, 40, 48],
        }
    }

    /// The planes of a table of `fabric` at `resolution`.
    pub fn plane_specs(self, fabric: &Fabric, resolution: u32) -> Vec<PlaneSpec> {
        match self {
            Layout::Grid4d => vec![grid4d::spec(resolution)],
            Layout::ThreadFrame => thread_frame::Geometry::new(fabric, resolution).specs(),
        }
    }

    /// Bytes of f16 texel data of a table of `fabric` at `resolution`.
    pub fn byte_size(self, fabric: &Fabric, resolution: u32) -> usize {
        self.plane_specs(fabric, resolution)
            .iter()
            .map(PlaneSpec::byte_size)
            .sum()
    }
}

impl fmt::Display for Layout {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
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
}

/// How a table's planes are looked up.
#[derive(Clone, Debug, PartialEq)]
pub enum Geometry {
    Grid4d,
    ThreadFrame(Box<thread_frame::Geometry>),
}

/// A baked table: layout, resolution, the fabric it was baked from, and its planes.
#[derive(Clone, Debug, PartialEq)]
pub struct Table {
    pub layout: Layout,
    pub resolution: u32,
    pub fabric: Fabric,
    planes: Vec<Plane>,
    geometry: Geometry,
    albedo: [DVec3; 2],
}

impl Table {
    /// Assembles a table, checking that the planes have exactly the layout's shapes.
    pub fn new(
        layout: Layout,
        resolution: u32,
        fabric: &Fabric,
        planes: Vec<Plane>,
    ) -> Result<Self, String> {
        let geometry = match layout {
            Layout::Grid4d => Geometry::Grid4d,
            Layout::ThreadFrame => {
                Geometry::ThreadFrame(Box::new(thread_frame::Geometry::new(fabric, resolution)))
            }
        };
        let specs = layout.plane_specs(fabric, resolution);
        let shapes: Vec<&PlaneSpec> = planes.iter().map(|p| &p.spec).collect();
        if shapes != specs.iter().collect::<Vec<_>>() {
            return Err(format!(
                "planes {shapes:?} do not match the layout's {specs:?}"
            ));
        }
        if let Some(p) = planes
            .iter()
            .find(|p| p.data.len() != p.spec.texel_count() * p.spec.channels.len())
        {
            return Err(format!(
                "plane {} holds {} values, expected {}",
                p.spec.name,
                p.data.len(),
                p.spec.texel_count() * p.spec.channels.len()
            ));
        }
        let albedo = fabric.threads().map(|t| DVec3::from_array(t.albedo_rgb()));
        Ok(Self {
            layout,
            resolution,
            fabric: fabric.clone(),
            planes,
            geometry,
            albedo,
        })
    }

    pub fn planes(&self) -> &[Plane] {
        &self.planes
    }

    pub fn geometry(&self) -> &Geometry {
        &self.geometry
    }

    /// Bytes of texel data as stored (f16 channels).
    pub fn byte_size(&self) -> usize {
        self.planes.iter().map(|p| p.spec.byte_size()).sum()
    }

    /// The interpolated terms (reflection, transmission1, transmission2), divided by Q, for
    /// unit `wi`, `wo`, exactly as the GPU lookup computes them. 0 below the horizon.
    pub fn lookup_terms(&self, wi: DVec3, wo: DVec3) -> [f64; 3] {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return [0.0; 3];
        }
        match &self.geometry {
            Geometry::Grid4d => grid4d::lookup_terms(&self.planes[0], self.resolution, wi, wo),
            Geometry::ThreadFrame(geometry) => geometry.lookup_terms(&self.planes, wi, wo),
        }
    }

    /// The table's estimate of `F(wi, wo)` (RGB).
    pub fn lookup(&self, wi: DVec3, wo: DVec3) -> DVec3 {
        let [r, t1, t2] = self.lookup_terms(wi, wo);
        DVec3::splat(r) + self.albedo[0] * t1 + self.albedo[1] * t2
    }
}
