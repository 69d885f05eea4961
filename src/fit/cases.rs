//! The measured fits of issue 46, built in one place for the example that prints their
//! errors (`examples/fit_round_trips.rs`) and the benchmark that times them (`benches/fit.rs`):
//! a built-in fabric moved by up to [`CASE_MOVE`] and fitted like the unmoved one (a round
//! trip), or one of the paper's woven fabrics fitted from its weave and fibre alone; either
//! from [`CASE_SAMPLES`] samples of the truth's F (four fifths on uniform pairs, the rest on
//! its highlight cones) with [`CASE_NOISE`] multiplicative noise.

use super::parameters::{LikeFabric, Parametrisation, perturbed};
use super::samples::{Samples, synthetic_samples};
use super::weave::WeaveParameters;
use crate::formats::fabric_toml::FabricSet;
use crate::measure::direction_sets::{highlight_pairs, uniform_pairs};
use crate::model::Fabric;
use crate::weave::{Fibre, NamedWeave, Weave};

/// Samples of a case: four fifths on uniform pairs, the rest on the truth's highlight cones.
pub const CASE_SAMPLES: usize = 2000;
/// Multiplicative noise of a case's samples.
pub const CASE_NOISE: f64 = 0.03;
/// Largest move of a round trip's parameters, as a fraction of each one's range.
pub const CASE_MOVE: f64 = 0.3;

/// How a case describes its truth to the fit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CaseKind {
    /// `--like` the unmoved fabric; the truth is the fabric moved.
    RoundTrip,
    /// `--weave` with the fabric's weave and fibre; the truth is the fabric itself.
    ByWeave,
}

/// One fit to measure: what it fits, the truth it should recover, and the samples.
pub struct FitCase {
    pub parametrisation: Box<dyn Parametrisation>,
    /// The truth's values in the parametrisation where it has them (a round trip's moved
    /// vector), else the start.
    pub truth_values: Vec<f64>,
    pub truth: Fabric,
    pub samples: Samples,
    /// The seed the case's pairs and noise came from; fresh pairs for errors take the next
    /// ones (`seed + 4`, `seed + 5`).
    pub seed: u64,
}

/// The weave and fibre of a built-in fabric: the paper's five woven fabrics. Crepe de chine
/// and shot silk are plain (taffeta) weaves; the back of a warp satin, its weft floats along
/// x (`--back --swap`), is again a warp satin.
pub fn woven_as(name: &str) -> Option<(&'static str, Fibre)> {
    match name {
        "linen_plain" => Some(("plain", Fibre::Linen)),
        "silk_crepe_de_chine" | "silk_shot" => Some(("plain", Fibre::Silk)),
        "polyester_satin_charmeuse" | "polyester_satin_charmeuse_back" => {
            Some(("satin:5", Fibre::Polyester))
        }
        _ => None,
    }
}

/// The case of the built-in fabric `name`, with `samples` samples (a fifth of them on the
/// highlight cones); `None` for a name that is not built in, or not woven `ByWeave`. Seeds
/// follow the fabric's place in the built-in set, so a case is the same whichever others run.
pub fn fit_case(name: &str, kind: CaseKind, samples: usize) -> Option<FitCase> {
    let set = FabricSet::builtin();
    let k = set.fabrics().iter().position(|f| f.name == name)?;
    let fabric = set.fabrics()[k].clone();
    let seed = 0x46_0000 + 16 * k as u64;
    let (parametrisation, truth_values, truth): (Box<dyn Parametrisation>, _, _) = match kind {
        CaseKind::ByWeave => {
            let (spelling, fibre) = woven_as(name)?;
            let draft = spelling.parse::<NamedWeave>().ok()?.draft();
            let parameters = WeaveParameters::new(&Weave::new(draft), name, Some(fibre.eta()));
            let start = parameters.start();
            (Box::new(parameters), start, fabric)
        }
        CaseKind::RoundTrip => {
            let like = LikeFabric::new(&fabric, None);
            let moved_values = perturbed(&like, CASE_MOVE, seed);
            let moved = like.fabric(&moved_values);
            (Box::new(like), moved_values, moved)
        }
    };
    let uniform = samples * 4 / 5;
    let mut pairs = uniform_pairs(uniform, seed + 1);
    pairs.extend(highlight_pairs(&truth, samples - uniform, seed + 2));
    let samples = Samples {
        samples: synthetic_samples(&truth, &pairs, CASE_NOISE, seed + 3),
        origin: "synthetic".into(),
        sha256: String::new(),
    };
    Some(FitCase {
        parametrisation,
        truth_values,
        truth,
        samples,
        seed,
    })
}
