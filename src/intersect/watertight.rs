//! Watertight ray–triangle intersection (Woop, Benthin, Wald 2013, JCGT 2(1)).
//!
//! The ray is made the z axis of a sheared space: translate to the ray's origin, permute so the
//! direction's largest component is z, shear x and y so the direction becomes (0, 0, 1). The triangle
//! is then tested in 2D with three edge functions U, V, W, each computed from the two vertices of its
//! edge alone — so a shared edge gets the same value from both triangles, and no ray slips between.
//!
//! The paper recomputes an edge function in higher precision when it is exactly zero. raylab goes
//! further, so that decisions are exactly right, not only crack-free: each edge function and t carries
//! a conservative error bound (from counting roundings, doubled), and whenever a value is within its
//! bound of zero — or anything overflowed — the whole case is decided in exact rational arithmetic.
//! [`Answer::exact_fallback`] says when that happened.

use super::reference::reference;
use super::{Answer, Case, Float, finite, record};
use crate::trace::StepSink;

/// One sheared vertex: (x, y, z) with the ray along z, and the magnitudes that bound the error of x, y.
struct Sheared<F> {
    x: F,
    y: F,
    z: F,
    /// |P'x| + |Sx·P'z|: the size of the terms whose difference is x.
    mag_x: F,
    /// |P'y| + |Sy·P'z|.
    mag_y: F,
}

/// Intersects watertightly; decides in exact arithmetic where rounding could flip the answer.
pub fn intersect<F: Float>(case: &Case<F>) -> Answer<F> {
    intersect_recorded(case, &mut ())
}

/// Intersects, sending the steps to `rec` (`()` records nothing, at no cost).
pub fn intersect_recorded<F: Float>(case: &Case<F>, rec: &mut impl StepSink) -> Answer<F> {
    let answer = decide_case(case, rec);
    record::finish(rec, answer)
}

fn decide_case<F: Float>(case: &Case<F>, rec: &mut impl StepSink) -> Answer<F> {
    // NaN and infinities are outside the method's range: say so, and miss.
    if !finite(case) {
        return Answer {
            invalid_input: true,
            ..Answer::miss()
        };
    }
    match float_path(case, rec) {
        Some(answer) => answer,
        None => {
            // Exact big-integer determinants on the very same float inputs.
            let exact = reference(case);
            Answer {
                hit: exact.hit,
                values: exact.values.map(|v| v.map(F::of)),
                exact_fallback: true,
                invalid_input: false,
            }
        }
    }
}

/// The float computation, or `None` when a value is too close to zero (or not finite) to trust.
fn float_path<F: Float>(case: &Case<F>, rec: &mut impl StepSink) -> Option<Answer<F>> {
    let d = case.dir;
    // Permute: z is the direction's largest component; swap x and y to keep the winding when dz < 0.
    let kz = (0..3).max_by(|&i, &j| {
        d[i].abs()
            .partial_cmp(&d[j].abs())
            .unwrap_or(std::cmp::Ordering::Equal)
    })?;
    let (mut kx, mut ky) = ((kz + 1) % 3, (kz + 2) % 3);
    if d[kz] < F::zero() {
        std::mem::swap(&mut kx, &mut ky);
    }
    if d[kz] == F::zero() {
        return Some(Answer::miss());
    }
    // Shear constants: the direction becomes (0, 0, 1).
    let sz = F::one().div(d[kz]);
    let sx = d[kx] * sz;
    let sy = d[ky] * sz;
    // Translate each vertex to the ray's origin, permute, shear.
    let shear = |p: &[F; 3]| {
        let t = [
            p[0] - case.origin[0],
            p[1] - case.origin[1],
            p[2] - case.origin[2],
        ];
        Sheared {
            x: t[kx] - sx * t[kz],
            y: t[ky] - sy * t[kz],
            z: sz * t[kz],
            mag_x: t[kx].abs() + (sx * t[kz]).abs(),
            mag_y: t[ky].abs() + (sy * t[kz]).abs(),
        }
    };
    let [a, b, c] = case.tri.each_ref().map(shear);
    // Edge functions: each from the two vertices of one edge.
    let edge = |p: &Sheared<F>, q: &Sheared<F>| p.x * q.y - p.y * q.x;
    // Bound: about 15 unit roundings reach each product (translation, shear, products, difference);
    // 16 ε = 32 units, twice that.
    let unit = F::EPS * F::of(16.0);
    let bound = |p: &Sheared<F>, q: &Sheared<F>| unit * (p.mag_x * q.mag_y + p.mag_y * q.mag_x);
    let (u, v, w) = (edge(&c, &b), edge(&a, &c), edge(&b, &a));
    let (bu, bv, bw) = (bound(&c, &b), bound(&a, &c), bound(&b, &a));
    record::vector(
        rec,
        "shear",
        "Shear (Sx, Sy, Sz)",
        "After permuting so z is the direction's largest axis: the ray becomes (0, 0, 1).",
        &[sx, sy, sz],
    );
    for (id, title, v) in [
        ("A'", "A sheared", &a),
        ("B'", "B sheared", &b),
        ("C'", "C sheared", &c),
    ] {
        record::vector(
            rec,
            id,
            title,
            "The vertex relative to the ray's origin, in the sheared space.",
            &[v.x, v.y, v.z],
        );
    }
    record::vector(
        rec,
        "UVW",
        "Edge functions U, V, W",
        "Each from the two vertices of one edge, so shared edges agree: all ≥ 0 or all ≤ 0 is inside.",
        &[u, v, w],
    );
    record::vector(
        rec,
        "bounds",
        "Their rounding bounds",
        "A value within its bound of zero is decided in exact arithmetic.",
        &[bu, bv, bw],
    );
    let all = [u, v, w, bu, bv, bw, a.z, b.z, c.z];
    if all.iter().any(|x| !x.is_finite()) {
        return None;
    }
    // The bounds are relative: near underflow (subnormal products) they no longer hold, so any
    // nonzero magnitude that small is decided exactly instead.
    let floor = F::MIN_POSITIVE.div(F::EPS);
    let tiny = |x: F| x != F::zero() && x.abs() < floor;
    let magnitudes = [
        a.mag_x, a.mag_y, a.z, b.mag_x, b.mag_y, b.z, c.mag_x, c.mag_y, c.z,
    ];
    let products = [
        c.mag_x * b.mag_y + c.mag_y * b.mag_x,
        a.mag_x * c.mag_y + a.mag_y * c.mag_x,
        b.mag_x * a.mag_y + b.mag_y * a.mag_x,
    ];
    if magnitudes.into_iter().chain(products).any(tiny) {
        return None;
    }
    // Too close to an edge to trust the sign: decide exactly.
    if u.abs() <= bu || v.abs() <= bv || w.abs() <= bw {
        return None;
    }
    // Outside if the signs differ (no back-face culling: both windings count).
    let negative = u < F::zero() || v < F::zero() || w < F::zero();
    let positive = u > F::zero() || v > F::zero() || w > F::zero();
    let det = u + v + w;
    let scaled_t = u * a.z + v * b.z + w * c.z;
    // Conservative bound on the scaled t: the edge functions' bounds and the z roundings.
    let t_bound = unit
        * ((u.abs() + bu) * a.z.abs() + (v.abs() + bv) * b.z.abs() + (w.abs() + bw) * c.z.abs())
        + bu * a.z.abs()
        + bv * b.z.abs()
        + bw * c.z.abs();
    let inv_det = F::one().div(det);
    let values = [scaled_t * inv_det, v * inv_det, w * inv_det];
    if negative && positive {
        return Some(Answer::with(false, values));
    }
    if scaled_t.abs() <= t_bound || tiny(scaled_t) || !values.iter().all(|x| x.is_finite()) {
        return None;
    }
    // t > 0 exactly when the scaled t has the determinant's sign.
    let in_front = (scaled_t > F::zero()) == (det > F::zero());
    Some(Answer::with(in_front, values))
}
