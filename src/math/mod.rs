//! The numbers everything else is built on: exact rationals ([`exact`]), the [`Real`] trait that lets a
//! solver run in f32, f64 or exact arithmetic ([`real`]), and small fixed-size vectors and matrices
//! ([`linalg`]). The bottom of the core: it imports nothing else of raylab.

pub mod exact;
pub mod linalg;
pub mod real;

pub use real::{InPrecision, Precision, Real, in_precision};
