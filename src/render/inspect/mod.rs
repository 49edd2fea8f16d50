//! The app's helpers, apart from the hot path: the pixel probe, a pixel's ray tree, and what each
//! effect costs.

pub mod cost;
pub mod probe;
pub mod ray_tree;
