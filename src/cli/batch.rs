//! `raylab solve --batch`: one JSON case per input line, one JSON result per output line.
//!
//! A case has `"kind"` (`segments`, `triangle`, `parallelogram`), the same fields as the flags
//! (`a1 a2 b1 b2`; `a b c origin dir tmin`; `corner e1 e2 origin dir`), each a string `"1,2"` or an
//! array `[1, 2]` (numbers, or strings such as `"1/3"`), and optionally `"precision"`.

use std::io::{BufRead, Write};

use serde_json::{Map, Value, json};

use super::input::{Coords, Literal};
use super::solve::{Case, run};
use crate::geometry::Precision;

/// Reads one case from a JSON object; the precision is the case's own or `default`.
pub fn parse_case(line: &str, default: Precision) -> Result<(Case, Precision), String> {
    let value: Value = serde_json::from_str(line).map_err(|e| format!("not valid JSON: {e}"))?;
    let Value::Object(object) = value else {
        return Err("expected a JSON object".into());
    };
    let kind = match object.get("kind") {
        Some(Value::String(kind)) => kind.clone(),
        Some(_) => return Err("field 'kind' must be a string".into()),
        None => return Err("missing field 'kind' (segments, triangle or parallelogram)".into()),
    };
    let precision = match object.get("precision") {
        None => default,
        Some(Value::String(p)) => p.parse().map_err(|e| format!("field 'precision': {e}"))?,
        Some(_) => return Err("field 'precision' must be a string".into()),
    };
    let allowed: &[&str] = match kind.as_str() {
        "segments" => &["a1", "a2", "b1", "b2"],
        "triangle" => &["a", "b", "c", "origin", "dir", "tmin"],
        "parallelogram" => &["corner", "e1", "e2", "origin", "dir"],
        other => {
            return Err(format!(
                "unknown kind '{other}' (expected segments, triangle or parallelogram)"
            ));
        }
    };
    if let Some(unknown) = object
        .keys()
        .find(|k| !allowed.contains(&k.as_str()) && !["kind", "precision"].contains(&k.as_str()))
    {
        return Err(format!(
            "unknown field '{unknown}' for kind {kind} (expected {})",
            allowed.join(", ")
        ));
    }
    let case = match kind.as_str() {
        "segments" => Case::Segments {
            points: [
                coords(&object, "a1")?,
                coords(&object, "a2")?,
                coords(&object, "b1")?,
                coords(&object, "b2")?,
            ],
        },
        "triangle" => Case::Triangle {
            vectors: [
                coords(&object, "a")?,
                coords(&object, "b")?,
                coords(&object, "c")?,
                coords(&object, "origin")?,
                coords(&object, "dir")?,
            ],
            t_min: match object.get("tmin") {
                None => Literal::parse("0").expect("0 is a number"),
                Some(v) => number(v).map_err(|e| format!("field 'tmin': {e}"))?,
            },
        },
        _ => Case::Parallelogram {
            vectors: [
                coords(&object, "corner")?,
                coords(&object, "e1")?,
                coords(&object, "e2")?,
                coords(&object, "origin")?,
                coords(&object, "dir")?,
            ],
        },
    };
    Ok((case, precision))
}

fn coords<const N: usize>(object: &Map<String, Value>, name: &str) -> Result<Coords<N>, String> {
    let value = object
        .get(name)
        .ok_or_else(|| format!("missing field '{name}'"))?;
    let parsed = match value {
        Value::String(text) => Coords::parse(text),
        Value::Array(items) => {
            let texts: Result<Vec<String>, String> = items.iter().map(number_text).collect();
            texts
                .and_then(|t| Coords::from_parts(&t.iter().map(String::as_str).collect::<Vec<_>>()))
        }
        _ => Err("expected a string \"x,y,…\" or an array of numbers".into()),
    };
    parsed.map_err(|e| format!("field '{name}': {e}"))
}

/// A JSON number or string as number text (JSON numbers print as their shortest decimal form).
fn number_text(value: &Value) -> Result<String, String> {
    match value {
        Value::Number(n) => Ok(n.to_string()),
        Value::String(s) => Ok(s.clone()),
        Value::Null => Err("null is not a number".into()),
        other => Err(format!("{other} is not a number")),
    }
}

fn number(value: &Value) -> Result<Literal, String> {
    Literal::parse(&number_text(value)?)
}

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
}

impl<R: BufRead> LineReader<R> {
    fn new(input: R) -> Self {
        LineReader {
            input,
            buf: Vec::new(),
            skipping: false,
        }
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
fn line_text<'a>(line: &RawLine, bytes: &'a [u8]) -> Result<&'a str, String> {
    match line {
        RawLine::TooLong => Err(format!(
            "the line is longer than {MAX_LINE_BYTES} bytes; skipped to its end"
        )),
        RawLine::Bytes => std::str::from_utf8(bytes).map_err(|e| {
            format!(
                "not valid UTF-8 (byte {} of the line); skipped",
                e.valid_up_to() + 1
            )
        }),
    }
}

/// Solves every line of `input`, writing one JSON line each to `output` and a one-line note for each
/// bad line to `errors`. Returns how many lines were bad. Blank lines are skipped.
///
/// A line that is not UTF-8 or is too long is a bad line like any other: the batch goes on. Only a
/// failure to read the input or to write `output` stops it; `errors` is best effort (it may be closed).
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
    while let Some(line) = lines.next_line()? {
        number += 1;
        let parsed = line_text(&line, &lines.buf).and_then(|text| {
            if text.trim().is_empty() {
                Ok(None)
            } else {
                parse_case(text, default).map(Some)
            }
        });
        let result = match parsed {
            Ok(None) => continue,
            Ok(Some((case, precision))) => {
                let mut value = run(&case, precision).to_json(with_trace);
                value["line"] = json!(number);
                value
            }
            Err(message) => {
                bad += 1;
                let _ = writeln!(errors, "raylab: line {number}: {message}");
                json!({"line": number, "status": "error", "error": message})
            }
        };
        writeln!(output, "{result}")?;
    }
    Ok(bad)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn accepts_strings_arrays_and_fractions() {
        let line = r#"{"kind":"triangle","a":"3,0,0","b":[0,3,0],"c":["0","0","3"],"origin":[0,0,0],"dir":[1,1,1],"precision":"exact"}"#;
        let (case, precision) = parse_case(line, Precision::F64).unwrap();
        assert_eq!(precision, Precision::Exact);
        assert_eq!(case.kind(), "triangle");
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
            let err = parse_case(line, Precision::F64).unwrap_err();
            assert!(err.contains(expected), "{line}: {err}");
        }
    }

    #[test]
    fn keeps_going_after_a_bad_line() {
        let input = "{\"kind\":\"segments\",\"a1\":\"1,2\",\"a2\":\"6,1\",\"b1\":\"2,6\",\"b2\":\"5,1\"}\n\nnonsense\n{\"kind\":\"segments\",\"a1\":\"1,1\",\"a2\":\"6,3\",\"b1\":\"2,6\",\"b2\":\"4,3\"}\n";
        let (mut out, mut err) = (Vec::new(), Vec::new());
        let bad = run_batch(
            input.as_bytes(),
            &mut out,
            &mut err,
            Precision::Exact,
            false,
        )
        .unwrap();
        assert_eq!(bad, 1);
        let lines: Vec<Value> = String::from_utf8(out)
            .unwrap()
            .lines()
            .map(|l| serde_json::from_str(l).unwrap())
            .collect();
        assert_eq!(lines.len(), 3);
        assert_eq!(lines[0]["status"], "crossing");
        assert_eq!(lines[0]["exact"]["t"], "17/22");
        assert_eq!(lines[1]["line"], 3);
        assert_eq!(lines[1]["status"], "error");
        assert_eq!(lines[2]["status"], "lines-cross-outside");
        assert!(
            String::from_utf8(err)
                .unwrap()
                .starts_with("raylab: line 3: not valid JSON")
        );
    }

    fn statuses(input: &[u8]) -> (usize, Vec<Value>) {
        let (mut out, mut err) = (Vec::new(), Vec::new());
        let bad = run_batch(input, &mut out, &mut err, Precision::F64, false).unwrap();
        let lines = String::from_utf8(out)
            .unwrap()
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
        let (mut out, mut err) = (Vec::new(), Vec::new());
        let bad = run_batch(reader, &mut out, &mut err, Precision::F64, false).unwrap();
        assert_eq!(bad, 1);
        let out = String::from_utf8(out).unwrap();
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
}
