//! Running the `raylab` binary as a user does, for the command-line tests.

use std::io::Write;
use std::process::{Command, Output, Stdio};

/// Runs `raylab args…` with `stdin` on its standard input. The input is written from a thread, so a
/// large input cannot block against a full output pipe.
pub fn raylab_with_stdin(args: &[&str], stdin: &[u8]) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_raylab"))
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the binary runs");
    let mut input = child.stdin.take().expect("a piped stdin");
    let bytes = stdin.to_vec();
    let writer = std::thread::spawn(move || input.write_all(&bytes));
    let output = child.wait_with_output().expect("the binary ends");
    writer
        .join()
        .expect("the writer ends")
        .expect("stdin takes the input");
    output
}
