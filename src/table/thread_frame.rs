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
//! ratios' limit there (see [`MASKING_FLOOR`]).
//!
//! ⟨P⟩_j depends only on the angles `β = atan2(w·t0, w·z)` of wi and wo in the t0–z plane,
//! and is stored in a 129×129 table over (βi, βo) ∈ [−90°, 90°]², clamped, texel i at
//! `−90° + 180°·i/128`, bilinear.
//!
//! A lookup for thread j: the four coordinates, a quadrilinear interpolation of the 4D table
//! (on a GPU: axes 0, 1, 3 by hardware filtering of a 3D texture, axis 2 by a manual blend of
//! two layers), and ⟨P⟩_j bilinearly from its 2D table; then
//! `R_j = reflection·⟨P⟩_j / max(1 − s², 1e-8)`, `T_j = transmission·⟨P⟩_j`,
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
use super::axis::{Axis, AxisF32, Warp};
use super::fast_math::{self, Lanes};
use super::gpu_bound::{self, GpuErrorBound};
use super::wgsl::{coverage_wgsl, wgsl_f32};
use super::{
    BATCH_LANES, LayoutUnit, Plane, PlaneSpec, TableLookup, TextureData, quadrilinear_corners,
};
use crate::model::fabric::TangentSampling;
use crate::model::{Fabric, Integration, patch::ThreadModel};
use glam::{DVec3, Vec3, Vec4, Vec4Swizzles};
use half::f16;
use std::any::Any;
use std::f64::consts::{FRAC_PI_2, PI};
use std::fmt::Write;
use std::sync::Arc;

/// The layout unit `thread_frame`.
pub struct ThreadFrame;

impl LayoutUnit for ThreadFrame {
    fn name(&self) -> &'static str {
        "thread_frame"
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
    fn bake(&self, fabric: &Fabric, resolution: u32, on_row: &(dyn Fn() + Sync)) -> Vec<Vec<f64>> {
        let geometry = Geometry::new(fabric, resolution);
        let mut planes = Vec::with_capacity(4);
        for (j, thread) in geometry.threads.iter().enumerate() {
            let model = ThreadModel::new(fabric, j, Integration::Baking);
            planes.push(bake_thread_plane(thread, on_row, |wi, wo, theta_d| {
                stored_ratios(&model, wi, wo, theta_d)
            }));
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

/// Texels of the ⟨P⟩ table per axis.
pub const MASKING_TEXELS: usize = 129;
/// Bytes of texel data a table may use: the βH axes of both threads shrink together to fit.
pub const BYTE_BUDGET: usize = 16 << 20;
/// ⟨P⟩ at or below which a texel stores 0 instead of its ratios.
///
/// Why 0: a sample contributes to ⟨P⟩ only while it faces both directions, and M and P both
/// vanish at the edge of that window (w·n(α) = 0 for one of them). As the window closes,
/// ⟨s⟩ = ⟨f_s M P cos θi⟩ vanishes faster than ⟨P⟩, and the stored ratios, a ⟨P⟩-weighted
/// mean of f_s·M·cos θi, go to 0 with it. Over 400,000 uniform pairs, where
/// 10⁻⁶ < ⟨P⟩ ≤ 10⁻⁵ the reflection ratio is at most 7% of each thread's largest (velvet's
/// transmission ratio, with its tiny albedo, 23%); where 10⁻⁴ < ⟨P⟩ ≤ 10⁻³ it reaches the
/// largest, so the floor must sit well below 10⁻³.
///
/// Measured (20,000 uniform and 20,000 highlight pairs per fabric): storing 0 at or below
/// 1e-5, instead of filling the texels below 1e-3 from their neighbours as the baker did
/// before, took velvet's split_frame 32 from 1.86 / 1.66% to 1.28 / 1.08%, satin's
/// split_frame 32 highlight error from 0.69 to 0.47% and thread_frame 48's from 5.50 to
/// 3.50%, and made no fabric worse. Floors from 1e-4 to 1e-12 agree within 0.03 points;
/// storing 0 below 1e-3 instead took satin's split_frame 32 highlight error to 2.63%. The
/// neighbours' mean continued the ratios flat across the edge where they drop to 0 (along
/// velvet's masking kinks); a floor of 1e-3 cut off ratios that are still large there.
pub const MASKING_FLOOR: f64 = 1e-5;
const BETA_FOCUS: f64 = 0.7;
const BETA_TEXELS_PER_SIGMA: f64 = 3.0;
const MIN_BETA_TEXELS: usize = 16;
const THETA_WARP_K: f64 = 1.4;

/// How a thread's axes are sized: βH texels per σs on the ridge band, the share of the
/// axis the band gets and the density on a band's edge zone (`RidgeBands::edge`), the
/// texels of θd', u and v per unit of resolution, and the θd' warp strength. The
/// thread_frame layout uses [`AxisPlan::THREAD_FRAME`]; other layouts that tabulate a
/// thread in the same coordinates choose their own.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AxisPlan {
    pub beta_texels_per_sigma: f64,
    pub beta_focus: f64,
    /// The βH density on the edge zone of a band that reaches an end of the axis, as a
    /// multiple of the band's (1: no edge zone).
    pub beta_edge_density: f64,
    /// θd', u, v texels = these × resolution (at least 4, 3, 4).
    pub inner_per_resolution: [f64; 3],
    pub theta_warp_k: f64,
}

impl AxisPlan {
    pub const THREAD_FRAME: AxisPlan = AxisPlan {
        beta_texels_per_sigma: BETA_TEXELS_PER_SIGMA,
        beta_focus: BETA_FOCUS,
        beta_edge_density: 1.0,
        inner_per_resolution: [1.0, 0.29, 0.83],
        theta_warp_k: THETA_WARP_K,
    };

    /// Texels of the non-βH axes (θd', u, v) at `resolution`. The v count is the odd number
    /// nearest to the plan's, so that v = 0 is a texel line: there φi' = φo', where the
    /// resonant sample's masking min(M(wi), M(wo)) kinks (split_frame 31 with 26 v texels
    /// read velvet 1.14 / 1.16%, with 27 0.81 / 0.75%).
    pub fn inner_texels(&self, resolution: u32) -> [usize; 3] {
        let r = resolution as f64;
        let [t, u, v] = self.inner_per_resolution;
        [
            ((t * r).round() as usize).max(4),
            ((u * r).round() as usize).max(3),
            2 * (((v * r - 1.0) / 2.0).round() as usize).max(2) + 1,
        ]
    }

    /// βH texels of thread `index` of `fabric` before any byte budget: the plan's texels
    /// per σs on the ridge bands, at least 16.
    pub fn beta_texels(&self, fabric: &Fabric, index: usize) -> usize {
        let bands = RidgeBands::of(fabric, index);
        ((bands.weighted_length(self) / bands.sigma_s * self.beta_texels_per_sigma
            / self.beta_focus)
            .ceil() as usize)
            .max(MIN_BETA_TEXELS)
    }
}

/// One thread's lookup geometry.
#[derive(Clone, Debug, PartialEq)]
pub struct ThreadGeometry {
    pub t0: DVec3,
    pub b: DVec3,
    pub axes: [Axis; 4],
    pub masking_axis: Axis,
}

/// Thread `index`'s base tangent t0 and rotation axis b: thread 1 runs along x, thread 2
/// along y.
pub(crate) fn thread_frame_of(index: usize) -> (DVec3, DVec3) {
    if index == 0 {
        (DVec3::X, DVec3::Y)
    } else {
        (DVec3::Y, DVec3::X)
    }
}

/// The components (w·t0, w·b, w·z) of the `L::WIDTH` directions `w` in the axes of thread 1
/// (t0 = x, b = y), or of thread 2 (t0 = y, b = x) when `thread2`, one lane per direction.
#[inline(always)]
pub(crate) fn lanes_in_thread_axes<L: Lanes>(thread2: bool, w: &[Vec3]) -> [L; 3] {
    let lanes = |f: fn(Vec3) -> f32| L::from_fn(|k| f(w[k]));
    let along: fn(Vec3) -> f32 = if thread2 { |w| w.y } else { |w| w.x };
    let across: fn(Vec3) -> f32 = if thread2 { |w| w.x } else { |w| w.y };
    [lanes(along), lanes(across), lanes(|w| w.z)]
}

/// Where thread `index`'s ridges lie on the βH axis: each segment of its tangent curve
/// (offsets α from a to b; with control-point sampling, each control point) puts ridges on
/// βH ∈ [−b, −a], widened by 4σs on either side
/// (radians, within [−90°, 90°]); overlapping bands merged, in increasing order.
///
/// A curve with a jump has a gap between its bands where no ridge lies (velvet's thread 2:
/// −90° to −55°, then 55° to 90°), and only the broad volume lobes and the diffuse term
/// vary there, slowly.
#[derive(Clone, Debug, PartialEq)]
struct RidgeBands {
    bands: Vec<(f64, f64)>,
    sigma_s: f64,
}

impl RidgeBands {
    fn of(fabric: &Fabric, index: usize) -> Self {
        let thread = fabric.threads()[index];
        let sigma_s = fabric
            .options
            .lobe_sigma_deg(thread.gamma_s_deg)
            .to_radians();
        let offsets = &thread.offsets_deg;
        let at_points = fabric.options.tangent_sampling == TangentSampling::ControlPoints;
        // Not empty: a fabric's lengths are not all 0 (`Thread::validate`).
        let spans: Vec<(f64, f64)> = if offsets.len() == 1 || at_points {
            offsets.iter().map(|&a| (a, a)).collect()
        } else {
            (0..offsets.len() - 1)
                .filter(|&k| offsets.len() == 2 || thread.lengths[k] > 0.0)
                .map(|k| {
                    (
                        offsets[k].min(offsets[k + 1]),
                        offsets[k].max(offsets[k + 1]),
                    )
                })
                .collect()
        };
        let mut bands: Vec<(f64, f64)> = spans
            .iter()
            .map(|&(a, b)| {
                (
                    (-b.to_radians() - 4.0 * sigma_s).max(-FRAC_PI_2),
                    (-a.to_radians() + 4.0 * sigma_s).min(FRAC_PI_2),
                )
            })
            .collect();
        bands.sort_by(|x, y| x.0.total_cmp(&y.0));
        let mut merged: Vec<(f64, f64)> = Vec::new();
        for (lo, hi) in bands {
            match merged.last_mut() {
                Some(last) if lo <= last.1 => last.1 = last.1.max(hi),
                _ => merged.push((lo, hi)),
            }
        }
        Self {
            bands: merged,
            sigma_s,
        }
    }

    /// The total length of the bands (radians).
    fn length(&self) -> f64 {
        self.bands.iter().map(|(lo, hi)| hi - lo).sum()
    }

    /// Where two bands reach the two ends of the axis, the gap between them (radians).
    fn gap(&self) -> Option<(f64, f64)> {
        let edge = FRAC_PI_2 - 1e-6;
        match self.bands[..] {
            [(a_lo, a_hi), (b_lo, b_hi)] if a_lo <= -edge && b_hi >= edge => Some((a_hi, b_lo)),
            _ => None,
        }
    }

    /// Where a single band reaches one end of the axis (velvet's thread 1, −90° to −50°,
    /// reaches βH = 90°), the zone around its other edge: from that edge 7σs into the band.
    /// The band starts 4σs before the segment's end, so the zone holds the end's smoothed
    /// step, −4σs to +3σs about it, where the curve sum changes fastest along βH; inside
    /// the segment it varies slowly. None where the band is no longer than the zone, or
    /// where `plan` gives the zone no extra density.
    fn edge(&self, plan: &AxisPlan) -> Option<(f64, f64)> {
        let width = 7.0 * self.sigma_s;
        match self.bands[..] {
            _ if plan.beta_edge_density <= 1.0 => None,
            [(lo, hi)] if hi - lo <= width => None,
            [(lo, hi)] if hi >= FRAC_PI_2 && lo > -FRAC_PI_2 => Some((lo, lo + width)),
            [(lo, hi)] if lo <= -FRAC_PI_2 && hi < FRAC_PI_2 => Some((hi - width, hi)),
            _ => None,
        }
    }

    /// The length the βH texels are counted over: the bands, plus a gap at the share
    /// `1 − focus` of their density (nothing narrow lies in it), plus an edge zone's extra
    /// density. With one band the plan puts `focus` of the texels on it and spreads the
    /// rest outside.
    fn weighted_length(&self, plan: &AxisPlan) -> f64 {
        let gap = self.gap().map_or(0.0, |(lo, hi)| hi - lo);
        let edge = self.edge(plan).map_or(0.0, |(lo, hi)| hi - lo);
        self.length() + (1.0 - plan.beta_focus) * gap + (plan.beta_edge_density - 1.0) * edge
    }

    /// The smallest interval holding every band.
    fn hull(&self) -> (f64, f64) {
        (self.bands[0].0, self.bands[self.bands.len() - 1].1)
    }
}

/// βH texels of both threads: 3 per σs on each ridge band, scaled down together (to at
/// least 16 each) when the table would exceed [`BYTE_BUDGET`].
fn beta_texels(fabric: &Fabric, resolution: u32) -> [usize; 2] {
    let plan = AxisPlan::THREAD_FRAME;
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

impl ThreadGeometry {
    /// The axes of thread `index` of `fabric` at `resolution` in the thread_frame layout.
    pub fn new(fabric: &Fabric, index: usize, resolution: u32) -> Self {
        let n_beta = beta_texels(fabric, resolution)[index];
        Self::planned(fabric, index, resolution, n_beta, &AxisPlan::THREAD_FRAME)
    }

    /// The axes of thread `index` of `fabric` at `resolution` by `plan`, with `n_beta` βH
    /// texels.
    pub fn planned(
        fabric: &Fabric,
        index: usize,
        resolution: u32,
        n_beta: usize,
        plan: &AxisPlan,
    ) -> Self {
        let (t0, b) = thread_frame_of(index);
        let bands = RidgeBands::of(fabric, index);
        let (lo, hi) = bands.hull();
        let [n_theta, n_u, n_v] = plan.inner_texels(resolution);
        let beta = if let Some((gap_lo, gap_hi)) = bands.gap() {
            // Two bands reaching the ends of the axis: texels at one density on both, and at
            // (1 − focus) of it on the gap between them (`RidgeBands::weighted_length`).
            let total = bands.weighted_length(plan);
            let x1 = (gap_lo + FRAC_PI_2) / total;
            let x2 = x1 + (1.0 - plan.beta_focus) * (gap_hi - gap_lo) / total;
            Axis::clamped(
                n_beta,
                Warp::Knots {
                    xs: [0.0, x1, x2, 1.0],
                    vs: [-FRAC_PI_2, gap_lo, gap_hi, FRAC_PI_2],
                },
            )
        } else if hi - lo > 0.9 * PI {
            Axis::clamped(
                n_beta,
                Warp::Linear {
                    lo: -FRAC_PI_2,
                    hi: FRAC_PI_2,
                },
            )
        } else if let Some((edge_lo, edge_hi)) = bands.edge(plan) {
            // One band reaching an end of the axis: `1 − focus` of the texels outside it,
            // `focus` on it, split between its edge zone (at `beta_edge_density` times the
            // density) and the rest of the band.
            let weighted = bands.weighted_length(plan);
            let edge_share =
                plan.beta_focus * plan.beta_edge_density * (edge_hi - edge_lo) / weighted;
            // The zone lies between the outside and the rest of the band, in axis order.
            let zone_start = if hi >= FRAC_PI_2 {
                1.0 - plan.beta_focus
            } else {
                plan.beta_focus - edge_share
            };
            Axis::clamped(
                n_beta,
                Warp::Knots {
                    xs: [0.0, zone_start, zone_start + edge_share, 1.0],
                    vs: [-FRAC_PI_2, edge_lo, edge_hi, FRAC_PI_2],
                },
            )
        } else {
            // The two outer parts share the remaining texels in proportion to their length.
            let (left, right) = ((lo + FRAC_PI_2).max(1e-6), (FRAC_PI_2 - hi).max(1e-6));
            let x1 = (1.0 - plan.beta_focus) * left / (left + right);
            let vs = [
                -FRAC_PI_2,
                lo.max(-FRAC_PI_2 + 1e-6),
                hi.min(FRAC_PI_2 - 1e-6),
                FRAC_PI_2,
            ];
            Axis::clamped(
                n_beta,
                Warp::Knots {
                    xs: [0.0, x1, x1 + plan.beta_focus, 1.0],
                    vs,
                },
            )
        };
        let theta_limit = FRAC_PI_2 - 1e-4;
        Self {
            t0,
            b,
            axes: [
                beta,
                Axis::clamped(
                    n_theta,
                    Warp::SinEnds {
                        hi: theta_limit,
                        k: plan.theta_warp_k,
                    },
                ),
                Axis::clamped(
                    n_u,
                    Warp::Linear {
                        lo: 0.0,
                        hi: FRAC_PI_2,
                    },
                ),
                Axis::clamped(
                    n_v,
                    Warp::Linear {
                        lo: -FRAC_PI_2,
                        hi: FRAC_PI_2,
                    },
                ),
            ],
            masking_axis: Axis::clamped(
                MASKING_TEXELS,
                Warp::Linear {
                    lo: -FRAC_PI_2,
                    hi: FRAC_PI_2,
                },
            ),
        }
    }

    /// The plane holding this thread's 4D table.
    pub fn spec(&self, index: usize) -> PlaneSpec {
        let [a0, a1, a2, a3] = self.axes.map(|a| a.texels);
        PlaneSpec::new(
            format!("thread{}", index + 1),
            a0,
            a1 * a2 * a3,
            &["reflection", "transmission"],
        )
    }

    /// Row-major index of texel `(i0, i1, i2, i3)` in the plane.
    #[inline]
    pub fn texel_index(&self, i: [usize; 4]) -> usize {
        let n = self.axes.map(|a| a.texels);
        ((i[2] * n[3] + i[3]) * n[1] + i[1]) * n[0] + i[0]
    }

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

    /// The WGSL function `name(wi, wo) -> vec4<f32>` sampling this thread
    /// (`cloth_sample_thread` of `shaders/table/thread_geometry.wgsl`: reflection, transmission,
    /// ⟨P⟩, cos²θd') from the 3D texture `table` and layer `layer` of the masking array
    /// texture `masking`, with its frame and axes as literals.
    pub fn wgsl_function(&self, name: &str, table: &str, masking: &str, layer: usize) -> String {
        let n = self.axes.map(|a| a.texels);
        let swizzle = if self.t0 == DVec3::X { "xyz" } else { "yxz" };
        let names = ["c.beta_h", "c.theta_d", "c.u", "c.v"];
        let labels = ["βH", "θd'", "u", "v"];
        let mut f = format!(
            "\n// t0 = {t0}, b = {b}; 4D table {table}, ⟨P⟩ in layer {layer} of {masking}.\n\
             fn {name}(wi: vec3<f32>, wo: vec3<f32>) -> vec4<f32> {{\n    \
             let c = cloth_thread_coordinates(wi.{swizzle}, wo.{swizzle});\n    \
             // Continuous texel coordinates of the 4D table (`Axis::locate`).\n    \
             let g = vec4<f32>(\n",
            t0 = self.t0,
            b = self.b,
        );
        for a in 0..4 {
            let (call, about) = AxisF32::wgsl_texel(&self.axes[a], names[a]);
            let _ = writeln!(
                f,
                "        // Axis {a}, {}: {about}.\n        {call},",
                labels[a]
            );
        }
        let (bi, about) = AxisF32::wgsl_texel(&self.masking_axis, "c.beta_i");
        let (bo, _) = AxisF32::wgsl_texel(&self.masking_axis, "c.beta_o");
        let _ = write!(
            f,
            "    );\n    // ⟨P⟩ table over (βi, βo): {about} per axis.\n    \
             let gm = vec2<f32>(\n        {bi},\n        {bo},\n    );\n    \
             return cloth_sample_thread({table}, {masking}, {layer}, g, vec4<f32>({}, {}, {}, {}), gm, {}, c.cos2_d);\n}}\n",
            wgsl_f32(n[0] as f64),
            wgsl_f32(n[1] as f64),
            wgsl_f32(n[2] as f64),
            wgsl_f32(n[3] as f64),
            wgsl_f32(self.masking_axis.texels as f64),
        );
        f
    }

    /// This thread's axes in f32: the four 4D axes, then the masking axis.
    pub fn fast_axes(&self) -> [AxisF32; 5] {
        let [a0, a1, a2, a3] = self.axes.each_ref().map(AxisF32::new);
        [a0, a1, a2, a3, AxisF32::new(&self.masking_axis)]
    }

    /// The table coordinates (βH, θd', u, v) of a pair, folded to u ≥ 0.
    pub fn coordinates(&self, wi: DVec3, wo: DVec3) -> [f64; 4] {
        let h = wi + wo;
        let beta_h = h.dot(self.t0).atan2(h.z);
        let (t_res, n_res) = self.resonant_frame(beta_h);
        let theta_d = (0.5 * (wi.dot(t_res) - wo.dot(t_res)))
            .clamp(-1.0, 1.0)
            .asin();
        let phi_i = wi.dot(self.b).atan2(wi.dot(n_res));
        let phi_o = wo.dot(self.b).atan2(wo.dot(n_res));
        let (u, v) = (0.5 * (phi_i + phi_o), 0.5 * (phi_i - phi_o));
        let sign = if u < 0.0 { -1.0 } else { 1.0 };
        [beta_h, theta_d, sign * u, sign * v]
    }

    /// The pair at table coordinates (the inverse of [`Self::coordinates`]).
    pub fn directions(&self, [beta_h, theta_d, u, v]: [f64; 4]) -> (DVec3, DVec3) {
        let (t_res, n_res) = self.resonant_frame(beta_h);
        let (sin_d, cos_d) = theta_d.sin_cos();
        let across = |phi: f64| cos_d * (phi.cos() * n_res + phi.sin() * self.b);
        (
            sin_d * t_res + across(u + v),
            -sin_d * t_res + across(u - v),
        )
    }

    /// t(α') and n(α') for the resonant sample α' = −βH.
    fn resonant_frame(&self, beta_h: f64) -> (DVec3, DVec3) {
        let (s, c) = beta_h.sin_cos();
        (c * self.t0 - s * DVec3::Z, s * self.t0 + c * DVec3::Z)
    }

    /// The angle of w in the t0–z plane, the masking table's coordinate.
    #[inline]
    pub fn beta(&self, w: DVec3) -> f64 {
        w.dot(self.t0).atan2(w.z)
    }
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
        let threads = [0, 1].map(|j| ThreadGeometry::new(fabric, j, resolution));
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
            reflection += self.coverage[j] * r * masking / cos2_d.max(1e-8);
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
            reflection += a * r * masking / cos2_d.max(1e-8);
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
        let mut out = coverage_wgsl(self.coverage, self.gap);
        for j in 0..2 {
            out += &self.threads[j].wgsl_function(
                &format!("cloth_thread{}", j + 1),
                &format!("cloth_thread{}_table", j + 1),
                "cloth_masking_table",
                j,
            );
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
            (errors[j], fold[j]) =
                gpu_bound::thread_errors(thread, &planes[j], &planes[2 + j], wi, wo);
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
            let c = c2.max(1e-8);
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

    fn as_any(&self) -> &dyn Any {
        self
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
    // left as a call once both layouts used this, and cost thread_frame 12% of a lookup.
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

/// The 3D texture of thread `j` (see "GPU textures"): 2 channels, depth N2·(N3 + 2).
pub fn thread_texture(plane: &Plane, thread: &ThreadGeometry, j: usize) -> TextureData {
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
        name: format!("thread{}", j + 1),
        binding: 4 + j as u32,
        three_d: true,
        size: [n0 as u32, n1 as u32, (n2 * block) as u32],
        channels: 2,
        texels,
    }
}

/// Masking planes as the layers of one one-channel array texture (thread_frame: both).
pub fn masking_texture(planes: &[Plane]) -> TextureData {
    let n = MASKING_TEXELS as u32;
    TextureData {
        name: "masking".into(),
        binding: 6,
        three_d: false,
        size: [n, n, planes.len() as u32],
        channels: 1,
        texels: planes
            .iter()
            .flat_map(|p| p.data.iter().map(|&v| f16::from_f32(v)))
            .collect(),
    }
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

/// The stored channels of every texel of one thread's 4D table, flattened in plane order:
/// `ratios(wi, wo, θd')` at each texel's direction pair and θd', then replaced by the node
/// values of their least-squares quadrilinear fit ([`super::prefilter`]). Rows in
/// parallel, each sample a pure function of its coordinates and the fit a pure function of
/// the samples, so the result is the same for any thread count.
pub fn bake_thread_plane(
    geometry: &ThreadGeometry,
    on_row: &(dyn Fn() + Sync),
    ratios: impl Fn(DVec3, DVec3, f64) -> [f64; 2] + Sync,
) -> Vec<f64> {
    use rayon::prelude::*;
    let n = geometry.axes.map(|a| a.texels);
    let values: [Vec<f64>; 4] =
        std::array::from_fn(|a| (0..n[a]).map(|i| geometry.axes[a].texel_value(i)).collect());
    let rows = n[1] * n[2] * n[3];
    let mut plane: Vec<f64> = (0..rows)
        .into_par_iter()
        .flat_map_iter(|row| {
            let (i1, i3, i2) = (row % n[1], (row / n[1]) % n[3], row / (n[1] * n[3]));
            let (values, ratios) = (&values, &ratios);
            let row_values: Vec<f64> = (0..n[0])
                .flat_map(|i0| {
                    let theta_d = values[1][i1];
                    let (wi, wo) =
                        geometry.directions([values[0][i0], theta_d, values[2][i2], values[3][i3]]);
                    ratios(wi, wo, theta_d)
                })
                .collect();
            on_row();
            row_values
        })
        .collect();
    // Plane order, fastest first: βH, θd', v, u.
    super::prefilter::fit_for_multilinear(&mut plane, 2, &[n[0], n[1], n[3], n[2]]);
    plane
}

/// The stored channels of "Channels and lookup" for a pair at θd' from the thread's curve
/// means: (R·cos²θd'/⟨P⟩, T/⟨P⟩), 0 where ⟨P⟩ ≤ [`MASKING_FLOOR`].
pub fn stored_ratios(model: &ThreadModel, wi: DVec3, wo: DVec3, theta_d: f64) -> [f64; 2] {
    let m = model.means(wi, wo);
    if m.masking <= MASKING_FLOOR {
        return [0.0; 2];
    }
    [
        m.reflection * theta_d.cos().powi(2) / m.masking,
        m.transmission / m.masking,
    ]
}

/// The masking plane of one thread: ⟨P⟩ at (βi, βo) for directions in the t0–z plane
/// (⟨P⟩ depends on nothing else), with the baking rule: ⟨P⟩ is smooth in α, and the rule's
/// 3e-4 bound on F holds for it too.
pub fn bake_masking(fabric: &Fabric, geometry: &ThreadGeometry, index: usize) -> Vec<f64> {
    use rayon::prelude::*;
    let model = ThreadModel::new(fabric, index, Integration::Baking);
    let axis = geometry.masking_axis;
    let in_plane = |beta: f64| beta.sin() * geometry.t0 + beta.cos() * DVec3::Z;
    (0..axis.texels * axis.texels)
        .into_par_iter()
        .map(|k| {
            let (i, j) = (k % axis.texels, k / axis.texels);
            model
                .means(in_plane(axis.texel_value(i)), in_plane(axis.texel_value(j)))
                .masking
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thread_texture_pads_u_blocks_with_edge_copies() {
        use crate::table::{Layout, PlaneSpec};
        let fabric = crate::formats::fabric_toml::FabricSet::builtin().fabrics()[0].clone();
        let geometry = Geometry::new(&fabric, 4);
        let thread = &geometry.threads[0];
        let spec: PlaneSpec = Layout::THREAD_FRAME.plane_specs(&fabric, 4)[0].clone();
        let values = spec.texel_count() * 2;
        // Values 0, 1, 2, … up to 2048 are exact in f16; stay below by taking them mod 2048.
        let plane = Plane {
            spec,
            data: (0..values).map(|k| (k % 2048) as f32).collect(),
        };
        let texture = thread_texture(&plane, thread, 0);
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

    /// Velvet's thread 1 (−90° to −50°) has one band reaching βH = 90°: under split_frame's
    /// plan its texels are denser on the zone around the band's other edge, where the
    /// segment's end makes the curve sum change fastest.
    #[test]
    fn a_band_reaching_an_end_of_the_axis_is_denser_around_its_other_edge() {
        let fabrics = crate::formats::fabric_toml::FabricSet::builtin();
        let velvet = fabrics.get("velvet").unwrap();
        // Thread 1, −90° to −50°: one band from 50° − 4σs up to βH = 90°.
        let plan = crate::table::split_frame::PLAN;
        let bands = RidgeBands::of(velvet, 0);
        let (lo, hi) = bands.edge(&plan).expect("an edge zone");
        assert_eq!(lo, bands.bands[0].0);
        assert!((hi - lo - 7.0 * bands.sigma_s).abs() < 1e-12);
        // A band reaching both ends, or two bands, has none.
        assert_eq!(RidgeBands::of(velvet, 1).edge(&plan), None);

        let n = plan.beta_texels(velvet, 0);
        let axis = ThreadGeometry::planned(velvet, 0, 31, n, &plan).axes[0];
        let count = |a: f64, b: f64| {
            (0..n)
                .filter(|&i| (a..b).contains(&axis.texel_value(i)))
                .count()
        };
        let edge_density = count(lo, hi) as f64 / (hi - lo);
        let band_density = count(hi, FRAC_PI_2 + 1e-9) as f64 / (FRAC_PI_2 - hi);
        let ratio = edge_density / band_density;
        assert!((ratio - plan.beta_edge_density).abs() < 0.25, "{ratio}");
        // Outside the band: `1 − focus` of the texels, give or take one on its edge.
        let outside = count(-FRAC_PI_2 - 1e-9, lo) as f64 / n as f64;
        assert!(
            (outside - (1.0 - plan.beta_focus)).abs() < 1.5 / n as f64,
            "{outside}"
        );

        // thread_frame's plan keeps one density on the band: its axis is as before the zone.
        let plan = AxisPlan::THREAD_FRAME;
        let n = plan.beta_texels(velvet, 0);
        let axis = ThreadGeometry::planned(velvet, 0, 16, n, &plan).axes[0];
        assert!(matches!(axis.warp, Warp::Knots { vs, .. } if vs[2] >= FRAC_PI_2 - 1e-6));
    }

    /// Velvet's thread 2 jumps from −55° to 55°: two bands reaching the ends of the axis,
    /// with the gap between them free of ridges, where the βH texels are (1 − focus) as
    /// dense as on the bands. A curve without a jump (satin's thread 1) keeps one band.
    #[test]
    fn a_curve_that_jumps_has_a_ridge_band_per_segment() {
        let set = crate::formats::fabric_toml::FabricSet::builtin();
        let (velvet, satin) = (
            set.get("velvet").unwrap(),
            set.get("polyester_satin_charmeuse").unwrap(),
        );
        let four_sigma = 4.0 * velvet.options.lobe_sigma_deg(6.0);
        let bands = RidgeBands::of(velvet, 1).bands;
        let degrees: Vec<(f64, f64)> = bands
            .iter()
            .map(|&(lo, hi)| (lo.to_degrees(), hi.to_degrees()))
            .collect();
        assert_eq!(degrees.len(), 2, "{degrees:?}");
        assert!((degrees[0].0 + 90.0).abs() < 1e-9 && (degrees[1].1 - 90.0).abs() < 1e-9);
        assert!(
            (degrees[0].1 - (-55.0 + four_sigma)).abs() < 1e-9,
            "{degrees:?}"
        );
        assert!(
            (degrees[1].0 - (55.0 - four_sigma)).abs() < 1e-9,
            "{degrees:?}"
        );
        assert_eq!(RidgeBands::of(satin, 0).bands.len(), 1);

        let plan = AxisPlan::THREAD_FRAME;
        let n = plan.beta_texels(velvet, 1);
        let axis = ThreadGeometry::planned(velvet, 1, 16, n, &plan).axes[0];
        let in_gap = (0..n)
            .filter(|&i| axis.texel_value(i).abs() < bands[1].0)
            .count();
        // The gap's share of the texels: its length at (1 − focus) of the bands' density,
        // give or take the texels on its edges.
        let (gap_lo, gap_hi) = (bands[0].1, bands[1].0);
        let gap = (1.0 - plan.beta_focus) * (gap_hi - gap_lo);
        let expected = gap / (gap + (bands[0].1 - bands[0].0) + (bands[1].1 - bands[1].0));
        let share = in_gap as f64 / n as f64;
        assert!(
            (share - expected).abs() < 2.5 / n as f64,
            "{share} {expected}"
        );
    }
}
