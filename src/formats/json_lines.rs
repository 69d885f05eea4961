//! The JSON-lines interfaces of `clothbake eval` and `clothbake sample`: one request per
//! input line, one answer per output line, in order.
//!
//! - `eval`: `{"wi":[x,y,z],"wo":[x,y,z]}` (the patch frame of docs/model.md#frames-and-directions,
//!   normalised here) → `{"f":[r,g,b]}`, plus `"table"` and `"pdf"` when asked for.
//! - `sample`: `{"wo":[x,y,z],"u":[u1,u2,u3]}` (u in [0, 1)) →
//!   `{"wi":[x,y,z],"pdf":p,"weight":[r,g,b]}`, `"wi":null` when the draw is rejected.
//!
//! Input is read on its own thread into a bounded queue; whatever lines are waiting (up to
//! [`CHUNK_LINES`]) are evaluated in parallel and written before more are read, so memory
//! stays constant on any input length and an interactive caller gets each answer as soon
//! as its line arrives.

use glam::DVec3;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::io::{BufRead, Read, Write};
use std::sync::mpsc;

/// Most lines evaluated together (and held in memory at once).
pub const CHUNK_LINES: usize = 4096;
/// Longest accepted input line; a pair of directions needs well under 200 bytes.
pub const MAX_LINE_BYTES: usize = 64 * 1024;

/// One input line.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct DirectionPair {
    wi: [f64; 3],
    wo: [f64; 3],
}

/// One output line of `eval`: `f` always, `table` when a table is being compared, `pdf`
/// (the fabric sampler's density of wi given wo) when asked for.
#[derive(Clone, Copy, Debug, Serialize, PartialEq)]
pub struct EvalOutput {
    pub f: [f64; 3],
    #[serde(skip_serializing_if = "Option::is_none")]
    pub table: Option<[f64; 3]>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pdf: Option<f64>,
}

/// One input line of `sample`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct SampleRequest {
    wo: [f64; 3],
    u: [f64; 3],
}

/// One output line of `sample`: the drawn direction, its density and F/pdf; a rejected
/// draw is `"wi":null,"pdf":0,"weight":[0,0,0]`.
#[derive(Clone, Copy, Debug, Serialize, PartialEq)]
pub struct SampleOutput {
    pub wi: Option<[f64; 3]>,
    pub pdf: f64,
    pub weight: [f64; 3],
}

impl SampleOutput {
    /// The answer for a rejected draw.
    pub const REJECTED: Self = Self {
        wi: None,
        pdf: 0.0,
        weight: [0.0; 3],
    };
}

/// Parses one `sample` line into a unit `wo` and three uniform numbers, each in [0, 1).
pub fn parse_sample_line(text: &str) -> Result<(DVec3, [f64; 3]), LineError> {
    let request: SampleRequest = serde_json::from_str(text).map_err(|source| LineError::Json {
        expected: r#"{"wo":[x,y,z],"u":[u1,u2,u3]}"#,
        source,
    })?;
    for (index, &value) in request.u.iter().enumerate() {
        if !(0.0..1.0).contains(&value) {
            return Err(LineError::Uniform { index, value });
        }
    }
    Ok((unit_direction(request.wo, "wo")?, request.u))
}

/// Why a stream stopped.
#[derive(Debug, thiserror::Error)]
pub enum EvalStreamError {
    #[error("input line {line}: {problem}")]
    BadLine { line: u64, problem: LineError },
    #[error("i/o error: {0}")]
    Io(#[from] std::io::Error),
}

/// What is wrong with one input line.
#[derive(Debug, thiserror::Error)]
pub enum LineError {
    #[error("expected {expected}: {source}")]
    Json {
        expected: &'static str,
        source: serde_json::Error,
    },
    #[error("u[{index}] = {value} is not in [0, 1)")]
    Uniform { index: usize, value: f64 },
    #[error(transparent)]
    Direction(#[from] DirectionError),
    #[error("longer than {MAX_LINE_BYTES} bytes")]
    TooLong,
    #[error("read error: {0}")]
    Read(std::io::Error),
    #[error("is not UTF-8")]
    NotUtf8,
}

/// What is wrong with a direction a user gave.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
pub enum DirectionProblem {
    #[error("has a non-finite component")]
    NonFinite,
    #[error("is the zero vector")]
    Zero,
    /// Where F is 0 by definition: at or below the patch's horizon (a fit's samples).
    #[error("is at or below the horizon (z ≤ 0): F is 0 there")]
    BelowHorizon,
}

/// A refused direction, named by its field.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{field} {problem}")]
pub struct DirectionError {
    pub field: String,
    pub problem: DirectionProblem,
}

/// Normalises a direction given by the user; `field` names it in the error.
pub fn unit_direction(v: [f64; 3], field: &str) -> Result<DVec3, DirectionError> {
    let refuse = |problem| DirectionError {
        field: field.to_string(),
        problem,
    };
    let v = DVec3::from_array(v);
    if !v.is_finite() {
        return Err(refuse(DirectionProblem::NonFinite));
    }
    // Scale by the largest component first so that huge or tiny vectors normalise exactly.
    let scale = v.abs().max_element();
    if scale == 0.0 {
        return Err(refuse(DirectionProblem::Zero));
    }
    Ok((v / scale).normalize())
}

/// Parses one input line into unit directions `(wi, wo)`.
pub fn parse_line(text: &str) -> Result<(DVec3, DVec3), LineError> {
    let pair: DirectionPair = serde_json::from_str(text).map_err(|source| LineError::Json {
        expected: r#"{"wi":[x,y,z],"wo":[x,y,z]}"#,
        source,
    })?;
    Ok((
        unit_direction(pair.wi, "wi")?,
        unit_direction(pair.wo, "wo")?,
    ))
}

type RawLine = Result<Vec<u8>, LineError>;

/// Reads raw lines (without the newline) into `queue` until end of input, an error, or the
/// consumer hanging up.
fn read_lines(mut input: impl BufRead, queue: mpsc::SyncSender<RawLine>) {
    loop {
        let mut line = Vec::new();
        let read = (&mut input)
            .take(MAX_LINE_BYTES as u64 + 1)
            .read_until(b'\n', &mut line);
        let item = match read {
            Ok(0) => return,
            Ok(_) if line.last() != Some(&b'\n') && line.len() > MAX_LINE_BYTES => {
                Err(LineError::TooLong)
            }
            Ok(_) => {
                if line.last() == Some(&b'\n') {
                    line.pop();
                    if line.last() == Some(&b'\r') {
                        line.pop();
                    }
                }
                Ok(line)
            }
            Err(e) => Err(LineError::Read(e)),
        };
        let stop = item.is_err();
        if queue.send(item).is_err() || stop {
            return;
        }
    }
}

/// Evaluates every line of `input` (pairs of directions) with `evaluate` and writes one JSON
/// line per input line to `output`, in order. Stops at the first bad line, after writing the
/// results of all lines before it. Returns the number of lines evaluated.
pub fn eval_stream<R, W, E>(input: R, output: W, evaluate: E) -> Result<u64, EvalStreamError>
where
    R: BufRead + Send + 'static,
    W: Write,
    E: Fn(DVec3, DVec3) -> EvalOutput + Sync,
{
    json_lines(input, output, parse_line, |(wi, wo)| evaluate(wi, wo))
}

/// [`eval_stream`] for `sample` lines: `draw(wo, u)` answers each.
pub fn sample_stream<R, W, D>(input: R, output: W, draw: D) -> Result<u64, EvalStreamError>
where
    R: BufRead + Send + 'static,
    W: Write,
    D: Fn(DVec3, [f64; 3]) -> SampleOutput + Sync,
{
    json_lines(input, output, parse_sample_line, |(wo, u)| draw(wo, u))
}

/// The stream both commands share: lines parsed by `parse`, answered by `answer` in
/// parallel chunks, written in order.
fn json_lines<R, W, T, O>(
    input: R,
    mut output: W,
    parse: fn(&str) -> Result<T, LineError>,
    answer: impl Fn(T) -> O + Sync,
) -> Result<u64, EvalStreamError>
where
    R: BufRead + Send + 'static,
    W: Write,
    T: Send + Sync + Copy,
    O: Serialize + Send,
{
    let (sender, receiver) = mpsc::sync_channel(2 * CHUNK_LINES);
    // Not joined on error: the reader may be blocked on input that never comes, and it ends
    // when it next tries to send to the dropped receiver.
    let reader = std::thread::spawn(move || read_lines(input, sender));
    let mut done: u64 = 0;
    let mut requests = Vec::with_capacity(CHUNK_LINES);
    let mut text = Vec::new();
    while let Ok(first) = receiver.recv() {
        requests.clear();
        let mut failure = None;
        for (offset, raw) in std::iter::once(first)
            .chain(receiver.try_iter().take(CHUNK_LINES - 1))
            .enumerate()
        {
            let line = done + offset as u64 + 1;
            let parsed = raw
                .and_then(|bytes| String::from_utf8(bytes).map_err(|_| LineError::NotUtf8))
                .and_then(|s| parse(&s));
            match parsed {
                Ok(request) => requests.push(request),
                Err(problem) => {
                    failure = Some(EvalStreamError::BadLine { line, problem });
                    break;
                }
            }
        }
        let results: Vec<O> = requests
            .par_iter()
            .map(|&request| answer(request))
            .collect();
        text.clear();
        for result in &results {
            serde_json::to_writer(&mut text, result).map_err(std::io::Error::other)?;
            text.push(b'\n');
        }
        output.write_all(&text)?;
        output.flush()?;
        done += results.len() as u64;
        if let Some(error) = failure {
            return Err(error);
        }
    }
    reader.join().expect("the line reader does not panic");
    Ok(done)
}
