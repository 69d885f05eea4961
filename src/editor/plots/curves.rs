//! The pictures of a fabric's structure: each thread's tangent-curve distribution (the share
//! of the curve at each tangent offset α, as the model integrates over it) and a weave's
//! drawdown.

use crate::model::curve::{Integration, curve_pieces};
use crate::model::{ModelOptions, Thread};
use crate::weave::draft::Draft;

/// The distribution of a thread's tangent offset α over its curve, the weights the model's
/// curve mean ⟨x⟩ gives each α (docs/model.md#tangent-curves): segments that sweep α hold
/// their arc-length share uniformly over their α interval (the histogram), flat segments
/// and single control points hold theirs at one α (the point masses). The histogram's
/// masses and the point masses add up to 1.
#[derive(Clone, Debug, PartialEq)]
pub struct CurveDistribution {
    /// The share of the curve in each of the equal bins over α from −90° to 90°, bin k
    /// covering −90° + k·w to −90° + (k + 1)·w with w = 180°/bins.
    pub histogram: Vec<f64>,
    /// (α in degrees, share of the curve) of each point mass, in curve order.
    pub point_masses: Vec<(f64, f64)>,
    /// The control points as (cumulative arc-length fraction in [0, 1], offset in degrees),
    /// for a line plot of the curve: α against the position along it.
    pub control_points: Vec<(f64, f64)>,
}

impl CurveDistribution {
    /// The distribution of `thread`'s curve under `options` (its tangent sampling: uniform
    /// in arc length, or the control points alone), its histogram in `bins` bins (≥ 1).
    pub fn of(thread: &Thread, options: &ModelOptions, bins: usize) -> Self {
        let bins = bins.max(1);
        let width = 180.0 / bins as f64;
        let mut histogram = vec![0.0; bins];
        let mut point_masses = Vec::new();
        // The intervals and masses are the same for every integration rule that integrates
        // the segments (only their midpoint counts differ); the direct rule's are taken.
        for piece in curve_pieces(thread, options, Integration::Direct) {
            let (a, b) = (piece.start.to_degrees(), piece.end.to_degrees());
            if piece.end <= piece.start {
                point_masses.push((a, piece.weight));
                continue;
            }
            // Spread the piece's share over the bins by the length of its overlap with each.
            let first = (((a + 90.0) / width).floor().max(0.0) as usize).min(bins - 1);
            let last = (((b + 90.0) / width).ceil().max(1.0) as usize).min(bins);
            for (k, bin) in histogram.iter_mut().enumerate().take(last).skip(first) {
                let lo = -90.0 + k as f64 * width;
                let overlap = (b.min(lo + width) - a.max(lo)).max(0.0);
                *bin += piece.weight * overlap / (b - a);
            }
        }
        Self {
            histogram,
            point_masses,
            control_points: control_points(thread),
        }
    }

    /// Width of one histogram bin in degrees.
    pub fn bin_width_deg(&self) -> f64 {
        180.0 / self.histogram.len() as f64
    }

    /// The centre of bin `k` in degrees.
    pub fn bin_centre_deg(&self, k: usize) -> f64 {
        -90.0 + (k as f64 + 0.5) * self.bin_width_deg()
    }

    /// The histogram as a density per degree (each bin's share over its width).
    pub fn density_per_deg(&self) -> Vec<f64> {
        let width = self.bin_width_deg();
        self.histogram.iter().map(|m| m / width).collect()
    }
}

/// `thread`'s control points against the cumulative share of arc length before each: the
/// segment lengths normalised to add up to 1 (one segment is the whole curve, whatever its
/// length; a lone control point sits at 0).
fn control_points(thread: &Thread) -> Vec<(f64, f64)> {
    let offsets = &thread.offsets_deg;
    let segments = offsets.len().saturating_sub(1);
    let total: f64 = thread.lengths.iter().take(segments).sum();
    let mut along = 0.0;
    offsets
        .iter()
        .enumerate()
        .map(|(k, &offset)| {
            if k > 0 {
                along += if segments == 1 {
                    1.0
                } else if total > 0.0 {
                    thread.lengths.get(k - 1).copied().unwrap_or(0.0) / total
                } else {
                    0.0
                };
            }
            (along, offset)
        })
        .collect()
}

/// Most ends and picks of a drawdown shown: a repeat of any named weave fits many times
/// over, and a WIF's full draft (up to thousands of threads) is cut to its first corner.
pub const DRAWDOWN_MAX_SIDE: usize = 64;

/// A weave's drawdown as a grid of crossings: pick 1 the top row, end 1 the left column
/// (the orientation of `clothbake weave --drawdown`).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Drawdown {
    /// Ends (columns) and picks (rows) shown.
    pub ends: usize,
    pub picks: usize,
    /// `warp_up[pick * ends + end]`: the warp end lies over the weft pick.
    pub warp_up: Vec<bool>,
    /// The draft's own ends and picks (larger than those shown where it was cut).
    pub draft_ends: usize,
    pub draft_picks: usize,
}

impl Drawdown {
    /// The drawdown of `draft`'s first [`DRAWDOWN_MAX_SIDE`] ends and picks at most.
    pub fn of(draft: &Draft) -> Self {
        let ends = draft.ends().min(DRAWDOWN_MAX_SIDE);
        let picks = draft.picks().min(DRAWDOWN_MAX_SIDE);
        Self {
            ends,
            picks,
            warp_up: (0..picks)
                .flat_map(|pick| (0..ends).map(move |end| draft.warp_up(end, pick)))
                .collect(),
            draft_ends: draft.ends(),
            draft_picks: draft.picks(),
        }
    }

    /// Whether the warp is on top at (`end`, `pick`), 0-based.
    pub fn warp_up(&self, end: usize, pick: usize) -> bool {
        self.warp_up[pick * self.ends + end]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::formats::fabric_toml::FabricSet;
    use crate::model::TangentSampling;
    use crate::weave::draft::NamedWeave;

    fn total(d: &CurveDistribution) -> f64 {
        d.histogram.iter().sum::<f64>() + d.point_masses.iter().map(|m| m.1).sum::<f64>()
    }

    #[test]
    fn every_built_in_thread_s_distribution_sums_to_one() {
        for fabric in FabricSet::builtin().fabrics() {
            for thread in fabric.threads() {
                for bins in [1, 7, 90, 180] {
                    let d = CurveDistribution::of(thread, &fabric.options, bins);
                    assert_eq!(d.histogram.len(), bins);
                    assert!(
                        (total(&d) - 1.0).abs() < 1e-12,
                        "{}: {}",
                        fabric.name,
                        total(&d)
                    );
                    assert!(d.histogram.iter().all(|&m| m >= 0.0));
                }
            }
        }
    }

    fn thread(offsets: &[f64], lengths: &[f64]) -> Thread {
        let mut t = FabricSet::builtin().fabrics()[0].thread1.clone();
        t.offsets_deg = offsets.to_vec();
        t.lengths = lengths.to_vec();
        t
    }

    #[test]
    fn a_sweep_spreads_uniformly_and_a_flat_segment_is_a_point_mass() {
        // −30° → 30° over half the arc length, then flat at 30° for the other half.
        let t = thread(&[-30.0, 30.0, 30.0], &[1.0, 1.0]);
        let d = CurveDistribution::of(&t, &ModelOptions::default(), 18);
        // Bins of 10°: the sweep covers bins 6..12 with 1/12 each.
        for (k, &m) in d.histogram.iter().enumerate() {
            let expected = if (6..12).contains(&k) { 0.5 / 6.0 } else { 0.0 };
            assert!((m - expected).abs() < 1e-12, "bin {k}: {m}");
        }
        assert_eq!(d.point_masses.len(), 1);
        assert!((d.point_masses[0].0 - 30.0).abs() < 1e-12);
        assert!((d.point_masses[0].1 - 0.5).abs() < 1e-12);
        assert_eq!(
            d.control_points,
            vec![(0.0, -30.0), (0.5, 30.0), (1.0, 30.0)]
        );
        assert!((d.density_per_deg()[6] - 0.5 / 60.0).abs() < 1e-15);
        assert_eq!(d.bin_centre_deg(0), -85.0);
    }

    #[test]
    fn control_point_sampling_and_a_single_point_are_point_masses_only() {
        let t = thread(&[-20.0, 10.0, 40.0], &[3.0, 1.0]);
        let options = ModelOptions {
            tangent_sampling: TangentSampling::ControlPoints,
            ..ModelOptions::default()
        };
        let d = CurveDistribution::of(&t, &options, 90);
        assert!(d.histogram.iter().all(|&m| m == 0.0));
        assert_eq!(d.point_masses.len(), 3);
        assert!((total(&d) - 1.0).abs() < 1e-12);
        assert_eq!(
            d.control_points,
            vec![(0.0, -20.0), (0.75, 10.0), (1.0, 40.0)]
        );
        let single = CurveDistribution::of(&thread(&[5.0], &[]), &options, 9);
        assert_eq!(single.point_masses.len(), 1);
        assert_eq!(single.control_points, vec![(0.0, 5.0)]);
    }

    #[test]
    fn a_sweep_to_the_ends_of_the_range_stays_in_the_histogram() {
        let t = thread(&[-90.0, 90.0], &[1.0]);
        let d = CurveDistribution::of(&t, &ModelOptions::default(), 4);
        assert!(
            d.histogram.iter().all(|&m| (m - 0.25).abs() < 1e-12),
            "{d:?}"
        );
    }

    #[test]
    fn the_drawdown_is_the_draft_s_and_a_large_draft_is_cut() {
        let draft = "twill:2/1".parse::<NamedWeave>().unwrap().draft();
        let d = Drawdown::of(&draft);
        assert_eq!((d.ends, d.picks), (draft.ends(), draft.picks()));
        for pick in 0..d.picks {
            for end in 0..d.ends {
                assert_eq!(d.warp_up(end, pick), draft.warp_up(end, pick));
            }
        }
        let large = Draft::from_fn(100, 70, |e, p| (e + p) % 3 == 0).unwrap();
        let d = Drawdown::of(&large);
        assert_eq!((d.ends, d.picks), (DRAWDOWN_MAX_SIDE, DRAWDOWN_MAX_SIDE));
        assert_eq!((d.draft_ends, d.draft_picks), (100, 70));
        assert!(d.warp_up(3, 0) && !d.warp_up(1, 0) && d.warp_up(2, 1));
    }
}
