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

/// Solves every line of `input`, writing one JSON line each to `output` and a one-line note for each
/// bad line to `errors`. Returns how many lines were bad. Blank lines are skipped.
pub fn run_batch(
    input: impl BufRead,
    mut output: impl Write,
    mut errors: impl Write,
    default: Precision,
    with_trace: bool,
) -> std::io::Result<usize> {
    let mut bad = 0;
    for (index, line) in input.lines().enumerate() {
        let number = index + 1;
        let line = line?;
        if line.trim().is_empty() {
            continue;
        }
        let result = match parse_case(&line, default) {
            Ok((case, precision)) => {
                let mut value = run(&case, precision).to_json(with_trace);
                value["line"] = json!(number);
                value
            }
            Err(message) => {
                bad += 1;
                writeln!(errors, "raylab: line {number}: {message}")?;
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
}
