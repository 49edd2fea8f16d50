//! `raylab solve --batch`: one JSON case per input line, one JSON result per output line.
//!
//! A case has `"kind"` (`segments`, `triangle`, `parallelogram`), the same fields as the flags
//! (`a1 a2 b1 b2`; `a b c origin dir tmin`; `corner e1 e2 origin dir`), each a string `"1,2"` or an
//! array `[1, 2]` (numbers, or strings such as `"1/3"`), and optionally `"precision"`.

//!
//! Numbers are read as written, straight from the line's text: a float precision parses them to floats
//! (no exact value is built, so a batch runs at JSON speed), exact precision reads every digit.

use std::borrow::Cow;
use std::fmt;
use std::io::{BufRead, Write};

use serde::de::{self, Deserializer, IgnoredAny, MapAccess, SeqAccess, Visitor};
use serde_json::json;
use serde_json::value::RawValue;

use super::input::{InputError, ReadNumber, quoted};
use super::scan;
use super::solve::{FieldSink, Posed, solve_posed, solve_posed_traced};
use crate::geometry::parallelogram::RayParallelogram;
use crate::geometry::segments::SegmentPair;
use crate::geometry::triangle::RayTriangle;
use crate::geometry::{Precision, Real};
use crate::math::exact::{Exact, ParseExactError};

/// Every field a case may have besides `kind` and `precision`.
const FIELDS: [&str; 13] = [
    "a1", "a2", "b1", "b2", "a", "b", "c", "origin", "dir", "tmin", "corner", "e1", "e2",
];

/// The fields of one kind of case, in order.
fn allowed(kind: &str) -> Option<&'static [&'static str]> {
    match kind {
        "segments" => Some(&["a1", "a2", "b1", "b2"]),
        "triangle" => Some(&["a", "b", "c", "origin", "dir", "tmin"]),
        "parallelogram" => Some(&["corner", "e1", "e2", "origin", "dir"]),
        _ => None,
    }
}

/// One line's JSON object, its values kept as the raw JSON text of the line (nothing parsed yet).
#[derive(Default)]
struct RawCase<'a> {
    kind: Option<&'a str>,
    precision: Option<&'a str>,
    /// By index in [`FIELDS`], with the key's position in the object.
    values: [Option<(usize, &'a str)>; FIELDS.len()],
    /// The first key that is no field at all, with its position.
    stranger: Option<(usize, Cow<'a, str>)>,
    /// How many members so far.
    count: usize,
}

impl<'a> RawCase<'a> {
    /// Adds the next member (a later duplicate replaces an earlier one, as in serde_json's maps).
    fn add(&mut self, key: Cow<'a, str>, value: &'a str) {
        let position = self.count;
        self.count += 1;
        match key.as_ref() {
            "kind" => self.kind = Some(value),
            "precision" => self.precision = Some(value),
            name => match FIELDS.iter().position(|f| *f == name) {
                Some(i) => self.values[i] = Some((position, value)),
                None if self.stranger.is_none() => self.stranger = Some((position, key)),
                None => {}
            },
        }
    }

    /// Reads a line: the hand-written scanner for the common shape, serde_json for anything else.
    fn read(line: &'a str) -> Result<RawCase<'a>, LineError> {
        let mut case = RawCase::default();
        if scanner_on() && scan::object(line, |key, v| case.add(Cow::Borrowed(key), v)).is_some() {
            return Ok(case);
        }
        serde_json::from_str(line).map_err(|e| LineError::Json(e.to_string()))
    }
}

impl<'de> de::Deserialize<'de> for RawCase<'de> {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        deserializer.deserialize_map(RawCaseVisitor)
    }
}

struct RawCaseVisitor;

impl<'de> Visitor<'de> for RawCaseVisitor {
    type Value = RawCase<'de>;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("a JSON object")
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<RawCase<'de>, A::Error> {
        let mut case = RawCase::default();
        while let Some(key) = map.next_key::<Cow<'de, str>>()? {
            let value: &'de RawValue = map.next_value()?;
            case.add(key, value.get());
        }
        Ok(case)
    }
}

#[cfg(test)]
thread_local! {
    /// Set by a test that compares the scanner's answers with serde_json's alone.
    static SERDE_ONLY: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

/// True where the scanner reads first (everywhere but in that test).
fn scanner_on() -> bool {
    #[cfg(test)]
    return !SERDE_ONLY.with(std::cell::Cell::get);
    #[cfg(not(test))]
    true
}

/// A JSON string's text (borrowed unless it has escapes), or `None` if the value is not a string.
/// `raw` is valid JSON (read by the scanner or serde_json).
fn string_of(raw: &str) -> Option<Cow<'_, str>> {
    if !raw.starts_with('"') {
        return None;
    }
    if !raw.contains('\\') {
        return Some(Cow::Borrowed(&raw[1..raw.len() - 1]));
    }
    serde_json::from_str::<String>(raw).ok().map(Cow::Owned)
}

/// The items of a JSON array: the first `N` raw values, and how many there were.
struct Items<'a, const N: usize> {
    first: [Option<&'a RawValue>; N],
    count: usize,
}

impl<'de, const N: usize> de::Deserialize<'de> for Items<'de, N> {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct ItemsVisitor<const N: usize>;
        impl<'de, const N: usize> Visitor<'de> for ItemsVisitor<N> {
            type Value = Items<'de, N>;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("an array")
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Items<'de, N>, A::Error> {
                let mut items = Items {
                    first: [None; N],
                    count: 0,
                };
                while items.count < N {
                    match seq.next_element::<&'de RawValue>()? {
                        Some(item) => items.first[items.count] = Some(item),
                        None => return Ok(items),
                    }
                    items.count += 1;
                }
                while seq.next_element::<IgnoredAny>()?.is_some() {
                    items.count += 1;
                }
                Ok(items)
            }
        }
        deserializer.deserialize_seq(ItemsVisitor::<N>)
    }
}

/// One number of a case as number text: a JSON number as written, or a string's text.
fn number_text(raw: &str) -> Result<Cow<'_, str>, InputError> {
    let text = raw;
    match text.as_bytes().first() {
        Some(b'-' | b'0'..=b'9') => Ok(Cow::Borrowed(text)),
        Some(b'"') => string_of(raw).ok_or(InputError::BadString),
        _ if text == "null" => Err(InputError::Null),
        _ => Err(ParseExactError::NotANumber(quoted(text)).into()),
    }
}

/// The wrong count of numbers in a vector.
fn count_error<const N: usize>(got: usize) -> InputError {
    InputError::Count { expected: N, got }
}

/// Reads N numbers, given as `"x,y,z"` or `[x, y, z]`, into precision `R`.
#[allow(
    clippy::expect_used,
    reason = "the items were counted to be N, and each component read or returned its error, just above"
)]
fn vector<R: ReadNumber, const N: usize>(raw: &str) -> Result<[R; N], InputError> {
    let component = |i: usize, text: &str| R::read(text).map_err(|e| e.in_component(i));
    let mut values: [Option<R>; N] = std::array::from_fn(|_| None);
    if let Some(text) = string_of(raw) {
        let mut parts: [&str; N] = [""; N];
        let mut count = 0;
        for part in text.split(',') {
            if let Some(slot) = parts.get_mut(count) {
                *slot = part;
            }
            count += 1;
        }
        if count != N {
            return Err(count_error::<N>(count));
        }
        for (i, part) in parts.iter().enumerate() {
            values[i] = Some(component(i, part)?);
        }
    } else if raw.starts_with('[') {
        let (first, count) = match scanner_on().then(|| scan::array::<N>(raw)).flatten() {
            Some(items) => items,
            None => {
                let items: Items<N> =
                    serde_json::from_str(raw).map_err(|e| InputError::Json(e.to_string()))?;
                (items.first.map(|item| item.map(RawValue::get)), items.count)
            }
        };
        if count != N {
            return Err(count_error::<N>(count));
        }
        for (i, item) in first.iter().enumerate() {
            let text =
                number_text(item.expect("N items counted")).map_err(|e| e.in_component(i))?;
            values[i] = Some(component(i, &text)?);
        }
    } else {
        return Err(InputError::NotAVector);
    }
    Ok(values.map(|v| v.expect("every component read")))
}

/// Why a batch line gives no answer; the message is the `error` of its output line.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum LineError {
    /// More than [`MAX_LINE_BYTES`] bytes.
    #[error("the line is longer than {MAX_LINE_BYTES} bytes; skipped to its end")]
    TooLong,
    /// Not UTF-8, at this byte of the line (from 1).
    #[error("not valid UTF-8 (byte {0} of the line); skipped")]
    NotUtf8(usize),
    /// Not JSON (serde_json's message).
    #[error("not valid JSON: {0}")]
    Json(String),
    /// JSON, but not an object.
    #[error("expected a JSON object")]
    NotAnObject,
    /// No `kind`.
    #[error("missing field 'kind' (segments, triangle or parallelogram)")]
    MissingKind,
    /// A field that must be a string and is not.
    #[error("field '{0}' must be a string")]
    NotAString(&'static str),
    /// A precision word that names no precision.
    #[error("field 'precision': {0}")]
    Precision(crate::names::UnknownName),
    /// A kind word that names no kind (quoted).
    #[error("unknown kind {0} (expected segments, triangle or parallelogram)")]
    UnknownKind(String),
    /// A field the kind does not have.
    #[error("unknown field {field} for kind {kind} (expected {})", .expected.join(", "))]
    UnknownField {
        /// The field, quoted.
        field: String,
        /// The line's kind.
        kind: String,
        /// The kind's fields.
        expected: &'static [&'static str],
    },
    /// A field the kind needs.
    #[error("missing field '{0}'")]
    MissingField(&'static str),
    /// A field whose value cannot be read.
    #[error("field '{name}': {error}")]
    Field {
        /// The field.
        name: &'static str,
        /// Why.
        error: InputError,
    },
}

/// One line's case, its precision settled, its numbers still text.
pub struct LineCase<'a> {
    /// `segments`, `triangle` or `parallelogram`.
    pub kind: &'static str,
    /// The case's own precision, or the batch's.
    pub precision: Precision,
    raw: RawCase<'a>,
}

/// Reads one case from a JSON object; the precision is the case's own or `default`. Numbers are not
/// read yet ([`LineCase::pose`] reads them in the case's precision).
pub fn parse_case(line: &str, default: Precision) -> Result<LineCase<'_>, LineError> {
    if !line.trim_start().starts_with('{') {
        return Err(match serde_json::from_str::<IgnoredAny>(line) {
            Ok(_) => LineError::NotAnObject,
            Err(e) => LineError::Json(e.to_string()),
        });
    }
    let raw = RawCase::read(line)?;
    let kind = match raw.kind.map(string_of) {
        Some(Some(kind)) => kind,
        Some(None) => return Err(LineError::NotAString("kind")),
        None => return Err(LineError::MissingKind),
    };
    let precision = match raw.precision {
        None => default,
        Some(p) => string_of(p)
            .ok_or(LineError::NotAString("precision"))?
            .parse()
            .map_err(LineError::Precision)?,
    };
    let Some(fields) = allowed(&kind) else {
        return Err(LineError::UnknownKind(quoted(&kind)));
    };
    let misplaced = FIELDS
        .iter()
        .zip(&raw.values)
        .filter_map(|(name, v)| v.map(|(at, _)| (at, Cow::Borrowed(*name))))
        .filter(|(_, name)| !fields.contains(&name.as_ref()));
    if let Some((_, unknown)) = misplaced.chain(raw.stranger.clone()).min() {
        return Err(LineError::UnknownField {
            field: quoted(&unknown),
            kind: kind.to_string(),
            expected: fields,
        });
    }
    let kind = match kind.as_ref() {
        "segments" => "segments",
        "triangle" => "triangle",
        _ => "parallelogram",
    };
    Ok(LineCase {
        kind,
        precision,
        raw,
    })
}

impl LineCase<'_> {
    #[allow(
        clippy::expect_used,
        reason = "the field was found among FIELDS just above"
    )]
    fn field(&self, name: &'static str) -> Result<&str, LineError> {
        let index = FIELDS
            .iter()
            .position(|f| *f == name)
            .expect("a known field");
        self.raw.values[index]
            .map(|(_, raw)| raw)
            .ok_or(LineError::MissingField(name))
    }

    fn vector<R: ReadNumber, const N: usize>(
        &self,
        name: &'static str,
    ) -> Result<[R; N], LineError> {
        vector(self.field(name)?).map_err(|error| LineError::Field { name, error })
    }

    /// The case in precision `R`, every number read from its text.
    pub fn pose<R: ReadNumber>(&self) -> Result<Posed<R>, LineError> {
        Ok(match self.kind {
            "segments" => Posed::Segments(SegmentPair {
                a1: self.vector("a1")?,
                a2: self.vector("a2")?,
                b1: self.vector("b1")?,
                b2: self.vector("b2")?,
            }),
            "triangle" => Posed::Triangle(RayTriangle {
                a: self.vector("a")?,
                b: self.vector("b")?,
                c: self.vector("c")?,
                origin: self.vector("origin")?,
                dir: self.vector("dir")?,
                t_min: match self.field("tmin") {
                    Err(_) => R::zero(),
                    Ok(raw) => {
                        number_text(raw)
                            .and_then(|text| R::read(&text))
                            .map_err(|error| LineError::Field {
                                name: "tmin",
                                error,
                            })?
                    }
                },
            }),
            _ => Posed::Parallelogram(RayParallelogram {
                corner: self.vector("corner")?,
                e1: self.vector("e1")?,
                e2: self.vector("e2")?,
                origin: self.vector("origin")?,
                dir: self.vector("dir")?,
            }),
        })
    }

    /// Solves the case in its precision and writes its report as one JSON line (with `"line"`, and
    /// the trace if asked for) to `out`.
    pub fn solve_into(
        &self,
        line: usize,
        with_trace: bool,
        out: &mut Vec<u8>,
    ) -> Result<(), LineError> {
        match self.precision {
            Precision::F32 => write_report(&self.pose::<f32>()?, line, with_trace, out),
            Precision::F64 => write_report(&self.pose::<f64>()?, line, with_trace, out),
            Precision::Exact => write_report(&self.pose::<Exact>()?, line, with_trace, out),
        }
        Ok(())
    }
}

/// Writes a JSON object's fields one by one as they come, with no map in between.
struct JsonLine<'a> {
    out: &'a mut Vec<u8>,
    empty: bool,
}

impl FieldSink for JsonLine<'_> {
    #[allow(
        clippy::expect_used,
        reason = "serde_json writes any value made of maps with string keys, numbers and strings"
    )]
    fn put(&mut self, key: &'static str, value: impl serde::Serialize) {
        self.out.push(if self.empty { b'{' } else { b',' });
        self.empty = false;
        self.out.push(b'"');
        self.out.extend_from_slice(key.as_bytes());
        self.out.extend_from_slice(b"\":");
        serde_json::to_writer(&mut *self.out, &value).expect("report fields always serialize");
    }
}

fn write_report<R: Real>(posed: &Posed<R>, line: usize, with_trace: bool, out: &mut Vec<u8>) {
    let mut fields = JsonLine { out, empty: true };
    if with_trace {
        let trace = solve_posed_traced(posed, &mut fields);
        fields.put("trace", &trace);
    } else {
        solve_posed(posed, &mut fields, &mut ());
    }
    fields.put("line", line);
    fields.out.extend_from_slice(b"}\n");
}

/// Output is written in chunks of about this many bytes (and whenever the input may block).
const OUTPUT_CHUNK: usize = 1 << 16;

/// The longest batch line read, in bytes; a longer line is refused (and skipped to its end) without
/// being held in memory.
pub const MAX_LINE_BYTES: usize = 1 << 20;

/// One line of input, read with bounded memory.
enum RawLine {
    /// The line's bytes (in [`LineReader::buf`]), without the line break.
    Bytes,
    /// The line has more than [`MAX_LINE_BYTES`] bytes: reported at once, the rest skipped unread.
    TooLong,
}

/// Splits input into lines of at most [`MAX_LINE_BYTES`], whatever the input holds (no line break at
/// all, as from `/dev/zero`, included).
struct LineReader<R> {
    input: R,
    buf: Vec<u8>,
    /// Inside a line already reported as too long: drop bytes up to its line break.
    skipping: bool,
    /// The input's buffer was used up by the last read.
    drained: bool,
}

impl<R: BufRead> LineReader<R> {
    fn new(input: R) -> Self {
        LineReader {
            input,
            buf: Vec::new(),
            skipping: false,
            drained: true,
        }
    }

    /// True if the next read may wait for more input (everything read so far is used).
    fn will_wait(&self) -> bool {
        self.drained
    }

    /// The next line; `None` at the end of the input.
    fn next_line(&mut self) -> std::io::Result<Option<RawLine>> {
        self.buf.clear();
        let mut read_any = false;
        loop {
            let available = match self.input.fill_buf() {
                Ok(bytes) => bytes,
                Err(e) if e.kind() == std::io::ErrorKind::Interrupted => continue,
                Err(e) => return Err(e),
            };
            if available.is_empty() {
                return Ok((read_any && !self.skipping).then_some(RawLine::Bytes));
            }
            let (chunk, ends_line) = match available.iter().position(|&b| b == b'\n') {
                Some(i) => (&available[..i], true),
                None => (available, false),
            };
            let used = chunk.len() + usize::from(ends_line);
            self.drained = used == available.len();
            if self.skipping {
                self.input.consume(used);
                self.skipping = !ends_line;
                continue;
            }
            read_any = true;
            if self.buf.len() + chunk.len() > MAX_LINE_BYTES {
                self.input.consume(used);
                self.skipping = !ends_line;
                self.buf.clear();
                return Ok(Some(RawLine::TooLong));
            }
            self.buf.extend_from_slice(chunk);
            self.input.consume(used);
            if ends_line {
                if self.buf.last() == Some(&b'\r') {
                    self.buf.pop();
                }
                return Ok(Some(RawLine::Bytes));
            }
        }
    }
}

/// The text of a line, or why it cannot be read as text.
fn line_text<'a>(line: &RawLine, bytes: &'a [u8]) -> Result<&'a str, LineError> {
    match line {
        RawLine::TooLong => Err(LineError::TooLong),
        RawLine::Bytes => {
            std::str::from_utf8(bytes).map_err(|e| LineError::NotUtf8(e.valid_up_to() + 1))
        }
    }
}

/// Solves every line of `input`, writing one JSON line each to `output` and a one-line note for each
/// bad line to `errors`. Returns how many lines were bad. Blank lines are skipped.
///
/// A line that is not UTF-8 or is too long is a bad line like any other: the batch goes on. Only a
/// failure to read the input or to write `output` stops it; `errors` is best effort (it may be closed).
#[allow(
    clippy::expect_used,
    reason = "serde_json writes any value made of maps with string keys, numbers and strings"
)]
pub fn run_batch(
    input: impl BufRead,
    mut output: impl Write,
    mut errors: impl Write,
    default: Precision,
    with_trace: bool,
) -> std::io::Result<usize> {
    let mut bad = 0;
    let mut lines = LineReader::new(input);
    let mut number = 0;
    let mut out = Vec::with_capacity(OUTPUT_CHUNK + 4096);
    loop {
        if lines.will_wait() || out.len() >= OUTPUT_CHUNK {
            // Before the input may block, send what is answered (someone may be waiting for it).
            output.write_all(&out)?;
            out.clear();
            if lines.will_wait() {
                output.flush()?;
            }
        }
        let Some(line) = lines.next_line()? else {
            break;
        };
        number += 1;
        let start = out.len();
        let solved = line_text(&line, &lines.buf).and_then(|text| {
            // A byte-order mark (as some Windows editors write) opens the first line, not its JSON.
            let text = if number == 1 {
                text.strip_prefix('\u{feff}').unwrap_or(text)
            } else {
                text
            };
            if text.trim().is_empty() {
                return Ok(());
            }
            parse_case(text, default)?.solve_into(number, with_trace, &mut out)
        });
        if let Err(error) = solved {
            let message = error.to_string();
            out.truncate(start);
            bad += 1;
            let _ = writeln!(errors, "raylab: line {number}: {message}");
            let error = json!({"line": number, "status": "error", "error": message});
            serde_json::to_writer(&mut out, &error).expect("JSON values always serialize");
            out.push(b'\n');
        }
    }
    output.write_all(&out)?;
    output.flush()?;
    Ok(bad)
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::Value;

    /// Runs a batch over `input` without traces: how many lines were bad, then what it wrote to
    /// standard output and to standard error.
    fn batch(input: impl BufRead, default: Precision) -> (usize, String, String) {
        let (mut out, mut err) = (Vec::new(), Vec::new());
        let bad = run_batch(input, &mut out, &mut err, default, false).unwrap();
        let err = String::from_utf8_lossy(&err).into_owned();
        (bad, String::from_utf8(out).unwrap(), err)
    }

    #[test]
    fn a_byte_order_mark_before_the_first_line_is_not_part_of_it() {
        let line = r#"{"kind":"segments","a1":"0,0","a2":"4,4","b1":"0,4","b2":"4,0"}"#;
        let input = format!("\u{feff}{line}\n{line}\n");
        let (bad, out, errors) = batch(input.as_bytes(), Precision::F64);
        assert_eq!(bad, 0, "{errors}");
        assert_eq!(out.lines().count(), 2);
    }

    #[test]
    fn accepts_strings_arrays_and_fractions() {
        let line = r#"{"kind":"triangle","a":"3,0,0","b":[0,3,0],"c":["0","0","3"],"origin":[0,0,0],"dir":[1,1,1],"precision":"exact"}"#;
        let case = parse_case(line, Precision::F64).unwrap();
        assert_eq!(case.precision, Precision::Exact);
        assert_eq!(case.kind, "triangle");
        assert!(case.solve_into(1, false, &mut Vec::new()).is_ok());
    }

    #[test]
    fn names_the_problem() {
        let cases = [
            ("{", "not valid JSON"),
            ("[1]", "expected a JSON object"),
            (r#"{"a":1}"#, "missing field 'kind'"),
            (r#"{"kind":"cube"}"#, "unknown kind 'cube'"),
            (
                r#"{"kind":"segments","a1":"1,2","a2":"1,2","b1":"1,2"}"#,
                "missing field 'b2'",
            ),
            (
                r#"{"kind":"segments","a1":"1,2,3","a2":"1,2","b1":"1,2","b2":"1,2"}"#,
                "field 'a1': expected 2 numbers",
            ),
            (
                r#"{"kind":"segments","a1":"1,2","a2":"1,2","b1":"1,2","b2":"1,2","x":1}"#,
                "unknown field 'x'",
            ),
            (
                r#"{"kind":"segments","a1":[1,null],"a2":"1,2","b1":"1,2","b2":"1,2"}"#,
                "null is not a number",
            ),
            (
                r#"{"kind":"segments","a1":"1,2","a2":"1,2","b1":"1,2","b2":"1,2","precision":"f16"}"#,
                "unknown precision",
            ),
        ];
        for (line, expected) in cases {
            let err = parse_case(line, Precision::F64)
                .and_then(|case| case.solve_into(1, false, &mut Vec::new()))
                .unwrap_err()
                .to_string();
            assert!(err.contains(expected), "{line}: {err}");
        }
    }

    #[test]
    fn keeps_going_after_a_bad_line() {
        let input = "{\"kind\":\"segments\",\"a1\":\"1,2\",\"a2\":\"6,1\",\"b1\":\"2,6\",\"b2\":\"5,1\"}\n\nnonsense\n{\"kind\":\"segments\",\"a1\":\"1,1\",\"a2\":\"6,3\",\"b1\":\"2,6\",\"b2\":\"4,3\"}\n";
        let (bad, out, err) = batch(input.as_bytes(), Precision::Exact);
        assert_eq!(bad, 1);
        let lines: Vec<Value> = out
            .lines()
            .map(|l| serde_json::from_str(l).unwrap())
            .collect();
        assert_eq!(lines.len(), 3);
        assert_eq!(lines[0]["status"], "crossing");
        assert_eq!(lines[0]["exact"]["t"], "17/22");
        assert_eq!(lines[1]["line"], 3);
        assert_eq!(lines[1]["status"], "error");
        assert_eq!(lines[2]["status"], "lines-cross-outside");
        assert!(err.starts_with("raylab: line 3: not valid JSON"), "{err}");
    }

    fn statuses(input: &[u8]) -> (usize, Vec<Value>) {
        let (bad, out, _) = batch(input, Precision::F64);
        let lines = out
            .lines()
            .map(|l| serde_json::from_str(l).unwrap())
            .collect();
        (bad, lines)
    }

    #[test]
    fn a_line_of_invalid_utf8_is_one_bad_line() {
        let good = br#"{"kind":"segments","a1":"1,2","a2":"6,1","b1":"2,6","b2":"5,1"}"#;
        let mut input = Vec::new();
        input.extend_from_slice(good);
        input.extend_from_slice(b"\n\xff\xfe\r\n");
        input.extend_from_slice(good);
        let (bad, lines) = statuses(&input);
        assert_eq!(bad, 1);
        assert_eq!(lines.len(), 3);
        assert_eq!(lines[1]["line"], 2);
        assert!(lines[1]["error"].as_str().unwrap().contains("UTF-8"));
        assert_eq!(lines[2]["line"], 3);
        assert_eq!(lines[2]["status"], "crossing");
    }

    #[test]
    fn a_line_past_the_limit_is_refused_and_the_batch_goes_on() {
        let good = br#"{"kind":"segments","a1":"1,2","a2":"6,1","b1":"2,6","b2":"5,1"}"#;
        let mut input = vec![b' '; MAX_LINE_BYTES + 10];
        input.push(b'\n');
        input.extend_from_slice(good);
        // A reader that hands out small chunks, as a pipe does.
        let reader = std::io::BufReader::with_capacity(1000, input.as_slice());
        let (bad, out, _) = batch(reader, Precision::F64);
        assert_eq!(bad, 1);
        let lines: Vec<&str> = out.lines().collect();
        assert_eq!(lines.len(), 2);
        assert!(lines[0].contains("longer than"), "{}", lines[0]);
        assert!(lines[1].contains("\"line\":2"), "{}", lines[1]);
    }

    #[test]
    fn the_last_line_needs_no_line_break() {
        let (bad, lines) =
            statuses(br#"{"kind":"segments","a1":"1,2","a2":"6,1","b1":"2,6","b2":"5,1"}"#);
        assert_eq!((bad, lines.len()), (0, 1));
    }

    /// Every answer and every error message is the same with the scanner as with serde_json alone,
    /// on real lines and on thousands of mutations of them (bytes dropped, swapped or added).
    #[test]
    fn the_scanner_answers_as_serde_json_alone() {
        use rand::{Rng, SeedableRng};
        let seeds = [
            r#"{"kind":"triangle","a":[3,0,0],"b":[0,3,0],"c":[0,0,3],"origin":[0.25,-1.5e-1,0],"dir":[1,1,1]}"#,
            r#"{"kind":"triangle","a":"3,0,0","b":"0,3,0","c":"0,0,3","origin":"0,0,0","dir":"1,1,1","tmin":"1/2"}"#,
            r#" { "kind" : "segments" , "a1" : [ 1 , "2" ] , "a2":[6,1],"b1":"2,6","b2":[5,1] } "#,
            r#"{"kind":"parallelogram","corner":[0,0,0],"e1":[2,0,0],"e2":[0,1,0],"origin":[0.5,0.5,1],"dir":[0,0,-1],"precision":"exact"}"#,
            r#"{"kind":"segments","a1":"1,2","a2":"6,1","b1":"2,6","b2":"5,1","kind":"triangle","x":[]}"#,
            r#"{"kind":"segm\u0065nts","a1":["1","2"],"a2":[6,1E0],"b1":[2,6],"b2":[5,-0]}"#,
        ];
        let alphabet: Vec<char> = "{}[],:\" -.0123456789eE+nul\t\\/xé".chars().collect();
        let mut rng = rand_pcg::Pcg64::seed_from_u64(15);
        let mut input = String::new();
        for seed in seeds {
            input.push_str(seed);
            input.push('\n');
            for _ in 0..3000 {
                let mut chars: Vec<char> = seed.chars().collect();
                for _ in 0..rng.random_range(1..=3) {
                    let at = rng.random_range(0..chars.len());
                    let new = alphabet[rng.random_range(0..alphabet.len())];
                    match rng.random_range(0..3) {
                        0 => drop(chars.remove(at)),
                        1 => chars[at] = new,
                        _ => chars.insert(at, new),
                    }
                }
                input.extend(chars);
                input.push('\n');
            }
        }
        let answers = |serde_only: bool| {
            SERDE_ONLY.with(|s| s.set(serde_only));
            let mut out = Vec::new();
            for precision in [Precision::F64, Precision::Exact] {
                run_batch(
                    input.as_bytes(),
                    &mut out,
                    std::io::sink(),
                    precision,
                    false,
                )
                .unwrap();
            }
            SERDE_ONLY.with(|s| s.set(false));
            String::from_utf8(out).unwrap()
        };
        let (fast, slow) = (answers(false), answers(true));
        for (i, (a, b)) in fast.lines().zip(slow.lines()).enumerate() {
            assert_eq!(a, b, "line {}", i + 1);
        }
        assert_eq!(fast.lines().count(), slow.lines().count());
        assert!(fast.contains("\"status\":\"error\"") && fast.contains("\"status\":\"hit\""));
    }
}
