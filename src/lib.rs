//! raylab: an interactive teaching visualizer for parametric forms and ray–primitive intersection.
//!
//! Imports go one way, bottom to top (see [`layers`], which a test enforces): `platform` and `files`;
//! `math`; `trace`; `geometry`; `intersect`, `symbolic`, `exercise`; `scene`; `render`, `accuracy`,
//! `lesson`; `class` (the live class); `app` and `cli`. Everything below `app` and `cli` is the pure core: it builds without egui,
//! eframe or clap (`cargo build --lib --no-default-features`). The same app runs in a web page (wasm32):
//! what differs between a desktop and a browser lives in `platform`, and the command line is
//! desktop-only.

// Tests may unwrap: a panic is how a test fails.
#![cfg_attr(test, allow(clippy::unwrap_used, clippy::expect_used))]

pub mod accuracy;
#[cfg(feature = "app")]
pub mod app;
pub mod class;
#[cfg(all(feature = "app", not(target_arch = "wasm32")))]
pub mod cli;
pub mod exercise;
pub mod files;
pub mod geometry;
pub mod intersect;
pub mod layers;
pub mod lesson;
pub mod math;
pub mod names;
pub mod platform;
pub mod render;
pub mod scene;
pub mod symbolic;
pub mod trace;
