//! A fit from a weave draft alone (`clothbake fit --weave`): the draft fixes the floats and
//! the face fractions; the fit chooses each yarn's shape knobs, its cover where the draft's
//! spacing and thickness do not fix it, and its optics.

use super::parameters::{
    ETA_RANGE, FreeParameter, GAMMA_S_RANGE_DEG, GAMMA_V_RANGE_DEG, Parametrisation,
};
use crate::model::Fabric;
use crate::weave::{Family, Weave, Yarn};

/// Largest crimp a fit tries, in degrees: steeper than any woven yarn's tilt, short of the
/// pile's 90°.
pub const CRIMP_RANGE_DEG: (f64, f64) = (0.0, 80.0);
/// Largest share of straight legs a fit tries.
pub const LEGS_RANGE: (f64, f64) = (0.0, 0.9);
/// Range of an arc's squash: down to an ellipse of aspect 0.05.
pub const SQUASH_RANGE: (f64, f64) = (0.0, 0.95);
/// Range of the tilt where an arc's two pieces meet, as a share of the crimp.
pub const KNEE_RANGE: (f64, f64) = (0.05, 0.95);
/// Range of a float's sag: up to the steepest crimp a fit tries.
pub const SAG_RANGE_DEG: (f64, f64) = CRIMP_RANGE_DEG;
/// Least start of `legs`, `squash` and `sag` in a fit. At 0 each is where the fit can barely
/// move it: `legs` and `squash` sit on their lower bound, where the bound transform's slope
/// vanishes; `sag` at 0 is a stationary point of F (its curve's ±sag parts move in opposite
/// directions), and at `squash` 0 the `knee` changes nothing. A yarn's own larger value is
/// kept.
pub const START_LEGS: f64 = 0.3;
pub const START_SQUASH: f64 = 0.3;
pub const START_SAG_DEG: f64 = 5.0;
/// Starts of a fit from a weave: the two schedules of broadened lobes from the knobs, and one
/// perturbed start. The knobs' shapes overlap (a squashed arc and straight legs both put
/// length at large tilts), so the objective has more than one basin from a default start.
pub const WEAVE_STARTS: usize = 3;
/// Smallest cover factor a fit tries: a gauze.
pub const COVER_RANGE: (f64, f64) = (0.05, 1.0);

/// What each free parameter of a [`WeaveParameters`] sets, per family (0 warp, 1 weft).
#[derive(Clone, Copy, Debug, PartialEq)]
enum Knob {
    Crimp,
    Legs,
    Flatten,
    Squash,
    Knee,
    Sag,
    Cover,
    Eta,
    Albedo(usize),
    Kd,
    GammaS,
    GammaV,
}

/// The free parameters of a weave: per yarn crimp, legs, squash, knee, flatten and sag (these
/// two only where the yarn floats over more than one crossing, for they shape nothing else),
/// cover (unless the draft's spacing and thickness or the yarn's knob fix it), η (unless a
/// fibre fixes it), the RGB albedo A (each channel in [0, 1]), kd, γs and γv. The fabric is
/// the weave's ([`Weave::fabric`]) with A written as `albedo = A / max A`, `albedo_scale =
/// max A`.
#[derive(Clone, Debug)]
pub struct WeaveParameters {
    weave: Weave,
    name: String,
    parameters: Vec<FreeParameter>,
    knobs: Vec<(usize, Knob)>,
}

impl WeaveParameters {
    /// Frees the knobs of `weave`'s yarns, starting from their values; `fixed_eta` fixes η.
    pub fn new(weave: &Weave, name: &str, fixed_eta: Option<f64>) -> Self {
        let mut weave = weave.clone();
        let mut parameters = Vec::new();
        let mut knobs = Vec::new();
        for (j, family) in [Family::Warp, Family::Weft].into_iter().enumerate() {
            let cover_free = weave.yarn(family).cover.is_none() && {
                let yarns = weave.draft.yarns(family);
                yarns.spacing.is_none() || yarns.thickness.is_none()
            };
            let colour = weave.colour(family);
            let long_floats = weave.draft.floats(family).iter().any(|&(l, _)| l > 1);
            let yarn = match family {
                Family::Warp => &mut weave.warp,
                Family::Weft => &mut weave.weft,
            };
            if let Some(eta) = fixed_eta {
                yarn.eta = eta;
            }
            let label = ["warp", "weft"][j];
            let mut free = |knob: Knob, name: &str, (lo, hi): (f64, f64), start: f64| {
                parameters.push(FreeParameter::new(format!("{label}.{name}"), lo, hi, start));
                knobs.push((j, knob));
            };
            free(Knob::Crimp, "crimp", CRIMP_RANGE_DEG, yarn.crimp_deg);
            free(Knob::Legs, "legs", LEGS_RANGE, yarn.legs.max(START_LEGS));
            free(
                Knob::Squash,
                "squash",
                SQUASH_RANGE,
                yarn.squash.max(START_SQUASH),
            );
            free(Knob::Knee, "knee", KNEE_RANGE, yarn.knee);
            if long_floats {
                free(Knob::Flatten, "flatten", (0.0, 1.0), yarn.flatten);
                free(
                    Knob::Sag,
                    "sag_deg",
                    SAG_RANGE_DEG,
                    yarn.sag_deg.max(START_SAG_DEG),
                );
            }
            if cover_free {
                free(Knob::Cover, "cover", COVER_RANGE, yarn.cover.unwrap_or(1.0));
            }
            if fixed_eta.is_none() {
                free(Knob::Eta, "eta", ETA_RANGE, yarn.eta);
            }
            for (c, value) in colour.into_iter().enumerate() {
                let a = (value * yarn.albedo_scale).min(1.0);
                free(Knob::Albedo(c), &format!("A[{c}]"), (0.0, 1.0), a);
            }
            free(Knob::Kd, "kd", (0.0, 1.0), yarn.kd);
            free(
                Knob::GammaS,
                "gamma_s_deg",
                GAMMA_S_RANGE_DEG,
                yarn.gamma_s_deg,
            );
            free(
                Knob::GammaV,
                "gamma_v_deg",
                GAMMA_V_RANGE_DEG,
                yarn.gamma_v_deg,
            );
        }
        Self {
            weave,
            name: name.to_string(),
            parameters,
            knobs,
        }
    }
}

impl Parametrisation for WeaveParameters {
    fn parameters(&self) -> &[FreeParameter] {
        &self.parameters
    }

    fn default_starts(&self) -> Option<usize> {
        Some(WEAVE_STARTS)
    }

    fn fabric(&self, values: &[f64]) -> Fabric {
        let mut yarns: [Yarn; 2] = [self.weave.warp.clone(), self.weave.weft.clone()];
        let mut albedo = [[0.0; 3]; 2];
        for (((j, knob), p), &v) in self.knobs.iter().zip(&self.parameters).zip(values) {
            let v = if v.is_finite() { p.clamp(v) } else { p.start };
            let yarn = &mut yarns[*j];
            match knob {
                Knob::Crimp => yarn.crimp_deg = v,
                Knob::Legs => yarn.legs = v,
                Knob::Flatten => yarn.flatten = v,
                Knob::Squash => yarn.squash = v,
                Knob::Knee => yarn.knee = v,
                Knob::Sag => yarn.sag_deg = v,
                Knob::Cover => yarn.cover = Some(v),
                Knob::Eta => yarn.eta = v,
                Knob::Albedo(c) => albedo[*j][*c] = v,
                Knob::Kd => yarn.kd = v,
                Knob::GammaS => yarn.gamma_s_deg = v,
                Knob::GammaV => yarn.gamma_v_deg = v,
            }
        }
        let [warp, weft] = yarns;
        let weave = Weave {
            draft: self.weave.draft.clone(),
            warp,
            weft,
        };
        // Every knob within its bounds makes a valid fabric (tested); should one not, the
        // start does, which the fit then sees as no improvement rather than a crash.
        let mut fabric = weave.fabric(&self.name).unwrap_or_else(|_| {
            self.weave
                .fabric(&self.name)
                .expect("the start is validated when the parameters are made")
        });
        for (thread, a) in [&mut fabric.thread1, &mut fabric.thread2]
            .into_iter()
            .zip(albedo)
        {
            super::parameters::set_albedo(thread, a);
        }
        fabric
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fit::parameters::assert_every_vector_is_valid;
    use crate::weave::NamedWeave;

    #[test]
    fn every_vector_within_the_bounds_is_a_valid_fabric() {
        for spelling in ["plain", "twill:2/1", "satin:8", "sateen:5"] {
            let mut weave = Weave::new(spelling.parse::<NamedWeave>().unwrap().draft());
            let parameters = WeaveParameters::new(&weave, "w", None);
            let start = parameters.fabric(&parameters.start());
            // The start is the weave's own knobs, raised to the least starts.
            for yarn in [&mut weave.warp, &mut weave.weft] {
                yarn.set_all(&format!(
                    "legs={START_LEGS},squash={START_SQUASH},sag={START_SAG_DEG}"
                ))
                .unwrap();
            }
            assert_eq!(
                start.thread1.offsets_deg,
                weave.fabric("w").unwrap().thread1.offsets_deg
            );
            assert_every_vector_is_valid(&parameters, 3);
            let fixed = WeaveParameters::new(&weave, "w", Some(1.345));
            assert_eq!(fixed.parameters().len() + 2, parameters.parameters().len());
        }
    }
}
