//! A weave's yarn knobs as fields (`warp.crimp`, `weft.colour`, …), set through
//! [`crate::weave::Yarn::set`], and what each decides of the fabric when the weave is woven
//! again.

use super::{Access, ColourSpace, EditValue, FieldKind, FieldSpec};
use crate::model::Fabric;
use crate::weave::{Family, Weave, Yarn};

/// What a yarn knob decides of its thread when the weave is woven again: the rest of the
/// fabric keeps what it holds, hand edits included.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Decides {
    /// The thread's tangent curve (`offsets_deg` and `lengths`).
    Curve,
    /// Both threads' coverages (a family's cover changes how much of the other is seen).
    Coverages,
    Eta,
    /// The thread's `albedo`.
    Colour,
    AlbedoScale,
    Kd,
    GammaS,
    GammaV,
}

impl Decides {
    /// Copies what this knob decides of `family`'s thread from `woven`, the fabric the weave
    /// makes, into `fabric`.
    pub fn take(self, family: Family, woven: &Fabric, fabric: &mut Fabric) {
        if self == Decides::Coverages {
            fabric.thread1.coverage = woven.thread1.coverage;
            fabric.thread2.coverage = woven.thread2.coverage;
            return;
        }
        let (from, to) = match family {
            Family::Warp => (&woven.thread1, &mut fabric.thread1),
            Family::Weft => (&woven.thread2, &mut fabric.thread2),
        };
        match self {
            Decides::Curve => {
                to.offsets_deg.clone_from(&from.offsets_deg);
                to.lengths.clone_from(&from.lengths);
            }
            Decides::Coverages => {}
            Decides::Eta => to.eta = from.eta,
            Decides::Colour => to.albedo = from.albedo,
            Decides::AlbedoScale => to.albedo_scale = from.albedo_scale,
            Decides::Kd => to.kd = from.kd,
            Decides::GammaS => to.gamma_s_deg = from.gamma_s_deg,
            Decides::GammaV => to.gamma_v_deg = from.gamma_v_deg,
        }
    }
}

/// The sRGB encoding of a linear component in [0, 1] (IEC 61966-2-1), the inverse of
/// [`crate::weave::srgb_to_linear`].
pub fn linear_to_srgb(c: f64) -> f64 {
    if c <= 0.0031308 {
        c * 12.92
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    }
}

/// A yarn knob of one family.
macro_rules! knob {
    ($family:ident, $prefix:literal, $key:literal, $label:expr, $unit:expr, $range:expr,
     $decides:ident, $get:expr) => {
        knob!(
            $family,
            $prefix,
            $key,
            $label,
            $unit,
            $range,
            $decides,
            $get,
            FieldKind::Number
        )
    };
    ($family:ident, $prefix:literal, $key:literal, $label:expr, $unit:expr, $range:expr,
     $decides:ident, $get:expr, $kind:expr) => {
        FieldSpec {
            path: concat!($prefix, ".", $key),
            label: $label,
            unit: $unit,
            range: $range,
            access: Access::Knob {
                family: Family::$family,
                key: $key,
                kind: $kind,
                get: $get,
                decides: Decides::$decides,
            },
        }
    };
}

/// Every knob of one family, as the `weave` command spells them (`YARN_KEYS`), with
/// `fibre` left out: it is a name for an η, which `eta` sets.
macro_rules! knobs {
    ($family:ident, $prefix:literal) => {
        [
            knob!(
                $family,
                $prefix,
                "crimp",
                "crimp, largest tilt",
                "°",
                (0.0, 89.0),
                Curve,
                |w, f| EditValue::Number(w.yarn(f).crimp_deg)
            ),
            knob!(
                $family,
                $prefix,
                "legs",
                "legs, share of straight legs",
                "",
                (0.0, 0.95),
                Curve,
                |w, f| EditValue::Number(w.yarn(f).legs)
            ),
            knob!(
                $family,
                $prefix,
                "flatten",
                "flatten, flat share of long floats",
                "",
                (0.0, 1.0),
                Curve,
                |w, f| EditValue::Number(w.yarn(f).flatten)
            ),
            knob!(
                $family,
                $prefix,
                "squash",
                "squash of the arc",
                "",
                (0.0, 0.95),
                Curve,
                |w, f| EditValue::Number(w.yarn(f).squash)
            ),
            knob!(
                $family,
                $prefix,
                "knee",
                "knee of a squashed arc",
                "",
                (0.05, 0.95),
                Curve,
                |w, f| EditValue::Number(w.yarn(f).knee)
            ),
            knob!(
                $family,
                $prefix,
                "sag",
                "sag of long floats",
                "°",
                (0.0, 89.0),
                Curve,
                |w, f| EditValue::Number(w.yarn(f).sag_deg)
            ),
            knob!(
                $family,
                $prefix,
                "cover",
                "cover factor",
                "",
                (0.01, 1.0),
                Coverages,
                |w, f| EditValue::Number(w.cover(f))
            ),
            knob!(
                $family,
                $prefix,
                "eta",
                "η, refractive index",
                "",
                (1.0, 3.0),
                Eta,
                |w, f| EditValue::Number(w.yarn(f).eta)
            ),
            knob!(
                $family,
                $prefix,
                "colour",
                "colour, sRGB",
                "",
                (0.0, 1.0),
                Colour,
                |w, f| EditValue::Vector(yarn_colour(w, f).to_vec()),
                FieldKind::Colour(ColourSpace::Srgb)
            ),
            knob!(
                $family,
                $prefix,
                "albedo_scale",
                "albedo scale",
                "",
                (0.0, 10.0),
                AlbedoScale,
                |w, f| EditValue::Number(w.yarn(f).albedo_scale)
            ),
            knob!(
                $family,
                $prefix,
                "kd",
                "kd, isotropic share",
                "",
                (0.0, 1.0),
                Kd,
                |w, f| EditValue::Number(w.yarn(f).kd)
            ),
            knob!(
                $family,
                $prefix,
                "gamma_s",
                "γs, surface lobe width",
                "°",
                (0.1, 90.0),
                GammaS,
                |w, f| EditValue::Number(w.yarn(f).gamma_s_deg)
            ),
            knob!(
                $family,
                $prefix,
                "gamma_v",
                "γv, volume lobe width",
                "°",
                (0.1, 90.0),
                GammaV,
                |w, f| EditValue::Number(w.yarn(f).gamma_v_deg)
            ),
        ]
    };
}

/// A family's colour in sRGB: the yarn's knob, else the draft's (decoded, weighted by face,
/// [`Weave::colour`]) encoded again.
fn yarn_colour(weave: &Weave, family: Family) -> [f64; 3] {
    let yarn: &Yarn = weave.yarn(family);
    yarn.colour
        .unwrap_or_else(|| weave.colour(family).map(linear_to_srgb))
}

pub(super) const WARP: [FieldSpec; 13] = knobs!(Warp, "warp");
pub(super) const WEFT: [FieldSpec; 13] = knobs!(Weft, "weft");
