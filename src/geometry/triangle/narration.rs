//! What the triangle solver says in words: the explanations of its tolerances and the verdict's
//! sentence, kept apart from the arithmetic.

use super::{Barycentric, TriangleMiss, TriangleOutcome};
use crate::math::Real;
use crate::trace::Number;

pub(super) fn area_explanation<R: Real>() -> &'static str {
    if R::TOLERANCE == 0.0 {
        "Exact arithmetic: the triangle is degenerate only if (A−B)×(A−C) is exactly zero."
    } else {
        "In floating point the area counts as zero when |(A−B)×(A−C)| ≤ 16ε·|A−B|·|A−C| (the sine of the angle at A is below 16ε)."
    }
}

pub(super) fn parallel_explanation<R: Real>() -> &'static str {
    if R::TOLERANCE == 0.0 {
        "Exact arithmetic: the ray is parallel to the plane only if |M| is exactly zero."
    } else {
        "|M| = ((A−B)×(A−C))·D; it counts as zero when |M| ≤ 16ε·|(A−B)×(A−C)|·|D|, i.e. the ray is within 16ε radians of the plane."
    }
}

pub(super) fn verdict_sentence(outcome: &TriangleOutcome) -> String {
    match outcome {
        TriangleOutcome::Hit => "All four checks pass.".into(),
        _ => "What the checks decide.".into(),
    }
}

pub(super) fn verdict_message<R: Real>(
    outcome: &TriangleOutcome,
    s: Option<&Barycentric<R>>,
) -> String {
    let t_text = || s.map(|s| Number::of(&s.t).shown()).unwrap_or_default();
    match outcome {
        TriangleOutcome::Hit => format!("the ray hits the triangle at t = {}", t_text()),
        TriangleOutcome::Miss(miss) => match miss {
            TriangleMiss::Outside { edges } => {
                let names: Vec<String> = edges
                    .iter()
                    .map(|e| format!("{} (fails {})", e.name(), e.inequality()))
                    .collect();
                format!(
                    "the ray meets the plane outside the triangle, beyond edge {}",
                    names.join(" and ")
                )
            }
            TriangleMiss::Behind => format!(
                "the point is inside the triangle but t = {} is not greater than t_min: behind the ray's origin",
                t_text()
            ),
            TriangleMiss::Parallel { in_plane: true } => {
                "the ray is parallel to the triangle's plane and lies in it (|M| = 0, or negligible in floats)".into()
            }
            TriangleMiss::Parallel { in_plane: false } => {
                "the ray is parallel to the triangle's plane and never meets it (|M| = 0, or negligible in floats)".into()
            }
            TriangleMiss::DegenerateTriangle => {
                "A, B and C are collinear: the triangle has no area".into()
            }
            TriangleMiss::ZeroDirection => "the direction D is the zero vector: no ray".into(),
            TriangleMiss::InvalidInput(bad) => format!("invalid input: {bad}"),
        },
    }
}
