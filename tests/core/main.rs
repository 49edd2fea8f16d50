//! The pure core, tested without a window or the command line: the lecture's worked examples, every
//! named outcome, property tests against exact arithmetic, the accuracy study's claims and the hard
//! cases. One test binary for the area, so a change links it once (`cargo test --test core`; one part:
//! `cargo test --test core hard_cases::`).

// A test or benchmark fails by panicking: unwrap and expect are how it says so.
#![allow(clippy::unwrap_used, clippy::expect_used)]

mod accuracy;
mod hard_cases;
mod named_cases;
mod properties;
mod seeds;
