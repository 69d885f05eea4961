//! The pictures of F beside the drape (issue 48, "the BRDF in pictures"), as plain data
//! that the viewer draws (`src/viewer/edit/plots_ui.rs`) and a test reads back:
//!
//! - F in the plane of incidence of a chosen wi, one series per incident angle;
//! - F over the outgoing hemisphere for one wi, as values and a false-colour image;
//! - the directional albedo over outgoing elevation ([`crate::sampling::albedo_curve`],
//!   what `clothbake albedo` prints);
//! - each thread's tangent-curve distribution ([`curves`]) and a weave's drawdown.
//!
//! F comes from one evaluator of the registry, prepared for the fabric as `clothbake eval
//! --evaluator SPELLING` prepares it, and the directions are normalised as `eval` normalises
//! its input, so each plotted value is the one `eval` prints for the same pair
//! (tests/cli/plots.rs). Angles θ are
//! measured from the normal (z), azimuths φ from thread 1 (x) towards thread 2 (y).

pub mod colour;
pub mod curves;

pub use colour::{HEMISPHERE_DECADES, colour_map, luminance};
pub use curves::{CurveDistribution, DRAWDOWN_MAX_SIDE, Drawdown};

use crate::evaluator::{self, EvaluationContext, Evaluator, EvaluatorError, FabricEvaluator};
use crate::formats::json_lines::unit_direction;
use crate::model::{Fabric, FabricError};
use crate::sampling::{AlbedoRow, Sampler, albedo_curve};
use glam::DVec3;
use std::hash::{Hash, Hasher};
use std::sync::Arc;

/// What the plots show and how finely; [`PlotSettings::default`] is what the editor draws.
#[derive(Clone)]
pub struct PlotSettings {
    /// The evaluation of F (default: `resonant`, the editor's live shading).
    pub evaluator: Arc<dyn Evaluator>,
    /// Azimuth φi of wi in degrees, for the plane of incidence and the hemisphere.
    pub phi_i_deg: f64,
    /// The incident angles θi (degrees from the normal, in [0, 90)) of the plane's series.
    pub plane_theta_i_deg: Vec<f64>,
    /// Points per plane series, evenly spaced over signed θo from −90° to 90°.
    pub plane_points: usize,
    /// The incident angle θi (degrees from the normal) of the hemisphere image.
    pub hemisphere_theta_i_deg: f64,
    /// Pixels per side of the hemisphere image.
    pub hemisphere_size: usize,
    /// Importance samples per outgoing direction of the albedo curve.
    pub albedo_samples: usize,
    /// The density the albedo curve draws wi from: the fabric's own sampler
    /// ([`Sampler::for_fabric`], what `clothbake albedo` draws with) where the caller has
    /// one, or (`None`) [`uniform_sampler`]. Building the fabric's sampler tabulates F over
    /// every cell of every node, seconds per fabric, too slow for every edit; any density is
    /// unbiased where it covers F's support, and the uniform one covers the hemisphere, so
    /// only the estimate's variance (its rows' `standard_error`) changes.
    pub albedo_sampler: Option<Arc<Sampler>>,
    /// Bins of a curve's histogram over −90°..90°.
    pub curve_bins: usize,
}

impl Default for PlotSettings {
    fn default() -> Self {
        Self {
            evaluator: evaluator::parse("resonant").expect("the resonant spelling parses"),
            phi_i_deg: 0.0,
            plane_theta_i_deg: vec![15.0, 45.0, 75.0],
            plane_points: 181,
            hemisphere_theta_i_deg: 45.0,
            hemisphere_size: 96,
            albedo_samples: 512,
            albedo_sampler: None,
            curve_bins: 90,
        }
    }
}

impl std::fmt::Debug for PlotSettings {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        // The sampler's tables are millions of numbers: only whether there is one.
        f.debug_struct("PlotSettings")
            .field("evaluator", &self.evaluator.spelling())
            .field("phi_i_deg", &self.phi_i_deg)
            .field("plane_theta_i_deg", &self.plane_theta_i_deg)
            .field("plane_points", &self.plane_points)
            .field("hemisphere_theta_i_deg", &self.hemisphere_theta_i_deg)
            .field("hemisphere_size", &self.hemisphere_size)
            .field("albedo_samples", &self.albedo_samples)
            .field(
                "albedo_sampler",
                &self.albedo_sampler.as_ref().map(|_| ".."),
            )
            .field("curve_bins", &self.curve_bins)
            .finish()
    }
}

/// The sampler of a constant F: wi uniform in solid angle over the hemisphere (with the
/// sampler's cosine share), the same for every fabric, so built once.
pub fn uniform_sampler() -> &'static Sampler {
    static UNIFORM: std::sync::OnceLock<Sampler> = std::sync::OnceLock::new();
    UNIFORM.get_or_init(|| Sampler::build(|_, _| DVec3::ONE))
}

/// Largest sizes a setting may ask for: far beyond what a panel shows, and a bound on the
/// work one recomputation can be asked to do.
const MAX_PLANE_POINTS: usize = 4096;
const MAX_PLANE_SERIES: usize = 16;
const MAX_HEMISPHERE_SIZE: usize = 1024;
const MAX_ALBEDO_SAMPLES: usize = 1 << 20;
const MAX_CURVE_BINS: usize = 1800;

/// Why the plots could not be computed.
#[derive(Debug, thiserror::Error)]
pub enum PlotError {
    #[error(transparent)]
    Fabric(#[from] FabricError),
    #[error(transparent)]
    Evaluator(#[from] EvaluatorError),
    #[error("plot setting '{field}': {message}")]
    Setting {
        field: &'static str,
        message: String,
    },
}

impl PlotSettings {
    /// Checks every setting is finite and within its range, naming the one that is not.
    pub fn validate(&self) -> Result<(), PlotError> {
        let fail = |field, message: String| Err(PlotError::Setting { field, message });
        let incident = |theta: f64| theta.is_finite() && (0.0..90.0).contains(&theta);
        if !self.phi_i_deg.is_finite() {
            return fail(
                "phi_i_deg",
                format!("must be finite, got {}", self.phi_i_deg),
            );
        }
        if self.plane_theta_i_deg.len() > MAX_PLANE_SERIES {
            return fail("plane_theta_i_deg", format!("at most {MAX_PLANE_SERIES}"));
        }
        if let Some(t) = self.plane_theta_i_deg.iter().find(|&&t| !incident(t)) {
            return fail("plane_theta_i_deg", format!("must be in [0, 90), got {t}"));
        }
        if !incident(self.hemisphere_theta_i_deg) {
            let t = self.hemisphere_theta_i_deg;
            return fail(
                "hemisphere_theta_i_deg",
                format!("must be in [0, 90), got {t}"),
            );
        }
        for (field, value, range) in [
            ("plane_points", self.plane_points, 2..=MAX_PLANE_POINTS),
            (
                "hemisphere_size",
                self.hemisphere_size,
                1..=MAX_HEMISPHERE_SIZE,
            ),
            (
                "albedo_samples",
                self.albedo_samples,
                16..=MAX_ALBEDO_SAMPLES,
            ),
            ("curve_bins", self.curve_bins, 1..=MAX_CURVE_BINS),
        ] {
            if !range.contains(&value) {
                let (lo, hi) = (range.start(), range.end());
                return fail(field, format!("must be in {lo}..={hi}, got {value}"));
            }
        }
        Ok(())
    }
}

/// The unit direction at angle `theta_deg` from the normal and azimuth `phi_deg`, normalised
/// as `clothbake eval` normalises its input (so `eval`, given it, evaluates the same vector
/// to within an ulp).
pub fn direction(theta_deg: f64, phi_deg: f64) -> DVec3 {
    let (sin_t, cos_t) = theta_deg.to_radians().sin_cos();
    let (sin_p, cos_p) = phi_deg.to_radians().sin_cos();
    as_eval_reads([sin_t * cos_p, sin_t * sin_p, cos_t])
}

/// `v` normalised as `eval` normalises a direction it reads.
fn as_eval_reads(v: [f64; 3]) -> DVec3 {
    unit_direction(v, "w").expect("plotted directions are finite and non-zero")
}

/// One point of a plane-of-incidence series.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlanePoint {
    /// Signed θo in degrees: positive towards the mirror direction (azimuth φi + 180°),
    /// negative back towards the light (azimuth φi).
    pub theta_o_deg: f64,
    /// The outgoing direction evaluated.
    pub wo: [f64; 3],
    /// F(wi, wo), RGB, cosines included.
    pub f: [f64; 3],
}

impl PlanePoint {
    /// The luminance of F ([`luminance`]).
    pub fn luminance(&self) -> f64 {
        luminance(self.f)
    }
}

/// F in the plane of incidence for one wi.
#[derive(Clone, Debug, PartialEq)]
pub struct PlaneSeries {
    /// θi in degrees from the normal.
    pub theta_i_deg: f64,
    pub wi: [f64; 3],
    /// Points in order of θo, from −90° to 90°.
    pub points: Vec<PlanePoint>,
}

/// The outgoing direction at signed angle `theta_o_deg` in the plane of azimuth `phi_i_deg`
/// (positive towards the mirror side, see [`PlanePoint::theta_o_deg`]).
pub fn plane_direction(theta_o_deg: f64, phi_i_deg: f64) -> DVec3 {
    direction(-theta_o_deg, phi_i_deg)
}

/// F over the outgoing hemisphere for one wi, on a square grid over the orthographic
/// projection of wo: pixel (column, row) has its centre at x = 2(column + ½)/size − 1
/// (thread 1, rightwards), y = 1 − 2(row + ½)/size (thread 2, upwards), and wo =
/// (x, y, √(1 − x² − y²)) where x² + y² < 1. Equal areas of the image are equal
/// projected solid angles (cos θo dwo).
#[derive(Clone, Debug, PartialEq)]
pub struct HemisphereImage {
    pub size: usize,
    /// θi in degrees from the normal; wi's azimuth is the settings' φi.
    pub theta_i_deg: f64,
    pub wi: [f64; 3],
    /// F per pixel, row-major from the top row; `None` outside the disc.
    pub f: Vec<Option<[f64; 3]>>,
    /// The false colour per pixel ([`colour::false_colour`]): the luminance of F on a log
    /// scale over [`Self::log10_range`], transparent outside the disc.
    pub rgba: Vec<[u8; 4]>,
    /// log10 of the luminance at the bottom and the top of the colour map.
    pub log10_range: (f64, f64),
    /// A hash of `size` and `rgba`: the same key, the same picture (a texture is uploaded
    /// again only when it changes).
    pub key: u64,
}

impl HemisphereImage {
    /// The outgoing direction at the centre of pixel (`column`, `row`), `None` outside the
    /// disc.
    pub fn wo(size: usize, column: usize, row: usize) -> Option<DVec3> {
        let x = 2.0 * (column as f64 + 0.5) / size as f64 - 1.0;
        let y = 1.0 - 2.0 * (row as f64 + 0.5) / size as f64;
        let r2 = x * x + y * y;
        (r2 < 1.0).then(|| as_eval_reads([x, y, (1.0 - r2).sqrt()]))
    }
}

/// Every picture of F for one fabric and one set of [`PlotSettings`].
#[derive(Clone, Debug, PartialEq)]
pub struct BrdfPlots {
    /// The fabric's name.
    pub fabric: String,
    /// The evaluator's spelling (what `eval --evaluator` takes to give the same F).
    pub evaluator: String,
    /// Azimuth φi of every wi, degrees.
    pub phi_i_deg: f64,
    /// One series per θi of the settings, in their order.
    pub plane: Vec<PlaneSeries>,
    pub hemisphere: HemisphereImage,
    /// The directional albedo ∫F dwi over outgoing elevation, by `clothbake albedo`'s
    /// estimator ([`albedo_curve`]) with the settings' sampler and samples per direction
    /// (with the fabric's own sampler, the very rows `clothbake albedo` prints).
    pub albedo: Vec<AlbedoRow>,
    /// Thread 1's and thread 2's tangent-curve distributions.
    pub curves: [CurveDistribution; 2],
}

impl BrdfPlots {
    /// The plots of `fabric` with F from `settings.evaluator`, prepared for the fabric (in
    /// the default [`EvaluationContext`], as `eval` prepares it). Deterministic: evaluations
    /// run in parallel but every value is computed alone.
    pub fn compute(fabric: &Fabric, settings: &PlotSettings) -> Result<Self, PlotError> {
        settings.validate()?;
        fabric.validate()?;
        let evaluation = settings
            .evaluator
            .prepare(fabric, &EvaluationContext::default())?;
        Ok(Self::of_evaluation(
            fabric,
            &settings.evaluator.spelling(),
            evaluation.as_ref(),
            settings,
        ))
    }

    /// The plots of `fabric` with F from `evaluation`, an evaluation already prepared for it
    /// by the evaluator spelt `spelling`; `settings` must be valid
    /// ([`PlotSettings::validate`]) and its evaluator is not used.
    pub fn of_evaluation(
        fabric: &Fabric,
        spelling: &str,
        evaluation: &dyn FabricEvaluator,
        settings: &PlotSettings,
    ) -> Self {
        let phi = settings.phi_i_deg;
        let n = settings.plane_points;
        let theta_o = |k: usize| -90.0 + 180.0 * k as f64 / (n - 1) as f64;
        let size = settings.hemisphere_size;
        let hemisphere_wi = direction(settings.hemisphere_theta_i_deg, phi);
        let disc: Vec<Option<DVec3>> = (0..size * size)
            .map(|p| HemisphereImage::wo(size, p % size, p / size))
            .collect();
        // One batch for the plane and the hemisphere: the plane's pairs first, then the
        // disc's pixels in row order.
        let plane_wi: Vec<DVec3> = settings
            .plane_theta_i_deg
            .iter()
            .map(|&t| direction(t, phi))
            .collect();
        let mut pairs: Vec<(DVec3, DVec3)> = plane_wi
            .iter()
            .flat_map(|&wi| (0..n).map(move |k| (wi, plane_direction(theta_o(k), phi))))
            .collect();
        pairs.extend(disc.iter().flatten().map(|&wo| (hemisphere_wi, wo)));
        let values = evaluation.eval_batch(&pairs);
        let (plane_values, disc_values) = values.split_at(plane_wi.len() * n);

        let plane = settings
            .plane_theta_i_deg
            .iter()
            .zip(&plane_wi)
            .zip(plane_values.chunks(n))
            .map(|((&theta_i_deg, wi), f)| PlaneSeries {
                theta_i_deg,
                wi: wi.to_array(),
                points: (0..n)
                    .map(|k| PlanePoint {
                        theta_o_deg: theta_o(k),
                        wo: plane_direction(theta_o(k), phi).to_array(),
                        f: f[k].to_array(),
                    })
                    .collect(),
            })
            .collect();

        let mut disc_values = disc_values.iter();
        let f: Vec<Option<[f64; 3]>> = disc
            .iter()
            .map(|wo| wo.map(|_| disc_values.next().expect("a value per pixel").to_array()))
            .collect();
        let (rgba, log10_range) = colour::false_colour(&f);
        let mut hasher = std::collections::hash_map::DefaultHasher::new();
        (size, &rgba).hash(&mut hasher);
        let hemisphere = HemisphereImage {
            size,
            theta_i_deg: settings.hemisphere_theta_i_deg,
            wi: hemisphere_wi.to_array(),
            f,
            rgba,
            log10_range,
            key: hasher.finish(),
        };

        let sampler = settings
            .albedo_sampler
            .as_deref()
            .unwrap_or_else(|| uniform_sampler());
        let albedo = albedo_curve(
            sampler,
            |wi, wo| evaluation.eval(wi, wo),
            settings.albedo_samples,
        );
        let curves = fabric
            .threads()
            .map(|t| CurveDistribution::of(t, &fabric.options, settings.curve_bins));
        Self {
            fabric: fabric.name.clone(),
            evaluator: spelling.to_string(),
            phi_i_deg: phi,
            plane,
            hemisphere,
            albedo,
            curves,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::formats::fabric_toml::FabricSet;

    fn small() -> PlotSettings {
        PlotSettings {
            plane_points: 37,
            hemisphere_size: 24,
            albedo_samples: 64,
            ..PlotSettings::default()
        }
    }

    fn satin() -> Fabric {
        FabricSet::builtin()
            .require("polyester_satin_charmeuse")
            .unwrap()
            .clone()
    }

    #[test]
    fn values_are_finite_and_not_negative_and_the_series_span_the_plane() {
        let plots = BrdfPlots::compute(&satin(), &small()).unwrap();
        assert_eq!(plots.evaluator, "resonant:6/5/2");
        assert_eq!(plots.plane.len(), 3);
        for series in &plots.plane {
            assert_eq!(series.points.len(), 37);
            assert_eq!(series.points[0].theta_o_deg, -90.0);
            assert_eq!(series.points[36].theta_o_deg, 90.0);
            assert!((DVec3::from(series.wi).length() - 1.0).abs() < 1e-15);
            for p in &series.points {
                assert!(p.f.iter().all(|c| c.is_finite() && *c >= 0.0), "{p:?}");
            }
            // Some light is reflected in the plane at every incident angle.
            assert!(series.points.iter().any(|p| p.luminance() > 0.0));
        }
        let pixels = plots.hemisphere.f.iter().flatten();
        assert!(pixels.flatten().all(|c| c.is_finite() && *c >= 0.0));
        for row in &plots.albedo {
            let rgb = row.mean.to_array();
            assert!(rgb.iter().all(|c| c.is_finite() && *c >= 0.0), "{row:?}");
        }
    }

    #[test]
    fn the_mirror_side_is_positive_theta_o() {
        // A satin's surface lobe lies about the mirror direction: the brightest point of the
        // 45° series is on the positive side.
        let plots = BrdfPlots::compute(&satin(), &small()).unwrap();
        let series = &plots.plane[1];
        let top = series
            .points
            .iter()
            .max_by(|a, b| a.luminance().total_cmp(&b.luminance()))
            .unwrap();
        assert!(top.theta_o_deg > 0.0, "{top:?}");
        let wo = DVec3::from(top.wo);
        assert!(wo.x < 0.0 && wo.z > 0.0, "{wo}");
    }

    #[test]
    fn the_image_is_transparent_outside_the_disc_and_opaque_inside() {
        let plots = BrdfPlots::compute(&satin(), &small()).unwrap();
        let image = &plots.hemisphere;
        assert_eq!(image.rgba.len(), 24 * 24);
        let mut inside = 0;
        for row in 0..24 {
            for column in 0..24 {
                let p = row * 24 + column;
                let wo = HemisphereImage::wo(24, column, row);
                assert_eq!(wo.is_some(), image.f[p].is_some());
                assert_eq!(image.rgba[p][3], if wo.is_some() { 255 } else { 0 });
                inside += usize::from(wo.is_some());
            }
        }
        // The disc covers π/4 of the square, to within its staircase edge.
        let share = inside as f64 / (24.0 * 24.0);
        assert!(
            (share - std::f64::consts::FRAC_PI_4).abs() < 0.03,
            "{share}"
        );
        // Corners out, centre in; the top row is thread 2's positive side.
        assert_eq!(image.rgba[0][3], 0);
        assert!(HemisphereImage::wo(24, 12, 0).is_some_and(|w| w.y > 0.9));
        assert!(HemisphereImage::wo(24, 23, 12).is_some_and(|w| w.x > 0.9));
    }

    #[test]
    fn the_result_does_not_depend_on_the_thread_count() {
        let run = |threads| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| BrdfPlots::compute(&satin(), &small()).unwrap())
        };
        assert_eq!(run(1), run(3));
    }

    #[test]
    fn bad_settings_and_fabrics_are_refused_by_name() {
        let refused = |settings: PlotSettings| {
            BrdfPlots::compute(&satin(), &settings)
                .unwrap_err()
                .to_string()
        };
        let message = refused(PlotSettings {
            plane_theta_i_deg: vec![30.0, f64::NAN],
            ..small()
        });
        assert!(message.contains("plane_theta_i_deg"), "{message}");
        let message = refused(PlotSettings {
            hemisphere_size: 0,
            ..small()
        });
        assert!(message.contains("hemisphere_size"), "{message}");
        let message = refused(PlotSettings {
            hemisphere_theta_i_deg: 90.0,
            ..small()
        });
        assert!(message.contains("hemisphere_theta_i_deg"), "{message}");
        let mut fabric = satin();
        fabric.thread1.coverage = 2.0;
        let message = BrdfPlots::compute(&fabric, &small())
            .unwrap_err()
            .to_string();
        assert!(message.contains("coverage"), "{message}");
    }
}
