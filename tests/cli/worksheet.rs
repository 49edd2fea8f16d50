//! `raylab worksheet`: the sheet and key compile with pdflatex, every answer in the key is what
//! `raylab solve --precision exact` says, the same seed writes the same files, and bad arguments get
//! one line.
//!
//! pdflatex (Debian: texlive-latex-base) is needed for the compile test; where it is missing that test
//! prints `skipped: pdflatex is not installed` and passes, unless `RAYLAB_LATEX_TEST=require`.

// A test or benchmark fails by panicking: unwrap and expect are how it says so.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use crate::run;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use serde_json::Value;

fn raylab(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_raylab"))
        .args(args)
        .output()
        .unwrap()
}

/// A fresh scratch folder for one test.
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("raylab-worksheet-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

fn write_sheet(dir: &Path, seed: &str, count: &str, level: Option<&str>) {
    let mut args = vec!["worksheet", "--seed", seed, "--count", count, "-o"];
    let dir_text = dir.to_str().unwrap();
    args.push(dir_text);
    if let Some(level) = level {
        args.extend(["--level", level]);
    }
    let output = raylab(&args);
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
}

fn read(dir: &Path, name: &str) -> String {
    std::fs::read_to_string(dir.join(name)).unwrap()
}

#[test]
fn worksheet_and_key_compile_with_pdflatex() {
    if !run::pdflatex_or_skip() {
        return;
    }
    let dir = scratch("pdflatex");
    write_sheet(&dir, "11", "15", None);
    for name in ["worksheet", "key"] {
        let run = Command::new("pdflatex")
            .args(["-interaction=nonstopmode", "-halt-on-error"])
            .arg(format!("{name}.tex"))
            .current_dir(&dir)
            .output()
            .unwrap();
        let log = String::from_utf8_lossy(&run.stdout).to_string();
        assert!(run.status.success(), "{name}.tex: pdflatex failed:\n{log}");
        assert!(dir.join(format!("{name}.pdf")).exists());
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The key's `% key N: outcome=… id=value …` comments, by problem number.
fn key_answers(key: &str) -> BTreeMap<u64, BTreeMap<String, String>> {
    key.lines()
        .filter_map(|line| line.strip_prefix("% key "))
        .map(|rest| {
            let (number, fields) = rest.split_once(": ").unwrap();
            let fields = fields
                .split_whitespace()
                .map(|field| {
                    let (name, value) = field.split_once('=').unwrap();
                    (name.to_string(), value.to_string())
                })
                .collect();
            (number.parse().unwrap(), fields)
        })
        .collect()
}

/// The printed answer of problem `number`: its `\textbf{Answer:}` line in the key.
fn printed_answer(key: &str, number: u64) -> String {
    let start = key.find(&format!("% key {number}:")).unwrap();
    let item = &key[start..];
    let line = item
        .lines()
        .find(|l| l.starts_with("\\textbf{Answer:}"))
        .unwrap();
    line.to_string()
}

/// `3`, `\frac{1}{4}`, `-\frac{3}{2}` for a fraction as `raylab solve` writes it.
fn latex_fraction(fraction: &str) -> String {
    let (sign, unsigned) = match fraction.strip_prefix('-') {
        Some(rest) => ("-", rest),
        None => ("", fraction),
    };
    match unsigned.split_once('/') {
        Some((n, d)) => format!("{sign}\\frac{{{n}}}{{{d}}}"),
        None => fraction.to_string(),
    }
}

/// `raylab solve`'s flag for each input the JSON names.
fn flag(kind: &str, name: &str) -> String {
    let flag = match (kind, name) {
        (_, "L" | "o") => "origin",
        (_, "D" | "d") => "dir",
        ("parallelogram", "c") => "corner",
        (_, other) => return format!("--{}", other.to_lowercase()),
    };
    format!("--{flag}")
}

/// The outcome `raylab solve` reports, in the key's words.
fn outcome_of(kind: &str, solved: &Value) -> String {
    let status = solved["status"].as_str().unwrap();
    let strings = |key: &str| -> Vec<String> {
        solved[key]
            .as_array()
            .map(|a| a.iter().map(|v| v.as_str().unwrap().to_string()).collect())
            .unwrap_or_default()
    };
    match status {
        "hit" | "crossing" => "hit".into(),
        "miss-behind" => "behind".into(),
        "parallel" => "parallel".into(),
        "degenerate-triangle" | "degenerate-segment" => "degenerate".into(),
        "lines-cross-outside" => {
            let outside = strings("outside");
            assert_eq!(outside.len(), 1, "{solved}");
            format!("outside:{}", if outside[0] == "t" { "A" } else { "B" })
        }
        "miss-outside" if kind == "triangle" => {
            let edges = strings("beyond_edges");
            assert_eq!(edges.len(), 1, "{solved}");
            format!("outside:{}", edges[0])
        }
        "miss-outside" => {
            let failed = strings("failed");
            assert_eq!(failed.len(), 1, "{solved}");
            let side = match failed[0].as_str() {
                "α ≥ 0" => "alpha=0",
                "α ≤ 1" => "alpha=1",
                "β ≥ 0" => "beta=0",
                "β ≤ 1" => "beta=1",
                other => panic!("unexpected bound {other}"),
            };
            format!("outside:{side}")
        }
        other => panic!("unexpected status {other}"),
    }
}

#[test]
fn every_answer_in_the_key_is_what_raylab_solve_exact_says() {
    let dir = scratch("key");
    write_sheet(&dir, "2026", "20", None);
    let key_text = read(&dir, "key.tex");
    let key = key_answers(&key_text);
    let problems: Value = serde_json::from_str(&read(&dir, "problems.json")).unwrap();
    let problems = problems["problems"].as_array().unwrap();
    assert_eq!(problems.len(), 20);
    assert_eq!(key.len(), 20);
    let mut levels = std::collections::BTreeSet::new();
    for problem in problems {
        let number = problem["number"].as_u64().unwrap();
        let kind = problem["kind"].as_str().unwrap();
        levels.insert(problem["level"].as_str().unwrap().to_string());
        let mut args = vec!["solve".to_string(), kind.to_string()];
        for (name, coords) in problem["inputs"].as_object().unwrap() {
            let parts: Vec<&str> = coords
                .as_array()
                .unwrap()
                .iter()
                .map(|c| c.as_str().unwrap())
                .collect();
            args.push(flag(kind, name));
            args.push(parts.join(","));
        }
        args.extend(["--precision", "exact", "--format", "json", "--no-trace"].map(String::from));
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let output = raylab(&args);
        assert!(output.status.success(), "{args:?}");
        let solved: Value = serde_json::from_slice(&output.stdout).unwrap();

        let answer = &key[&number];
        assert_eq!(
            answer["outcome"],
            outcome_of(kind, &solved),
            "problem {number}"
        );
        let values: BTreeMap<&String, &String> = answer
            .iter()
            .filter(|(name, _)| *name != "outcome")
            .collect();
        let exact = solved["exact"].as_object();
        let unknowns: &[&str] = match kind {
            "segments" => &["t", "s"],
            "triangle" => &["beta", "gamma", "t"],
            _ => &["alpha", "beta", "t"],
        };
        for unknown in unknowns {
            let solved_value = exact.and_then(|e| e.get(*unknown)).and_then(Value::as_str);
            let key_value = values.get(&unknown.to_string()).map(|v| v.as_str());
            assert_eq!(key_value, solved_value, "problem {number}: {unknown}");
            if let Some(fraction) = solved_value {
                let symbol = if *unknown == "t" || *unknown == "s" {
                    ""
                } else {
                    "\\"
                };
                let printed = format!("${symbol}{unknown} = {}$", latex_fraction(fraction));
                let line = printed_answer(&key_text, number);
                assert!(
                    line.contains(&printed),
                    "problem {number}: {line} lacks {printed}"
                );
            }
            // problems.json carries the same exact answer.
            let json_value = problem["answer"]["values"][*unknown].as_str();
            assert_eq!(json_value, solved_value, "problem {number}: {unknown}");
        }
        assert_eq!(
            values.len(),
            if exact.is_some() { unknowns.len() } else { 0 }
        );
    }
    assert_eq!(levels.len(), 5, "the levels in turn: {levels:?}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_same_seed_writes_the_same_files() {
    let (first, second, other) = (scratch("same-1"), scratch("same-2"), scratch("same-3"));
    write_sheet(&first, "5", "8", Some("outside"));
    write_sheet(&second, "5", "8", Some("outside"));
    write_sheet(&other, "6", "8", Some("outside"));
    for name in ["worksheet.tex", "key.tex", "problems.json"] {
        assert_eq!(read(&first, name), read(&second, name), "{name}");
        assert_ne!(read(&first, name), read(&other, name), "{name}");
    }
    let problems: Value = serde_json::from_str(&read(&first, "problems.json")).unwrap();
    for problem in problems["problems"].as_array().unwrap() {
        assert_eq!(problem["level"], "outside");
    }
    for dir in [first, second, other] {
        let _ = std::fs::remove_dir_all(dir);
    }
}

fn expect_one_line_error(args: &[&str], says: &[&str]) {
    let output = raylab(args);
    assert!(!output.status.success(), "{args:?} succeeded");
    let message = String::from_utf8_lossy(&output.stderr).to_string();
    assert_eq!(message.trim_end().lines().count(), 1, "{message}");
    for word in says {
        assert!(
            message.contains(word),
            "{args:?}: '{message}' lacks '{word}'"
        );
    }
}

#[test]
fn bad_arguments_get_one_line() {
    let dir = scratch("bad");
    let dir_text = dir.to_str().unwrap();
    let base = |extra: &[&'static str]| -> Vec<String> {
        let mut args = vec!["worksheet", "--seed", "1", "-o", dir_text];
        args.extend(extra);
        args.into_iter().map(String::from).collect()
    };
    let run = |args: Vec<String>, says: &[&str]| {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        expect_one_line_error(&args, says);
    };
    run(
        base(&["--count", "3", "--level", "sideways"]),
        &["--level", "sideways", "expected hit"],
    );
    run(base(&["--count", "0"]), &["--count", "1..=100"]);
    run(base(&["--count", "101"]), &["--count", "1..=100"]);
    run(base(&["--count", "three"]), &["--count"]);
    run(base(&[]), &["--count"]);
    expect_one_line_error(&["worksheet", "--count", "2", "-o", dir_text], &["--seed"]);

    std::fs::write(&dir, "a file, not a folder").unwrap();
    run(base(&["--count", "2"]), &["exists and is not a directory"]);
    assert_eq!(
        std::fs::read_to_string(&dir).unwrap(),
        "a file, not a folder"
    );
    let _ = std::fs::remove_file(&dir);
}

#[test]
fn a_worksheet_is_replaced_only_when_asked_and_written_all_or_none() {
    let dir = scratch("replace");
    write_sheet(&dir, "3", "4", None);
    let before: Vec<String> = ["worksheet.tex", "key.tex", "problems.json"]
        .iter()
        .map(|name| read(&dir, name))
        .collect();
    let dir_text = dir.to_str().unwrap();
    // Without --force a worksheet already there is kept, and the message says what to do.
    let again = raylab(&["worksheet", "--seed", "4", "--count", "4", "-o", dir_text]);
    assert_eq!(again.status.code(), Some(1));
    let says = String::from_utf8_lossy(&again.stderr);
    assert!(
        says.contains("worksheet.tex: exists (pass --force"),
        "{says}"
    );
    assert_eq!(read(&dir, "worksheet.tex"), before[0]);
    // With --force, but problems.json cannot be written (a folder stands in its place): the two
    // other files are not replaced either, and no temporary file is left.
    std::fs::remove_file(dir.join("problems.json")).unwrap();
    std::fs::create_dir(dir.join("problems.json")).unwrap();
    let forced = [
        "worksheet",
        "--seed",
        "4",
        "--count",
        "4",
        "-o",
        dir_text,
        "--force",
    ];
    let failed = raylab(&forced);
    assert_eq!(failed.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&failed.stderr).contains("problems.json"));
    assert_eq!(read(&dir, "worksheet.tex"), before[0]);
    assert_eq!(read(&dir, "key.tex"), before[1]);
    let mut names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(names, ["key.tex", "problems.json", "worksheet.tex"]);
    // With --force and room to write, all three are the new seed's.
    std::fs::remove_dir(dir.join("problems.json")).unwrap();
    let replaced = raylab(&forced);
    assert!(
        replaced.status.success(),
        "{}",
        String::from_utf8_lossy(&replaced.stderr)
    );
    assert_ne!(read(&dir, "worksheet.tex"), before[0]);
    assert!(read(&dir, "problems.json").contains("\"seed\": 4"));
    let _ = std::fs::remove_dir_all(&dir);
}
