//! Running the `raylab` binary as a user does, for the command-line tests.

use std::io::Write;
use std::process::{Command, Output, Stdio};

/// A ray straight down onto the parallelogram 2 × 1 at the origin, through α = 1/4, β = 1/2 at t = 1.
#[allow(dead_code, reason = "not every command-line test solves it")]
pub const PARALLELOGRAM_HIT: [&str; 12] = [
    "solve",
    "parallelogram",
    "--corner",
    "0,0,0",
    "--e1",
    "2,0,0",
    "--e2",
    "0,1,0",
    "--origin",
    "0.5,0.5,1",
    "--dir",
    "0,0,-1",
];

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

/// Whether pdflatex is here to compile LaTeX. Without it a LaTeX test prints `skipped: <why>` and passes,
/// unless `RAYLAB_LATEX_TEST=require` (which `.ci/run` sets, as it installs texlive), where a missing
/// pdflatex is a failure, not a silent skip.
#[allow(dead_code, reason = "only the LaTeX tests compile LaTeX")]
pub fn pdflatex_or_skip() -> bool {
    if Command::new("pdflatex").arg("--version").output().is_ok() {
        return true;
    }
    let required = std::env::var("RAYLAB_LATEX_TEST").is_ok_and(|v| v == "require");
    assert!(
        !required,
        "RAYLAB_LATEX_TEST=require, but pdflatex is not installed"
    );
    println!("skipped: pdflatex is not installed");
    false
}
