//! Möller–Trumbore for the renderer's lone triangles: the very same float operations as
//! [`crate::intersect::moller_trumbore::intersect`] in f64 (the same generic functions, in the same
//! order), so the same (t, β, γ) and verdict to the last bit, but on the triangle in place: no
//! [`crate::intersect::Case`] copied for each ray, no answer to unpack. Every ray of the image tests
//! each lone triangle, so this copy was most of their cost.

use crate::intersect::decide;
use crate::math::linalg::{V3, cross, dot, sub};

/// (t, β, γ) when the ray hits the triangle (Möller–Trumbore's decision), else `None`.
#[inline(always)]
pub fn moller_trumbore(
    [a, b, c]: &[V3<f64>; 3],
    origin: &V3<f64>,
    dir: &V3<f64>,
) -> Option<[f64; 3]> {
    let e1 = sub(b, a);
    let e2 = sub(c, a);
    let p = cross(dir, &e2);
    let det = dot(&e1, &p);
    if det == 0.0 {
        return None;
    }
    let inv_det = 1.0 / det;
    let s = sub(origin, a);
    let beta = dot(&s, &p) * inv_det;
    let q = cross(&s, &e1);
    let gamma = dot(dir, &q) * inv_det;
    let t = dot(&e2, &q) * inv_det;
    decide(t, beta, gamma).then_some([t, beta, gamma])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::intersect::{Case, moller_trumbore};
    use rand::{Rng, SeedableRng};

    /// Bit for bit the core's (t, β, γ) and verdict: random triangles, rays aimed near their edges
    /// and vertices, behind, parallel to the plane, and with zero or non-finite numbers.
    #[test]
    fn the_inlined_test_gives_the_cores_bits() {
        let mut random = rand_pcg::Pcg64::seed_from_u64(3);
        let mut hits = 0;
        for i in 0..200_000 {
            let v = |random: &mut rand_pcg::Pcg64, r: f64| -> V3<f64> {
                std::array::from_fn(|_| random.random_range(-r..r))
            };
            let tri = [
                v(&mut random, 3.0),
                v(&mut random, 3.0),
                v(&mut random, 3.0),
            ];
            let origin = v(&mut random, 8.0);
            let near = |random: &mut rand_pcg::Pcg64| match random.random_range(0..3) {
                0 => random.random_range(-1e-13..1e-13),
                _ => random.random_range(-0.3..1.0),
            };
            let (beta, gamma) = (near(&mut random), near(&mut random));
            let target: V3<f64> = std::array::from_fn(|k| {
                tri[0][k] + beta * (tri[1][k] - tri[0][k]) + gamma * (tri[2][k] - tri[0][k])
            });
            let mut dir = sub(&target, &origin);
            match i % 20 {
                0 => dir = sub(&tri[1], &tri[0]),
                1 => dir = [0.0; 3],
                2 => dir[2] = f64::INFINITY,
                3 => dir = dir.map(|x| -x),
                _ => {}
            }
            let case = Case { tri, origin, dir };
            let answer = moller_trumbore::intersect(&case);
            let expected = answer.values.filter(|_| answer.hit);
            let got = moller_trumbore(&tri, &origin, &dir);
            let bits = |x: Option<[f64; 3]>| x.map(|x| x.map(f64::to_bits));
            assert_eq!(bits(got), bits(expected), "{case:?}");
            hits += expected.is_some() as usize;
        }
        assert!(hits > 50_000, "{hits}");
    }
}
