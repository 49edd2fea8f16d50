//! The app, driven as a person would (egui_kittest, rendered on the CPU): the views and panels, a
//! classroom projector at 100%, 150% and 200%, and the image snapshots and screenshots. One test binary
//! for the area (`cargo test --test app`; one part: `cargo test --test app screenshots::`).

// A test or benchmark fails by panicking: unwrap and expect are how it says so.
#![allow(clippy::unwrap_used, clippy::expect_used)]

#[allow(dead_code, reason = "each part uses some of the shared steps")]
#[path = "../common/mod.rs"]
mod common;

mod app_ui;
mod keyboard;
mod lessons;
mod projector;
mod screenshots;
