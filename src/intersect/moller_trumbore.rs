//! Möller–Trumbore (1997): Cramer's rule with the common terms collected (seed 002's advice). The
//! determinants become scalar triple products sharing the cross products p = D × e2 and q = s × e1.

use super::{Answer, Case, Float, decide, record};
use crate::math::linalg::{V3, cross, dot, sub};
use crate::trace::StepSink;

/// Intersects by Möller–Trumbore.
pub fn intersect<F: Float>(case: &Case<F>) -> Answer<F> {
    intersect_recorded(case, &mut ())
}

/// Intersects, sending the steps to `rec` (a `Recorder`, or `()` for none at no cost).
pub fn intersect_recorded<F: Float>(case: &Case<F>, rec: &mut impl StepSink) -> Answer<F> {
    let values = values(&case.tri, &case.origin, &case.dir);
    record::vector(
        rec,
        "p",
        "p = D × e2",
        "The cross product shared by |M| and β.",
        &values.p,
    );
    record::scalar(
        rec,
        "det",
        "det = e1 · p",
        "Equals −|M| of the lecture's system (M = [A−B | A−C | D] = [−e1 | −e2 | D]).",
        "det",
        values.det,
    );
    let Some((q, [t, beta, gamma])) = values.solved else {
        return record::finish(rec, Answer::miss());
    };
    record::vector(rec, "q", "q = s × e1", "Shared by γ and t; s = L − A.", &q);
    record::scalar(rec, "beta", "β = s · p / det", "", "β", beta);
    record::scalar(rec, "gamma", "γ = D · q / det", "", "γ", gamma);
    record::scalar(rec, "t", "t = e2 · q / det", "", "t", t);
    record::finish(rec, Answer::with(decide(t, beta, gamma), [t, beta, gamma]))
}

/// The method's values for one ray: p, det and, unless det = 0, q and (t, β, γ).
pub struct Values<F> {
    /// p = D × e2.
    pub p: V3<F>,
    /// det = e1 · p.
    pub det: F,
    /// q = s × e1 and (t, β, γ); `None` when det = 0 (parallel: no tolerance).
    pub solved: Option<(V3<F>, [F; 3])>,
}

/// The arithmetic of Möller–Trumbore, once: [`intersect_recorded`] records it, the renderer's lone
/// triangles use it directly (inlined, on the triangle in place).
#[inline(always)]
pub fn values<F: Float>([a, b, c]: &[V3<F>; 3], origin: &V3<F>, dir: &V3<F>) -> Values<F> {
    // Edge vectors from A.
    let e1 = sub(b, a);
    let e2 = sub(c, a);
    // Determinant: |M| up to sign, as D · (e2 × ... ) collected into p.
    let p = cross(dir, &e2);
    let det = dot(&e1, &p);
    if det == F::zero() {
        return Values {
            p,
            det,
            solved: None,
        };
    }
    let inv_det = F::one().div(det);
    // Barycentric β from the vector s = L − A.
    let s = sub(origin, a);
    let beta = dot(&s, &p) * inv_det;
    // Barycentric γ and t share q = s × e1.
    let q = cross(&s, &e1);
    let gamma = dot(dir, &q) * inv_det;
    let t = dot(&e2, &q) * inv_det;
    Values {
        p,
        det,
        solved: Some((q, [t, beta, gamma])),
    }
}

/// (t, β, γ) when the ray hits the triangle, by this method's decision; nothing recorded.
#[inline(always)]
pub fn hit<F: Float>(tri: &[V3<F>; 3], origin: &V3<F>, dir: &V3<F>) -> Option<[F; 3]> {
    let (_, [t, beta, gamma]) = values(tri, origin, dir).solved?;
    decide(t, beta, gamma).then_some([t, beta, gamma])
}
