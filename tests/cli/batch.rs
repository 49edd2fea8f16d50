//! `raylab solve --batch` and the standard streams under hostile input, run as a user runs the binary:
//! bytes that are not UTF-8, lines with no end, closed pipes.

// A test or benchmark fails by panicking: unwrap and expect are how it says so.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use crate::run;

use std::io::{BufRead, BufReader};
use std::process::{Command, Output, Stdio};

use serde_json::Value;

const BIN: &str = env!("CARGO_BIN_EXE_raylab");

const SEED000: &str = r#"{"kind":"segments","a1":"1,2","a2":"6,1","b1":"2,6","b2":"5,1"}"#;

fn batch(args: &[&str], stdin: &[u8]) -> Output {
    let all: Vec<&str> = ["solve", "--batch"]
        .into_iter()
        .chain(args.iter().copied())
        .collect();
    run::raylab_with_stdin(&all, stdin)
}

fn json_lines(output: &Output) -> Vec<Value> {
    String::from_utf8(output.stdout.clone())
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).expect("each output line is JSON"))
        .collect()
}

#[test]
fn an_invalid_utf8_line_in_the_middle_loses_nothing_else() {
    let mut input = Vec::new();
    input.extend_from_slice(b"{\"kind\":\"triangle\"}\n");
    input.extend_from_slice(b"\xff\xfe\n");
    for _ in 0..3 {
        input.extend_from_slice(SEED000.as_bytes());
        input.push(b'\n');
    }
    let output = batch(&["--no-trace"], &input);
    assert_eq!(output.status.code(), Some(1));
    let lines = json_lines(&output);
    let numbers: Vec<u64> = lines.iter().map(|l| l["line"].as_u64().unwrap()).collect();
    assert_eq!(numbers, [1, 2, 3, 4, 5]);
    assert_eq!(lines[0]["status"], "error");
    assert_eq!(lines[1]["status"], "error");
    assert!(
        lines[1]["error"]
            .as_str()
            .unwrap()
            .contains("not valid UTF-8")
    );
    for line in &lines[2..] {
        assert_eq!(line["status"], "crossing");
    }
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.contains("raylab: line 2: not valid UTF-8"),
        "{stderr}"
    );
    assert!(stderr.contains("2 bad line(s)"), "{stderr}");
}

/// Runs `script` (with `$0` the binary) under `sh`, its address space limited to `kib` KiB.
fn limited(kib: u32, script: &str) -> Command {
    let mut command = Command::new("sh");
    command
        .arg("-c")
        .arg(format!("ulimit -v {kib} && {script}"))
        .arg(BIN);
    command
}

#[test]
fn a_line_past_the_limit_is_refused_in_bounded_memory_and_the_batch_goes_on() {
    // 150 MB of one line: more than the address space allows, had it been held.
    let script = format!(
        "{{ echo '{SEED000}'; head -c 150000000 /dev/zero; echo; echo '{SEED000}'; }} | \
         \"$0\" solve --batch --no-trace"
    );
    let output = limited(150_000, &script).output().unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    let lines = json_lines(&output);
    assert_eq!(lines.len(), 3, "{stderr}");
    assert!(
        lines[1]["error"]
            .as_str()
            .unwrap()
            .contains("longer than 1048576 bytes")
    );
    assert_eq!(lines[2]["line"], 3);
    assert_eq!(lines[2]["status"], "crossing");
}

#[test]
fn dev_zero_as_input_is_refused_at_once_and_memory_stays_bounded() {
    let mut child = limited(150_000, "exec \"$0\" solve --batch < /dev/zero")
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let mut first = String::new();
    BufReader::new(child.stdout.take().unwrap())
        .read_line(&mut first)
        .unwrap();
    assert!(first.contains("longer than"), "{first:?}");
    // It keeps reading (and dropping) zeros, well past the address-space limit, without dying.
    std::thread::sleep(std::time::Duration::from_millis(700));
    let still_running = child.try_wait().unwrap().is_none();
    let _ = child.kill();
    let _ = child.wait();
    assert!(still_running, "the batch died reading /dev/zero");
}

/// Segments A = (0,0)–(x,0) and B = (1,1)–(1,−1): they meet at (1,0), the end of A when x = 1.
fn segments_ending_at(x: &str) -> String {
    format!(r#"{{"kind":"segments","a1":[0,0],"a2":[{x},0],"b1":[1,1],"b2":[1,-1]}}"#)
}

#[test]
fn exact_reads_json_numbers_as_written_even_with_a_thousand_digits() {
    // 0.999…9 with 999 nines: just short of 1, so B crosses A's line beyond A's end.
    let x = format!("0.{}", "9".repeat(999));
    let input = format!(
        "{}\n{}\n",
        segments_ending_at(&x),
        segments_ending_at("1.0000000000000000000001")
            .replace("\"kind\"", "\"precision\":\"f64\",\"kind\"")
    );
    let clock = std::time::Instant::now();
    let output = batch(&["--precision", "exact", "--no-trace"], input.as_bytes());
    let seconds = clock.elapsed().as_secs_f64();
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let lines = json_lines(&output);
    assert_eq!(lines[0]["status"], "lines-cross-outside");
    let t = format!("1{}/{}", "0".repeat(999), "9".repeat(999));
    assert_eq!(lines[0]["exact"]["t"], t.as_str());
    // The same numbers in f64 round to 1: touching.
    assert_eq!(lines[1]["status"], "touching");
    // Only a hang is caught here (the old behaviour: a long decimal took minutes); the speed of the
    // batch is a benchmark's figure (`cargo bench --bench batch`), not a test's.
    assert!(seconds < 60.0, "{seconds} s: a hang");
}

#[test]
fn exact_keeps_every_digit_of_a_long_integer() {
    let line = r#"{"kind":"triangle","a":[123456789012345678901234567890,0,0],"b":[0,3,0],"c":[0,0,3],"origin":[0,0,0],"dir":[1,1,1]}"#;
    let output = batch(&["--precision", "exact", "--no-trace"], line.as_bytes());
    let lines = json_lines(&output);
    assert_eq!(lines[0]["status"], "hit");
    // The plane through (a,0,0), (0,3,0), (0,0,3) meets x = y = z at 1/(1/a + 2/3).
    let a: u128 = 123456789012345678901234567890;
    let (numerator, denominator) = (3 * a, 2 * a + 3);
    let gcd = |mut x: u128, mut y: u128| {
        while y != 0 {
            (x, y) = (y, x % y);
        }
        x
    };
    let g = gcd(numerator, denominator);
    let expected = format!("{}/{}", numerator / g, denominator / g);
    assert_eq!(lines[0]["exact"]["t"], expected.as_str());
}

#[test]
fn numbers_past_the_limits_are_refused_fast_with_short_messages() {
    let million = "1".repeat(1_000_000);
    let mut input = String::new();
    for precision in ["f32", "f64", "exact"] {
        input += &format!(
            r#"{{"kind":"segments","precision":"{precision}","a1":[{million},0],"a2":[1,0],"b1":[1,1],"b2":[1,-1]}}"#
        );
        input.push('\n');
    }
    let huge = format!("1{}", "0".repeat(5000));
    input += &segments_ending_at(&huge);
    input.push('\n');
    let clock = std::time::Instant::now();
    let output = batch(&["--no-trace"], input.as_bytes());
    // Refused before any arithmetic: a guard against the minutes a million digits used to take.
    assert!(clock.elapsed().as_secs_f64() < 10.0);
    let lines = json_lines(&output);
    for line in &lines[..3] {
        let error = line["error"].as_str().unwrap();
        assert!(error.contains("longer than the limit of 10000"), "{error}");
        assert!(error.len() < 120, "{error}");
    }
    let error = lines[3]["error"].as_str().unwrap();
    assert!(error.contains("too large for a 64-bit float"), "{error}");
    assert!(error.len() < 160, "{error}");
}

#[test]
fn a_flag_beyond_the_float_range_is_exact_in_exact_mode_and_refused_briefly_in_f64() {
    let huge = format!("1{}", "0".repeat(5000));
    let args = |precision: &str| {
        [
            "solve",
            "segments",
            "--a1",
            "0,0",
            "--a2",
            &format!("{huge},0"),
            "--b1",
            "1,1",
            "--b2",
            "1,-1",
            "--format",
            "json",
            "--no-trace",
            "--precision",
            precision,
        ]
        .map(String::from)
    };
    let exact = Command::new(BIN).args(args("exact")).output().unwrap();
    assert!(
        exact.status.success(),
        "{}",
        String::from_utf8_lossy(&exact.stderr)
    );
    let report: Value = serde_json::from_slice(&exact.stdout).unwrap();
    assert_eq!(report["status"], "crossing");
    assert_eq!(report["exact"]["t"], format!("1/{huge}").as_str());
    let float = Command::new(BIN).args(args("f64")).output().unwrap();
    assert_eq!(float.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&float.stderr);
    assert!(stderr.starts_with("raylab: --a2: component 1:"), "{stderr}");
    assert!(stderr.contains("too large for a 64-bit float"), "{stderr}");
    assert!(stderr.len() < 160, "{stderr}");
}

/// Runs the binary with standard output and standard error both a pipe whose reading end is already
/// closed: every write fails with EPIPE, deterministically.
fn with_closed_streams(args: &[&str], stdin: Stdio) -> Option<i32> {
    let (reader, writer) = std::io::pipe().unwrap();
    drop(reader);
    Command::new(BIN)
        .args(args)
        .stdin(stdin)
        .stdout(writer.try_clone().unwrap())
        .stderr(writer)
        .status()
        .unwrap()
        .code()
}

fn lecture() -> Stdio {
    Stdio::from(std::fs::File::open("assets/examples/lecture.jsonl").unwrap())
}

#[test]
fn closed_streams_never_panic() {
    // A panic exits with 101; each of these must end with its own status instead.
    assert_eq!(
        with_closed_streams(&["solve", "--batch"], lecture()),
        Some(1)
    );
    assert_eq!(with_closed_streams(&["solve"], Stdio::null()), Some(2));
    assert_eq!(
        with_closed_streams(&["solve", "segments", "--a1", "x"], Stdio::null()),
        Some(2)
    );
    assert_eq!(
        with_closed_streams(&["solve", "--batch", "--format", "text"], Stdio::null()),
        Some(2)
    );
    assert_eq!(
        with_closed_streams(&["bench", "--hard-cases"], Stdio::null()),
        Some(0)
    );
    let missing = with_closed_streams(
        &["render", "no-such-scene.ron", "-o", "x.png"],
        Stdio::null(),
    );
    assert_eq!(missing, Some(1));
}

/// Runs `pipeline` under `sh` with `$0` the binary; returns what it printed and the binary's status.
fn through_head(command: &str) -> (String, String) {
    let dir = std::env::temp_dir().join(format!("raylab-head-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let status_file = dir.join(format!("status-{}", command.len()));
    let script = format!(
        "{{ \"$0\" {command} 2>&1; echo $? > '{}'; }} | head -1",
        status_file.display()
    );
    let output = Command::new("sh")
        .arg("-c")
        .arg(script)
        .arg(BIN)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .unwrap();
    let status = std::fs::read_to_string(&status_file).unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    (
        String::from_utf8_lossy(&output.stdout).into_owned(),
        status.trim().to_string(),
    )
}

#[test]
fn piping_both_streams_into_head_does_not_panic() {
    let (first, status) = through_head("solve --batch < assets/examples/lecture.jsonl");
    assert!(first.starts_with('{'), "{first}");
    // 0 if everything fit in the pipe before head left, 1 if a write failed: never 101.
    assert!(status == "0" || status == "1", "status {status}");
    let (_, status) = through_head("solve");
    assert_eq!(status, "2");
}
