//! raylab: an interactive teaching visualizer for parametric forms and ray–primitive intersection.
//!
//! The pure core (`geometry`, `exact`, `trace`) never imports a UI crate; the command line in `cli`
//! reads and prints the core's [`trace::Trace`]. The same app runs in a web page (wasm32): what differs
//! between a desktop and a browser lives in `platform`, and the command line is desktop-only.

pub mod accuracy;
pub mod app;
#[cfg(not(target_arch = "wasm32"))]
pub mod cli;
pub mod exercise;
pub mod files;
pub mod geometry;
pub mod intersect;
pub mod lesson;
pub mod math;
pub mod platform;
pub mod render;
pub mod scene;
pub mod symbolic;
pub mod trace;
