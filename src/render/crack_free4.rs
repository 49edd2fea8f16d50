//! The crack-free test of [`super::crack_free`] for one ray and four triangles at once, with AVX2 on
//! four f64 lanes (a BVH leaf's triangles).
//!
//! Each lane does the one-triangle test's arithmetic in the same order, without fused multiply-adds,
//! so it gets the same numbers. Where all three edge functions are clear of their rounding bounds
//! their float signs are the exact signs, and the lane is decided here exactly as the one-triangle
//! test decides it; two clear edge functions of opposite signs are a miss whatever the third. Every
//! other lane (an edge function near zero, a zero determinant, a t that is not finite) is handed back
//! to be tested by [`ShearedRay::intersect`] itself. So the decisions, and the hits' numbers, are the
//! one-triangle test's to the bit.

// The AVX2 kernel: its unsafe blocks say in SAFETY comments why they are sound.
#![allow(unsafe_code)]

use super::crack_free::ShearedRay;
use crate::math::linalg::V3;

/// Four triangles' vertices as `[vertex][axis][lane]`, aligned for 32-byte loads.
#[derive(Clone, Debug)]
#[repr(C, align(32))]
pub struct Quad {
    /// Vertex A, B, C; axis x, y, z; one lane per triangle.
    pub v: [[[f64; 4]; 3]; 3],
}

impl Quad {
    /// Up to four triangles; missing lanes repeat the first triangle (callers mask them off).
    pub fn new(triangles: &[[V3<f64>; 3]]) -> Quad {
        let v = std::array::from_fn(|vertex| {
            std::array::from_fn(|axis| {
                std::array::from_fn(|lane| {
                    let t = triangles.get(lane).or(triangles.first());
                    t.map_or(0.0, |t| t[vertex][axis])
                })
            })
        });
        Quad { v }
    }
}

/// What the four-lane test found, a bit per lane in the masks.
pub struct QuadHits {
    /// Lanes decided here as hits with t > t_min.
    pub hit: u32,
    /// Lanes to test again one at a time with [`ShearedRay::intersect`].
    pub again: u32,
    /// Per lane: t, and the edge functions V, W and their sum (β = V / det, γ = W / det).
    pub t: [f64; 4],
    pub v: [f64; 4],
    pub w: [f64; 4],
    pub det: [f64; 4],
}

/// Tests the lanes in `lanes` (a bit each) of `quad` against `ray`.
///
/// # Safety
/// Only call on a processor with AVX2 and FMA (the function is compiled for them).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
#[inline]
pub unsafe fn intersect4(ray: &ShearedRay, quad: &Quad, t_min: f64, lanes: u32) -> QuadHits {
    use std::arch::x86_64::*;
    let (origin, [kx, ky, kz], [sx, sy, sz]) = ray.parts();
    let (ox, oy, oz) = (
        _mm256_set1_pd(origin[kx]),
        _mm256_set1_pd(origin[ky]),
        _mm256_set1_pd(origin[kz]),
    );
    let (sx, sy, sz) = (_mm256_set1_pd(sx), _mm256_set1_pd(sy), _mm256_set1_pd(sz));
    // SAFETY: each row is four f64s in a 32-byte aligned struct.
    let load =
        |vertex: usize, axis: usize| unsafe { _mm256_load_pd(quad.v[vertex][axis].as_ptr()) };
    // As `ShearedRay::shear`: x' = (x − ox) − sx·z, y' = (y − oy) − sy·z, z' = sz·z with z = z − oz.
    let shear = |vertex: usize| {
        let z = _mm256_sub_pd(load(vertex, kz), oz);
        [
            _mm256_sub_pd(_mm256_sub_pd(load(vertex, kx), ox), _mm256_mul_pd(sx, z)),
            _mm256_sub_pd(_mm256_sub_pd(load(vertex, ky), oy), _mm256_mul_pd(sy, z)),
            _mm256_mul_pd(sz, z),
        ]
    };
    let (a, b, c) = (shear(0), shear(1), shear(2));
    let magnitude = |x: __m256d| _mm256_andnot_pd(_mm256_set1_pd(-0.0), x);
    // As `edge_sign_and_value`: P × Q, and whether it is clear of its rounding bound.
    let edge = |p: &[__m256d; 3], q: &[__m256d; 3]| {
        let left = _mm256_mul_pd(p[0], q[1]);
        let right = _mm256_mul_pd(p[1], q[0]);
        let value = _mm256_sub_pd(left, right);
        let sum = _mm256_add_pd(magnitude(left), magnitude(right));
        let bound = _mm256_mul_pd(_mm256_set1_pd(2.0 * f64::EPSILON), sum);
        let clear = _mm256_and_pd(
            _mm256_cmp_pd::<_CMP_GT_OQ>(magnitude(value), bound),
            _mm256_cmp_pd::<_CMP_GT_OQ>(sum, _mm256_set1_pd(super::crack_free::TINY)),
        );
        (value, clear)
    };
    let (u, u_clear) = edge(&c, &b);
    let (v, v_clear) = edge(&a, &c);
    let (w, w_clear) = edge(&b, &a);
    let zero = _mm256_setzero_pd();
    let positive =
        |x: __m256d, clear: __m256d| _mm256_and_pd(clear, _mm256_cmp_pd::<_CMP_GT_OQ>(x, zero));
    let negative =
        |x: __m256d, clear: __m256d| _mm256_and_pd(clear, _mm256_cmp_pd::<_CMP_LT_OQ>(x, zero));
    let (u_pos, v_pos, w_pos) = (
        positive(u, u_clear),
        positive(v, v_clear),
        positive(w, w_clear),
    );
    let (u_neg, v_neg, w_neg) = (
        negative(u, u_clear),
        negative(v, v_clear),
        negative(w, w_clear),
    );
    let any_pos = _mm256_or_pd(_mm256_or_pd(u_pos, v_pos), w_pos);
    let any_neg = _mm256_or_pd(_mm256_or_pd(u_neg, v_neg), w_neg);
    let all_pos = _mm256_and_pd(_mm256_and_pd(u_pos, v_pos), w_pos);
    let all_neg = _mm256_and_pd(_mm256_and_pd(u_neg, v_neg), w_neg);
    let outside = _mm256_and_pd(any_pos, any_neg);
    let inside = _mm256_or_pd(all_pos, all_neg);
    // As the one-triangle test: det = U + V + W, t = (U·Az + V·Bz + W·Cz) / det.
    let det = _mm256_add_pd(_mm256_add_pd(u, v), w);
    let scaled_t = _mm256_add_pd(
        _mm256_add_pd(_mm256_mul_pd(u, a[2]), _mm256_mul_pd(v, b[2])),
        _mm256_mul_pd(w, c[2]),
    );
    let t = _mm256_div_pd(scaled_t, det);
    let usable = _mm256_and_pd(
        _mm256_cmp_pd::<_CMP_NEQ_OQ>(det, zero),
        _mm256_cmp_pd::<_CMP_LT_OQ>(magnitude(t), _mm256_set1_pd(f64::INFINITY)),
    );
    let decided = _mm256_and_pd(inside, usable);
    let hit = _mm256_and_pd(
        decided,
        _mm256_cmp_pd::<_CMP_GT_OQ>(t, _mm256_set1_pd(t_min)),
    );
    let hit = _mm256_movemask_pd(hit) as u32 & lanes;
    let settled = _mm256_movemask_pd(_mm256_or_pd(decided, outside)) as u32;
    let mut out = QuadHits {
        hit,
        again: lanes & !settled,
        t: [0.0; 4],
        v: [0.0; 4],
        w: [0.0; 4],
        det: [0.0; 4],
    };
    if hit != 0 {
        // SAFETY: four f64s into each four-f64 array.
        unsafe {
            _mm256_storeu_pd(out.t.as_mut_ptr(), t);
            _mm256_storeu_pd(out.v.as_mut_ptr(), v);
            _mm256_storeu_pd(out.w.as_mut_ptr(), w);
            _mm256_storeu_pd(out.det.as_mut_ptr(), det);
        }
    }
    out
}
