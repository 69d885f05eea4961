//! Importance sampling of a fabric: directions `wi` drawn with a density close to
//! `F(wi, wo)` (docs/model.md#the-patch-transfer-f) for a given `wo`, with that density `pdf(wi | wo)` (per unit solid
//! angle) evaluable for any pair, on the CPU ([`Sampler`]) and in WGSL
//! (`shaders/sampling/fabric_sampler.wgsl`, the same layout, see [`Sampler::wgsl_constants`]).
//!
//! The sampler is tabulated, as Dupuy and Jakob (2018) tabulate measured BRDFs: the model's
//! lobes are too many and too narrow (satin's γs = 2.5°, masking kinks, two threads with
//! several tangent segments each) for a closed-form inversion of every lobe, and a table gives
//! an exact, cheap pdf. It is built from any evaluation of F (the resonant quadrature by
//! default, or a baked table's lookup), so it never has to match F exactly: a sample's
//! weight is F(wi, wo)/pdf with F evaluated by whoever asks.
//!
//! ## Layout (one place; the WGSL mirrors it)
//!
//! - **Nodes over wo.** `wo` is placed on a grid of `ELEVATION_NODES` elevations (node i at
//!   90°·(i/(E − 1))^1.5, dense towards the horizon where the patch's normalisation changes
//!   F fastest; node 0 built at [`GRAZING_NODE_DEG`] because F is 0 at exactly 0°) by
//!   `AZIMUTH_NODES` azimuths (node j at j·360°/A, azimuth measured from thread 1, x,
//!   towards thread 2, y; periodic). The density for a given `wo` is the bilinear mixture of
//!   its four surrounding nodes' densities, so it is continuous in `wo` (no seams where a
//!   renderer's `wo` crosses a node) and still exact: the mixture is sampled by picking a
//!   node with its bilinear weight.
//! - **Cells over wi.** Each node holds a piecewise-constant density over `ROWS` elevation
//!   bands of equal angle (row r spans elevations r·90°/R to (r + 1)·90°/R, so the bands near
//!   the normal are not a single cap as equal-area bands would be) by `COLUMNS` azimuth
//!   sectors. A cell's probability is proportional to its integral of the mean RGB of F,
//!   estimated from two points on the cell's diagonal; inside a cell wi is uniform in solid
//!   angle (uniform in z = sin(elevation) and in azimuth), so the cell's density is its
//!   probability over its solid angle (z_{r+1} − z_r)·2π/C.
//! - **Data.** Per node `n = i·A + j`, `NODE_STRIDE` f32: the marginal CDF over rows
//!   (R + 1 values, 0 first, exactly 1 last), then per row the conditional CDF over columns
//!   (C + 1 values each). Probabilities are differences of stored neighbours, in sampling and
//!   in the pdf alike, so the f32 rounding of the CDFs cannot make them disagree.
//! - **A cosine share.** With probability [`COSINE_SHARE`] wi is drawn from the cosine
//!   density cos θ/π restricted to F's support for `wo` ([`support`]: the whole hemisphere
//!   for every built-in fabric but velvet) instead: every direction where F can be non-zero
//!   keeps a density of at least COSINE_SHARE·cos θ/π, so a lobe the cell's two points
//!   missed costs variance, never bias.
//! - **The support.** The density is 0 wherever F is 0 by the model's geometry: a table
//!   draw outside the support is rejected (its cell straddles the support's edge, or a
//!   neighbouring node's support differs), and the pdf is 0 there, so the density integrates
//!   to the accepted fraction, 1 less that lost part of the table's share.
//! - **Data.** After the nodes, at `SUPPORT_BASE`: 1 if the support is restricted (else 0),
//!   the two threads' interval counts n1 and n2, then their curve intervals (start, end) in
//!   radians, thread 1's first.
//!
//! The three uniform numbers: u3 picks cosine or table, then (rescaled) the node; u1 the row
//! and then z inside it; u2 the column and then the azimuth inside it.

mod albedo;
pub mod environment;
mod support;
pub mod taps;

pub use albedo::{
    ALBEDO_AZIMUTHS, ALBEDO_ELEVATIONS_DEG, ALBEDO_MAP_AZIMUTHS, ALBEDO_MAP_ELEVATIONS, AlbedoMap,
    AlbedoRow, albedo_curve, describe_albedo, directional_albedo, hammersley,
};
pub use environment::{EnvironmentSampler, SAMPLER_MAX_WIDTH};
pub use taps::SampleTaps;

use crate::model::{Fabric, Integration, Patch, ResonantNodes};
use glam::DVec3;
use rayon::prelude::*;
use std::f64::consts::{FRAC_PI_2, TAU};
use support::{Lunes, Support};

/// Elevation nodes over wo (0° to 90°).
pub const ELEVATION_NODES: usize = 17;
/// Azimuth nodes over wo (periodic).
pub const AZIMUTH_NODES: usize = 32;
/// Elevation bands of a node's density over wi.
pub const ROWS: usize = 32;
/// Azimuth sectors of a node's density over wi.
pub const COLUMNS: usize = 64;
/// f32 values per node: the row CDF and one column CDF per row.
pub const NODE_STRIDE: usize = (ROWS + 1) + ROWS * (COLUMNS + 1);
/// Nodes over wo.
pub const NODES: usize = ELEVATION_NODES * AZIMUTH_NODES;
/// Where the support's block starts in [`Sampler::data`], after the nodes.
pub const SUPPORT_BASE: usize = NODES * NODE_STRIDE;
/// The elevation at which node 0 (nominally 0°) is built: F vanishes at exactly 0°.
pub const GRAZING_NODE_DEG: f64 = 0.1;
/// The probability of drawing from the cosine density instead of the table.
pub const COSINE_SHARE: f64 = 0.1;
/// Resonant node counts of the evaluation the built-in sampler is built from: the density
/// only has to follow F's shape, which coarser nodes than the default keep (their error against
/// the direct rule: report/REPORT.md).
pub const BUILD_NODES: ResonantNodes = ResonantNodes {
    surface: 3,
    volume: 2,
    base: 2,
};

/// A sampled direction and its density.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample {
    /// Unit, in the patch frame, above the horizon.
    pub wi: DVec3,
    /// `pdf(wi | wo)` per unit solid angle.
    pub pdf: f64,
}

/// The tabulated sampler of one fabric (see the module doc for the layout).
#[derive(Clone, Debug, PartialEq)]
pub struct Sampler {
    data: Vec<f32>,
    support: Support,
}

/// z = sin(elevation) at the lower edge of row `r` (r = ROWS: the normal).
fn row_z(r: usize) -> f64 {
    // Computed once: the taps' build asks for row boundaries hundreds of millions of times.
    static ROW_Z: std::sync::LazyLock<[f64; ROWS + 1]> = std::sync::LazyLock::new(|| {
        std::array::from_fn(|r| (r as f64 * FRAC_PI_2 / ROWS as f64).sin())
    });
    ROW_Z[r]
}

/// The solid angle of one cell of row `r`: (z_{r+1} − z_r)·2π/C.
fn cell_solid_angle(r: usize) -> f64 {
    (row_z(r + 1) - row_z(r)) * (TAU / COLUMNS as f64)
}

/// The unit direction of elevation `elevation` and azimuth `azimuth` (radians).
fn direction(elevation: f64, azimuth: f64) -> DVec3 {
    let (sin_e, cos_e) = elevation.sin_cos();
    let (sin_a, cos_a) = azimuth.sin_cos();
    DVec3::new(cos_e * cos_a, cos_e * sin_a, sin_e)
}

/// The direction at height `z` (≥ 0) and azimuth `azimuth`.
fn direction_at_z(z: f64, azimuth: f64) -> DVec3 {
    let r = (1.0 - z * z).max(0.0).sqrt();
    let (sin_a, cos_a) = azimuth.sin_cos();
    DVec3::new(r * cos_a, r * sin_a, z)
}

/// Azimuth in [0, 2π) measured from x towards y.
fn azimuth_of(w: DVec3) -> f64 {
    let a = w.y.atan2(w.x);
    if a < 0.0 { a + TAU } else { a }
}

/// Elevation in [0, π/2] of a direction with w.z ≥ 0.
fn elevation_of(w: DVec3) -> f64 {
    w.z.atan2(w.x.hypot(w.y))
}

/// `cdf` (f64 partial sums of non-negative weights, `weights.len() + 1` values) normalised
/// into `out` as f32, 0 first and exactly 1 last; all-zero weights give the uniform CDF.
pub(crate) fn write_cdf(weights: &[f64], out: &mut [f32]) {
    let total: f64 = weights.iter().sum();
    let n = weights.len();
    let mut sum = 0.0;
    out[0] = 0.0;
    for (k, w) in weights.iter().enumerate() {
        sum += w;
        out[k + 1] = if total > 0.0 {
            (sum / total) as f32
        } else {
            (k + 1) as f32 / n as f32
        };
    }
    out[n] = 1.0;
}

/// The interval `k` of `cdf` (n + 1 non-decreasing values from 0 to 1) holding `u` in
/// [0, 1), cdf[k] ≤ u < cdf[k + 1], and u rescaled to [0, 1) inside it. Intervals of zero
/// probability are never chosen.
pub(crate) fn invert_cdf(cdf: &[f32], u: f64) -> (usize, f64) {
    let n = cdf.len() - 1;
    // First index in 1..=n whose value exceeds u; cdf[n] = 1 > u bounds it.
    let k = cdf[1..=n].partition_point(|&c| c as f64 <= u).min(n - 1);
    let (lo, hi) = (cdf[k] as f64, cdf[k + 1] as f64);
    let rescaled = if hi > lo { (u - lo) / (hi - lo) } else { 0.0 };
    (k, rescaled.clamp(0.0, 1.0 - f64::EPSILON / 2.0))
}

/// The elevation (radians) of row `i` of `rows` on the grids over wo (the sampler's nodes,
/// the albedo map's rows): 90°·(i/(rows − 1))^1.5, dense at the horizon where F changes
/// fastest, row 0 at [`GRAZING_NODE_DEG`] because F is 0 at exactly 0°.
fn grid_elevation(i: usize, rows: usize) -> f64 {
    (90.0 * (i as f64 / (rows - 1) as f64).powf(1.5))
        .max(GRAZING_NODE_DEG)
        .to_radians()
}

/// The inverse of [`grid_elevation`]: `wo`'s fractional row on a grid of `rows`, in
/// [0, rows − 1].
fn grid_row(wo: DVec3, rows: usize) -> f64 {
    ((elevation_of(wo) / FRAC_PI_2).max(0.0).powf(2.0 / 3.0) * (rows - 1) as f64)
        .clamp(0.0, (rows - 1) as f64)
}

/// The four nodes around `wo` on a grid of `elevations` × `azimuths` nodes (rows at
/// [`grid_elevation`], azimuth j·360°/azimuths, node index i·azimuths + j) and their bilinear
/// weights (node index, weight).
fn grid_nodes(wo: DVec3, elevations: usize, azimuths: usize) -> [(usize, f64); 4] {
    let x = grid_row(wo, elevations);
    let i0 = (x.floor() as usize).min(elevations - 2);
    let fx = x - i0 as f64;
    let y = azimuth_of(wo) / TAU * azimuths as f64;
    let j0 = (y.floor() as usize) % azimuths;
    let fy = (y - y.floor()).clamp(0.0, 1.0);
    let j1 = (j0 + 1) % azimuths;
    let node = |i: usize, j: usize| i * azimuths + j;
    [
        (node(i0, j0), (1.0 - fx) * (1.0 - fy)),
        (node(i0, j1), (1.0 - fx) * fy),
        (node(i0 + 1, j0), fx * (1.0 - fy)),
        (node(i0 + 1, j1), fx * fy),
    ]
}

/// The sampler's four nodes around `wo` and their bilinear weights.
fn node_weights(wo: DVec3) -> [(usize, f64); 4] {
    grid_nodes(wo, ELEVATION_NODES, AZIMUTH_NODES)
}

/// The node of `nodes` that `pick` in [0, 1) falls on when the unit interval is cut into
/// their weights in order (a node of weight 0 is never chosen).
fn pick_node(nodes: &[(usize, f64); 4], mut pick: f64) -> usize {
    let mut chosen = nodes[0].0;
    for &(n, w) in nodes {
        if w > 0.0 {
            chosen = n;
            if pick < w {
                break;
            }
            pick -= w;
        }
    }
    chosen
}

impl Sampler {
    /// The sampler of `fabric`, built from the resonant quadrature with [`BUILD_NODES`].
    pub fn for_fabric(fabric: &Fabric) -> Self {
        let patch = Patch::new(fabric, Integration::Resonant(BUILD_NODES));
        Self::build(|wi, wo| patch.eval(wi, wo)).with_support(Support::of_fabric(fabric))
    }

    /// The sampler of a baked table's fabric, built from the table's f32 lookup (its batch
    /// entry point, [`crate::table::Table::lookup_batch`], the same values as single
    /// lookups): a small fraction of the resonant quadrature's cost, and the density
    /// follows the F that a renderer using the table shades with.
    pub fn for_table(table: &crate::table::Table) -> Self {
        Self::build_batched(|pairs, out| {
            crate::measure::accuracy::lookup_batch_f64(table, pairs, out)
        })
        .with_support(Support::of_fabric(&table.fabric))
    }

    /// This sampler with its density 0 outside `support` (the data's support block
    /// rewritten).
    fn with_support(mut self, support: Support) -> Self {
        self.data.truncate(SUPPORT_BASE);
        let curves = [support.curve(0), support.curve(1)];
        self.data
            .push(if support.is_everywhere() { 0.0 } else { 1.0 });
        self.data.extend(curves.map(|c| c.len() as f32));
        for &(start, end) in curves.into_iter().flatten() {
            self.data.extend([start as f32, end as f32]);
        }
        self.support = support;
        self
    }

    /// A sampler whose cell probabilities follow `f(wi, wo)` (RGB, the patch transfer; its
    /// mean over the channels is used), with no restriction of its support. Nodes in
    /// parallel, each computed alone: the result does not depend on the thread count.
    pub fn build(f: impl Fn(DVec3, DVec3) -> DVec3 + Sync) -> Self {
        Self::build_batched(|pairs, out| {
            for (value, &(wi, wo)) in out.iter_mut().zip(pairs) {
                *value = f(wi, wo);
            }
        })
    }

    /// [`Self::build`] from `f(pairs, out)`, which writes F of every pair into `out`: each
    /// node asks for all its cells' pairs at once, so that a batch evaluation can be used.
    pub fn build_batched(f: impl Fn(&[(DVec3, DVec3)], &mut [DVec3]) + Sync) -> Self {
        let nodes: Vec<Vec<f32>> = (0..NODES)
            .into_par_iter()
            .map(|n| {
                let (i, j) = (n / AZIMUTH_NODES, n % AZIMUTH_NODES);
                let elevation = grid_elevation(i, ELEVATION_NODES);
                let wo = direction(elevation, j as f64 * TAU / AZIMUTH_NODES as f64);
                Self::build_node(&f, wo)
            })
            .collect();
        Self {
            data: nodes.concat(),
            support: Support::everywhere(),
        }
        .with_support(Support::everywhere())
    }

    /// One node's CDFs for outgoing direction `wo`.
    fn build_node(f: &impl Fn(&[(DVec3, DVec3)], &mut [DVec3]), wo: DVec3) -> Vec<f32> {
        let column_width = TAU / COLUMNS as f64;
        // Two points on each cell's diagonal: half the cost of 2 × 2, and the variance of
        // the tests' albedo estimates moved by less than a factor 2.
        const POINTS: [(f64, f64); 2] = [(0.25, 0.25), (0.75, 0.75)];
        let mut pairs = Vec::with_capacity(ROWS * COLUMNS * POINTS.len());
        for r in 0..ROWS {
            let (z0, z1) = (row_z(r), row_z(r + 1));
            for c in 0..COLUMNS {
                for (a, b) in POINTS {
                    let wi = direction_at_z(z0 + a * (z1 - z0), (c as f64 + b) * column_width);
                    pairs.push((wi, wo));
                }
            }
        }
        let mut values = vec![DVec3::ZERO; pairs.len()];
        f(&pairs, &mut values);
        let mut out = vec![0.0f32; NODE_STRIDE];
        let mut row_weights = [0.0f64; ROWS];
        let mut cells = [0.0f64; COLUMNS];
        for (r, row_weight) in row_weights.iter_mut().enumerate() {
            let (z0, z1) = (row_z(r), row_z(r + 1));
            for (c, cell) in cells.iter_mut().enumerate() {
                let at = (r * COLUMNS + c) * POINTS.len();
                let sum: f64 = values[at..at + POINTS.len()]
                    .iter()
                    .map(|v| (v.x + v.y + v.z) / 3.0)
                    .sum();
                // Mean value × solid angle; a non-finite or negative F is treated as 0.
                let value = sum / POINTS.len() as f64 * (z1 - z0) * column_width;
                *cell = if value.is_finite() && value > 0.0 {
                    value
                } else {
                    0.0
                };
            }
            *row_weight = cells.iter().sum();
            let start = ROWS + 1 + r * (COLUMNS + 1);
            write_cdf(&cells, &mut out[start..start + COLUMNS + 1]);
        }
        write_cdf(&row_weights, &mut out[..ROWS + 1]);
        out
    }

    /// The f32 data in the layout of the module doc (what the GPU reads).
    pub fn data(&self) -> &[f32] {
        &self.data
    }

    fn node(&self, n: usize) -> &[f32] {
        &self.data[n * NODE_STRIDE..(n + 1) * NODE_STRIDE]
    }

    fn row_cdf(node: &[f32]) -> &[f32] {
        &node[..ROWS + 1]
    }

    fn column_cdf(node: &[f32], r: usize) -> &[f32] {
        let start = ROWS + 1 + r * (COLUMNS + 1);
        &node[start..start + COLUMNS + 1]
    }

    /// The probability of cell (`r`, `c`) in node `n`.
    fn cell_probability(&self, n: usize, r: usize, c: usize) -> f64 {
        let node = self.node(n);
        let rows = Self::row_cdf(node);
        let columns = Self::column_cdf(node, r);
        (rows[r + 1] as f64 - rows[r] as f64) * (columns[c + 1] as f64 - columns[c] as f64)
    }

    /// The density at `wi` (w.z > 0, inside `lunes`) of the mixture of `nodes` (one wo's
    /// bilinear weights) and the cosine share on `lunes`: wi's cell and its solid angle are
    /// the same in every node, so they are found once.
    fn mixture_pdf(&self, nodes: &[(usize, f64); 4], lunes: &Lunes, wi: DVec3) -> f64 {
        let r = ((elevation_of(wi) / FRAC_PI_2 * ROWS as f64) as usize).min(ROWS - 1);
        let c = ((azimuth_of(wi) / TAU * COLUMNS as f64) as usize).min(COLUMNS - 1);
        let table: f64 = nodes
            .iter()
            .filter(|&&(_, w)| w > 0.0)
            .map(|&(n, w)| w * self.cell_probability(n, r, c))
            .sum();
        COSINE_SHARE * lunes.cosine_pdf(wi) + (1.0 - COSINE_SHARE) * table / cell_solid_angle(r)
    }

    /// `pdf(wi | wo)` per unit solid angle, as [`Sampler::sample`] draws it; 0 when either
    /// direction is not above the horizon or wi is outside F's support. Both unit, in the
    /// patch frame.
    pub fn pdf(&self, wo: DVec3, wi: DVec3) -> f64 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return 0.0;
        }
        let lunes = self.support.lunes(wo);
        if !lunes.contains(wi) {
            return 0.0;
        }
        self.mixture_pdf(&node_weights(wo), &lunes, wi)
    }

    /// A direction drawn for unit `wo` from three uniform numbers in [0, 1), and its density;
    /// `None` when `wo` is not above the horizon, the draw lands on the horizon itself, or a
    /// table draw lands outside F's support.
    pub fn sample(&self, wo: DVec3, u: [f64; 3]) -> Option<Sample> {
        if wo.z <= 0.0 {
            return None;
        }
        let weights = node_weights(wo);
        let lunes = self.support.lunes(wo);
        let wi = if u[2] < COSINE_SHARE {
            lunes.sample_cosine([u[0], u[1]], u[2] / COSINE_SHARE)?
        } else {
            let pick = (u[2] - COSINE_SHARE) / (1.0 - COSINE_SHARE);
            let node = self.node(pick_node(&weights, pick));
            let (r, ur) = invert_cdf(Self::row_cdf(node), u[0]);
            let (c, uc) = invert_cdf(Self::column_cdf(node, r), u[1]);
            let z = row_z(r) + ur * (row_z(r + 1) - row_z(r));
            direction_at_z(z, (c as f64 + uc) * TAU / COLUMNS as f64)
        };
        if wi.z <= 0.0 || !lunes.contains(wi) {
            return None;
        }
        let pdf = self.mixture_pdf(&weights, &lunes, wi);
        (pdf > 0.0).then_some(Sample { wi, pdf })
    }

    /// The WGSL constants `shaders/sampling/fabric_sampler.wgsl` and
    /// `shaders/sampling/sample_taps.wgsl` require (the layouts' sizes): the generated module
    /// [`crate::shader::SAMPLER_CONSTANTS`]. Those files hold `sampling_sample`, `sampling_pdf`
    /// and `sampling_tap` and the helpers they need, without a binding (the module that
    /// requires them declares `sampling_data` or `sampling_taps`).
    pub fn wgsl_constants() -> String {
        use crate::table::wgsl::{wgsl_f32, wgsl_vec};
        let axes: String = (0..2)
            .map(|j| {
                let (t0, b) = crate::model::thread_axes(j);
                format!(
                    "const SAMPLING_T0_{j} = {};\nconst SAMPLING_B_{j} = {};\n",
                    wgsl_vec(&t0.to_array()),
                    wgsl_vec(&b.to_array())
                )
            })
            .collect();
        axes + &format!(
            "const SAMPLING_ELEVATION_NODES: u32 = {ELEVATION_NODES}u;\n\
             const SAMPLING_AZIMUTH_NODES: u32 = {AZIMUTH_NODES}u;\n\
             const SAMPLING_ROWS: u32 = {ROWS}u;\n\
             const SAMPLING_COLUMNS: u32 = {COLUMNS}u;\n\
             const SAMPLING_NODE_STRIDE: u32 = {NODE_STRIDE}u;\n\
             const SAMPLING_SUPPORT_BASE: u32 = {SUPPORT_BASE}u;\n\
             const SAMPLING_COSINE_SHARE: f32 = {};\n\
             const SAMPLING_TAP_ELEVATIONS: u32 = {}u;\n\
             const SAMPLING_TAP_AZIMUTHS: u32 = {}u;\n\
             const SAMPLING_TAP_LOG2_SOLID_ANGLE_LOW: f32 = {};\n\
             const SAMPLING_TAP_LOG2_SOLID_ANGLE_SPAN: f32 = {};\n",
            wgsl_f32(COSINE_SHARE),
            taps::TAP_ELEVATIONS,
            taps::TAP_AZIMUTHS,
            wgsl_f32(taps::LOG2_SOLID_ANGLE_LOW as f64),
            wgsl_f32(taps::LOG2_SOLID_ANGLE_SPAN as f64),
        )
    }
}
