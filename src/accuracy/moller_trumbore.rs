//! Möller–Trumbore (1997): Cramer's rule with the common terms collected (seed 002's advice). The
//! determinants become scalar triple products sharing the cross products p = D × e2 and q = s × e1.

use super::{Answer, Case, Float, decide};
use crate::geometry::linalg::{cross, dot, sub};

/// Intersects by Möller–Trumbore.
pub fn intersect<F: Float>(case: &Case<F>) -> Answer<F> {
    let [a, b, c] = &case.tri;
    // Edge vectors from A.
    let e1 = sub(b, a);
    let e2 = sub(c, a);
    // Determinant: |M| up to sign, as D · (e2 × ... ) collected into p.
    let p = cross(&case.dir, &e2);
    let det = dot(&e1, &p);
    // Reject parallel (only an exact zero: no tolerance).
    if det == F::zero() {
        return Answer::miss();
    }
    let inv_det = F::one().div(det);
    // Barycentric β from the vector s = L − A.
    let s = sub(&case.origin, a);
    let beta = dot(&s, &p) * inv_det;
    // Barycentric γ and t share q = s × e1.
    let q = cross(&s, &e1);
    let gamma = dot(&case.dir, &q) * inv_det;
    let t = dot(&e2, &q) * inv_det;
    Answer::with(decide(t, beta, gamma), [t, beta, gamma])
}
