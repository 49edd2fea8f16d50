//! The renderer's crack-free ray–triangle test for meshes: Woop, Benthin and Wald's watertight test
//! with exact signs and a consistent tie rule, and no big-integer arithmetic on its path.
//!
//! The ray is made the z axis of a sheared space (translate to the origin, permute so the direction's
//! largest component is z, shear x and y away). Each vertex's sheared (x, y) depends only on the vertex
//! and the ray, so triangles that share a vertex see the very same numbers. The edge function of edge
//! P→Q is the 2D cross product P × Q; its neighbour's, Q × P, is its exact negation.
//!
//! - **Exact signs.** An edge function whose float value is within its rounding bound of zero has its
//!   sign recomputed exactly from the same sheared coordinates: the products by fused multiply-add
//!   (error-free), their difference as a four-term expansion (Shewchuk's two-two-diff). So the sign is
//!   the true sign of P × Q for those coordinates, the same for both triangles of an edge.
//! - **Ties.** An edge function that is exactly zero (the ray runs along the edge, or through a vertex)
//!   is decided as if the ray were moved by (ε, ε²) in the sheared plane, ε → 0⁺: the edge counts when
//!   σ·(−Δy), or σ·Δx where Δy = 0, is positive, with Δ = Q − P and σ the triangle's orientation. This
//!   is the rasteriser's top-left rule; because it is a symbolic perturbation of one ray, the ray is
//!   decided exactly as a ray that misses every edge and vertex would be: on a closed mesh it enters
//!   exactly one of the triangles around an edge or vertex it runs through — none lost, none doubled.
//!
//! The exact-deciding test ([`crate::intersect::watertight`], big integers near zero) stays what the
//! study, the probe and `--method watertight-exact` use.

use crate::math::linalg::V3;
use crate::render::TriangleHit;

/// A ray prepared for the sheared test: its origin, the permutation and the shear constants.
#[derive(Clone, Copy, Debug)]
pub struct ShearedRay {
    origin: V3<f64>,
    /// Indices of the axes that become x, y and z.
    axes: [usize; 3],
    /// Shear constants: x' = x − sx·z, y' = y − sy·z, z' = sz·z.
    shear: [f64; 3],
}

impl ShearedRay {
    /// The ray o + t d; `None` when d is zero or the ray is not finite (it hits nothing).
    #[inline(always)]
    pub fn new(origin: &V3<f64>, dir: &V3<f64>) -> Option<ShearedRay> {
        // Each array alone: a chained iterator was left uninlined in the hot walks.
        if !(origin.iter().all(|c| c.is_finite()) && dir.iter().all(|c| c.is_finite())) {
            return None;
        }
        let a = dir.map(f64::abs);
        let kz = if a[0] >= a[1] && a[0] >= a[2] {
            0
        } else if a[1] >= a[2] {
            1
        } else {
            2
        };
        if dir[kz] == 0.0 {
            return None;
        }
        let (mut kx, mut ky) = ((kz + 1) % 3, (kz + 2) % 3);
        // Keep the winding when the ray goes down its main axis.
        if dir[kz] < 0.0 {
            std::mem::swap(&mut kx, &mut ky);
        }
        let sz = 1.0 / dir[kz];
        Some(ShearedRay {
            origin: *origin,
            axes: [kx, ky, kz],
            shear: [dir[kx] * sz, dir[ky] * sz, sz],
        })
    }

    /// The origin, the axes that become x, y and z, and the shear constants (sx, sy, sz), for the
    /// four-triangle kernel of [`super::crack_free4`].
    #[inline(always)]
    #[cfg_attr(
        not(target_arch = "x86_64"),
        allow(dead_code, reason = "used by the x86-64 kernels only")
    )]
    pub(super) fn parts(&self) -> (&V3<f64>, [usize; 3], &[f64; 3]) {
        (&self.origin, self.axes, &self.shear)
    }

    /// A vertex in the sheared space: (x, y) in the plane across the ray, z along it (scaled by 1/d_z).
    #[inline(always)]
    fn shear(&self, p: &V3<f64>) -> [f64; 3] {
        let [kx, ky, kz] = self.axes;
        let [sx, sy, sz] = self.shear;
        let z = p[kz] - self.origin[kz];
        [
            (p[kx] - self.origin[kx]) - sx * z,
            (p[ky] - self.origin[ky]) - sy * z,
            sz * z,
        ]
    }

    /// Tests a triangle: X = (β, γ, t) when the ray hits it with `t_min < t`, else `None`.
    #[inline(always)]
    pub fn intersect(&self, [a, b, c]: &[V3<f64>; 3], t_min: f64) -> Option<TriangleHit> {
        let (a, b, c) = (self.shear(a), self.shear(b), self.shear(c));
        // U for edge C→B, V for A→C, W for B→A: each from its edge's two vertices alone.
        let u = edge_sign_and_value(&c, &b);
        let v = edge_sign_and_value(&a, &c);
        // Most tests are misses: opposite signs already on two edges end the test.
        if u.0 * v.0 < 0 {
            return None;
        }
        let w = edge_sign_and_value(&b, &a);
        let signs = [u.0, v.0, w.0];
        let positive = signs.contains(&1);
        let negative = signs.contains(&-1);
        if positive == negative {
            // Both signs (outside), or all three zero (a triangle seen edge-on).
            return None;
        }
        let orientation = if positive { 1 } else { -1 };
        // An edge the ray runs along (or a vertex it goes through) counts only by the tie rule.
        for (sign, p, q) in [(u.0, &c, &b), (v.0, &a, &c), (w.0, &b, &a)] {
            if sign == 0 && perturbed_sign(p, q) != orientation {
                return None;
            }
        }
        let (u, v, w) = (u.1, v.1, w.1);
        let det = u + v + w;
        let scaled_t = u * a[2] + v * b[2] + w * c[2];
        let t = scaled_t / det;
        if det != 0.0 && t.is_finite() {
            let (beta, gamma) = (v / det, w / det);
            return (t > t_min).then_some(TriangleHit { beta, gamma, t });
        }
        // The edge functions' floats all underflowed to zero while their exact signs agree: a
        // sliver far below the pixel's size. Its t from the plane, its centre as the barycentrics.
        let t = plane_t(&a, &b, &c);
        let centre = TriangleHit {
            beta: 1.0 / 3.0,
            gamma: 1.0 / 3.0,
            t,
        };
        (t.is_finite() && t > t_min).then_some(centre)
    }
}

/// t where the ray (the sheared z axis) meets the plane through a, b, c, whose z is already t.
fn plane_t(a: &[f64; 3], b: &[f64; 3], c: &[f64; 3]) -> f64 {
    let e1 = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    let e2 = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
    let n = crate::math::linalg::cross(&e1, &e2);
    (n[0] * a[0] + n[1] * a[1] + n[2] * a[2]) / n[2]
}

/// The edge function P × Q = Px·Qy − Py·Qx: its exact sign (−1, 0, 1) and its float value.
#[inline(always)]
fn edge_sign_and_value(p: &[f64; 3], q: &[f64; 3]) -> (i8, f64) {
    let left = p[0] * q[1];
    let right = p[1] * q[0];
    let value = left - right;
    // Shewchuk's bound for a 2x2 determinant, (3 + 16u)u with u = 2⁻⁵³, rounded up to 4u: beyond it
    // the float's sign is the exact sign.
    let bound = 2.0 * f64::EPSILON * (left.abs() + right.abs());
    let sum = left.abs() + right.abs();
    if value.abs() > bound && sum > TINY {
        return (sign(value), value);
    }
    (exact_cross_sign(p[0], q[1], p[1], q[0]), value)
}

/// Products smaller than this could lose bits to underflow: their signs are decided differently.
pub(super) const TINY: f64 = 1e-280;

fn sign(x: f64) -> i8 {
    if x > 0.0 {
        1
    } else if x < 0.0 {
        -1
    } else {
        0
    }
}

/// The sign the edge function P × Q takes when the ray is moved by (ε, ε²), ε → 0⁺, given P × Q = 0:
/// (P − s) × (Q − s) = P × Q − Δy·ε + Δx·ε² with Δ = Q − P. Zero only when P = Q.
#[inline(always)]
fn perturbed_sign(p: &[f64; 3], q: &[f64; 3]) -> i8 {
    // The sign of a float difference is the sign of the exact difference.
    let (dx, dy) = (q[0] - p[0], q[1] - p[1]);
    if dy != 0.0 { -sign(dy) } else { sign(dx) }
}

/// The exact sign of a·b − c·d for finite floats: error-free products and a four-term expansion
/// when they cannot underflow, else exact rationals (only for coordinates below about 1e-140).
pub fn exact_cross_sign(a: f64, b: f64, c: f64, d: f64) -> i8 {
    let (p, q) = (a * b, c * d);
    // A product is exact as p + pe when it is a true zero or far from underflow and overflow.
    let fits = |x: f64, y: f64, product: f64| {
        (x == 0.0 || y == 0.0) || (product.abs() > TINY && product.is_finite())
    };
    let operands_fit = [a, b, c, d].iter().all(|x| x.is_finite());
    if fits(a, b, p) && fits(c, d, q) && operands_fit {
        // a·b = p + pe and c·d = q + qe exactly.
        let pe = a.mul_add(b, -p);
        let qe = c.mul_add(d, -q);
        let [x3, x2, x1, x0] = two_two_diff(p, pe, q, qe);
        // A nonoverlapping expansion: its sign is its largest nonzero term's.
        return [x3, x2, x1, x0]
            .into_iter()
            .find(|x| *x != 0.0)
            .map_or(0, sign);
    }
    rational_cross_sign(a, b, c, d)
}

/// The exact sign of a·b − c·d in rational arithmetic (reached only when products underflow).
fn rational_cross_sign(a: f64, b: f64, c: f64, d: f64) -> i8 {
    use num_rational::BigRational;
    use num_traits::{Signed, Zero};
    let r = |x: f64| BigRational::from_float(x).unwrap_or_else(BigRational::zero);
    let value = r(a) * r(b) - r(c) * r(d);
    if value.is_positive() {
        1
    } else if value.is_negative() {
        -1
    } else {
        0
    }
}

/// s + e = a + b exactly (Knuth's two-sum).
#[inline(always)]
fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bv = s - a;
    let av = s - bv;
    (s, (a - av) + (b - bv))
}

/// (a1 + a0) − b as three nonoverlapping terms, largest first.
#[inline(always)]
fn two_one_diff(a1: f64, a0: f64, b: f64) -> [f64; 3] {
    let (i, x0) = two_sum(a0, -b);
    let (x2, x1) = two_sum(a1, i);
    [x2, x1, x0]
}

/// (a1 + a0) − (b1 + b0) as four nonoverlapping terms, largest first (Shewchuk 1997).
#[inline(always)]
fn two_two_diff(a1: f64, a0: f64, b1: f64, b0: f64) -> [f64; 4] {
    let [j, k, x0] = two_one_diff(a1, a0, b0);
    let [x3, x2, x1] = two_one_diff(j, k, b1);
    [x3, x2, x1, x0]
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};

    /// The expansion's sign is the rational sign, on products that cancel to the last bit and beyond.
    #[test]
    fn exact_cross_sign_agrees_with_rationals() {
        let mut random = rand_pcg::Pcg64::seed_from_u64(12);
        let mut zeros = 0;
        for i in 0..200_000 {
            let a: f64 = random.random_range(-4.0..4.0);
            let b: f64 = random.random_range(-4.0..4.0);
            // c·d close to a·b: c = a·b / d rounded, nudged by a few ulps, or exactly equal.
            let d: f64 = random.random_range(0.5..3.0) * if i % 2 == 0 { 1.0 } else { -1.0 };
            let mut c = a * b / d;
            for _ in 0..(i % 5) {
                c = f64::from_bits(c.to_bits() + 1);
            }
            let (a, b, c, d) = match i % 7 {
                0 => (a, b, b, a),
                1 => (a * 1e-150, b * 1e-150, c * 1e-150, d * 1e-150),
                _ => (a, b, c, d),
            };
            let exact = rational_cross_sign(a, b, c, d);
            assert_eq!(exact_cross_sign(a, b, c, d), exact, "{a} {b} {c} {d}");
            zeros += (exact == 0) as usize;
        }
        assert!(zeros > 10_000, "{zeros}");
    }

    fn hits(ray: &ShearedRay, triangles: &[[V3<f64>; 3]]) -> usize {
        triangles
            .iter()
            .filter(|t| ray.intersect(t, 0.0).is_some())
            .count()
    }

    /// A fan of triangles around a vertex, and every ray through the vertex or along a spoke: each
    /// hits exactly one triangle, whichever way the fan is wound and the ray points.
    #[test]
    fn rays_through_a_fan_hit_exactly_one_triangle() {
        for spokes in [3, 4, 5, 6, 8, 12] {
            for flip in [false, true] {
                let centre = [0.25, -0.5, 2.0];
                let rim: Vec<V3<f64>> = (0..spokes)
                    .map(|k| {
                        let angle = std::f64::consts::TAU * k as f64 / spokes as f64;
                        [centre[0] + angle.cos(), centre[1] + angle.sin(), 2.0]
                    })
                    .collect();
                let fan: Vec<[V3<f64>; 3]> = (0..spokes)
                    .map(|k| {
                        let (p, q) = (rim[k], rim[(k + 1) % spokes]);
                        if flip { [centre, q, p] } else { [centre, p, q] }
                    })
                    .collect();
                for (origin_z, dir_z) in [(0.0, 1.0), (4.0, -1.0)] {
                    // Through the centre, and through points along each spoke.
                    for target in std::iter::once(centre).chain(rim.iter().flat_map(|r| {
                        [0.25, 0.5]
                            .map(|s| std::array::from_fn(|k| centre[k] + (r[k] - centre[k]) * s))
                    })) {
                        let origin = [0.0, 0.0, origin_z];
                        let dir: V3<f64> = std::array::from_fn(|k| target[k] - origin[k]);
                        let dir = [dir[0], dir[1], dir_z * dir[2].abs()];
                        let ray = ShearedRay::new(&origin, &dir).unwrap();
                        assert_eq!(hits(&ray, &fan), 1, "{spokes} spokes, {target:?}");
                    }
                }
            }
        }
    }

    /// Rays along the shared diagonal of a square of two triangles hit exactly one of them.
    #[test]
    fn rays_along_a_seam_hit_exactly_one_triangle() {
        let [a, b, c, d] = [
            [-1.0, -1.0, 3.0],
            [1.0, -1.0, 3.0],
            [1.0, 1.0, 3.0],
            [-1.0, 1.0, 3.0],
        ];
        let square = [[a, b, c], [a, c, d]];
        for i in 1..100 {
            let s = -1.0 + 2.0 * i as f64 / 100.0;
            let ray = ShearedRay::new(&[0.0, 0.0, 0.0], &[s, s, 3.0]).unwrap();
            assert_eq!(hits(&ray, &square), 1, "{s}");
        }
    }
}
