//! Seed 003's method: intersect the plane, then test the point against each edge with cross products —
//! with the seed's `and` corrected to `or` (the point is outside if ANY edge test fails).
//!
//! The barycentrics are the edge tests divided by |n|², so the decision and the reported β, γ agree.

use super::{Answer, Case, Float, decide, record};
use crate::geometry::linalg::{add, cross, dot, scale, sub};
use crate::trace::StepSink;

/// Intersects the plane, then tests inside-outside.
pub fn intersect<F: Float>(case: &Case<F>) -> Answer<F> {
    intersect_recorded(case, &mut ())
}

/// Intersects, sending the steps to `rec` (`()` records nothing, at no cost).
pub fn intersect_recorded<F: Float>(case: &Case<F>, rec: &mut impl StepSink) -> Answer<F> {
    let [a, b, c] = &case.tri;
    // Normal n = (B − A) × (C − A), not normalised.
    let n = cross(&sub(b, a), &sub(c, a));
    let n_dot_d = dot(&n, &case.dir);
    record::vector(
        rec,
        "n",
        "n = (B − A) × (C − A)",
        "The plane's normal, not normalised.",
        &n,
    );
    record::scalar(
        rec,
        "n_dot_d",
        "n · D",
        "Zero when the ray is parallel to the plane.",
        "n·D",
        n_dot_d,
    );
    if n_dot_d == F::zero() {
        let answer = Answer::miss();
        record::outcome(rec, &answer);
        return answer;
    }
    // Plane hit: t = n·(A − L) / n·D, P = L + tD.
    let t = dot(&n, &sub(a, &case.origin)).div(n_dot_d);
    let p = add(&case.origin, &scale(&t, &case.dir));
    // Edge tests: ((C − B) × (P − B))·n ≥ 0 and so on, one per edge.
    let edge = |from: &[F; 3], to: &[F; 3]| dot(&cross(&sub(to, from), &sub(&p, from)), &n);
    let n2 = dot(&n, &n);
    let alpha = edge(b, c).div(n2);
    let beta = edge(c, a).div(n2);
    let gamma = edge(a, b).div(n2);
    record::vector(
        rec,
        "P",
        "P = L + tD, t = n·(A − L) / n·D",
        "Where the ray meets the plane.",
        &p,
    );
    record::scalar(
        rec,
        "alpha",
        "α = ((C−B)×(P−B))·n / |n|²",
        "Edge BC's test: negative means outside.",
        "α",
        alpha,
    );
    // Outside if any test fails (seed 003 wrote `and`): decide on β, γ and α = the third test.
    let inside = alpha >= F::zero() && decide(t, beta, gamma);
    let answer = Answer::with(inside, [t, beta, gamma]);
    record::outcome(rec, &answer);
    answer
}
