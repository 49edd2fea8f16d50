//! Möller–Trumbore (1997): Cramer's rule with the common terms collected (seed 002's advice). The
//! determinants become scalar triple products sharing the cross products p = D × e2 and q = s × e1.

use super::{Answer, Case, Float, decide, record};
use crate::math::linalg::{cross, dot, sub};
use crate::trace::StepSink;

/// Intersects by Möller–Trumbore.
pub fn intersect<F: Float>(case: &Case<F>) -> Answer<F> {
    intersect_recorded(case, &mut ())
}

/// Intersects, sending the steps to `rec` (a `Recorder`, or `()` for none at no cost).
pub fn intersect_recorded<F: Float>(case: &Case<F>, rec: &mut impl StepSink) -> Answer<F> {
    let [a, b, c] = &case.tri;
    // Edge vectors from A.
    let e1 = sub(b, a);
    let e2 = sub(c, a);
    // Determinant: |M| up to sign, as D · (e2 × ... ) collected into p.
    let p = cross(&case.dir, &e2);
    let det = dot(&e1, &p);
    record::vector(
        rec,
        "p",
        "p = D × e2",
        "The cross product shared by |M| and β.",
        &p,
    );
    record::scalar(
        rec,
        "det",
        "det = e1 · p",
        "Equals −|M| of the lecture's system (M = [A−B | A−C | D] = [−e1 | −e2 | D]).",
        "det",
        det,
    );
    // Reject parallel (only an exact zero: no tolerance).
    if det == F::zero() {
        return record::finish(rec, Answer::miss());
    }
    let inv_det = F::one().div(det);
    // Barycentric β from the vector s = L − A.
    let s = sub(&case.origin, a);
    let beta = dot(&s, &p) * inv_det;
    // Barycentric γ and t share q = s × e1.
    let q = cross(&s, &e1);
    let gamma = dot(&case.dir, &q) * inv_det;
    let t = dot(&e2, &q) * inv_det;
    record::vector(rec, "q", "q = s × e1", "Shared by γ and t; s = L − A.", &q);
    record::scalar(rec, "beta", "β = s · p / det", "", "β", beta);
    record::scalar(rec, "gamma", "γ = D · q / det", "", "γ", gamma);
    record::scalar(rec, "t", "t = e2 · q / det", "", "t", t);
    record::finish(rec, Answer::with(decide(t, beta, gamma), [t, beta, gamma]))
}
