//! The fields the editor edits, as data: one registry, [`FIELDS`], of every fabric parameter
//! (by its path in the fabric file, `thread1.gamma_s_deg`, `options.sigma_u_deg`, …) and every
//! yarn knob of a weave (`warp.crimp`, `weft.colour`, …), each with its label, unit, slider
//! extents and how it is read and written. The panel draws one widget per entry and a script
//! names entries by path; neither matches on field names.
//!
//! The slider extents are only that: whether a value is allowed is decided by
//! [`Fabric::validate`] for the fabric's fields and by [`crate::weave::Yarn::set`] for the knobs.

mod fabric;
mod knobs;

pub use knobs::{Decides, linear_to_srgb};

use crate::model::Fabric;
use crate::model::fabric::MAX_CONTROL_POINTS;
use crate::weave::{Family, Weave};

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

/// Concatenates the groups into one array.
const fn concat<const N: usize>(groups: [&[FieldSpec]; 5]) -> [FieldSpec; N] {
    let mut out = [fabric::FABRIC[0]; N];
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

const ALL: [FieldSpec; 48] = concat([
    &fabric::FABRIC,
    &fabric::THREAD1,
    &fabric::THREAD2,
    &knobs::WARP,
    &knobs::WEFT,
]);

/// Every editable field, in the panel's order: the name and options, thread 1, thread 2,
/// then the warp's and the weft's yarn knobs (shown only for a session opened from a weave).
pub const FIELDS: &[FieldSpec] = &ALL;
