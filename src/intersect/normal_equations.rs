//! Seed 004's barycentrics by a 2x2 system of dot products: intersect the plane for P, then solve
//! [e1·e1 e1·e2; e2·e1 e2·e2] (β, γ) = ((P − A)·e1, (P − A)·e2) by Cramer's rule.

use super::plane::{PlaneHit, plane_hit};
use super::{Answer, Case, Float, decide, record};
use crate::math::linalg::{dot, sub};
use crate::trace::StepSink;

/// Intersects the plane, then solves the normal equations for β and γ.
pub fn intersect<F: Float>(case: &Case<F>) -> Answer<F> {
    intersect_recorded(case, &mut ())
}

/// Intersects, sending the steps to `rec` (`()` records nothing, at no cost).
pub fn intersect_recorded<F: Float>(case: &Case<F>, rec: &mut impl StepSink) -> Answer<F> {
    let [a, b, c] = &case.tri;
    let e1 = sub(b, a);
    let e2 = sub(c, a);
    // Plane hit, as in seed 003.
    let Some(PlaneHit { t, point: p, .. }) = plane_hit(case, rec) else {
        return record::finish(rec, Answer::miss());
    };
    // The 2x2 system of dot products.
    let (d11, d12, d22) = (dot(&e1, &e1), dot(&e1, &e2), dot(&e2, &e2));
    let ap = sub(&p, a);
    let (c1, c2) = (dot(&ap, &e1), dot(&ap, &e2));
    let det = d11 * d22 - d12 * d12;

    record::vector(
        rec,
        "gram",
        "e1·e1, e1·e2, e2·e2",
        "The 2x2 system's matrix (symmetric).",
        &[d11, d12, d22],
    );
    record::scalar(
        rec,
        "det",
        "det = (e1·e1)(e2·e2) − (e1·e2)²",
        "Zero for a degenerate triangle.",
        "det",
        det,
    );
    if det == F::zero() {
        return record::finish(rec, Answer::miss());
    }
    let beta = (c1 * d22 - d12 * c2).div(det);
    let gamma = (d11 * c2 - d12 * c1).div(det);
    record::finish(rec, Answer::with(decide(t, beta, gamma), [t, beta, gamma]))
}
