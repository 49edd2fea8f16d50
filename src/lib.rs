//! raylab: an interactive teaching visualizer for parametric forms and ray–primitive intersection.
//!
//! Imports go one way, bottom to top (see [`layers`], which a test enforces by parsing every source file):
//! `platform`, `files` and `names`; `math`; `trace`; `geometry`; `intersect`, `symbolic`, `exercise`;
//! `scene`; `render`, `accuracy`, `lesson`; `class` (the live class); `app` and `cli`. Everything below
//! `app` and `cli` is the pure core: it builds without egui, eframe or clap
//! (`cargo build --lib --no-default-features`). The same app runs in a web page (wasm32): what differs
//! between a desktop and a browser lives in `platform`, and the command line is desktop-only.
//! `src/ARCHITECTURE.md` describes the layers and each module.
//!
//! # Conventions
//!
//! raylab writes the lecture's notation, and keeps to it everywhere:
//!
//! - **A ray is L + tD** (o + t d in seed 001), with `t` a plain number.
//! - **D is not normalised.** `t` counts steps of length |D|: the distance along the ray is t·|D|, equal to
//!   `t` only for a unit D. Scaling D scales t inversely and changes no decision. In an object's space the
//!   renderer transforms D without normalising it either, so `t` means the same in both spaces.
//! - **t_min is open: a hit needs t > t_min** (`--tmin`, default 0), so a ray that starts on a triangle
//!   does not hit it. The same holds for every method of [`intersect`] (t > 0) and for the renderer
//!   (t_min < t ≤ t_max, ties to the lower triangle index). One exception, as its seed writes it: the
//!   lecture's parallelogram solver ([`geometry::parallelogram`], seed 001) takes t in [0, ∞), so t = 0
//!   counts.
//! - **Edges count as hits.** A triangle is hit when β ≥ 0, γ ≥ 0 and β + γ ≤ 1, every bound closed; a
//!   parallelogram when 0 ≤ α ≤ 1 and 0 ≤ β ≤ 1; a segment when 0 ≤ t ≤ 1 and 0 ≤ s ≤ 1. The
//!   watertight test counts a point on an edge as inside too (its edge functions all ≥ 0 or all ≤ 0).
//! - **X = (β, γ, t).** L + tD = A + β(B−A) + γ(C−A) is solved as M X = Y with M = [A−B | A−C | D],
//!   X = (β, γ, t) and Y = A − L; for the parallelogram X = (α, β, t), for segments X = (t, s). The
//!   lecture's solvers, traces and JSON output use this order, and the renderer names them
//!   ([`render::Ray`], [`render::TriangleHit`], [`render::Hit`]). One place still holds the three
//!   numbers in another order, (t, β, γ): the accuracy study's [`intersect::Answer::values`].
//! - **Matrices are row-major.** raylab's own matrices ([`math::linalg::M2`], [`math::linalg::M3`], the
//!   matrices of a trace) are arrays of rows, `m[row][column]`, as the slides write them, and every
//!   determinant is expanded along the first row. Images are row-major too (pixel (x, y) at
//!   `y·width + x`). glam's types, used at the edges (inputs, drawing, the renderer's object transforms,
//!   the `inverse` method), keep glam's own column-major storage.

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
