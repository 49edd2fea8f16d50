//! Seed 003's method: intersect the plane, then test the point against each edge with cross products —
//! with the seed's `and` corrected to `or` (the point is outside if ANY edge test fails).
//!
//! The barycentrics are the edge tests divided by |n|², so the decision and the reported β, γ agree.

use super::{Answer, Case, Float, decide, record};
use crate::math::linalg::{V3, add, cross, dot, scale, sub};
use crate::trace::StepSink;

/// Intersects the plane, then tests inside-outside.
pub fn intersect<F: Float>(case: &Case<F>) -> Answer<F> {
    intersect_recorded(case, &mut ())
}

/// Intersects, sending the steps to `rec` (`()` records nothing, at no cost).
pub fn intersect_recorded<F: Float>(case: &Case<F>, rec: &mut impl StepSink) -> Answer<F> {
    let [a, b, c] = &case.tri;
    let Some(PlaneHit {
        normal: n,
        t,
        point: p,
    }) = plane_hit(case, rec)
    else {
        return record::finish(rec, Answer::miss());
    };
    // Edge tests: ((C − B) × (P − B))·n ≥ 0 and so on, one per edge.
    let edge = |from: &[F; 3], to: &[F; 3]| dot(&cross(&sub(to, from), &sub(&p, from)), &n);
    let n2 = dot(&n, &n);
    let alpha = edge(b, c).div(n2);
    let beta = edge(c, a).div(n2);
    let gamma = edge(a, b).div(n2);
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
    record::finish(rec, Answer::with(inside, [t, beta, gamma]))
}

/// Where the ray meets the triangle's plane.
pub(crate) struct PlaneHit<F> {
    /// n = (B − A) × (C − A), not normalised.
    pub normal: V3<F>,
    /// t = n·(A − L) / n·D.
    pub t: F,
    /// P = L + tD.
    pub point: V3<F>,
}

/// The plane hit of seed 003 (shared with the normal equations, which start the same way); `None`
/// when the ray is parallel to the plane (n · D = 0 exactly).
pub(crate) fn plane_hit<F: Float>(case: &Case<F>, rec: &mut impl StepSink) -> Option<PlaneHit<F>> {
    let [a, b, c] = &case.tri;
    let normal = cross(&sub(b, a), &sub(c, a));
    let n_dot_d = dot(&normal, &case.dir);
    record::vector(
        rec,
        "n",
        "n = (B − A) × (C − A)",
        "The plane's normal, not normalised.",
        &normal,
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
        return None;
    }
    let t = dot(&normal, &sub(a, &case.origin)).div(n_dot_d);
    let point = add(&case.origin, &scale(&t, &case.dir));
    record::vector(
        rec,
        "P",
        "P = L + tD, t = n·(A − L) / n·D",
        "Where the ray meets the plane.",
        &point,
    );
    Some(PlaneHit { normal, t, point })
}
