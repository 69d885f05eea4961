//! The fields the editor edits, as data: one registry, [`FIELDS`], of every fabric parameter
//! (by its path in the fabric file, `thread1.gamma_s_deg`, `options.sigma_u_deg`, …) and every
//! yarn knob of a weave (`warp.crimp`, `weft.colour`, …), each with its label, unit, slider
//! extents and how it is read and written. The panel draws one widget per entry and a script
//! names entries by path; neither matches on field names.
//!
//! The slider extents are only that: whether a value is allowed is decided by
//! [`Fabric::validate`] for the fabric's fields and by [`Yarn::set`] for the knobs.

use crate::model::Fabric;
use crate::model::fabric::MAX_CONTROL_POINTS;
use crate::weave::{Family, Weave, Yarn};
use serde::de::{DeserializeOwned, IntoDeserializer};

/// A value set on a field: by a slider or a number box ([`EditValue::Number`]), a colour
/// picker or a list of control points ([`EditValue::Vector`]), a menu ([`EditValue::Choice`])
/// or a text box ([`EditValue::Text`]).
#[derive(Clone, Debug, PartialEq)]
pub enum EditValue {
    Number(f64),
    Vector(Vec<f64>),
    Choice(String),
    Text(String),
}

/// An edit of one field, as the panel's widgets and a script's `set` make it.
#[derive(Clone, Debug, PartialEq)]
pub struct Edit {
    /// The field's path, [`FieldSpec::path`].
    pub field: String,
    pub value: EditValue,
}

impl Edit {
    pub fn new(field: impl Into<String>, value: EditValue) -> Self {
        Self {
            field: field.into(),
            value,
        }
    }
}

/// The space a colour's components are in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ColourSpace {
    /// Linear RGB, as the fabric's `albedo`.
    Linear,
    /// sRGB-encoded, as a yarn's `colour` knob.
    Srgb,
}

/// What a field holds, and so which widget edits it and how typed text is read.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FieldKind {
    /// One number.
    Number,
    /// A list of at most [`MAX_CONTROL_POINTS`] numbers (a tangent curve's offsets or lengths).
    List,
    /// Three components in [0, 1] (the albedo's may exceed 1).
    Colour(ColourSpace),
    /// One of the listed names.
    Choice(&'static [&'static str]),
    /// A name.
    Text,
}

/// How a fabric field is read and written. The setters take a value already checked against
/// the field's kind; whether the fabric it makes is valid is for [`Fabric::validate`].
#[derive(Clone, Copy, Debug)]
pub enum Access {
    Number {
        get: fn(&Fabric) -> f64,
        set: fn(&mut Fabric, f64),
    },
    List {
        get: fn(&Fabric) -> &[f64],
        set: fn(&mut Fabric, Vec<f64>),
    },
    Rgb {
        get: fn(&Fabric) -> [f64; 3],
        set: fn(&mut Fabric, [f64; 3]),
    },
    /// An option's variant, by its name in the fabric file (the serde name, so the file and
    /// the editor cannot spell it differently).
    Choice {
        choices: &'static [&'static str],
        /// Whether the fabric holds the named variant.
        holds: fn(&Fabric, &str) -> bool,
        /// Sets the named variant; false for a name that is none.
        set: fn(&mut Fabric, &str) -> bool,
    },
    /// The fabric's name.
    Name,
    /// A yarn knob of a weave, set through [`Yarn::set`] with `key`; `decides` is what of
    /// the fabric the knob makes when the weave is woven again.
    Knob {
        family: Family,
        key: &'static str,
        kind: FieldKind,
        get: fn(&Weave, Family) -> EditValue,
        decides: Decides,
    },
}

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

/// One editable field.
#[derive(Clone, Copy, Debug)]
pub struct FieldSpec {
    /// The path in the fabric file (`thread1.coverage`), or `warp.`/`weft.` and the
    /// `weave` command's knob key (`warp.crimp`).
    pub path: &'static str,
    pub label: &'static str,
    /// The unit shown after the value (`°`), or empty.
    pub unit: &'static str,
    /// The slider's extents; not the valid range (see the module's documentation).
    pub range: (f64, f64),
    pub access: Access,
}

impl FieldSpec {
    /// What the field holds.
    pub fn kind(&self) -> FieldKind {
        match self.access {
            Access::Number { .. } => FieldKind::Number,
            Access::List { .. } => FieldKind::List,
            Access::Rgb { .. } => FieldKind::Colour(ColourSpace::Linear),
            Access::Choice { choices, .. } => FieldKind::Choice(choices),
            Access::Name => FieldKind::Text,
            Access::Knob { kind, .. } => kind,
        }
    }

    /// Whether the field is a yarn knob (only a session opened from a weave has them).
    pub fn is_knob(&self) -> bool {
        matches!(self.access, Access::Knob { .. })
    }

    /// The panel's group: the path before its first dot (`thread1`, `options`, `warp`), or
    /// the whole path.
    pub fn group(&self) -> &'static str {
        self.path.split_once('.').map_or(self.path, |(g, _)| g)
    }

    /// The value a fabric field holds in `fabric`; `None` for a knob.
    pub fn get(&self, fabric: &Fabric) -> Option<EditValue> {
        Some(match self.access {
            Access::Number { get, .. } => EditValue::Number(get(fabric)),
            Access::List { get, .. } => EditValue::Vector(get(fabric).to_vec()),
            Access::Rgb { get, .. } => EditValue::Vector(get(fabric).to_vec()),
            Access::Choice { choices, holds, .. } => {
                EditValue::Choice(choices.iter().find(|c| holds(fabric, c))?.to_string())
            }
            Access::Name => EditValue::Text(fabric.name.clone()),
            Access::Knob { .. } => return None,
        })
    }

    /// Sets a fabric field on `fabric` from a value of its kind; the fabric is not validated
    /// here. A knob, or a value of another kind, is refused with nothing changed.
    pub fn set(&self, fabric: &mut Fabric, value: EditValue) -> Result<(), ValueProblem> {
        match (self.access, value) {
            (Access::Number { set, .. }, EditValue::Number(v)) => set(fabric, finite(v)?),
            (Access::List { set, .. }, EditValue::Vector(v)) => set(fabric, list(v)?),
            (Access::Rgb { set, .. }, EditValue::Vector(v)) => set(fabric, rgb(&v)?),
            (Access::Choice { choices, set, .. }, EditValue::Choice(c)) => {
                if !set(fabric, c.trim()) {
                    return Err(ValueProblem::NotAChoice {
                        text: c,
                        choices: choices.join(", "),
                    });
                }
            }
            (Access::Name, EditValue::Text(name)) => fabric.name = name.trim().to_string(),
            (Access::Knob { .. }, _) => return Err(ValueProblem::Knob),
            (_, value) => {
                return Err(ValueProblem::WrongKind {
                    expected: self.kind(),
                    got: value,
                });
            }
        }
        Ok(())
    }

    /// The value a person typed, read as this field's kind: a number; numbers separated by
    /// spaces or commas (brackets allowed around them) for a list or a colour; a choice's name;
    /// the text itself for a name. "nan", "inf", numbers beyond f64 and empty text are refused,
    /// but for a list, which may be empty (the lengths of a curve of one point).
    pub fn parse_text(&self, text: &str) -> Result<EditValue, ValueProblem> {
        let text = text.trim();
        match self.kind() {
            FieldKind::Number => number(text).map(EditValue::Number),
            // A curve of one point has no lengths: an empty list is for validation to judge.
            FieldKind::List if list_is_empty(text) => Ok(EditValue::Vector(Vec::new())),
            FieldKind::List | FieldKind::Colour(_) => numbers(text).map(EditValue::Vector),
            FieldKind::Choice(_) => Ok(EditValue::Choice(text.to_string())),
            FieldKind::Text => Ok(EditValue::Text(text.to_string())),
        }
    }
}

/// Why a value does not fit its field (before the fabric is validated).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ValueProblem {
    #[error("no value given")]
    Empty,
    #[error("'{0}' is not a number")]
    NotANumber(String),
    #[error("must be a finite number, got {0}")]
    NotFinite(String),
    #[error("takes {expected} numbers, got {got}")]
    Count { expected: usize, got: usize },
    #[error("takes at most {MAX_CONTROL_POINTS} numbers, got {0}")]
    ListLength(usize),
    #[error("'{text}' is not one of {choices}")]
    NotAChoice { text: String, choices: String },
    #[error("takes a value of kind {expected:?}, got {got:?}")]
    WrongKind { expected: FieldKind, got: EditValue },
    #[error("is a yarn knob, set through the weave")]
    Knob,
}

fn finite(v: f64) -> Result<f64, ValueProblem> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(ValueProblem::NotFinite(v.to_string()))
    }
}

fn list(v: Vec<f64>) -> Result<Vec<f64>, ValueProblem> {
    if v.len() > MAX_CONTROL_POINTS {
        return Err(ValueProblem::ListLength(v.len()));
    }
    for &x in &v {
        finite(x)?;
    }
    Ok(v)
}

fn rgb(v: &[f64]) -> Result<[f64; 3], ValueProblem> {
    match *v {
        [r, g, b] => Ok([finite(r)?, finite(g)?, finite(b)?]),
        _ => Err(ValueProblem::Count {
            expected: 3,
            got: v.len(),
        }),
    }
}

/// A finite number from its text.
pub fn number(text: &str) -> Result<f64, ValueProblem> {
    let text = text.trim();
    if text.is_empty() {
        return Err(ValueProblem::Empty);
    }
    let v: f64 = text
        .parse()
        .map_err(|_| ValueProblem::NotANumber(text.to_string()))?;
    if v.is_finite() {
        Ok(v)
    } else {
        Err(ValueProblem::NotFinite(text.to_string()))
    }
}

/// Whether `text` is an empty list: blank, or `[]` with blanks.
fn list_is_empty(text: &str) -> bool {
    let text = text.trim();
    let inner = text
        .strip_prefix('[')
        .and_then(|t| t.strip_suffix(']'))
        .unwrap_or(text);
    inner.trim().is_empty()
}

/// Finite numbers separated by spaces or commas, optionally within `[` `]`; at most
/// [`MAX_CONTROL_POINTS`], counted before any is kept.
pub fn numbers(text: &str) -> Result<Vec<f64>, ValueProblem> {
    let text = text.trim();
    let inner = text
        .strip_prefix('[')
        .and_then(|t| t.strip_suffix(']'))
        .unwrap_or(text);
    let parts = || {
        inner
            .split(|c: char| c == ',' || c.is_whitespace())
            .filter(|p| !p.is_empty())
    };
    let count = parts().count();
    if count == 0 {
        return Err(ValueProblem::Empty);
    }
    if count > MAX_CONTROL_POINTS {
        return Err(ValueProblem::ListLength(count));
    }
    parts().map(number).collect()
}

/// The text a value is shown as, which [`FieldSpec::parse_text`] reads back to the same
/// value (numbers in Rust's shortest form that parses back exactly).
pub fn value_text(value: &EditValue) -> String {
    match value {
        EditValue::Number(v) => v.to_string(),
        EditValue::Vector(v) => v.iter().map(f64::to_string).collect::<Vec<_>>().join(", "),
        EditValue::Choice(t) | EditValue::Text(t) => t.clone(),
    }
}

/// The variant of a serde enum named `text` as the fabric file names it.
fn variant<T: DeserializeOwned>(text: &str) -> Option<T> {
    T::deserialize(IntoDeserializer::<serde::de::value::Error>::into_deserializer(text)).ok()
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

/// The registry entry of `path`.
pub fn field(path: &str) -> Option<&'static FieldSpec> {
    FIELDS.iter().find(|f| f.path == path)
}

/// The registered path nearest to `path` in edit distance, when near enough to be a typo.
pub fn suggestion(path: &str) -> Option<&'static str> {
    FIELDS
        .iter()
        .map(|f| (edit_distance(path, f.path), f.path))
        .min()
        .filter(|&(d, _)| d <= 3.max(path.len() / 4))
        .map(|(_, p)| p)
}

/// Levenshtein distance over characters.
fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut diagonal = row[0];
        row[0] = i + 1;
        for (j, &cb) in b.iter().enumerate() {
            let substitute = diagonal + usize::from(ca != cb);
            diagonal = row[j + 1];
            row[j + 1] = substitute.min(row[j] + 1).min(diagonal + 1);
        }
    }
    row[b.len()]
}

/// A number of a thread.
macro_rules! thread_number {
    ($t:ident . $f:ident, $label:expr, $unit:expr, $range:expr) => {
        FieldSpec {
            path: concat!(stringify!($t), ".", stringify!($f)),
            label: $label,
            unit: $unit,
            range: $range,
            access: Access::Number {
                get: |fabric| fabric.$t.$f,
                set: |fabric, v| fabric.$t.$f = v,
            },
        }
    };
}

/// A list of a thread's tangent curve.
macro_rules! thread_list {
    ($t:ident . $f:ident, $label:expr, $unit:expr, $range:expr, $set:expr) => {
        FieldSpec {
            path: concat!(stringify!($t), ".", stringify!($f)),
            label: $label,
            unit: $unit,
            range: $range,
            access: Access::List {
                get: |fabric| &fabric.$t.$f,
                set: $set,
            },
        }
    };
}

/// Every field of one thread.
macro_rules! thread_fields {
    ($t:ident) => {
        [
            thread_number!($t.eta, "η, refractive index", "", (1.0, 2.5)),
            FieldSpec {
                path: concat!(stringify!($t), ".albedo"),
                label: "albedo colour, linear RGB",
                unit: "",
                range: (0.0, 1.0),
                access: Access::Rgb {
                    get: |fabric| fabric.$t.albedo,
                    set: |fabric, v| fabric.$t.albedo = v,
                },
            },
            thread_number!($t.albedo_scale, "albedo scale", "", (0.0, 10.0)),
            thread_number!($t.kd, "kd, isotropic share", "", (0.0, 1.0)),
            thread_number!($t.gamma_s_deg, "γs, surface lobe width", "°", (0.1, 90.0)),
            thread_number!($t.gamma_v_deg, "γv, volume lobe width", "°", (0.1, 90.0)),
            thread_number!($t.coverage, "coverage", "", (0.0, 1.0)),
            thread_list!(
                $t.offsets_deg,
                "tangent curve offsets",
                "°",
                (-90.0, 90.0),
                |fabric, v| {
                    let thread = &mut fabric.$t;
                    resize_lengths(&mut thread.lengths, v.len());
                    thread.offsets_deg = v;
                }
            ),
            thread_list!(
                $t.lengths,
                "tangent curve segment lengths",
                "",
                (0.0, 10.0),
                |fabric, v| fabric.$t.lengths = v
            ),
        ]
    };
}

/// A list of offsets of another count of points keeps the lengths of the segments that
/// remain and gives each new segment the last segment's length (1 where there was none), so
/// that a curve can gain or lose points by editing its offsets alone.
fn resize_lengths(lengths: &mut Vec<f64>, points: usize) {
    let segments = points.saturating_sub(1);
    let last = lengths.last().copied().unwrap_or(1.0);
    lengths.resize(segments, last);
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

const THREAD1: [FieldSpec; 9] = thread_fields!(thread1);
const THREAD2: [FieldSpec; 9] = thread_fields!(thread2);
const WARP: [FieldSpec; 13] = knobs!(Warp, "warp");
const WEFT: [FieldSpec; 13] = knobs!(Weft, "weft");

const FABRIC: [FieldSpec; 4] = [
    FieldSpec {
        path: "name",
        label: "name",
        unit: "",
        range: (0.0, 0.0),
        access: Access::Name,
    },
    FieldSpec {
        path: "options.gaussian_width",
        label: "γ is σ or √2·σ",
        unit: "",
        range: (0.0, 0.0),
        access: Access::Choice {
            choices: &["std_dev", "sqrt2_std_dev"],
            holds: |fabric, c| variant(c) == Some(fabric.options.gaussian_width),
            set: |fabric, c| {
                variant(c)
                    .map(|v| fabric.options.gaussian_width = v)
                    .is_some()
            },
        },
    },
    FieldSpec {
        path: "options.sigma_u_deg",
        label: "σu, reweighting width",
        unit: "°",
        range: (0.1, 180.0),
        access: Access::Number {
            get: |fabric| fabric.options.sigma_u_deg,
            set: |fabric, v| fabric.options.sigma_u_deg = v,
        },
    },
    FieldSpec {
        path: "options.tangent_sampling",
        label: "tangent samples",
        unit: "",
        range: (0.0, 0.0),
        access: Access::Choice {
            choices: &["arc_length", "control_points"],
            holds: |fabric, c| variant(c) == Some(fabric.options.tangent_sampling),
            set: |fabric, c| {
                variant(c)
                    .map(|v| fabric.options.tangent_sampling = v)
                    .is_some()
            },
        },
    },
];

/// Concatenates the groups into one array.
const fn concat<const N: usize>(groups: [&[FieldSpec]; 5]) -> [FieldSpec; N] {
    let mut out = [FABRIC[0]; N];
    let (mut g, mut n) = (0, 0);
    while g < groups.len() {
        let mut i = 0;
        while i < groups[g].len() {
            out[n] = groups[g][i];
            n += 1;
            i += 1;
        }
        g += 1;
    }
    assert!(n == N, "the registry's length is the sum of its groups'");
    out
}

const ALL: [FieldSpec; 48] = concat([&FABRIC, &THREAD1, &THREAD2, &WARP, &WEFT]);

/// Every editable field, in the panel's order: the name and options, thread 1, thread 2,
/// then the warp's and the weft's yarn knobs (shown only for a session opened from a weave).
pub const FIELDS: &[FieldSpec] = &ALL;
