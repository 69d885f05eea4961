//! The edited fabric and its history: [`EditSession`] holds the last good fabric, the saved
//! one, undo and redo, the error of each field's last refused edit, and where the fabric came
//! from (a built-in fabric, a fabric file, or a weave with its draft and yarn knobs).
//!
//! Every edit is made on a copy and validated whole ([`Fabric::validate`]) before it is
//! kept, so what the session holds is always a fabric that bakes and shades.
//!
//! In a session opened from a weave, the yarn knobs are fields too (`warp.crimp`,
//! `weft.colour`, …; [`super::fields`]). A knob edit weaves the fabric again with the knob
//! changed, as `clothbake weave` would with that knob on its command line, and takes from
//! the woven fabric only what that knob decides ([`fields::Decides`]): a shape knob its
//! thread's tangent curve, `cover` both coverages, an optics knob its own parameter of its
//! thread.
//! Everything else keeps what it holds, so parameters edited by hand and the model options
//! (which the weave command leaves at their defaults) stay until the knob that makes them is
//! moved. With no hand edits the fabric is exactly the weave command's.

use super::fields::{self, Access, Edit, EditValue, FieldSpec, ValueProblem};
use crate::model::{Fabric, FabricError};
use crate::weave::{Draft, Family, KnobError, Weave, Yarn};
use std::collections::{BTreeMap, VecDeque};
use std::fmt;
use std::path::{Path, PathBuf};

mod files;

pub use files::{SessionError, Source};

/// The key of [`EditSession::error`] for the last refused open or save (the panel shows it
/// beside the file's name).
pub const FILE_FIELD: &str = "file";

/// Most undo steps kept: the oldest are dropped beyond it, so that a long session's history
/// stays bounded; far more than anyone walks back.
pub const MAX_UNDO: usize = 1000;

/// Why an edit was refused; the fabric is left as it was.
#[derive(Clone, Debug, PartialEq)]
pub enum EditError {
    /// No field has this path; `suggestion` is the nearest path, if near enough.
    UnknownField {
        field: String,
        suggestion: Option<&'static str>,
    },
    /// The value does not fit the field (not a number, not finite, a wrong count).
    Value {
        field: String,
        problem: ValueProblem,
    },
    /// The fabric it would make fails validation.
    Invalid { field: String, source: FabricError },
    /// The yarn knob refused the value.
    Knob { field: String, source: KnobError },
    /// A yarn knob, in a session not opened from a weave.
    NotAWeave { field: String },
}

impl EditError {
    /// The field the edit was of.
    pub fn field(&self) -> &str {
        match self {
            EditError::UnknownField { field, .. }
            | EditError::Value { field, .. }
            | EditError::Invalid { field, .. }
            | EditError::Knob { field, .. }
            | EditError::NotAWeave { field } => field,
        }
    }

    /// What is wrong, without the field's path: the text shown beside the field.
    pub fn message(&self) -> String {
        match self {
            EditError::UnknownField { suggestion, .. } => match suggestion {
                Some(s) => format!("no such field; did you mean '{s}'?"),
                None => "no such field".into(),
            },
            EditError::Value { problem, .. } => problem.to_string(),
            EditError::Invalid { source, .. } => source.to_string(),
            EditError::Knob { source, .. } => source.to_string(),
            EditError::NotAWeave { .. } => {
                "is a yarn knob, and the fabric was not opened from a weave".into()
            }
        }
    }
}

impl fmt::Display for EditError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.field(), self.message())
    }
}

impl std::error::Error for EditError {}

/// What undo and redo restore: the fabric and, in a weave session, the two yarns.
#[derive(Clone, Debug, PartialEq)]
struct State {
    fabric: Fabric,
    yarns: Option<[Yarn; 2]>,
}

/// A fabric being edited; see the module's documentation.
#[derive(Clone, Debug)]
pub struct EditSession {
    fabric: Fabric,
    saved: Fabric,
    saved_path: Option<PathBuf>,
    source: Source,
    /// The draft and the current yarns, in a weave session.
    weave: Option<Weave>,
    undo: VecDeque<State>,
    redo: Vec<State>,
    errors: BTreeMap<String, String>,
    revision: u64,
    /// The field of the edit that [`EditSession::apply_coalesced`] merges into, until
    /// anything else happens.
    gesture: Option<String>,
}

/// What an edit was given: text as typed, or a widget's value.
enum Input<'a> {
    Text(&'a str),
    Value(&'a EditValue),
}

impl EditSession {
    fn new(fabric: Fabric, source: Source, weave: Option<Weave>) -> Self {
        Self {
            saved: fabric.clone(),
            fabric,
            saved_path: None,
            source,
            weave,
            undo: VecDeque::new(),
            redo: Vec::new(),
            errors: BTreeMap::new(),
            revision: 0,
            gesture: None,
        }
    }

    /// The fabric as edited: always the last one that passed validation.
    pub fn fabric(&self) -> &Fabric {
        &self.fabric
    }

    /// The fabric as last saved, or as opened.
    pub fn saved(&self) -> &Fabric {
        &self.saved
    }

    /// Where the fabric was last saved in this session.
    pub fn saved_path(&self) -> Option<&Path> {
        self.saved_path.as_deref()
    }

    /// Whether the fabric differs from the saved one.
    pub fn is_dirty(&self) -> bool {
        self.fabric != self.saved
    }

    /// A counter that grows whenever the fabric (or a yarn knob) changes: by an edit, undo,
    /// redo or open. What is drawn from the fabric is stale when it differs.
    pub fn revision(&self) -> u64 {
        self.revision
    }

    pub fn source(&self) -> &Source {
        &self.source
    }

    /// The weave with its current yarns, in a session opened from a weave.
    pub fn weave(&self) -> Option<&Weave> {
        self.weave.as_ref()
    }

    /// The weave's draft (its drawdown is [`Draft::drawdown`], cell by cell
    /// [`Draft::warp_up`]), in a session opened from a weave.
    pub fn draft(&self) -> Option<&Draft> {
        self.weave.as_ref().map(|w| &w.draft)
    }

    /// The fields this session edits: the fabric's, and the yarn knobs in a weave session.
    /// The iterator does not borrow the session, so that a panel can edit while it draws.
    pub fn fields(&self) -> impl Iterator<Item = &'static FieldSpec> + use<> {
        let knobs = self.weave.is_some();
        fields::FIELDS.iter().filter(move |f| knobs || !f.is_knob())
    }

    /// The value `field` holds now.
    pub fn value(&self, field: &str) -> Result<EditValue, EditError> {
        let spec = spec(field)?;
        if let Access::Knob { family, get, .. } = spec.access {
            let weave = self.weave.as_ref().ok_or_else(|| EditError::NotAWeave {
                field: field.to_string(),
            })?;
            return Ok(get(weave, family));
        }
        Ok(spec
            .get(&self.fabric)
            .expect("a fabric field always has a value"))
    }

    /// The value of `field` as text that [`EditSession::apply_text`] reads back to it.
    pub fn text(&self, field: &str) -> Result<String, EditError> {
        self.value(field).map(|v| fields::value_text(&v))
    }

    /// The error of `field`'s last refused edit, until an edit of it is accepted
    /// ([`FILE_FIELD`] for opening and saving).
    pub fn error(&self, field: &str) -> Option<&str> {
        self.errors.get(field).map(String::as_str)
    }

    /// Every field's standing error, by path.
    pub fn errors(&self) -> impl Iterator<Item = (&str, &str)> {
        self.errors.iter().map(|(k, v)| (k.as_str(), v.as_str()))
    }

    /// Sets `field` from what a person typed ([`FieldSpec::parse_text`]; a knob's text as
    /// `clothbake weave` takes it, a colour also as three numbers). The fabric it makes is
    /// validated whole and kept only if valid: one undo step, the redo steps dropped, the
    /// revision advanced. On an error nothing changes but the error beside the field.
    pub fn apply_text(&mut self, field: &str, text: &str) -> Result<(), EditError> {
        self.edit(field, Input::Text(text), false)
    }

    /// Sets a field from a widget's value, as [`EditSession::apply_text`] does.
    pub fn apply(&mut self, edit: &Edit) -> Result<(), EditError> {
        self.edit(&edit.field, Input::Value(&edit.value), false)
    }

    /// As [`EditSession::apply`], but merged into the previous step while the edits are of
    /// the same field and nothing else happened in between, so that dragging a slider is one
    /// undo step. [`EditSession::end_gesture`] ends the merging (on the slider's release).
    pub fn apply_coalesced(&mut self, edit: &Edit) -> Result<(), EditError> {
        self.edit(&edit.field, Input::Value(&edit.value), true)
    }

    /// Ends the merging of [`EditSession::apply_coalesced`]: the next edit is a step of its
    /// own.
    pub fn end_gesture(&mut self) {
        self.gesture = None;
    }

    pub fn can_undo(&self) -> bool {
        !self.undo.is_empty()
    }

    pub fn can_redo(&self) -> bool {
        !self.redo.is_empty()
    }

    /// Goes back one step; false when there is none.
    pub fn undo(&mut self) -> bool {
        let Some(state) = self.undo.pop_back() else {
            return false;
        };
        let current = self.state();
        self.redo.push(current);
        self.restore(state);
        true
    }

    /// Goes forward one undone step; false when there is none.
    pub fn redo(&mut self) -> bool {
        let Some(state) = self.redo.pop() else {
            return false;
        };
        let current = self.state();
        self.undo.push_back(current);
        self.restore(state);
        true
    }

    fn state(&self) -> State {
        State {
            fabric: self.fabric.clone(),
            yarns: self.yarns(),
        }
    }

    fn yarns(&self) -> Option<[Yarn; 2]> {
        self.weave
            .as_ref()
            .map(|w| [w.warp.clone(), w.weft.clone()])
    }

    fn restore(&mut self, state: State) {
        self.fabric = state.fabric;
        if let (Some(weave), Some([warp, weft])) = (self.weave.as_mut(), state.yarns) {
            weave.warp = warp;
            weave.weft = weft;
        }
        self.revision += 1;
        self.gesture = None;
    }

    fn edit(&mut self, field: &str, input: Input<'_>, coalesce: bool) -> Result<(), EditError> {
        match self.candidate(field, input) {
            Ok(state) => {
                self.errors.remove(field);
                self.commit(field, state, coalesce);
                Ok(())
            }
            Err(error) => {
                if fields::field(field).is_some() {
                    self.errors.insert(field.to_string(), error.message());
                }
                Err(error)
            }
        }
    }

    /// The state an edit makes, validated; the session is left as it was.
    fn candidate(&mut self, field: &str, input: Input<'_>) -> Result<State, EditError> {
        let spec = spec(field)?;
        let value_error = |problem| EditError::Value {
            field: field.to_string(),
            problem,
        };
        let invalid = |source| EditError::Invalid {
            field: field.to_string(),
            source,
        };
        let Access::Knob {
            family,
            key,
            decides,
            ..
        } = spec.access
        else {
            let value = match input {
                Input::Text(text) => spec.parse_text(text).map_err(value_error)?,
                Input::Value(value) => value.clone(),
            };
            let mut fabric = self.fabric.clone();
            spec.set(&mut fabric, value).map_err(value_error)?;
            fabric.validate().map_err(invalid)?;
            return Ok(State {
                fabric,
                yarns: self.yarns(),
            });
        };
        let text = match input {
            Input::Text(text) => knob_text(text),
            Input::Value(EditValue::Number(v)) => v.to_string(),
            Input::Value(EditValue::Vector(v)) => {
                v.iter().map(f64::to_string).collect::<Vec<_>>().join("/")
            }
            Input::Value(value) => {
                return Err(value_error(ValueProblem::WrongKind {
                    expected: spec.kind(),
                    got: value.clone(),
                }));
            }
        };
        let name = self.fabric.name.clone();
        let weave = self.weave.as_mut().ok_or_else(|| EditError::NotAWeave {
            field: field.to_string(),
        })?;
        let mut yarn = weave.yarn(family).clone();
        yarn.set(key, &text).map_err(|source| EditError::Knob {
            field: field.to_string(),
            source,
        })?;
        // Woven with the new yarn in place, then the old one put back: the draft, which may be
        // large, is not copied.
        let slot = match family {
            Family::Warp => &mut weave.warp,
            Family::Weft => &mut weave.weft,
        };
        let old = std::mem::replace(slot, yarn);
        let woven = weave.fabric(&name);
        let yarns = [weave.warp.clone(), weave.weft.clone()];
        let slot = match family {
            Family::Warp => &mut weave.warp,
            Family::Weft => &mut weave.weft,
        };
        *slot = old;
        let woven = woven.map_err(invalid)?;
        let mut fabric = self.fabric.clone();
        decides.take(family, &woven, &mut fabric);
        fabric.validate().map_err(invalid)?;
        Ok(State {
            fabric,
            yarns: Some(yarns),
        })
    }

    fn commit(&mut self, field: &str, state: State, coalesce: bool) {
        let unchanged = state.fabric == self.fabric && state.yarns == self.yarns();
        if unchanged {
            if !coalesce {
                self.gesture = None;
            }
            return;
        }
        let merging = coalesce && self.gesture.as_deref() == Some(field) && self.can_undo();
        if !merging {
            if self.undo.len() >= MAX_UNDO {
                self.undo.pop_front();
            }
            let current = self.state();
            self.undo.push_back(current);
        }
        self.redo.clear();
        self.restore(state);
        self.gesture = coalesce.then(|| field.to_string());
    }
}

/// The registry entry of `field`, or an error with the nearest path.
fn spec(field: &str) -> Result<&'static FieldSpec, EditError> {
    fields::field(field).ok_or_else(|| EditError::UnknownField {
        field: field.to_string(),
        suggestion: fields::suggestion(field),
    })
}

/// A knob's typed text as [`Yarn::set`] takes it: a colour typed as three numbers is
/// written `r/g/b`; anything else is passed on for the knob to judge.
fn knob_text(text: &str) -> String {
    let text = text.trim();
    match fields::numbers(text) {
        Ok(numbers) if numbers.len() > 1 => numbers
            .iter()
            .map(f64::to_string)
            .collect::<Vec<_>>()
            .join("/"),
        _ => text.to_string(),
    }
}

#[cfg(test)]
mod tests;
