//! Editor scripts (`clothbake view --edit --script FILE`): one action per line, each what a
//! person does in the panel or the window, so that CI and a user's sweep drive the editor as a
//! person would (docs/editor.md#scripts).
//!
//! A line is an action's word and its arguments separated by spaces; an argument holding
//! spaces is written in double quotes. A line whose first character other than a space is `#`
//! is a comment (only whole lines: `#` starts a colour such as `#203050`), and blank lines
//! are skipped. `set FIELD VALUE...` keeps its value's text as written for
//! [`EditSession::apply_text`], so that a bad value reaches the session and is refused there
//! as it would be when typed; only the field must exist. Every other argument is checked
//! here: numbers finite and within their range, names among their choices.
//!
//! [`EditSession::run_editor_action`] carries out the editor's actions (`open`, `set`,
//! `undo`, `redo`, `save`); the viewer carries out the rest.

use super::fields;
use super::session::{EditError, EditSession, SessionError};
use crate::scene::MAX_LIGHTS;
use std::fmt;
use std::path::{Path, PathBuf};

/// Largest script file read: a sweep of many thousand lines is far smaller.
pub const MAX_SCRIPT_BYTES: u64 = 1 << 20;

/// Most frames one `frames` action draws, so that a typo cannot keep a run drawing for hours.
pub const MAX_FRAMES: u32 = 100_000;

/// The exposure's range, as the scene file's `exposure` takes it.
pub const EXPOSURE_RANGE: (f64, f64) = (1e-6, 1e6);

/// The orbit's yaw and pitch ranges in degrees, as the scene file's camera takes them.
pub const YAW_RANGE_DEG: (f64, f64) = (-3600.0, 3600.0);
pub const PITCH_RANGE_DEG: (f64, f64) = (-89.9, 89.9);

/// What the drape is shaded by.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Shading {
    /// The edited fabric (the model, until its table is baked).
    Edited,
    /// The edited fabric's baked table.
    Table,
    /// The saved fabric.
    Saved,
}

/// What the right half of a split screen shows, against the edited fabric on the left.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Compare {
    /// No split screen.
    Off,
    /// The baked table (the left half the model).
    Table,
    /// The saved fabric.
    Saved,
}

/// An exposure as written: a scale of radiance before tone mapping (the scene file's
/// `exposure`), or stops, `2^stops` (written with `ev`: `+1ev`, `-0.5EV`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Exposure {
    Scale(f64),
    Stops(f64),
}

impl Exposure {
    /// The scale of radiance before tone mapping.
    pub fn scale(self) -> f64 {
        match self {
            Exposure::Scale(s) => s,
            Exposure::Stops(ev) => ev.exp2(),
        }
    }
}

/// One action of a script or the panel.
#[derive(Clone, Debug, PartialEq)]
pub enum Action {
    /// `open TARGET [FABRIC]`: a fabric file (and which of its fabrics), a WIF file, a
    /// built-in fabric or a named weave ([`EditSession::from_target`]).
    Open {
        target: String,
        fabric: Option<String>,
    },
    /// `set FIELD VALUE...`: the value as typed.
    Set {
        field: String,
        value: String,
    },
    Undo,
    Redo,
    /// `save PATH`: the fabric as a fabric file.
    Save {
        path: PathBuf,
    },
    /// `wait-bake`: wait until the background bake of the current fabric is done.
    WaitBake,
    /// `save-table DIR`: the baked table of the current fabric stored in the tables
    /// directory DIR as `clothbake bake` stores it (`NAME.exr`, `NAME.taps`, the manifest).
    SaveTable {
        dir: PathBuf,
    },
    /// `screenshot PATH`: the window as a PNG.
    Screenshot {
        path: PathBuf,
    },
    /// `show edited|table|saved`.
    Show(Shading),
    /// `compare off|table|saved`.
    Compare(Compare),
    /// `exposure SCALE` or `exposure STOPSev`.
    Exposure(Exposure),
    /// `environment on|off`: the environment light.
    Environment(bool),
    /// `environment-map SOURCE`: the environment light from a built-in environment or a
    /// file, as `--env` names it (`none` removes it).
    EnvironmentMap {
        source: String,
    },
    /// `environment-rotation DEGREES`: the environment turned about +y.
    EnvironmentRotation {
        degrees: f64,
    },
    /// `light INDEX ELEVATION AZIMUTH`: the scene's light INDEX (from 0) set to come from
    /// this elevation above the horizontal (world +y up) and azimuth about +y (0 towards +z,
    /// 90 towards +x), in degrees, as the viewer's light control measures them: the
    /// direction `(cos e·sin a, sin e, cos e·cos a)`.
    Light {
        index: usize,
        elevation_deg: f64,
        azimuth_deg: f64,
    },
    /// `orbit YAW PITCH`: the camera's yaw about +y and pitch above the target, in degrees.
    Orbit {
        yaw_deg: f64,
        pitch_deg: f64,
    },
    /// `frames N`: draw N frames.
    Frames(u32),
    Exit,
}

impl Action {
    /// Whether the editor carries it out ([`EditSession::run_editor_action`]) rather than
    /// the viewer.
    pub fn is_editor(&self) -> bool {
        matches!(
            self,
            Action::Open { .. }
                | Action::Set { .. }
                | Action::Undo
                | Action::Redo
                | Action::Save { .. }
        )
    }
}

/// An argument as a script writes it: in quotes when it is empty or holds a space or quote.
fn quoted(text: &str) -> String {
    if text.is_empty() || text.contains(char::is_whitespace) || text.starts_with('"') {
        format!("\"{text}\"")
    } else {
        text.to_string()
    }
}

impl fmt::Display for Action {
    /// The action as a script line, which [`parse`] reads back to the same action.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let path = |p: &Path| quoted(&p.to_string_lossy());
        match self {
            Action::Open { target, fabric } => {
                write!(f, "open {}", quoted(target))?;
                if let Some(fabric) = fabric {
                    write!(f, " {}", quoted(fabric))?;
                }
                Ok(())
            }
            Action::Set { field, value } => write!(f, "set {field} {value}"),
            Action::Undo => f.write_str("undo"),
            Action::Redo => f.write_str("redo"),
            Action::Save { path: p } => write!(f, "save {}", path(p)),
            Action::WaitBake => f.write_str("wait-bake"),
            Action::SaveTable { dir } => write!(f, "save-table {}", path(dir)),
            Action::Screenshot { path: p } => write!(f, "screenshot {}", path(p)),
            Action::Show(s) => write!(f, "show {}", shading_name(*s)),
            Action::Compare(c) => write!(f, "compare {}", compare_name(*c)),
            Action::Exposure(Exposure::Scale(s)) => write!(f, "exposure {s}"),
            Action::Exposure(Exposure::Stops(ev)) => write!(f, "exposure {ev}ev"),
            Action::Environment(on) => write!(f, "environment {}", if *on { "on" } else { "off" }),
            Action::EnvironmentMap { source } => write!(f, "environment-map {}", quoted(source)),
            Action::EnvironmentRotation { degrees } => write!(f, "environment-rotation {degrees}"),
            Action::Light {
                index,
                elevation_deg,
                azimuth_deg,
            } => write!(f, "light {index} {elevation_deg} {azimuth_deg}"),
            Action::Orbit { yaw_deg, pitch_deg } => write!(f, "orbit {yaw_deg} {pitch_deg}"),
            Action::Frames(n) => write!(f, "frames {n}"),
            Action::Exit => f.write_str("exit"),
        }
    }
}

const SHADINGS: [(&str, Shading); 3] = [
    ("edited", Shading::Edited),
    ("table", Shading::Table),
    ("saved", Shading::Saved),
];
const COMPARES: [(&str, Compare); 3] = [
    ("off", Compare::Off),
    ("table", Compare::Table),
    ("saved", Compare::Saved),
];
const SWITCHES: [(&str, bool); 2] = [("on", true), ("off", false)];

fn shading_name(s: Shading) -> &'static str {
    SHADINGS
        .iter()
        .find(|(_, v)| *v == s)
        .map_or("", |(n, _)| n)
}

fn compare_name(c: Compare) -> &'static str {
    COMPARES
        .iter()
        .find(|(_, v)| *v == c)
        .map_or("", |(n, _)| n)
}

/// The actions of a script, each with its line number (from 1).
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Script {
    pub steps: Vec<(usize, Action)>,
}

impl Script {
    /// Reads and parses the script file at `path`.
    pub fn load(path: &Path) -> Result<Self, ScriptFileError> {
        let io = |source| ScriptFileError::Io {
            path: path.to_path_buf(),
            source,
        };
        let size = std::fs::metadata(path).map_err(io)?.len();
        if size > MAX_SCRIPT_BYTES {
            return Err(ScriptFileError::TooLarge {
                path: path.to_path_buf(),
                size,
            });
        }
        let text = std::fs::read_to_string(path).map_err(io)?;
        parse(&text).map_err(|source| ScriptFileError::Parse {
            path: path.to_path_buf(),
            source,
        })
    }
}

/// A line of a script that is not an action.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("line {line}: {message}")]
pub struct ScriptError {
    pub line: usize,
    pub message: String,
}

/// Why a script file was not read.
#[derive(Debug, thiserror::Error)]
pub enum ScriptFileError {
    #[error("cannot read script {path}: {source}")]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("script {path} is {size} bytes, larger than the {MAX_SCRIPT_BYTES}-byte limit")]
    TooLarge { path: PathBuf, size: u64 },
    #[error("script {path}, {source}")]
    Parse { path: PathBuf, source: ScriptError },
}

/// The actions of a script's text; the first line that is not an action is the error.
pub fn parse(text: &str) -> Result<Script, ScriptError> {
    let mut steps = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let line_number = i + 1;
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let action = parse_line(line).map_err(|message| ScriptError {
            line: line_number,
            message,
        })?;
        steps.push((line_number, action));
    }
    Ok(Script { steps })
}

/// One action from its line (trimmed, not a comment).
fn parse_line(line: &str) -> Result<Action, String> {
    let (word, rest) = line
        .split_once(char::is_whitespace)
        .map_or((line, ""), |(w, r)| (w, r.trim()));
    if word == "set" {
        let (field, value) = rest
            .split_once(char::is_whitespace)
            .map_or((rest, ""), |(f, v)| (f, v.trim()));
        if field.is_empty() {
            return Err("set needs a field and a value: set FIELD VALUE".into());
        }
        if fields::field(field).is_none() {
            return Err(match fields::suggestion(field) {
                Some(s) => format!("set: no field '{field}'; did you mean '{s}'?"),
                None => format!("set: no field '{field}'"),
            });
        }
        return Ok(Action::Set {
            field: field.to_string(),
            value: value.to_string(),
        });
    }
    let args = arguments(rest)?;
    let arity = |n: usize, syntax: &str| -> Result<(), String> {
        if args.len() == n {
            Ok(())
        } else {
            Err(format!(
                "{word} takes {n} argument{}, got {}: {syntax}",
                if n == 1 { "" } else { "s" },
                args.len()
            ))
        }
    };
    let number = |i: usize, what: &str, range: Option<(f64, f64)>| -> Result<f64, String> {
        let v = fields::number(&args[i]).map_err(|e| format!("{word}: {what} {e}"))?;
        match range {
            Some((lo, hi)) if !(lo..=hi).contains(&v) => Err(format!(
                "{word}: {what} must be within [{lo}, {hi}], got {v}"
            )),
            _ => Ok(v),
        }
    };
    let choice = |syntax: &str| -> Result<usize, String> {
        arity(1, syntax)?;
        let names: Vec<&str> = syntax.split('|').collect();
        names
            .iter()
            .position(|n| *n == args[0])
            .ok_or_else(|| format!("{word} takes {syntax}, got '{}'", args[0]))
    };
    let action = match word {
        "open" => {
            if args.is_empty() || args.len() > 2 {
                return Err(format!(
                    "open takes a file, built-in fabric or weave and optionally a fabric name, \
                     got {} arguments",
                    args.len()
                ));
            }
            Action::Open {
                target: args[0].clone(),
                fabric: args.get(1).cloned(),
            }
        }
        "undo" => arity(0, "undo").map(|()| Action::Undo)?,
        "redo" => arity(0, "redo").map(|()| Action::Redo)?,
        "wait-bake" => arity(0, "wait-bake").map(|()| Action::WaitBake)?,
        "exit" => arity(0, "exit").map(|()| Action::Exit)?,
        "save" => {
            arity(1, "save PATH")?;
            Action::Save {
                path: PathBuf::from(&args[0]),
            }
        }
        "save-table" => {
            arity(1, "save-table DIR")?;
            Action::SaveTable {
                dir: PathBuf::from(&args[0]),
            }
        }
        "screenshot" => {
            arity(1, "screenshot PATH.png")?;
            let path = PathBuf::from(&args[0]);
            if !path
                .extension()
                .is_some_and(|e| e.eq_ignore_ascii_case("png"))
            {
                return Err(format!(
                    "screenshot writes a PNG: the path must end in .png, got '{}'",
                    args[0]
                ));
            }
            Action::Screenshot { path }
        }
        "show" => Action::Show(SHADINGS[choice("edited|table|saved")?].1),
        "compare" => Action::Compare(COMPARES[choice("off|table|saved")?].1),
        "environment" => Action::Environment(SWITCHES[choice("on|off")?].1),
        "exposure" => {
            arity(1, "exposure SCALE or exposure STOPSev")?;
            let text = &args[0];
            let stops = text
                .len()
                .checked_sub(2)
                .filter(|&n| text.is_char_boundary(n) && text[n..].eq_ignore_ascii_case("ev"))
                .map(|n| &text[..n]);
            let exposure = match stops {
                Some(ev) => {
                    Exposure::Stops(fields::number(ev).map_err(|e| format!("exposure: stops {e}"))?)
                }
                None => Exposure::Scale(number(0, "scale", None)?),
            };
            let (lo, hi) = EXPOSURE_RANGE;
            let scale = exposure.scale();
            if !(lo..=hi).contains(&scale) {
                return Err(format!(
                    "exposure: the scale must be within [{lo}, {hi}], got {scale} from '{text}'"
                ));
            }
            Action::Exposure(exposure)
        }
        "environment-map" => {
            arity(1, "environment-map SOURCE")?;
            args[0]
                .parse::<crate::lighting::EnvironmentSource>()
                .map_err(|e| format!("environment-map: {e}"))?;
            Action::EnvironmentMap {
                source: args[0].clone(),
            }
        }
        "environment-rotation" => {
            arity(1, "environment-rotation DEGREES")?;
            Action::EnvironmentRotation {
                degrees: number(0, "degrees", None)?,
            }
        }
        "light" => {
            arity(3, "light INDEX ELEVATION_DEG AZIMUTH_DEG")?;
            let index: usize = args[0]
                .parse()
                .map_err(|_| format!("light: the index is a whole number, got '{}'", args[0]))?;
            if index >= MAX_LIGHTS {
                return Err(format!(
                    "light: a scene has at most {MAX_LIGHTS} lights, 0 to {}, got {index}",
                    MAX_LIGHTS - 1
                ));
            }
            Action::Light {
                index,
                elevation_deg: number(1, "elevation", Some((-90.0, 90.0)))?,
                azimuth_deg: number(2, "azimuth", None)?,
            }
        }
        "orbit" => {
            arity(2, "orbit YAW_DEG PITCH_DEG")?;
            Action::Orbit {
                yaw_deg: number(0, "yaw", Some(YAW_RANGE_DEG))?,
                pitch_deg: number(1, "pitch", Some(PITCH_RANGE_DEG))?,
            }
        }
        "frames" => {
            arity(1, "frames N")?;
            let n: u32 = args[0]
                .parse()
                .ok()
                .filter(|n| (1..=MAX_FRAMES).contains(n))
                .ok_or_else(|| {
                    format!(
                        "frames takes a whole number from 1 to {MAX_FRAMES}, got '{}'",
                        args[0]
                    )
                })?;
            Action::Frames(n)
        }
        other => {
            return Err(format!(
                "unknown action '{other}'; actions: open, set, undo, redo, save, wait-bake, \
                 screenshot, show, compare, exposure, environment, environment-rotation, light, \
                 orbit, frames, exit"
            ));
        }
    };
    Ok(action)
}

/// The arguments of a line: separated by spaces, an argument in double quotes kept whole.
fn arguments(text: &str) -> Result<Vec<String>, String> {
    let mut args = Vec::new();
    let mut rest = text.trim_start();
    while !rest.is_empty() {
        if let Some(quoted) = rest.strip_prefix('"') {
            let end = quoted
                .find('"')
                .ok_or_else(|| format!("a quote is not closed: {rest}"))?;
            args.push(quoted[..end].to_string());
            rest = &quoted[end + 1..];
            if rest.starts_with(|c: char| !c.is_whitespace()) {
                return Err(format!("a space must follow a closing quote: {rest}"));
            }
        } else {
            let end = rest.find(char::is_whitespace).unwrap_or(rest.len());
            args.push(rest[..end].to_string());
            rest = &rest[end..];
        }
        rest = rest.trim_start();
    }
    Ok(args)
}

/// Who carried out an action.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Handled {
    /// The editor did.
    Editor,
    /// It is the viewer's to carry out; the session did nothing.
    Viewer,
}

/// Why the editor could not carry out an action.
#[derive(Debug, thiserror::Error)]
pub enum ActionError {
    #[error(transparent)]
    Edit(#[from] EditError),
    #[error(transparent)]
    Session(#[from] SessionError),
    #[error("there is nothing to undo")]
    NothingToUndo,
    #[error("there is nothing to redo")]
    NothingToRedo,
}

/// A step of a script that failed: `line 4: set thread1.coverage 1.5: …`.
#[derive(Debug, thiserror::Error)]
#[error("line {line}: {action}: {source}")]
pub struct StepError {
    pub line: usize,
    pub action: Action,
    pub source: ActionError,
}

impl EditSession {
    /// Carries out an editor action (`open`, `set`, `undo`, `redo`, `save`), as the panel
    /// does; any other action is left to the viewer ([`Handled::Viewer`]). Undo and redo with
    /// nothing to go back or forward to are errors, so that a script that expects a step
    /// fails where it goes wrong.
    pub fn run_editor_action(&mut self, action: &Action) -> Result<Handled, ActionError> {
        match action {
            Action::Open { target, fabric } => self.open_target(target, fabric.as_deref())?,
            Action::Set { field, value } => self.apply_text(field, value)?,
            Action::Undo => {
                if !self.undo() {
                    return Err(ActionError::NothingToUndo);
                }
            }
            Action::Redo => {
                if !self.redo() {
                    return Err(ActionError::NothingToRedo);
                }
            }
            Action::Save { path } => self.save(path)?,
            _ => return Ok(Handled::Viewer),
        }
        Ok(Handled::Editor)
    }
}

#[cfg(test)]
mod tests;
