//! Cramer's rule as the lecture writes it: M = [A−B | A−C | D], Y = A − L, four 3x3 determinants.
//!
//! No tolerance: |M| = 0 is the only rejection, so the method's own rounding decides every edge case.

use super::{Answer, Case, Float, decide};
use crate::math::linalg::{det3, from_columns, sub, with_column};

/// Intersects by Cramer's rule.
pub fn intersect<F: Float>(case: &Case<F>) -> Answer<F> {
    let [a, b, c] = &case.tri;
    // The system M X = Y.
    let m = from_columns([&sub(a, b), &sub(a, c), &case.dir]);
    let y = sub(a, &case.origin);
    // The determinant; a singular system has no unique solution.
    let det_m = det3(&m);
    if det_m == F::zero() {
        return Answer::miss();
    }
    // β, γ, t from M1, M2, M3.
    let solve = |column: usize| det3(&with_column(&m, column, &y)).div(det_m);
    let (beta, gamma, t) = (solve(0), solve(1), solve(2));
    Answer::with(decide(t, beta, gamma), [t, beta, gamma])
}
