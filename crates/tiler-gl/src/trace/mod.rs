//! Traces: sequences of frames of context calls as JSON — reading them (checked, with errors
//! naming the frame, the call and the problem), replaying them, and writing what a context
//! recorded. The format is documented in `docs/trace-format.md`.
//!
//! ```json
//! {
//!   "format": "tiler-gl-trace",
//!   "version": 1,
//!   "config": { "width": 128, "height": 96 },
//!   "frames": [
//!     { "calls": [
//!       { "call": "clear", "color": true, "depth": true, "stencil": true },
//!       { "call": "swap_buffers" }
//!     ] },
//!     { "repeat": 3, "calls": [ ... ] }
//!   ]
//! }
//! ```
//!
//! A frame is the calls up to and including a `swap_buffers`, which may only be a frame's
//! last call; only the last frame may lack one. Bulk data is a [`DataSource`]: inline
//! numbers, base64, a range of a binary side file, or a glTF accessor. Memory stays bounded:
//! the data a trace may pull in is limited ([`Limits`]) before anything is allocated, the
//! context has a memory limit, and `repeat` replays one parsed frame without copying it.

mod gltf;
mod raw;
mod source;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use serde::de::IgnoredAny;
use serde::{Deserialize, Serialize};

pub use source::DataSource;

use crate::call::Call;
use crate::context::{Context, ContextConfig};
use crate::report::Report;

/// The `format` field of every trace.
pub const TRACE_FORMAT: &str = "tiler-gl-trace";
/// The trace format version this crate reads and writes.
pub const TRACE_VERSION: u32 = 1;

/// What a trace may make the reader and the replay do.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Limits {
    /// Bytes of data (inline, base64, side files, glTF buffers) a trace may pull in.
    pub max_data_bytes: u64,
    /// Frames after `repeat` is expanded.
    pub max_frames: u64,
    /// Calls after `repeat` is expanded (the report keeps a record per draw, so this bounds
    /// its memory too).
    pub max_calls: u64,
    /// Overrides the context's memory limit when set (the lower of the two applies).
    pub memory_limit: Option<u64>,
    /// Worker threads for the replay, instead of the trace's (results do not depend on it).
    pub threads: Option<usize>,
}

impl Default for Limits {
    fn default() -> Limits {
        Limits { max_data_bytes: 1 << 30, max_frames: 100_000, max_calls: 2_000_000, memory_limit: None, threads: None }
    }
}

/// Where a trace went wrong: the frame and call when there is one.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub struct TraceError {
    pub frame: Option<u32>,
    pub call: Option<u32>,
    pub message: String,
}

impl std::fmt::Display for TraceError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match (self.frame, self.call) {
            (Some(frame), Some(call)) => write!(f, "frame {frame}, call {call}: {}", self.message),
            (Some(frame), None) => write!(f, "frame {frame}: {}", self.message),
            _ => write!(f, "trace: {}", self.message),
        }
    }
}

impl TraceError {
    fn trace(message: impl Into<String>) -> TraceError {
        TraceError { frame: None, call: None, message: message.into() }
    }

    fn at(frame: u64, call: Option<usize>, message: impl Into<String>) -> TraceError {
        TraceError {
            frame: Some(frame.min(u32::MAX as u64) as u32),
            call: call.map(|c| c as u32),
            message: message.into(),
        }
    }
}

/// One entry of a trace's `frames`: calls, replayed `repeat` times.
#[derive(Clone, Debug, PartialEq)]
pub struct TraceFrame {
    pub repeat: u32,
    pub calls: Vec<Call>,
}

/// A parsed trace, its data read into memory.
#[derive(Clone, Debug, PartialEq)]
pub struct Trace {
    pub description: Option<String>,
    pub config: ContextConfig,
    pub frames: Vec<TraceFrame>,
}

/// What a replay produced: the report, and the context (for its images).
pub struct Replay {
    pub report: Report,
    pub context: Context,
}

/// Calls without arguments.
const UNIT_CALLS: [&str; 6] = ["flush", "finish", "swap_buffers", "end_query", "next_subpass", "end_pass"];

/// The most times one frame entry may repeat.
pub const MAX_REPEAT: u32 = 100_000;

/// The most values (numbers, strings, fields) one call may hold: reading a call costs about 32
/// bytes a value before its data is packed, so this bounds that to some 128 MiB. Bulk data
/// past it belongs in base64 (what the recorder writes) or a side file.
pub const MAX_CALL_VALUES: usize = 1 << 22;

impl Trace {
    /// Reads a trace file; side files and glTF files are found relative to its directory.
    ///
    /// # Errors
    /// The file cannot be read, or [`Trace::parse`] fails.
    pub fn read(path: &Path) -> Result<Trace, TraceError> {
        Trace::read_with(path, Limits::default())
    }

    /// [`Trace::read`] with limits.
    ///
    /// # Errors
    /// As [`Trace::read`].
    pub fn read_with(path: &Path, limits: Limits) -> Result<Trace, TraceError> {
        Ok(Trace::read_listing_inputs(path, limits)?.0)
    }

    /// [`Trace::read_with`], and the files it read: the trace, its side files and glTF files
    /// (so a command can refuse to overwrite any of them).
    ///
    /// The trace must be a regular file of at most `limits.max_data_bytes` bytes, read through
    /// that cap (never trusting its reported size: `/dev/zero` reads as empty); the files it
    /// names must be inside its folder ([`tiler_io::resolve_inside`]).
    ///
    /// # Errors
    /// As [`Trace::read`].
    pub fn read_listing_inputs(path: &Path, limits: Limits) -> Result<(Trace, Vec<PathBuf>), TraceError> {
        let text = tiler_io::read_text(path, limits.max_data_bytes).map_err(|e| TraceError::trace(e.to_string()))?;
        let base = path.parent().map(Path::to_path_buf).unwrap_or_default();
        let mut resolver = source::Resolver::new(Some(base), limits.max_data_bytes);
        let trace = Trace::parse_into(&text, &mut resolver, limits)?;
        let mut inputs = vec![path.to_path_buf()];
        inputs.extend(resolver.into_inputs());
        Ok((trace, inputs))
    }

    /// Parses a trace; relative data paths are resolved against `base` (none: they fail).
    ///
    /// # Errors
    /// Bad JSON (with its line and column), a wrong `format` or `version`, a bad `config`,
    /// and for each call: an unknown call, wrong or missing arguments, unreadable data, or a
    /// `swap_buffers` that is not the last call of its frame — naming the frame and the call.
    pub fn parse(json: &str, base: Option<&Path>) -> Result<Trace, TraceError> {
        Trace::parse_with(json, base, Limits::default())
    }

    /// [`Trace::parse`] with limits.
    ///
    /// # Errors
    /// As [`Trace::parse`], and anything beyond `limits`.
    pub fn parse_with(json: &str, base: Option<&Path>, limits: Limits) -> Result<Trace, TraceError> {
        let mut resolver = source::Resolver::new(base.map(Path::to_path_buf), limits.max_data_bytes);
        Trace::parse_into(json, &mut resolver, limits)
    }

    /// Parses a trace without building a tree of the whole JSON: the text is read once and
    /// split into raw pieces (a frame, a call) that borrow it ([`raw`]), and each call is deserialised
    /// straight into its typed form, its data resolved before the next call is read. Memory is
    /// the text, the resolved data and one call's numbers; the text counts against the data
    /// limit, since holding it is part of what reading the trace costs.
    fn parse_into(json: &str, resolver: &mut source::Resolver, limits: Limits) -> Result<Trace, TraceError> {
        resolver.charge(json.len() as u64).map_err(TraceError::trace)?;
        let root: raw::Root<'_> =
            serde_json::from_str(json).map_err(|e| TraceError::trace(format!("invalid JSON: {e}")))?;
        if root.not_object {
            return Err(TraceError::trace("a trace is a JSON object"));
        }
        match root.format.map(|v| (v, serde_json::from_str::<String>(v.get()))) {
            Some((_, Ok(f))) if f == TRACE_FORMAT => {}
            Some((other, _)) => {
                return Err(TraceError::trace(format!("\"format\" is {}, not \"{TRACE_FORMAT}\"", other.get())));
            }
            None => return Err(TraceError::trace(format!("missing \"format\": \"{TRACE_FORMAT}\""))),
        }
        match root.version {
            Some(v) if serde_json::from_str::<u64>(v.get()).ok() == Some(TRACE_VERSION as u64) => {}
            Some(other) => {
                return Err(TraceError::trace(format!(
                    "\"version\" is {}; this reader understands version {TRACE_VERSION}",
                    other.get()
                )));
            }
            None => return Err(TraceError::trace("missing \"version\"")),
        }
        let description = match root.description {
            None => None,
            Some(v) => Some(
                serde_json::from_str::<String>(v.get())
                    .map_err(|_| TraceError::trace(format!("\"description\" is {}, not a string", v.get())))?,
            ),
        };
        let config: ContextConfig = serde_json::from_str(
            root.config
                .ok_or_else(|| TraceError::trace("missing \"config\" (at least {\"width\": W, \"height\": H})"))?
                .get(),
        )
        .map_err(|e| TraceError::trace(format!("config: {}", without_position(&e))))?;
        let frames =
            root.frames.ok_or_else(|| TraceError::trace("missing \"frames\": an array of {\"calls\": [...]}"))?;
        if let Some(key) = root.unknown {
            return Err(TraceError::trace(format!("unknown field \"{key}\"")));
        }

        let mut out = Vec::new();
        let mut frame_index: u64 = 0;
        let mut total_calls: u64 = 0;
        let entries = frames.len();
        for (entry, frame) in frames.into_iter().enumerate() {
            if frame.not_object {
                return Err(TraceError::at(frame_index, None, "a frame is an object {\"calls\": [...]}"));
            }
            let repeat = match frame.repeat {
                None => 1,
                Some(v) => match serde_json::from_str::<serde_json::Number>(v.get()) {
                    Ok(n) => match n.as_u64() {
                        Some(r) if (1..=MAX_REPEAT as u64).contains(&r) => r as u32,
                        _ => {
                            return Err(TraceError::at(
                                frame_index,
                                None,
                                format!("\"repeat\" is {n}; it must be a whole number from 1 to {MAX_REPEAT}"),
                            ));
                        }
                    },
                    Err(_) => {
                        return Err(TraceError::at(
                            frame_index,
                            None,
                            format!("\"repeat\" is {}, not a number", v.get()),
                        ));
                    }
                },
            };
            let Some(calls) = frame.calls else {
                return Err(TraceError::at(frame_index, None, "missing \"calls\": an array of calls"));
            };
            if let Some(key) = frame.unknown {
                return Err(TraceError::at(
                    frame_index,
                    None,
                    format!("unknown field \"{key}\" (a frame has \"calls\" and \"repeat\")"),
                ));
            }
            // The limits hold before the calls are read, so a huge frame is refused up front.
            let expanded_calls = (repeat as u64).saturating_mul(calls.len() as u64);
            if total_calls.saturating_add(expanded_calls) > limits.max_calls {
                return Err(TraceError::at(frame_index, None, format!("more than {} calls", limits.max_calls)));
            }
            let mut parsed = Vec::with_capacity(calls.len());
            let count = calls.len();
            for (i, value) in calls.into_iter().enumerate() {
                // serde reads a call (an internally tagged enum) into a buffer of values first,
                // some 32 bytes for each number of an inline array: bound that before reading.
                let values = json_values(value.get());
                if values > MAX_CALL_VALUES {
                    return Err(TraceError::at(
                        frame_index,
                        Some(i),
                        format!(
                            "the call holds {values} values, more than the {MAX_CALL_VALUES} a call may; give \
                             large data as base64 or a side file"
                        ),
                    ));
                }
                // The call is read once; its name is looked up again only for an error message.
                let call: Call<DataSource> = serde_json::from_str(value.get()).map_err(|e| {
                    let name = serde_json::from_str::<CallName>(value.get()).ok().and_then(|c| c.call);
                    let message = without_position(&e);
                    let message = match name {
                        Some(n) => format!("{n}: {message}"),
                        None => message,
                    };
                    TraceError::at(frame_index, Some(i), message)
                })?;
                let name = call.name();
                // serde accepts extra fields on unit variants of a tagged enum: refuse them here.
                if UNIT_CALLS.contains(&name)
                    && let Ok(object) = serde_json::from_str::<BTreeMap<String, IgnoredAny>>(value.get())
                    && let Some(key) = object.keys().find(|k| *k != "call")
                {
                    return Err(TraceError::at(
                        frame_index,
                        Some(i),
                        format!("{name}: unknown field `{key}`, there are no fields"),
                    ));
                }
                let call = call
                    .try_map_data(|d| resolver.resolve(&d))
                    .map_err(|e| TraceError::at(frame_index, Some(i), format!("{name}: {e}")))?;
                if matches!(call, Call::SwapBuffers) && i + 1 != count {
                    return Err(TraceError::at(
                        frame_index,
                        Some(i),
                        "swap_buffers ends a frame: it must be the last call of its frame",
                    ));
                }
                parsed.push(call);
            }
            let swapped = matches!(parsed.last(), Some(Call::SwapBuffers));
            if !swapped && (entry + 1 != entries || repeat != 1) {
                return Err(TraceError::at(
                    frame_index,
                    None,
                    "a frame must end with swap_buffers (only the last frame, not repeated, may leave it out)",
                ));
            }
            frame_index += repeat as u64;
            total_calls = total_calls.saturating_add(expanded_calls);
            if frame_index > limits.max_frames {
                return Err(TraceError::at(
                    frame_index - repeat as u64,
                    None,
                    format!("more than {} frames", limits.max_frames),
                ));
            }
            out.push(TraceFrame { repeat, calls: parsed });
        }
        Ok(Trace { description, config, frames: out })
    }

    /// Frames after `repeat` is expanded.
    pub fn frame_count(&self) -> u64 {
        self.frames.iter().map(|f| f.repeat as u64).sum()
    }

    /// Replays the trace on a new context.
    ///
    /// # Errors
    /// The first call the context refuses, naming its frame and index.
    pub fn replay(&self) -> Result<Replay, TraceError> {
        self.replay_with(Limits::default())
    }

    /// [`Trace::replay`] with the memory limit and threads of `limits`.
    ///
    /// # Errors
    /// As [`Trace::replay`].
    pub fn replay_with(&self, limits: Limits) -> Result<Replay, TraceError> {
        let mut config = self.config.clone();
        if let Some(limit) = limits.memory_limit {
            config.memory_limit = config.memory_limit.min(limit);
        }
        if let Some(threads) = limits.threads {
            config.threads = threads;
        }
        let mut gl = Context::new(config).map_err(|m| TraceError::trace(format!("config: {m}")))?;
        for frame in &self.frames {
            for _ in 0..frame.repeat {
                for call in &frame.calls {
                    gl.call(call.clone()).map_err(|e| TraceError {
                        frame: Some(e.frame),
                        call: Some(e.call),
                        message: format!("{}: {}", e.name, e.message),
                    })?;
                }
            }
        }
        let report = gl.end().map_err(|e| TraceError {
            frame: Some(e.frame),
            call: None,
            message: format!("at the end of the trace: {}", e.message),
        })?;
        Ok(Replay { report, context: gl })
    }

    /// The trace as JSON, data inline as base64, one call per line.
    pub fn to_json(&self) -> String {
        self.write_json(|call| serde_json::to_string(call).expect("calls serialise"))
    }

    /// The trace as JSON with its data in a side file named `bin_name` (relative to the
    /// JSON's directory): returns the JSON and the side file's bytes.
    pub fn to_json_with_side_file(&self, bin_name: &str) -> (String, Vec<u8>) {
        let mut blob = Vec::new();
        let json = self.write_json(|call| {
            let call = call
                .clone()
                .try_map_data::<DataSource, std::convert::Infallible>(|bytes| {
                    let offset = blob.len() as u64;
                    blob.extend_from_slice(&bytes);
                    Ok(DataSource::File { path: bin_name.to_string(), offset, length: Some(bytes.len() as u64) })
                })
                .expect("infallible");
            serde_json::to_string(&call).expect("calls serialise")
        });
        (json, blob)
    }

    fn write_json(&self, mut call_json: impl FnMut(&Call) -> String) -> String {
        #[derive(Serialize)]
        struct Header<'a> {
            format: &'a str,
            version: u32,
            #[serde(skip_serializing_if = "Option::is_none")]
            description: Option<&'a str>,
            config: &'a ContextConfig,
        }
        let header = serde_json::to_string_pretty(&Header {
            format: TRACE_FORMAT,
            version: TRACE_VERSION,
            description: self.description.as_deref(),
            config: &self.config,
        })
        .expect("the header serialises");
        let mut out = header.trim_end_matches('}').trim_end().to_string();
        out.push_str(",\n  \"frames\": [\n");
        for (i, frame) in self.frames.iter().enumerate() {
            out.push_str("    {");
            if frame.repeat != 1 {
                out.push_str(&format!("\"repeat\": {}, ", frame.repeat));
            }
            out.push_str("\"calls\": [\n");
            for (j, call) in frame.calls.iter().enumerate() {
                out.push_str("      ");
                out.push_str(&call_json(call));
                out.push_str(if j + 1 < frame.calls.len() { ",\n" } else { "\n" });
            }
            out.push_str(if i + 1 < self.frames.len() { "    ]},\n" } else { "    ]}\n" });
        }
        out.push_str("  ]\n}\n");
        out
    }
}

impl Context {
    /// What a recording context was given, as a trace (one frame per swap).
    pub fn recording(&self) -> Option<Trace> {
        let frames = self.recorded_frames()?;
        let frames = frames
            .iter()
            .filter(|calls| !calls.is_empty())
            .map(|calls| TraceFrame { repeat: 1, calls: calls.clone() })
            .collect();
        Some(Trace { description: None, config: self.config().clone(), frames })
    }
}

/// The file `path` names, inside `base` (see [`tiler_io::resolve_inside`]).
pub(crate) fn resolve_path(base: &Option<PathBuf>, path: &str) -> Result<PathBuf, String> {
    match base {
        Some(base) => tiler_io::resolve_inside(base, path).map_err(|e| e.to_string()),
        None => Err(format!("\"{path}\" is a relative path, and this trace was not read from a file")),
    }
}

/// Just the name of a call, read before the call itself so errors can name it.
#[derive(Deserialize)]
struct CallName {
    call: Option<String>,
}

/// A serde error's message without " at line L column C": positions inside one call's text
/// would mislead, since the frame and call index already say where.
fn without_position(e: &serde_json::Error) -> String {
    let text = e.to_string();
    let suffix = format!(" at line {} column {}", e.line(), e.column());
    text.strip_suffix(&suffix).map(str::to_string).unwrap_or(text)
}

/// About how many values a JSON text holds: the commas outside strings, plus one (exact for a
/// flat array; an upper bound on the work of reading nested objects, to within their count).
fn json_values(text: &str) -> usize {
    let mut commas = 0;
    let mut in_string = false;
    let mut escaped = false;
    for &b in text.as_bytes() {
        if in_string {
            match b {
                _ if escaped => escaped = false,
                b'\\' => escaped = true,
                b'"' => in_string = false,
                _ => {}
            }
        } else if b == b'"' {
            in_string = true;
        } else if b == b',' {
            commas += 1;
        }
    }
    commas + 1
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_are_counted_outside_strings() {
        assert_eq!(json_values(r#"{"u8": [1, 2, 3]}"#), 3);
        assert_eq!(json_values(r#"{"call": "x", "s": "a,b,\",c"}"#), 2);
    }

    #[test]
    fn the_text_counts_against_the_data_limit() {
        let json = r#"{"format": "tiler-gl-trace", "version": 1, "config": {"width": 8, "height": 8},
            "frames": [{"calls": [{"call": "create_buffer", "id": 1, "data": {"base64": "AAAA"}}]}]}"#;
        let limits = |max_data_bytes| Limits { max_data_bytes, ..Limits::default() };
        assert!(Trace::parse_with(json, None, limits(json.len() as u64 + 3)).is_ok());
        let e = Trace::parse_with(json, None, limits(json.len() as u64 + 2)).unwrap_err().to_string();
        assert!(e.contains("exceeds its limit"), "{e}");
    }

    #[test]
    fn a_call_with_too_many_numbers_is_refused_before_it_is_read() {
        let numbers = "0,".repeat(MAX_CALL_VALUES);
        let json = format!(
            r#"{{"format": "tiler-gl-trace", "version": 1, "config": {{"width": 8, "height": 8}},
            "frames": [{{"calls": [{{"call": "create_buffer", "id": 1, "data": {{"u8": [{numbers}0]}}}}]}}]}}"#
        );
        let e = Trace::parse(&json, None).unwrap_err().to_string();
        assert!(e.contains("frame 0, call 0") && e.contains("base64 or a side file"), "{e}");
    }
}
