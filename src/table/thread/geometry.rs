//! A thread's table axes in its resonant frame (the coordinates derived in
//! [`crate::table::thread_frame`]'s module documentation): how many texels each axis gets and
//! where ([`AxisPlan`], the ridge bands of βH), the coordinates of a pair and their inverse,
//! and the WGSL constant that describes them.

use crate::model::fabric::TangentSampling;
use crate::model::{Fabric, thread_axes};
use crate::table::PlaneSpec;
use crate::table::axis::{Axis, AxisF32, Warp};
use crate::table::fast_math::Lanes;
use crate::table::wgsl::{wgsl_f32, wgsl_vec};
use glam::{DVec3, Vec3};
use std::f64::consts::{FRAC_PI_2, PI};
use std::fmt::Write;

/// Texels of the ⟨P⟩ table per axis.
pub const MASKING_TEXELS: usize = 129;
/// The fewest βH texels a thread gets.
pub const MIN_BETA_TEXELS: usize = 16;

/// How a thread's axes are sized: βH texels per σs on the ridge band, the share of the
/// axis the band gets and the density on a band's edge zone (`RidgeBands::edge`), the
/// texels of θd', u and v per unit of resolution, and the θd' warp strength. The
/// layouts that tabulate a thread in these coordinates each choose their own
/// (`thread_frame::PLAN`, `split_frame::PLAN`).
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
    /// Texels of the non-βH axes (θd', u, v) at `resolution`. The v count is the odd number
    /// nearest to the plan's, so that v = 0 is a texel line: there φi' = φo', where the
    /// resonant sample's masking min(M(wi), M(wo)) kinks, and a kink between texel lines is
    /// smeared over two of them (velvet shows it most: the figures are in
    /// docs/notebook/2026-12-07-figures-from-comments.md).
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

/// The components (w·t0, w·b, w·z) of the `L::WIDTH` directions `w` in the axes of thread 1
/// (t0 = x, b = y), or of thread 2 (t0 = y, b = x) when `thread2`, one lane per direction
/// ([`thread_axes`], unrolled for f32 lanes).
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

impl ThreadGeometry {
    /// The axes of thread `index` of `fabric` at `resolution` by `plan`, with `n_beta` βH
    /// texels.
    pub fn planned(
        fabric: &Fabric,
        index: usize,
        resolution: u32,
        n_beta: usize,
        plan: &AxisPlan,
    ) -> Self {
        let (t0, b) = thread_axes(index);
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

    /// The WGSL value `name()` describing this thread's table as `cloth_thread_sample` of
    /// `shaders/table/thread_geometry.wgsl` reads it (a `ClothThreadTable`: its frame, axes,
    /// texel counts and the layer of its ⟨P⟩ in the masking array texture), with a comment
    /// describing the axes.
    ///
    /// A function returning the literal rather than a module-scope `const`: naga's HLSL
    /// writes a struct or array constant through a constructor function, and glslang's HLSL
    /// front end reads two constants of one type as a recursion (the same reason as the
    /// resonant kernel's literals, `crate::evaluator::resonant::kernel`).
    pub fn wgsl_constant(&self, name: &str, layer: usize) -> String {
        let labels = ["βH", "θd'", "u", "v"];
        let mut out = format!(
            "\n// t0 = {t0}, b = {b}; ⟨P⟩ in layer {layer} of the masking texture.\n",
            t0 = self.t0,
            b = self.b,
        );
        let mut axes = Vec::new();
        for (a, axis) in self.axes.iter().enumerate() {
            let (value, about) = AxisF32::wgsl_axis(axis);
            let _ = writeln!(out, "// Axis {a}, {}: {about}.", labels[a]);
            axes.push(value);
        }
        let (masking, about) = AxisF32::wgsl_axis(&self.masking_axis);
        let _ = writeln!(out, "// ⟨P⟩ table over (βi, βo): {about} per axis.");
        let n = self.axes.map(|a| a.texels as f64);
        let _ = writeln!(
            out,
            "fn {name}() -> ClothThreadTable {{\n    return ClothThreadTable(\n        {},\n        \
             array<ClothAxis, 4>(\n            {},\n        ),\n        {},\n        {masking},\n        \
             {},\n        {layer}i,\n    );\n}}",
            self.t0 != DVec3::X,
            axes.join(",\n            "),
            wgsl_vec(&n),
            wgsl_f32(self.masking_axis.texels as f64),
        );
        out
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

#[cfg(test)]
mod tests {
    use super::*;

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
        let plan = crate::table::thread_frame::PLAN;
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

        let plan = crate::table::thread_frame::PLAN;
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
