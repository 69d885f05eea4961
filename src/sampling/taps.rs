//! Sample taps: the environment light's draws and weights, computed once per fabric.
//!
//! Filtered importance sampling of an environment map (`shaders/render/renderer.wgsl`)
//! estimates `∫ L(wi) F(wi, wo) dwi` by `(1/K) Σ_k L(wi_k) F(wi_k, wo)/pdf(wi_k | wo)` with
//! the K draws of the fabric's [`Sampler`] from one low-discrepancy set shared by every
//! pixel. In the patch frame a draw and its weight depend on `wo` alone, not on the pixel
//! or the map, so they are computed here, once, for a grid of `wo`: per pixel a sample then
//! costs one read of a tap and one filtered fetch of the map, instead of a sampler draw (two
//! CDF searches), a table lookup and that fetch (costs and errors: docs/sampling.md#sample-taps).
//!
//! # Layout
//! - **Nodes over wo**: [`TAP_ELEVATIONS`] × [`TAP_AZIMUTHS`], the sampler's grid rule
//!   (elevations 90°·(i/(E − 1))^1.5 from 0.1°, azimuths j·360°/A), four times as dense
//!   each way as the sampler's own nodes: where two nodes' estimates differ, a pixel between
//!   them blends them (below), so their spacing bounds how far a tap's `wo` is from the
//!   pixel's.
//! - **Values** ([`SampleTaps::values`], f32): first (K, 0, 0, 0), then the taps.
//! - **Taps**: per node `n` and sample `k < K`, at `4 + (n·K + k)·8`, eight f32: (wi, pdf),
//!   (w, 0), with wi the sampler's draw for the node's `wo` from the numbers
//!   `hammersley(k, K)`, pdf its density and w = F(wi, wo)/pdf (RGB). A rejected draw is all
//!   zeros (pdf 0). The taps serve exactly K samples per pixel: a Hammersley set's first
//!   coordinate, (k + ½)/K, strata the sampler's rows evenly only as a whole (a Halton
//!   sequence, whose every prefix would serve, reads higher errors at equal K:
//!   docs/sampling.md#what-was-tried).
//!
//! # The estimate for a pixel
//! For the pixel's `wo`, its four surrounding nodes and bilinear weights b_n; sample k reads
//! the tap k of the node that [`tap_choice`]`(k)` picks with the weights (the unit interval
//! cut into b_0 … b_3), so each node supplies about b_n·K of the K samples and the estimate
//! blends the four nodes' estimates bilinearly without reading more than K taps. The
//! picks are a second low-discrepancy sequence (the golden ratio's multiples modulo 1),
//! independent of the taps' numbers.
//!
//! Built from any batched evaluation of F, in parallel over nodes, each node alone: the taps
//! do not depend on the thread count.

use super::{AZIMUTH_NODES, ELEVATION_NODES, Sampler, direction, grid_elevation, grid_nodes};
use super::{hammersley, pick_node};
use glam::{DVec3, Vec3};
use rayon::prelude::*;
use std::f64::consts::TAU;

/// Elevation nodes of the taps' grid over wo.
pub const TAP_ELEVATIONS: usize = 4 * (ELEVATION_NODES - 1) + 1;
/// Azimuth nodes of the taps' grid over wo.
pub const TAP_AZIMUTHS: usize = 4 * AZIMUTH_NODES;
/// Nodes of the taps' grid.
pub const TAP_NODES: usize = TAP_ELEVATIONS * TAP_AZIMUTHS;
/// f32 values per tap.
pub const TAP_VALUES: usize = 8;

/// The number in [0, 1) that picks sample k's node: k times the golden ratio modulo 1, in
/// 24 bits (the top of k·⌊2³²/φ⌋ mod 2³²), so that the WGSL twin's f32 is exactly this.
pub fn tap_choice(k: u32) -> f32 {
    (k.wrapping_mul(0x9E37_79B9) >> 8) as f32 * (1.0 / 16_777_216.0)
}

/// One tap.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tap {
    /// The draw, unit, in the patch frame.
    pub wi: Vec3,
    /// Its density per unit solid angle (0: a rejected draw, weight 0).
    pub pdf: f32,
    /// F(wi, wo)/pdf, RGB.
    pub weight: Vec3,
}

/// A fabric's sample taps (see the module doc).
#[derive(Clone, Debug, PartialEq)]
pub struct SampleTaps {
    samples: u32,
    values: Vec<f32>,
}

impl SampleTaps {
    /// The taps of `sampler` for `samples` per pixel, with F from `f(pairs,
    /// out)`, which writes F of every (wi, wo) pair into `out`.
    pub fn build(
        sampler: &Sampler,
        samples: u32,
        f: impl Fn(&[(DVec3, DVec3)], &mut [DVec3]) + Sync,
    ) -> Self {
        let values: Vec<Vec<f32>> = (0..TAP_NODES)
            .into_par_iter()
            .map(|n| {
                let (i, j) = (n / TAP_AZIMUTHS, n % TAP_AZIMUTHS);
                let wo = direction(
                    grid_elevation(i, TAP_ELEVATIONS),
                    j as f64 * TAU / TAP_AZIMUTHS as f64,
                );
                let draws: Vec<_> = (0..samples)
                    .map(|k| sampler.sample(wo, hammersley(k, samples)))
                    .collect();
                let pairs: Vec<(DVec3, DVec3)> =
                    draws.iter().flatten().map(|s| (s.wi, wo)).collect();
                let mut values = vec![DVec3::ZERO; pairs.len()];
                f(&pairs, &mut values);
                let mut values = values.into_iter();
                draws
                    .iter()
                    .flat_map(|draw| match draw {
                        Some(s) => {
                            let w = values.next().expect("one value per draw") / s.pdf;
                            [s.wi.x, s.wi.y, s.wi.z, s.pdf, w.x, w.y, w.z, 0.0].map(|x| x as f32)
                        }
                        None => [0.0; TAP_VALUES],
                    })
                    .collect()
            })
            .collect();
        let mut header = vec![samples as f32, 0.0, 0.0, 0.0];
        header.extend(values.concat());
        Self {
            samples,
            values: header,
        }
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

    /// The taps' values (what the GPU reads as `array<vec4<f32>>`).
    pub fn values(&self) -> &[f32] {
        &self.values
    }

    /// Tap `k` of node `node`.
    pub fn tap(&self, node: usize, k: u32) -> Tap {
        let at = 4 + (node * self.samples as usize + k as usize) * TAP_VALUES;
        let v = &self.values[at..at + TAP_VALUES];
        Tap {
            wi: Vec3::new(v[0], v[1], v[2]),
            pdf: v[3],
            weight: Vec3::new(v[4], v[5], v[6]),
        }
    }

    /// Sample `k` of a pixel whose `wo` (unit, above the horizon) is given: the tap that
    /// `sampling_tap` reads in WGSL (`shaders/sampling/sample_taps.wgsl`).
    pub fn pick(&self, wo: DVec3, k: u32) -> Tap {
        let nodes = grid_nodes(wo, TAP_ELEVATIONS, TAP_AZIMUTHS);
        self.tap(pick_node(&nodes, tap_choice(k) as f64), k)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::Fabric;

    fn linen() -> Fabric {
        crate::formats::fabric_toml::FabricSet::builtin()
            .require("linen_plain")
            .expect("built in")
            .clone()
    }

    /// A node's tap is the sampler's draw for that node's wo with the tap's numbers, weighted
    /// by F/pdf, to f32 rounding.
    #[test]
    fn a_tap_is_the_samplers_draw_and_its_weight() {
        let fabric = linen();
        let patch = crate::model::Patch::new(
            &fabric,
            crate::model::Integration::Resonant(super::super::BUILD_NODES),
        );
        let sampler = Sampler::for_fabric(&fabric);
        let f = |pairs: &[(DVec3, DVec3)], out: &mut [DVec3]| {
            for (o, &(wi, wo)) in out.iter_mut().zip(pairs) {
                *o = patch.eval(wi, wo);
            }
        };
        let taps = SampleTaps::build(&sampler, 8, f);
        assert_eq!(taps.values().len(), 4 + TAP_NODES * 8 * TAP_VALUES);
        assert_eq!(taps.values()[0], 8.0);
        let mut checked = 0;
        for node in [0, 5, TAP_AZIMUTHS + 3, TAP_NODES / 2 + 17, TAP_NODES - 1] {
            let (i, j) = (node / TAP_AZIMUTHS, node % TAP_AZIMUTHS);
            let wo = direction(
                grid_elevation(i, TAP_ELEVATIONS),
                j as f64 * TAU / TAP_AZIMUTHS as f64,
            );
            for k in 0..8 {
                let tap = taps.tap(node, k);
                match sampler.sample(wo, hammersley(k, 8)) {
                    Some(s) => {
                        let weight = patch.eval(s.wi, wo) / s.pdf;
                        assert!(
                            (tap.wi.as_dvec3() - s.wi).length() < 1e-6,
                            "node {node} tap {k}"
                        );
                        assert!(
                            (tap.pdf as f64 / s.pdf - 1.0).abs() < 1e-6,
                            "node {node} tap {k}"
                        );
                        let difference = (tap.weight.as_dvec3() - weight).abs().max_element();
                        assert!(
                            difference <= 1e-6 * weight.max_element(),
                            "node {node} tap {k}"
                        );
                        checked += 1;
                    }
                    None => assert_eq!(tap.pdf, 0.0),
                }
            }
        }
        assert!(checked > 30, "{checked} taps checked");
    }

    /// Over many pixels' wo, each of the four nodes supplies close to its bilinear weight's
    /// share of the samples (what makes the estimate blend the nodes bilinearly).
    #[test]
    fn the_picks_follow_the_bilinear_weights() {
        let wo = DVec3::new(0.3, 0.5, 0.6).normalize();
        let nodes = grid_nodes(wo, TAP_ELEVATIONS, TAP_AZIMUTHS);
        let count = 4096;
        let mut shares = [0usize; 4];
        for k in 0..count {
            let chosen = pick_node(&nodes, tap_choice(k) as f64);
            shares[nodes
                .iter()
                .position(|&(n, _)| n == chosen)
                .expect("one of the four")] += 1;
        }
        for (share, &(_, weight)) in shares.iter().zip(&nodes) {
            assert!(
                (*share as f64 / count as f64 - weight).abs() < 2.0 / count as f64 * 8.0,
                "{shares:?} against {nodes:?}"
            );
        }
    }
}
