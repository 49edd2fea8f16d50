//! The renderer: images, covered pixels and counters without a window, the effects past ray casting,
//! and the Render view driven through the app (loading a large mesh, the effect toggles). One test
//! binary for the area (`cargo test --test render`; one part: `cargo test --test render effects::`).

// A test or benchmark fails by panicking: unwrap and expect are how it says so.
#![allow(clippy::unwrap_used, clippy::expect_used)]

#[allow(dead_code, reason = "each part uses some of the shared steps")]
#[path = "../common/mod.rs"]
mod common;
#[path = "../shipped/mod.rs"]
mod shipped;

mod effects;
mod render;
mod render_budget_ui;
mod render_effects_ui;
mod render_loading;
mod render_orbit_ui;
