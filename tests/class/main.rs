//! The live class, tested as it runs: `raylab class` started on a free loopback port with a temporary
//! database and driven by real WebSocket clients (and, in `browser`, a real phone-sized Chromium).

// A test fails by panicking: unwrap and expect are how it says so.
#![allow(clippy::unwrap_used, clippy::expect_used)]

mod browser;
mod client;
mod hostile;
mod protocol;
mod teacher;
