//! Seed 003's method: intersect the plane, then test the point against each edge with cross products —
//! with the seed's `and` corrected to `or` (the point is outside if ANY edge test fails).
//!
//! The barycentrics are the edge tests divided by |n|², so the decision and the reported β, γ agree.

use super::{Answer, Case, Float, decide};
use crate::geometry::linalg::{add, cross, dot, scale, sub};

/// Intersects the plane, then tests inside-outside.
pub fn intersect<F: Float>(case: &Case<F>) -> Answer<F> {
    let [a, b, c] = &case.tri;
    // Normal n = (B − A) × (C − A), not normalised.
    let n = cross(&sub(b, a), &sub(c, a));
    let n_dot_d = dot(&n, &case.dir);
    if n_dot_d == F::zero() {
        return Answer::miss();
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
    // Outside if any test fails (seed 003 wrote `and`): decide on β, γ and α = the third test.
    let inside = alpha >= F::zero() && decide(t, beta, gamma);
    Answer::with(inside, [t, beta, gamma])
}
