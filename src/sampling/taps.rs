//! Sample taps: the environment light's strata of F, computed once per fabric.
//!
//! The environment light (`shaders/render/renderer.wgsl`) estimates
//! `∫ L(wi) F(wi, wo) dwi` as a sum over K strata S_k of the hemisphere that tile it:
//! `Σ_k (∫_{S_k} F dwi) · L̄_k`, with L̄_k the map filtered over S_k, read as one fetch in
//! the direction of F's centroid in S_k at the mip level whose texels cover S_k's solid
//! angle (filtered importance sampling, Colbert and Křivánek, with each stratum's exact
//! integral of F in place of a draw's F/pdf). In the patch frame the strata and their
//! integrals depend on `wo` alone, not on the pixel or the map, so they are computed here,
//! once, for a grid of `wo`: per pixel a sample costs four reads of 16 bytes and one
//! filtered fetch of the map, and no table lookup (costs and errors:
//! docs/sampling.md#sample-taps).
//!
//! # Strata
//! The fabric's [`Sampler`] gives, for the node's `wo`, a piecewise-constant density over
//! its cells (the bilinear mixture of its own four nodes around `wo` and the cosine share).
//! The cells are put in the order of a Hilbert curve (`curve_order`), and the density
//! becomes one CDF along it; stratum k is the interval [k/K, (k + 1)/K) of that CDF. Its
//! probability is 1/K, so strata are small where F is large, and a run of a Hilbert curve is
//! a compact patch of the sphere, so a stratum is compact: what one isotropic filtered fetch
//! can stand for. (Strata cut by rows and columns of the CDF instead are bands or wedges
//! whose best shape depends on the lobe: docs/notebook/2026-12-07-sampling.md#what-was-tried.)
//!
//! [`POINTS_PER_NODE`] points, evenly spaced in probability along the curve (inside a cell
//! along the cell's own Hilbert curve, so uniformly in solid angle), give each stratum's
//! integral of F (the mean of F/pdf over its points, times 1/K) and F's centroid; its solid
//! angle is exact (whole cells, and the fractions of the cells at its ends).
//!
//! # Layout
//! - **Nodes over wo**: [`TAP_ELEVATIONS`] × [`TAP_AZIMUTHS`], the sampler's grid rule
//!   (elevations 90°·(i/(E − 1))^1.5 from 0.1°, azimuths j·360°/A), four times as dense
//!   each way as the sampler's own nodes.
//! - **Words** ([`SampleTaps::words`], u32): first (K, the bits of the f32 scale s, 0, 0),
//!   s the largest weight of any tap, then per node `n` and stratum `k < K`, at
//!   `4·(1 + n·K + k)`, one tap of [`TAP_WORDS`] words: the direction in snorm16
//!   (x | y << 16, z | ·), log2 of the solid angle in unorm16 over [−32, 4] (the high half of
//!   the second word), the weight K·∫F dwi (RGB) over s in unorm16 (r | g << 16, b). The
//!   taps serve exactly K samples per pixel.
//!
//! # The estimate for a pixel
//! For the pixel's `wo`, its four surrounding nodes and bilinear weights b_n; tap k is the
//! b-weighted blend of the four nodes' taps k (direction renormalised, log2 of the solid
//! angle and the weight blended), so the estimate is continuous in `wo`. Neighbouring nodes'
//! strata k cover nearly the same part of the sphere, so the blend tiles it as each node
//! does. (Picking one node per k instead, which reads a quarter as much, measured worse: the
//! picked strata overlap and leave holes; docs/notebook/2026-12-07-figures-from-comments.md.)
//!
//! # Weights matched to F's moments
//! A fetch reads the map blurred over about its stratum, which moves light from F's peak to
//! its flanks. So each node's weights are then moved, as little as their size allows, until
//! the blurred taps have F's spherical-harmonic moments up to order 8
//! ([`moments`], which derives it): the estimate becomes exact for maps of that band.
//!
//! Built from any batched evaluation of F, in parallel over nodes, each node alone: the taps
//! do not depend on the thread count.

pub mod moments;
pub mod stored;

use super::row_z;
use super::{AZIMUTH_NODES, ELEVATION_NODES, Sampler, direction, grid_elevation, grid_nodes};
use super::{COLUMNS, COSINE_SHARE, ROWS, cell_solid_angle, direction_at_z, node_weights};
use crate::table::progress::BakeProgress;
use glam::{DVec3, Vec3};
use moments::{MOMENT_ORDER, ShBasis, match_moments};
use rayon::prelude::*;
use std::f64::consts::TAU;

/// Elevation nodes of the taps' grid over wo.
pub const TAP_ELEVATIONS: usize = 4 * (ELEVATION_NODES - 1) + 1;
/// Azimuth nodes of the taps' grid over wo.
pub const TAP_AZIMUTHS: usize = 4 * AZIMUTH_NODES;
/// Nodes of the taps' grid.
pub const TAP_NODES: usize = TAP_ELEVATIONS * TAP_AZIMUTHS;
/// 32-bit words per tap (one `vec4<u32>`).
pub const TAP_WORDS: usize = 4;

/// One tap.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tap {
    /// The direction the map is read in: F's centroid over the tap's stratum, unit, in the
    /// patch frame.
    pub wi: Vec3,
    /// log2 of the stratum's solid angle (steradians), which sets the filtered read's
    /// footprint.
    pub log2_solid_angle: f32,
    /// K·∫F dwi over the stratum (RGB): the estimate is the mean over the K taps of weight
    /// times the map's filtered radiance.
    pub weight: Vec3,
}

/// WGSL's `pack2x16snorm` of one value: round(clamp(v, −1, 1)·32767) as 16 bits.
fn snorm16(v: f32) -> u32 {
    ((v.clamp(-1.0, 1.0) * 32767.0).round() as i16) as u16 as u32
}

/// WGSL's `unpack2x16snorm` of one value.
fn from_snorm16(bits: u32) -> f32 {
    ((bits as u16 as i16) as f32 / 32767.0).max(-1.0)
}

/// WGSL's `pack2x16unorm` of one value: round(clamp(v, 0, 1)·65535) as 16 bits.
fn unorm16(v: f32) -> u32 {
    (v.clamp(0.0, 1.0) * 65535.0).round() as u32
}

/// WGSL's `unpack2x16unorm` of one value.
fn from_unorm16(bits: u32) -> f32 {
    (bits & 0xFFFF) as f32 / 65535.0
}

/// The range of log2 of a tap's solid angle in its unorm16 word: 1e-9 to 2π steradians fit,
/// in steps of 36/65535 (0.04% in the solid angle).
pub(crate) const LOG2_SOLID_ANGLE_LOW: f32 = -32.0;
pub(crate) const LOG2_SOLID_ANGLE_SPAN: f32 = 36.0;

impl Tap {
    /// The four words of the layout (module doc), the weight as a fraction of `scale` (the
    /// largest weight of the taps): the direction in snorm16 (2⁻¹⁵, a thousandth of a
    /// degree), log2 of the solid angle and the weight in unorm16. Unsigned and signed
    /// normalised words, not f16, so that every adapter reads them (`unpack2x16float`
    /// needs a capability that downlevel adapters lack); a weight's step is scale/65535,
    /// far below what the K taps' sum resolves.
    fn packed(&self, scale: f32) -> [u32; TAP_WORDS] {
        let size = (self.log2_solid_angle - LOG2_SOLID_ANGLE_LOW) / LOG2_SOLID_ANGLE_SPAN;
        let weight = self.weight / scale;
        [
            snorm16(self.wi.x) | snorm16(self.wi.y) << 16,
            snorm16(self.wi.z) | unorm16(size) << 16,
            unorm16(weight.x) | unorm16(weight.y) << 16,
            unorm16(weight.z),
        ]
    }

    fn unpack(w: [u32; TAP_WORDS], scale: f32) -> Self {
        let low = |x: u32| x & 0xFFFF;
        Self {
            wi: Vec3::new(
                from_snorm16(low(w[0])),
                from_snorm16(w[0] >> 16),
                from_snorm16(low(w[1])),
            ),
            log2_solid_angle: LOG2_SOLID_ANGLE_LOW
                + LOG2_SOLID_ANGLE_SPAN * from_unorm16(w[1] >> 16),
            weight: scale
                * Vec3::new(
                    from_unorm16(w[2]),
                    from_unorm16(w[2] >> 16),
                    from_unorm16(w[3]),
                ),
        }
    }
}

/// A fabric's sample taps (see the module doc).
#[derive(Clone, Debug, PartialEq)]
pub struct SampleTaps {
    samples: u32,
    words: Vec<u32>,
}

impl SampleTaps {
    /// The taps of `sampler` for `samples` per pixel, with F from `f(pairs,
    /// out)`, which writes F of every (wi, wo) pair into `out`.
    pub fn build(
        sampler: &Sampler,
        samples: u32,
        f: impl Fn(&[(DVec3, DVec3)], &mut [DVec3]) + Sync,
    ) -> Self {
        Self::pack(samples, &node_taps(sampler, samples, &f, &|| {}))
    }

    /// [`Self::build`], telling `progress` of each node done ([`TAP_NODES`] rows in all);
    /// `None` once `progress` says it is cancelled (the nodes left are skipped).
    pub fn build_cancellable(
        sampler: &Sampler,
        samples: u32,
        f: impl Fn(&[(DVec3, DVec3)], &mut [DVec3]) + Sync,
        progress: &dyn BakeProgress,
    ) -> Option<Self> {
        let taps = node_taps(sampler, samples, &f, progress);
        (!progress.cancelled()).then(|| Self::pack(samples, &taps))
    }

    /// The words of every node's `taps` (module doc).
    fn pack(samples: u32, taps: &[Vec<Tap>]) -> Self {
        let scale = taps
            .iter()
            .flatten()
            .map(|t| t.weight.max_element())
            .fold(f32::MIN_POSITIVE, f32::max);
        let mut words = vec![samples, scale.to_bits(), 0, 0];
        words.extend(taps.iter().flatten().flat_map(|t| t.packed(scale)));
        Self { samples, words }
    }

    /// The taps of a baked table's fabric for `samples` per pixel, F by the table's
    /// batch lookup, from the sampler built from the same table.
    pub fn for_table(table: &crate::table::Table, sampler: &Sampler, samples: u32) -> Self {
        Self::build(sampler, samples, |pairs, out| {
            crate::measure::accuracy::lookup_batch_f64(table, pairs, out)
        })
    }

    /// The samples per pixel these taps serve.
    pub fn samples(&self) -> u32 {
        self.samples
    }

    /// The taps' words (what the GPU reads as `array<vec4<u32>>`).
    pub fn words(&self) -> &[u32] {
        &self.words
    }

    /// Tap `k` of node `node`, as stored.
    pub fn tap(&self, node: usize, k: u32) -> Tap {
        let at = TAP_WORDS * (1 + node * self.samples as usize + k as usize);
        let scale = f32::from_bits(self.words[1]);
        Tap::unpack(
            self.words[at..at + TAP_WORDS]
                .try_into()
                .expect("four words"),
            scale,
        )
    }

    /// Sample `k` of a pixel whose `wo` (unit, above the horizon) is given: the taps k of
    /// the four nodes around wo blended with their bilinear weights (the direction
    /// renormalised), in f32 as `sampling_tap` computes it in WGSL
    /// (`shaders/sampling/sample_taps.wgsl`).
    pub fn pick(&self, wo: DVec3, k: u32) -> Tap {
        let nodes = grid_nodes(wo, TAP_ELEVATIONS, TAP_AZIMUTHS);
        let mut sum = Tap {
            wi: Vec3::ZERO,
            log2_solid_angle: 0.0,
            weight: Vec3::ZERO,
        };
        for (node, b) in nodes {
            let (tap, b) = (self.tap(node, k), b as f32);
            sum.wi += b * tap.wi;
            sum.log2_solid_angle += b * tap.log2_solid_angle;
            sum.weight += b * tap.weight;
        }
        sum.wi = sum.wi.normalize();
        sum
    }
}

/// The taps of every node, in parallel (none for the nodes left once `progress` is
/// cancelled).
fn node_taps(
    sampler: &Sampler,
    samples: u32,
    f: &(impl Fn(&[(DVec3, DVec3)], &mut [DVec3]) + Sync),
    progress: &dyn BakeProgress,
) -> Vec<Vec<Tap>> {
    let order = curve_order();
    (0..TAP_NODES)
        .into_par_iter()
        .map(|n| {
            if progress.cancelled() {
                return Vec::new();
            }
            let (i, j) = (n / TAP_AZIMUTHS, n % TAP_AZIMUTHS);
            let wo = direction(
                grid_elevation(i, TAP_ELEVATIONS),
                j as f64 * TAU / TAP_AZIMUTHS as f64,
            );
            let taps = strata_taps(sampler, &order, samples, wo, f);
            progress.row_done();
            taps
        })
        .collect()
}

/// The taps of one node: the `samples` strata of `sampler`'s density at `wo` along the curve
/// `order`, F at their points from `f`.
fn strata_taps(
    sampler: &Sampler,
    order: &[(usize, usize)],
    samples: u32,
    wo: DVec3,
    f: &impl Fn(&[(DVec3, DVec3)], &mut [DVec3]),
) -> Vec<Tap> {
    let per_stratum = points_per_stratum(samples);
    let density = CurveDensity::new(sampler, wo, order);
    let count = samples as usize * per_stratum;
    let points: Vec<(DVec3, f64)> = (0..count)
        .map(|p| density.point((p as f64 + 0.5) / count as f64))
        .collect();
    let pairs: Vec<(DVec3, DVec3)> = points.iter().map(|&(wi, _)| (wi, wo)).collect();
    let mut values = vec![DVec3::ZERO; pairs.len()];
    f(&pairs, &mut values);
    for value in &mut values {
        *value = if value.is_finite() {
            value.max(DVec3::ZERO)
        } else {
            DVec3::ZERO
        };
    }
    let solid_angles = density.strata_solid_angles(samples as usize);
    let mut taps: Vec<Tap> = points
        .chunks(per_stratum)
        .zip(values.chunks(per_stratum))
        .zip(solid_angles)
        .map(|((points, values), solid_angle)| stratum_tap(points, values, solid_angle))
        .collect();
    let basis = &*MOMENT_BASIS;
    match_moments(basis, &mut taps, &basis.moments(&points, &values));
    taps
}

/// Cell (row, column) of the sampler's grid at each position along the curve that orders
/// the cells: a Hilbert curve over each half of the hemisphere (the grid is R × 2R: columns
/// 0 … R − 1, then the rest), each from its corner at row 0 to its other corner at row 0,
/// so that the two join into one closed curve around the azimuth. Cells close along the
/// curve are close on the sphere, so any interval of the curve is a compact patch. (Cells
/// split in two along the azimuth, square at the horizon, were tried:
/// docs/notebook/2026-12-07-sampling.md#what-was-tried.)
fn curve_order() -> Vec<(usize, usize)> {
    const _: () = assert!(COLUMNS == 2 * ROWS && ROWS.is_power_of_two());
    (0..2)
        .flat_map(|half| {
            (0..ROWS * ROWS).map(move |d| {
                let (x, y) = hilbert_point(ROWS, d);
                (y, half * ROWS + x)
            })
        })
        .collect()
}

/// The cell (x, y) of a side × side grid (side a power of two) at distance `d` along the
/// Hilbert curve that starts at (0, 0) and ends at (side − 1, 0).
fn hilbert_point(side: usize, d: usize) -> (usize, usize) {
    let (mut x, mut y, mut t) = (0, 0, d);
    let mut s = 1;
    while s < side {
        let rx = 1 & (t / 2);
        let ry = 1 & (t ^ rx);
        if ry == 0 {
            if rx == 1 {
                x = s - 1 - x;
                y = s - 1 - y;
            }
            std::mem::swap(&mut x, &mut y);
        }
        x += s * rx;
        y += s * ry;
        t /= 4;
        s *= 2;
    }
    (x, y)
}

/// Points per side of the sub-grid that places points inside a cell (along its own Hilbert
/// curve, so that a run of points is a compact part of the cell).
const CELL_SUBDIVISION: usize = 64;

/// The sampler's density for one `wo` (the bilinear mixture of its four nodes around wo
/// and the cosine share, piecewise constant over the sampler's cells), as one CDF along
/// the cells' curve ([`curve_order`]).
struct CurveDensity<'a> {
    order: &'a [(usize, usize)],
    /// The mixture's probability of the cells before position i on the curve, i = 0 ..= R·C.
    cumulative: Vec<f64>,
}

impl<'a> CurveDensity<'a> {
    fn new(sampler: &Sampler, wo: DVec3, order: &'a [(usize, usize)]) -> Self {
        let nodes = node_weights(wo);
        let mut cumulative = Vec::with_capacity(order.len() + 1);
        cumulative.push(0.0);
        let mut sum = 0.0;
        for &(r, c) in order {
            let table: f64 = nodes
                .iter()
                .map(|&(n, w)| w * sampler.cell_probability(n, r, c))
                .sum();
            let cosine = (row_z(r + 1).powi(2) - row_z(r).powi(2)) / COLUMNS as f64;
            sum += (1.0 - COSINE_SHARE) * table + COSINE_SHARE * cosine;
            cumulative.push(sum);
        }
        Self { order, cumulative }
    }

    /// The direction at `u` in [0, 1) along the curve and the density there (per unit
    /// solid angle): the cell that holds u, and inside it the point of the cell's own
    /// Hilbert curve at u's position in the cell (uniform in solid angle).
    fn point(&self, u: f64) -> (DVec3, f64) {
        let total = self.cumulative[self.order.len()];
        let (i, t) = locate(&self.cumulative, u * total);
        let (r, c) = self.order[i];
        let sub = CELL_SUBDIVISION * CELL_SUBDIVISION;
        let (x, y) = hilbert_point(CELL_SUBDIVISION, ((t * sub as f64) as usize).min(sub - 1));
        let (fx, fy) = (
            (x as f64 + 0.5) / CELL_SUBDIVISION as f64,
            (y as f64 + 0.5) / CELL_SUBDIVISION as f64,
        );
        let z = row_z(r) + fy * (row_z(r + 1) - row_z(r));
        let wi = direction_at_z(z, (c as f64 + fx) * TAU / COLUMNS as f64);
        let probability = (self.cumulative[i + 1] - self.cumulative[i]) / total;
        (wi, probability / cell_solid_angle(r))
    }

    /// The solid angles of the `count` strata of equal probability along the curve: each
    /// covers whole cells and fractions of the cells at its ends.
    fn strata_solid_angles(&self, count: usize) -> Vec<f64> {
        let total = self.cumulative[self.order.len()];
        let mut out = vec![0.0; count];
        for (i, &(r, _)) in self.order.iter().enumerate() {
            let (lo, hi) = (self.cumulative[i] / total, self.cumulative[i + 1] / total);
            if hi <= lo {
                continue;
            }
            let first = ((lo * count as f64) as usize).min(count - 1);
            let last = ((hi * count as f64).ceil() as usize).clamp(first + 1, count);
            for (k, solid_angle) in out.iter_mut().enumerate().take(last).skip(first) {
                let (a, b) = (k as f64 / count as f64, (k + 1) as f64 / count as f64);
                let overlap = hi.min(b) - lo.max(a);
                if overlap > 0.0 {
                    *solid_angle += overlap / (hi - lo) * cell_solid_angle(r);
                }
            }
        }
        out
    }
}

/// The interval k of the non-decreasing partial sums `sums` (0 first) that holds `target`,
/// sums[k] ≤ target < sums[k + 1] (never one of zero width), and target's position in it
/// in [0, 1].
fn locate(sums: &[f64], target: f64) -> (usize, f64) {
    let n = sums.len() - 1;
    let k = sums[1..].partition_point(|&s| s <= target).min(n - 1);
    let width = sums[k + 1] - sums[k];
    let t = if width > 0.0 {
        (target - sums[k]) / width
    } else {
        0.5
    };
    (k, t.clamp(0.0, 1.0))
}

/// Points at which F is evaluated per node, over all its strata (at least one per stratum):
/// twice as many barely moved the image error, half as many raised it
/// (docs/notebook/2026-12-07-sampling.md#what-was-tried).
pub const POINTS_PER_NODE: usize = 512;

/// Points per stratum for K = `samples`.
fn points_per_stratum(samples: u32) -> usize {
    (POINTS_PER_NODE / samples.max(1) as usize).max(1)
}

/// The basis of the moments the taps' weights match ([`match_moments`]).
static MOMENT_BASIS: std::sync::LazyLock<ShBasis> =
    std::sync::LazyLock::new(|| ShBasis::new(MOMENT_ORDER));

/// One stratum's tap from F's `values` (finite, non-negative) at its `points` (wi and the
/// density there, spaced evenly in probability) and its `solid_angle`: the weight K·∫F dwi
/// over the stratum (each point stands for 1/(K·points) of the probability, so K·∫F is the
/// mean of F/pdf), the direction of F's centroid in it.
fn stratum_tap(points: &[(DVec3, f64)], values: &[DVec3], solid_angle: f64) -> Tap {
    let (mut weight, mut centroid, mut spread) = (DVec3::ZERO, DVec3::ZERO, DVec3::ZERO);
    for (&(wi, pdf), &value) in points.iter().zip(values) {
        weight += value / pdf;
        centroid += wi * (value.element_sum() / pdf);
        spread += wi / pdf;
    }
    let wi = centroid
        .try_normalize()
        .or(spread.try_normalize())
        .unwrap_or(DVec3::Z);
    Tap {
        wi: wi.as_vec3(),
        // Every stratum has a positive probability, so a positive solid angle; the floor
        // keeps log2 finite all the same.
        log2_solid_angle: solid_angle.max(1e-9).log2() as f32,
        weight: (weight / points.len() as f64).as_vec3(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A narrow lobe around the mirror direction of wo (a normalised Phong lobe of exponent
    /// 400, about 4° wide, times cos θi, so that its integral drops towards grazing wo), RGB
    /// weighted unevenly so that the channels are not one.
    fn lobe(wi: DVec3, wo: DVec3) -> DVec3 {
        let mirror = DVec3::new(-wo.x, -wo.y, wo.z);
        let c = wi.dot(mirror).max(0.0);
        DVec3::new(1.0, 0.6, 0.3) * (402.0 / TAU * c.powi(400) * wi.z)
    }

    fn batch(pairs: &[(DVec3, DVec3)], out: &mut [DVec3]) {
        for (o, &(wi, wo)) in out.iter_mut().zip(pairs) {
            *o = lobe(wi, wo);
        }
    }

    /// ∫ lobe(wi, wo) dwi over the hemisphere by the midpoint rule on a fine grid in z and
    /// azimuth (uniform in solid angle).
    fn brute_force_integral(wo: DVec3) -> DVec3 {
        let (nz, na) = (3000, 6000);
        let mut sum = DVec3::ZERO;
        for i in 0..nz {
            let z = (i as f64 + 0.5) / nz as f64;
            for j in 0..na {
                sum += lobe(direction_at_z(z, (j as f64 + 0.5) * TAU / na as f64), wo);
            }
        }
        sum * (TAU / (nz * na) as f64)
    }

    /// The taps' strata tile the hemisphere (their solid angles sum to 2π) and their weights
    /// integrate F over it: the mean weight of a node is ∫F dwi, to the accuracy of the
    /// points inside each stratum. For this lobe, narrower than the sampler's cells, that is a
    /// deterministic quadrature error of the points per node, largest at the zenith and
    /// shrinking with more points; the bound sits above the worst measured
    /// (docs/notebook/2026-12-07-figures-from-comments.md).
    #[test]
    fn the_taps_integrate_f_over_strata_that_tile_the_hemisphere() {
        let sampler = Sampler::build(lobe);
        let samples = 16;
        let taps = SampleTaps::build(&sampler, samples, batch);
        assert_eq!(taps.words().len(), TAP_WORDS * (1 + TAP_NODES * 16));
        assert_eq!(taps.words()[0], 16);
        let mut worst = 0.0f64;
        for node in [
            5,
            TAP_AZIMUTHS + 3,
            2 * TAP_AZIMUTHS + 9,
            5 * TAP_AZIMUTHS + 1,
            TAP_NODES / 2 + 17,
            TAP_NODES - 1,
        ] {
            let (i, j) = (node / TAP_AZIMUTHS, node % TAP_AZIMUTHS);
            let wo = direction(
                grid_elevation(i, TAP_ELEVATIONS),
                j as f64 * TAU / TAP_AZIMUTHS as f64,
            );
            let node_taps: Vec<Tap> = (0..samples).map(|k| taps.tap(node, k)).collect();
            let solid_angle: f64 = node_taps
                .iter()
                .map(|t| (t.log2_solid_angle as f64).exp2())
                .sum();
            assert!(
                (solid_angle / TAU - 1.0).abs() < 2e-3,
                "node {node}: {solid_angle} sr"
            );
            let mean =
                node_taps.iter().map(|t| t.weight.as_dvec3()).sum::<DVec3>() / samples as f64;
            let exact = brute_force_integral(wo);
            let error = ((mean - exact) / exact).abs().max_element();
            println!(
                "node {node}: ∫F {exact:.4}, taps {mean:.4}, {:.3}%",
                100.0 * error
            );
            worst = worst.max(error);
            for tap in &node_taps {
                assert!(tap.wi.z >= 0.0 && (tap.wi.length() - 1.0).abs() < 1e-4);
            }
        }
        assert!(worst < 0.04, "{worst}");
    }

    /// A pixel's tap is its node's where wo is a node's, and blends the nodes continuously
    /// in between: two wo a hundredth of a degree apart read nearly the same tap.
    #[test]
    fn a_pixels_tap_blends_its_nodes_continuously() {
        let sampler = Sampler::build(lobe);
        let taps = SampleTaps::build(&sampler, 8, batch);
        let node = 20 * TAP_AZIMUTHS + 37;
        let wo = direction(
            grid_elevation(20, TAP_ELEVATIONS),
            37.0 * TAU / TAP_AZIMUTHS as f64,
        );
        for k in 0..8 {
            let (own, picked) = (taps.tap(node, k), taps.pick(wo, k));
            assert!((own.wi - picked.wi).length() < 1e-4, "tap {k}");
            assert!((own.weight - picked.weight).abs().max_element() < 1e-3 * own.weight.x);
            let step = 1e-4f64;
            let nearby = taps.pick((wo + DVec3::new(step, -step, 0.0)).normalize(), k);
            assert!((nearby.wi - picked.wi).length() < 1e-3, "tap {k}");
            assert!(
                (nearby.weight - picked.weight).abs().max_element() < 0.02 * picked.weight.x,
                "tap {k}: {} against {}",
                nearby.weight,
                picked.weight
            );
        }
    }
}
