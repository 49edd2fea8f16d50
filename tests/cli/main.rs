//! The command line as a user runs it: every subcommand through the real binary (flags, formats,
//! batch lines, exit codes, closed streams), hostile files, worksheets, the LaTeX output compiled, and
//! the fuzzed input parsers. One test binary for the area (`cargo test --test cli`; one part:
//! `cargo test --test cli hostile::`).

// A test or benchmark fails by panicking: unwrap and expect are how it says so.
#![allow(clippy::unwrap_used, clippy::expect_used)]

#[allow(dead_code, reason = "each part uses some of the shared steps")]
#[path = "../run/mod.rs"]
mod run;

mod batch;
mod cli;
mod fuzz;
mod hostile;
mod latex_compiles;
mod worksheet;
