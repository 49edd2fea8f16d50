//! The hard-case gallery: named cases from `assets/hard_cases.ron`, and what every method decides
//! on each, next to the exact reference.

use serde::Deserialize;

use crate::geometry::Precision;
use crate::intersect::reference::reference;
use crate::intersect::{Case, Float, Method, finite};

/// A named hard case.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HardCase {
    /// Its name.
    pub name: String,
    /// What makes it hard.
    pub note: String,
    /// Vertex A.
    pub a: [f64; 3],
    /// Vertex B.
    pub b: [f64; 3],
    /// Vertex C.
    pub c: [f64; 3],
    /// The ray's origin.
    pub origin: [f64; 3],
    /// The ray's direction.
    pub dir: [f64; 3],
    /// The `method/precision` pairs known to decide differently from the exact reference.
    pub disagree: Vec<String>,
}

impl HardCase {
    /// As a study case.
    pub fn case(&self) -> Case<f64> {
        Case {
            tri: [self.a, self.b, self.c],
            origin: self.origin,
            dir: self.dir,
        }
    }
}

/// The gallery, embedded at compile time.
#[allow(
    clippy::expect_used,
    reason = "the shipped gallery is embedded at build time; tests check every case"
)]
pub fn gallery() -> Vec<HardCase> {
    ron::from_str(include_str!("../../assets/hard_cases.ron")).expect("the shipped gallery parses")
}

/// One method's decision on a hard case.
#[derive(Clone, Debug, PartialEq)]
pub struct Verdict {
    /// `method/precision`, e.g. `moller-trumbore/f32`.
    pub who: String,
    /// Its decision.
    pub hit: bool,
    /// The exact decision on the same (rounded) inputs; non-finite inputs are a miss.
    pub exact_hit: bool,
    /// The method said the input is outside its range.
    pub invalid_input: bool,
}

/// Every float method in f32 and f64 on a case.
pub fn verdicts(case: &Case<f64>) -> Vec<Verdict> {
    let mut out = Vec::new();
    for method in Method::FLOAT {
        out.push(verdict(method, case, Precision::F64));
        out.push(verdict(method, &case.to_f32(), Precision::F32));
    }
    out
}

fn verdict<F: Float + crate::intersect::InverseSolve>(
    method: Method,
    case: &Case<F>,
    precision: Precision,
) -> Verdict {
    let exact_hit = finite(case) && reference(case).hit;
    let answer = method.run(case);
    Verdict {
        who: format!("{}/{}", method.name(), precision.name()),
        hit: answer.hit,
        exact_hit,
        invalid_input: answer.invalid_input,
    }
}
