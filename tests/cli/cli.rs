//! The `raylab` binary as a user runs it: flags in, text / JSON / LaTeX out, one-line errors.

// A test or benchmark fails by panicking: unwrap and expect are how it says so.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use crate::run;

use std::process::{Command, Output};

use run::{PARALLELOGRAM_HIT, raylab_with_stdin};
use serde_json::Value;

fn raylab(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_raylab"))
        .args(args)
        .output()
        .expect("the binary runs")
}

fn stdout(output: &Output) -> String {
    String::from_utf8(output.stdout.clone()).unwrap()
}

fn stderr(output: &Output) -> String {
    String::from_utf8(output.stderr.clone()).unwrap()
}

/// The standard output of `raylab args…`, which must succeed (its standard error is shown if not).
fn succeeds(args: &[&str]) -> String {
    let output = raylab(args);
    assert!(output.status.success(), "{}", stderr(&output));
    stdout(&output)
}

/// The standard error of `raylab args…`, which must fail.
fn fails(args: &[&str]) -> String {
    let output = raylab(args);
    assert!(!output.status.success(), "{args:?} should fail");
    stderr(&output)
}

fn json(args: &[&str]) -> Value {
    serde_json::from_str(&succeeds(args)).expect("one JSON object")
}

/// [`json`] for a scene's arguments followed by flags.
fn json_of(scene: &[&str], flags: &[&str]) -> Value {
    json(&[scene, flags].concat())
}

const SEED000_SEGMENTS: [&str; 10] = [
    "solve", "segments", "--a1", "1,2", "--a2", "6,1", "--b1", "2,6", "--b2", "5,1",
];
const LECTURE_TRIANGLE: [&str; 12] = [
    "solve", "triangle", "--a", "3,0,0", "--b", "0,3,0", "--c", "0,0,3", "--origin", "0,0,0",
    "--dir", "1,1,1",
];

#[test]
fn text_shows_every_step_of_the_lecture_example() {
    let output = raylab(&LECTURE_TRIANGLE);
    assert!(output.status.success());
    let text = stdout(&output);
    for expected in [
        "The system M X = Y",
        "M1: M with column 1 replaced by Y",
        "|M| = 3·|0 1; -3 1| − 3·|-3 1; 0 1| + 1·|-3 0; 0 -3|",
        "= 27",
        "β = |M1| / |M| = 9 / 27 = 0.3333333333",
        "t = |M3| / |M| = 27 / 27 = 1",
        "✓ β + γ ≤ 1",
        "⇒ HIT",
        "P = (1, 1, 1)",
        "t·|D| = 1.732050808",
    ] {
        assert!(text.contains(expected), "missing {expected:?} in\n{text}");
    }
}

#[test]
fn json_has_status_parameters_point_and_exact_strings() {
    let result = json_of(
        &SEED000_SEGMENTS,
        &["--format", "json", "--precision", "exact"],
    );
    assert_eq!(result["status"], "crossing");
    assert_eq!(result["exact"]["t"], "17/22");
    assert_eq!(result["exact"]["s"], "21/22");
    assert!((result["t"].as_f64().unwrap() - 17.0 / 22.0).abs() < 1e-15);
    assert_eq!(result["point"].as_array().unwrap().len(), 2);
    let steps = result["trace"]["steps"].as_array().unwrap();
    assert!(
        steps
            .iter()
            .any(|s| s["id"] == "det_M" && s["payload"]["kind"] == "determinant")
    );

    let result = json_of(
        &LECTURE_TRIANGLE,
        &["--format", "json", "--precision", "exact"],
    );
    assert_eq!(result["status"], "hit");
    assert_eq!(result["exact"]["beta"], "1/3");
    assert_eq!(result["exact"]["gamma"], "1/3");
    assert_eq!(result["exact"]["t"], "1");
    assert_eq!(result["exact"]["distance"], "√3");
    assert_eq!(result["t"], 1.0);
}

#[test]
fn float_json_has_no_exact_block_and_nulls_for_missing_parameters() {
    // The lecture triangle and origin, the ray along the triangle's plane.
    let result = json_of(
        &LECTURE_TRIANGLE[..10],
        &["--dir", "1,-1,0", "--format", "json", "--no-trace"],
    );
    assert_eq!(result["status"], "parallel");
    assert_eq!(result["t"], Value::Null);
    assert_eq!(result["point"], Value::Null);
    assert!(result.get("exact").is_none());
    assert!(result.get("trace").is_none());
}

#[test]
fn parallelogram_and_f32_run() {
    let result = json_of(
        &PARALLELOGRAM_HIT,
        &["--format", "json", "--precision", "f32"],
    );
    assert_eq!(result["status"], "hit");
    assert_eq!(result["precision"], "f32");
    assert_eq!(result["alpha"], 0.25);
    assert_eq!(result["beta"], 0.5);
    assert_eq!(result["t"], 1.0);
}

#[test]
fn latex_has_bmatrix_and_cramer_fractions() {
    let mut args = LECTURE_TRIANGLE.to_vec();
    args.extend(["--format", "latex", "--precision", "exact"]);
    let output = raylab(&args);
    let latex = stdout(&output);
    for expected in [
        "M = \\begin{bmatrix} 3 & 3 & 1 \\\\ -3 & 0 & 1 \\\\ 0 & -3 & 1 \\end{bmatrix}",
        "\\beta = \\frac{|M_1|}{|M|} = \\frac{9}{27} = \\frac{1}{3}",
        "\\begin{vmatrix}",
    ] {
        assert!(latex.contains(expected), "missing {expected:?} in\n{latex}");
    }
    assert!(
        latex.contains("{\\color{teal} 3}"),
        "replaced column is highlighted: {latex}"
    );
}

#[test]
fn exact_reads_decimals_as_written() {
    // Seed 003's ray, with 0.1 read as 1/10: the hit is exactly (9/76, 9/76, 45/38).
    let args = [
        "solve",
        "triangle",
        "--a",
        "0,1,1.5",
        "--b",
        "1,0,1.25",
        "--c",
        "-1,0,1",
        "--origin",
        "0,0,0",
        "--dir",
        "0.1,0.1,1",
        "--precision",
        "exact",
        "--format",
        "json",
    ];
    let result = json(&args);
    assert_eq!(
        result["exact"]["point"],
        serde_json::json!(["9/76", "9/76", "45/38"])
    );
}

/// Bad input: one line on stderr naming the flag, nothing on stdout, a non-zero exit.
fn expect_one_line_error(args: &[&str], names: &[&str]) {
    let output = raylab(args);
    assert!(!output.status.success(), "{args:?} should fail");
    assert!(stdout(&output).is_empty());
    let message = stderr(&output);
    assert_eq!(message.trim_end().lines().count(), 1, "{message}");
    for name in names {
        assert!(message.contains(name), "{message:?} should name {name}");
    }
}

#[test]
fn bad_input_gets_one_line_naming_the_flag() {
    let with = |flag: &str, value: &str| {
        let mut args: Vec<String> = SEED000_SEGMENTS.iter().map(|s| s.to_string()).collect();
        let at = args.iter().position(|a| a == flag).unwrap();
        args[at + 1] = value.to_string();
        args
    };
    let cases = [
        (with("--a1", "1,2,3"), vec!["--a1", "expected 2 numbers"]),
        (with("--b2", "nan,1"), vec!["--b2", "NaN"]),
        (with("--a2", "1,x"), vec!["--a2", "'x' is not a number"]),
        (with("--b1", "inf,1"), vec!["--b1", "finite"]),
        (with("--a1", "1e999,0"), vec!["--a1", "too large"]),
        (with("--a1", ""), vec!["--a1"]),
    ];
    for (args, names) in cases {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        expect_one_line_error(&args, &names);
    }
    expect_one_line_error(&["solve", "segments", "--a1", "1,2"], &["--a2"]);
    let mut bad_precision = LECTURE_TRIANGLE.to_vec();
    bad_precision.extend(["--precision", "f16"]);
    expect_one_line_error(&bad_precision, &["--precision"]);
    expect_one_line_error(&["solve"], &["segments"]);
}

#[test]
fn negative_numbers_and_fractions_are_values_not_flags() {
    let args = [
        "solve",
        "segments",
        "--a1",
        "-1,-1",
        "--a2",
        "1/2,1/2",
        "--b1",
        "-1,1",
        "--b2",
        "1,-1",
        "--format",
        "json",
        "--precision",
        "exact",
    ];
    let result = json(&args);
    assert_eq!(result["status"], "crossing");
    assert_eq!(result["exact"]["point"], serde_json::json!(["0", "0"]));
}

#[test]
fn batch_reads_lines_and_keeps_going_past_bad_ones() {
    let input = [
        r#"{"kind":"segments","a1":"1,2","a2":"6,1","b1":"2,6","b2":"5,1","precision":"exact"}"#,
        r#"{"kind":"triangle","a":[3,0,0],"b":[0,3,0],"c":[0,0,3],"origin":[0,0,0],"dir":[1,1,1]}"#,
        r#"{"kind":"triangle","a":[3,0,0],"b":[0,3,0]}"#,
        r#"{"kind":"parallelogram","corner":"0,0,0","e1":"1,0,0","e2":"0,1,0","origin":"0.5,0.5,1","dir":"0,0,-1"}"#,
    ]
    .join("\n");
    let output = raylab_with_stdin(&["solve", "--batch", "--no-trace"], input.as_bytes());
    assert_eq!(
        output.status.code(),
        Some(1),
        "a bad line makes the exit non-zero"
    );
    let lines: Vec<Value> = stdout(&output)
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(lines.len(), 4);
    assert_eq!(lines[0]["exact"]["t"], "17/22");
    assert_eq!(lines[1]["status"], "hit");
    assert_eq!(lines[1]["precision"], "f64");
    assert_eq!(lines[2]["status"], "error");
    assert_eq!(lines[2]["line"], 3);
    assert!(
        lines[2]["error"]
            .as_str()
            .unwrap()
            .contains("missing field 'c'")
    );
    assert_eq!(lines[3]["status"], "hit");
    assert!(stderr(&output).contains("line 3: missing field 'c'"));

    let good = raylab_with_stdin(
        &["solve", "--batch", "--precision", "exact"],
        &input.as_bytes()[..input.find('\n').unwrap()],
    );
    assert!(good.status.success());
    let line: Value = serde_json::from_str(stdout(&good).trim()).unwrap();
    assert!(line["trace"]["steps"].is_array());
}

#[test]
fn help_names_the_commands() {
    let output = raylab(&["--help"]);
    let help = stdout(&output) + &stderr(&output);
    assert!(help.contains("Usage: raylab"), "{help}");
    assert!(help.contains("solve"));
}

#[test]
fn the_lecture_examples_file_solves_as_the_readme_says() {
    let input = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/assets/examples/lecture.jsonl"
    ))
    .unwrap();
    let output = raylab_with_stdin(&["solve", "--batch", "--no-trace"], input.as_bytes());
    assert!(output.status.success(), "{}", stderr(&output));
    let statuses: Vec<String> = stdout(&output)
        .lines()
        .map(|l| serde_json::from_str::<Value>(l).unwrap()["status"].to_string())
        .collect();
    let expected = [
        "crossing",
        "lines-cross-outside",
        "hit",
        "hit",
        "hit",
        "hit",
        "hit",
        "hit",
    ];
    assert_eq!(statuses, expected.map(|s| format!("\"{s}\"")));
}

#[test]
fn solve_runs_any_study_method_with_its_trace() {
    let result = json_of(
        &LECTURE_TRIANGLE,
        &["--method", "watertight", "--format", "json"],
    );
    assert_eq!(result["method"], "watertight");
    assert_eq!(result["status"], "hit");
    assert_eq!(result["t"], 1.0);
    assert!(result["trace"]["steps"].as_array().unwrap().len() > 5);
    for method in [
        "cramer",
        "moller-trumbore",
        "plane",
        "normal-equations",
        "inverse",
        "exact",
    ] {
        let result = json_of(
            &LECTURE_TRIANGLE,
            &["--method", method, "--format", "json", "--precision", "f32"],
        );
        assert_eq!(result["status"], "hit", "{method}");
    }
    expect_one_line_error(
        &[
            &LECTURE_TRIANGLE[..],
            &["--method", "plane", "--precision", "exact"],
        ]
        .concat(),
        &["--method exact"],
    );
    expect_one_line_error(
        &[&LECTURE_TRIANGLE[..], &["--method", "fast"]].concat(),
        &["--method", "watertight"],
    );
}

#[test]
fn bench_prints_the_hard_case_gallery() {
    let output = raylab(&["bench", "--hard-cases"]);
    assert!(output.status.success());
    let text = stdout(&output);
    assert!(text.contains("through a vertex at a slant"));
    assert!(text.contains("wrong: cramer/f32 says miss"));
    assert!(text.contains("input out of range for: watertight/f64"));
}

/// Seed 003's facing-ratio render scene.
const FACING: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/assets/scenes/seed003-facing.ron"
);

/// A fresh scratch folder for one test, and the PNG path in it.
fn scratch(name: &str) -> (std::path::PathBuf, std::path::PathBuf) {
    let dir = std::env::temp_dir().join(format!("raylab-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let png = dir.join("out.png");
    (dir, png)
}

#[test]
fn render_writes_a_png_and_names_bad_scene_files() {
    let (dir, png) = scratch("render");
    let scene = FACING;
    let stats = succeeds(&[
        "render",
        scene,
        "-o",
        png.to_str().unwrap(),
        "--stats",
        "--method",
        "moller-trumbore",
    ]);
    assert!(stats.contains("covered pixels 38737"), "{stats}");
    assert!(stats.contains("colour interpolations 0"));
    assert!(std::fs::metadata(&png).unwrap().len() > 1000);
    let bad = dir.join("bad.ron");
    std::fs::write(&bad, "(title: \"x\",\n note: \"y\",\n problem: Render((width: 4, height: 4,\n camera: Sideways,\n objects: [], effects: [])))").unwrap();
    let message = fails(&["render", bad.to_str().unwrap(), "-o", png.to_str().unwrap()]);
    assert_eq!(message.trim_end().lines().count(), 1, "{message}");
    assert!(message.contains("bad.ron:4:"), "{message}");
    // A scene that parses but names a mesh that is not there: the file and what is missing.
    std::fs::write(&bad, "(title: \"x\", note: \"y\", problem: Render((width: 4, height: 4, camera: ImagePlane(x: (1.0, -1.0), y: (1.0, -1.0), z: 1.0), objects: [(shape: Mesh(obj: \"meshes/missing.obj\"))], effects: [\"coverage\"])))").unwrap();
    let message = fails(&["render", bad.to_str().unwrap(), "-o", png.to_str().unwrap()]);
    assert!(
        message.contains("object 1: cannot find 'meshes/missing.obj'"),
        "{message}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn render_takes_effects_and_a_bug_and_names_bad_ones() {
    let (dir, png) = scratch("render-flags");
    let png = png.to_str().unwrap();
    let scene = FACING;
    // Only coverage: the facing ratio the scene calls for is not computed.
    let stats = succeeds(&[
        "render",
        scene,
        "-o",
        png,
        "--stats",
        "--effects",
        "coverage",
    ]);
    assert!(stats.contains("shading 0,"), "{stats}");
    // Seed 003's `and` for `or`: far more of the plane is "hit".
    let stats = succeeds(&["render", scene, "-o", png, "--stats", "--bug", "and-for-or"]);
    assert!(!stats.contains("covered pixels 38737"));
    for (flag, value, expected) in [
        ("--bug", "and-for-and", "unknown bug 'and-for-and'"),
        ("--effects", "coverage,glow", "unknown effect 'glow'"),
    ] {
        let message = fails(&["render", scene, "-o", png, flag, value]);
        assert!(message.contains(expected), "{message}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn an_unknown_lesson_is_refused_before_a_window_opens() {
    expect_one_line_error(
        &["--lesson", "no-such-lesson"],
        &["no-such-lesson", "seed000-segments-and-triangle"],
    );
    assert_eq!(raylab(&["--lesson", "nope"]).status.code(), Some(2));
}

#[test]
fn symbolic_steps_derive_the_triangle_and_check_each_merge_on_the_numbers() {
    let mut args = LECTURE_TRIANGLE.to_vec();
    args.extend(["--precision", "symbolic"]);
    let text = succeeds(&args);
    assert!(text.contains("|M| = ax*by*dz - ax*bz*dy"), "{text}");
    // The lecture triangle: |M| = 27, |M1| = |M2| = 9, |M3| = 27, on both sides of every merge.
    for check in ["27 = 27", "9 = 9"] {
        assert!(
            text.contains(&format!("✓ on this scene: {check}")),
            "{text}"
        );
    }
    assert!(!text.contains('✗'), "{text}");
    assert!(
        text.contains("merged (q, r and four dot products, as Möller–Trumbore computes them): 24")
    );
    args.extend(["--format", "json"]);
    let json: serde_json::Value = serde_json::from_str(&stdout(&raylab(&args))).unwrap();
    assert_eq!(json["solver"], "triangle-symbolic");
    // Only the triangle has a symbolic derivation.
    expect_one_line_error(
        &[
            "solve",
            "segments",
            "--a1",
            "0,0",
            "--a2",
            "1,1",
            "--b1",
            "0,1",
            "--b2",
            "1,0",
            "--precision",
            "symbolic",
        ],
        &["symbolic", "triangle"],
    );
}

#[test]
fn exact_values_beyond_the_float_range_read_from_the_exact_value() {
    // t = 10^400 along a D of length √3·10^-400: a float would say t = ∞ and t·|D| = NaN.
    let mut args = LECTURE_TRIANGLE[..10].to_vec();
    args.extend(["--dir", "1e-400,1e-400,1e-400", "--precision", "exact"]);
    let text = stdout(&raylab(&args));
    assert!(
        text.contains("⇒ HIT: the ray hits the triangle at t = ≈1e400"),
        "{text}"
    );
    assert!(text.contains("t·|D| = √3 ≈ 1.732050808"), "{text}");
    for bad in ["inf", "NaN", "|D| = 0;"] {
        assert!(!text.contains(bad), "{bad} in {text}");
    }
    let mut json_args = args.to_vec();
    json_args.extend(["--format", "json", "--no-trace"]);
    let json: serde_json::Value = serde_json::from_str(&stdout(&raylab(&json_args))).unwrap();
    assert_eq!(json["t"], "≈1e400", "a string where a float cannot hold it");
    assert!((json["distance"].as_f64().unwrap() - 3f64.sqrt()).abs() < 1e-15);
    assert!(
        json["exact"]["t"]
            .as_str()
            .unwrap()
            .starts_with("1000000000")
    );
    let mut latex_args = args.to_vec();
    latex_args.extend(["--format", "latex"]);
    let latex = stdout(&raylab(&latex_args));
    assert!(latex.contains("\\approx 1 \\times 10^{400}"), "{latex}");
    assert!(
        !latex.contains("\\infty") && !latex.contains("NaN"),
        "{latex}"
    );
}

/// Runs `raylab args…` with `input` on standard input and standard output discarded, standard error
/// going to `stderr`; returns the exit code (None: killed by a signal).
fn exit_code_with(args: &[&str], input: &[u8], stderr: std::process::Stdio) -> Option<i32> {
    use std::io::Write as _;
    let mut child = Command::new(env!("CARGO_BIN_EXE_raylab"))
        .args(args)
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::null())
        .stderr(stderr)
        .spawn()
        .expect("the binary runs");
    let mut stdin = child.stdin.take().expect("stdin is piped");
    // A command that does not read its input may have exited already: a closed pipe here is fine.
    let _ = stdin.write_all(input);
    drop(stdin);
    child.wait().expect("the binary runs").code()
}

/// A pipe whose reader has gone (as `../shared/tools/closed_stderr.py` makes), to write standard
/// error into.
fn closed_pipe() -> std::process::Stdio {
    use std::os::fd::{FromRawFd, OwnedFd};
    let mut ends = [0; 2];
    #[allow(unsafe_code)]
    // SAFETY: pipe() fills two new file descriptors, which are owned from here on.
    let (reader, writer) = unsafe {
        assert_eq!(libc::pipe(ends.as_mut_ptr()), 0);
        (OwnedFd::from_raw_fd(ends[0]), OwnedFd::from_raw_fd(ends[1]))
    };
    drop(reader);
    std::process::Stdio::from(writer)
}

/// Every subcommand, on success and on failure, run twice: with standard error readable (its exit code
/// as the README says, and no panic message), then with standard error on a pipe whose reader has gone
/// (the same exit code: a message that cannot be written is no panic, exit 101).
#[test]
fn every_subcommand_exits_cleanly_with_standard_error_closed() {
    let folder = std::env::temp_dir().join(format!("raylab-closed-stderr-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&folder);
    std::fs::create_dir_all(&folder).unwrap();
    let out = |name: &str| folder.join(name).display().to_string();
    let scene = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/assets/scenes/seed003-facing.ron"
    );
    let lecture_scene = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/assets/scenes/seed000-triangle.ron"
    );
    let (png, sheets, sheets_there, db, results) = (
        out("facing.png"),
        out("sheets"),
        out("sheets-there"),
        out("class.sqlite3"),
        out("results"),
    );
    // A worksheet already there, which raylab replaces only with --force.
    std::fs::create_dir_all(&sheets_there).unwrap();
    std::fs::write(folder.join("sheets-there/worksheet.tex"), "old").unwrap();
    let segments = [
        "solve", "segments", "--a1", "0,0", "--a2", "4,4", "--b1", "0,4", "--b2", "4,0",
    ];
    let triangle = [
        "solve", "triangle", "--a", "1,0,0", "--b", "0,1,0", "--c", "0,0,1", "--origin", "0,0,0",
        "--dir", "1,1,1",
    ];
    fn with<'a>(base: &[&'a str], extra: &[&'a str]) -> Vec<&'a str> {
        [base, extra].concat()
    }
    let worksheet = ["worksheet", "--seed", "1", "--count", "2", "-o"];
    let good_line =
        br#"{"kind": "segments", "a1": [0, 0], "a2": [4, 4], "b1": [0, 4], "b2": [4, 0]}"#;
    let bad_lines = b"{\"kind\": \"segments\"}\nnot json\n";
    // (arguments, standard input, the exit code a user gets with standard error open)
    let cases: Vec<(Vec<&str>, &[u8], i32)> = vec![
        (vec!["--help"], b"", 0),
        (vec!["--version"], b"", 0),
        (vec!["solve", "--help"], b"", 0),
        (vec!["no-such-command"], b"", 2),
        (vec!["--lesson", "no-such-lesson"], b"", 2),
        // solve, in each format and precision, and refused
        (segments.to_vec(), b"", 0),
        (with(&segments, &["--format", "json"]), b"", 0),
        (with(&segments, &["--format", "latex"]), b"", 0),
        (
            with(&triangle, &["--precision", "exact", "--format", "json"]),
            b"",
            0,
        ),
        (
            with(&triangle, &["--method", "watertight", "--precision", "f32"]),
            b"",
            0,
        ),
        (
            with(&triangle, &["--precision", "symbolic", "--format", "latex"]),
            b"",
            0,
        ),
        (vec!["solve", "segments", "--a1", "0,0"], b"", 2),
        (vec!["solve"], b"", 2),
        (with(&segments, &["--precision", "symbolic"]), b"", 2),
        (
            with(
                &triangle,
                &["--method", "watertight", "--precision", "exact"],
            ),
            b"",
            2,
        ),
        (
            with(&triangle, &["--dir", "1e400,0,0", "--precision", "f32"]),
            b"",
            2,
        ),
        // batch
        (vec!["solve", "--batch"], good_line, 0),
        (
            vec!["solve", "--batch", "--precision", "exact"],
            good_line,
            0,
        ),
        (vec!["solve", "--batch"], bad_lines, 1),
        (vec!["solve", "--batch", "--format", "latex"], good_line, 2),
        (
            vec!["solve", "--batch", "--precision", "symbolic"],
            good_line,
            2,
        ),
        // render, a small scene
        (vec!["render", scene, "-o", &png, "--stats"], b"", 0),
        (
            vec!["render", scene, "-o", &png, "--effects", "coverage"],
            b"",
            0,
        ),
        (vec!["render", "no-such-scene.ron", "-o", &png], b"", 1),
        (vec!["render", lecture_scene, "-o", &png], b"", 1),
        (vec!["render", scene, "-o", "facing.jpg"], b"", 2),
        (
            vec!["render", scene, "-o", &png, "--effects", "sparkle"],
            b"",
            2,
        ),
        (
            vec!["render", scene, "-o", "/proc/no-such/facing.png"],
            b"",
            1,
        ),
        // worksheet
        (with(&worksheet, &[&sheets, "--force"]), b"", 0),
        (with(&worksheet, &[&sheets_there]), b"", 1),
        (with(&worksheet, &["/proc/no-such"]), b"", 1),
        (
            vec!["worksheet", "--seed", "1", "--count", "0", "-o", &sheets],
            b"",
            2,
        ),
        // bench: a tiny study writing its results, the gallery, and refusals
        (
            vec!["bench", "--quick", "--rays", "4", "--out", &results],
            b"",
            0,
        ),
        (vec!["bench", "--hard-cases"], b"", 0),
        (vec!["bench", "--out", scene], b"", 2),
        (vec!["bench", "--rays", "0"], b"", 2),
        // class: the export and the server's refusals (a server that starts runs until stopped)
        (vec!["class", "export", "NOSUCH", "--db", &db], b"", 1),
        (vec!["class", "--listen", "not-an-address"], b"", 2),
        (
            vec![
                "class",
                "--listen",
                "127.0.0.1:0",
                "--db",
                "/proc/no-such/class.sqlite3",
            ],
            b"",
            1,
        ),
    ];
    for (args, input, expected) in cases {
        let command = format!("raylab {}", args.join(" "));
        let readable = Command::new(env!("CARGO_BIN_EXE_raylab"))
            .args(&args)
            .stdin(std::process::Stdio::piped())
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .and_then(|mut child| {
                use std::io::Write as _;
                let _ = child.stdin.take().expect("stdin is piped").write_all(input);
                child.wait_with_output()
            })
            .expect("the binary runs");
        let said = stderr(&readable);
        assert_eq!(readable.status.code(), Some(expected), "{command}: {said}");
        assert!(!said.contains("panicked"), "{command}: {said}");
        if expected != 0 {
            assert!(said.starts_with("raylab"), "{command} says why: {said}");
        }
        assert_eq!(
            exit_code_with(&args, input, closed_pipe()),
            Some(expected),
            "{command} with standard error closed"
        );
    }
    let _ = std::fs::remove_dir_all(&folder);
}

/// A report that cannot be written (a full disk: `/dev/full`) is a failure with a message, in every
/// format, never a silent success.
#[test]
fn a_report_that_cannot_be_written_fails() {
    let full = std::path::Path::new("/dev/full");
    if !full.exists() {
        println!("skipped: no /dev/full on this system");
        return;
    }
    let segments = [
        "solve", "segments", "--a1", "0,0", "--a2", "4,4", "--b1", "0,4", "--b2", "4,0",
    ];
    let symbolic = [
        "solve",
        "triangle",
        "--a",
        "1,0,0",
        "--b",
        "0,1,0",
        "--c",
        "0,0,1",
        "--origin",
        "0,0,0",
        "--dir",
        "1,1,1",
        "--precision",
        "symbolic",
    ];
    for args in [&segments[..], &symbolic[..]] {
        for format in ["text", "json", "latex"] {
            let output = Command::new(env!("CARGO_BIN_EXE_raylab"))
                .args(args)
                .args(["--format", format])
                .stdout(std::fs::OpenOptions::new().write(true).open(full).unwrap())
                .output()
                .unwrap();
            assert_eq!(output.status.code(), Some(1), "{args:?} --format {format}");
            assert!(
                stderr(&output).contains("cannot write the output: No space left on device"),
                "{}",
                stderr(&output)
            );
        }
    }
}

#[test]
fn flags_that_would_be_ignored_are_refused_with_a_reason() {
    let mut symbolic = LECTURE_TRIANGLE.to_vec();
    symbolic.extend(["--precision", "symbolic"]);
    for (extra, says) in [
        (&["--tmin", "1/2"][..], "--tmin does not apply"),
        (
            &["--method", "moller-trumbore"][..],
            "--method does not apply",
        ),
        (
            &["--format", "json", "--no-trace"][..],
            "--no-trace does not apply",
        ),
    ] {
        let output = raylab(&[&symbolic[..], extra].concat());
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(2), "{extra:?}: {stderr}");
        assert!(stderr.contains(says), "{extra:?}: {stderr}");
    }
    // The symbolic JSON says whether every identity held, as other solves give a status.
    let json = [&symbolic[..], &["--format", "json"]].concat();
    let json: serde_json::Value = serde_json::from_str(&stdout(&raylab(&json))).unwrap();
    assert_eq!(json["status"], "identities-hold");
    // --lesson opens the app; with a subcommand it would be silently ignored.
    let output = raylab(
        &[
            &["--lesson", "seed000-segments-and-triangle"][..],
            &LECTURE_TRIANGLE,
        ]
        .concat(),
    );
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("does not apply to `raylab solve`"),
        "{stderr}"
    );
}

#[test]
fn a_huge_refused_argument_is_quoted_short() {
    let huge = "x".repeat(100_000);
    let output = raylab(&[
        "solve", "segments", "--a1", &huge, "--a2", "1,1", "--b1", "0,1", "--b2", "1,0",
    ]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(
        output.status.code(),
        Some(2),
        "{}",
        &stderr[..stderr.len().min(300)]
    );
    assert!(
        stderr.len() < 400,
        "{} bytes: {}",
        stderr.len(),
        &stderr[..300]
    );
    assert!(stderr.contains("(100000 characters)"), "{stderr}");
}
