//! raylab: an interactive teaching visualizer for parametric forms and ray–primitive intersection.
//!
//! The pure core (`geometry`, `exact`, `trace`) never imports a UI crate; the command line in `cli`
//! reads and prints the core's [`trace::Trace`].

pub mod accuracy;
pub mod app;
pub mod cli;
pub mod exact;
pub mod geometry;
pub mod platform;
pub mod render;
pub mod scene;
pub mod trace;
