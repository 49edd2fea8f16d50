//! `raylab solve --batch` and the standard streams under hostile input, run as a user runs the binary:
//! bytes that are not UTF-8, lines with no end, closed pipes.

use std::io::{BufRead, BufReader, Write};
use std::process::{Command, Output, Stdio};

use serde_json::Value;

const BIN: &str = env!("CARGO_BIN_EXE_raylab");

const SEED000: &str = r#"{"kind":"segments","a1":"1,2","a2":"6,1","b1":"2,6","b2":"5,1"}"#;

fn batch(args: &[&str], stdin: &[u8]) -> Output {
    let mut child = Command::new(BIN)
        .args(["solve", "--batch"])
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the binary runs");
    let mut input = child.stdin.take().unwrap();
    let bytes = stdin.to_vec();
    let writer = std::thread::spawn(move || input.write_all(&bytes));
    let output = child.wait_with_output().unwrap();
    writer.join().unwrap().unwrap();
    output
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
