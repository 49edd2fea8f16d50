//! A BVH node's four child boxes against one ray at once (AVX2, one f64 lane a box): the portable
//! box test's arithmetic (`Node::test` in [`crate::render::bvh`]) in the same order, so the same
//! boxes met and the same entry distances. No NaN can arise outside the axes the ray is parallel
//! to, which are tested by comparisons, so `max` and `min` agree with the portable ones.

// The kernel is x86-64 only: elsewhere (the web page) the portable box test serves.
#![cfg_attr(
    not(target_arch = "x86_64"),
    allow(dead_code, unused_imports, reason = "used by the x86-64 kernel only")
)]
// The AVX2 kernel: each unsafe block says in a SAFETY comment why it is sound.
#![allow(unsafe_code)]

use super::Avx2;
use crate::render::bvh::BoxRay;

/// Which of the four boxes (`min`, `max` per axis, a lane a box) the ray meets within
/// [t_min, t_max] (a bit a lane), and where it enters each (+∞ for the boxes it misses).
#[cfg(target_arch = "x86_64")]
#[inline(always)]
pub(in crate::render) fn test(
    _: Avx2,
    (min, max): (&[[f32; 4]; 3], &[[f32; 4]; 3]),
    ray: &BoxRay,
    t_min: f64,
    t_max: f64,
) -> (u32, [f64; 4]) {
    // SAFETY: an `Avx2` exists only on a processor with AVX2 and FMA.
    unsafe { test_unchecked((min, max), ray, t_min, t_max) }
}

/// [`test`] without the proof.
///
/// # Safety
/// Only call on a processor with AVX2 and FMA.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,popcnt,bmi1")]
#[inline]
unsafe fn test_unchecked(
    (min, max): (&[[f32; 4]; 3], &[[f32; 4]; 3]),
    ray: &BoxRay,
    t_min: f64,
    t_max: f64,
) -> (u32, [f64; 4]) {
    use std::arch::x86_64::*;
    const WIDEN: f64 = 2.0 * 3.0 * f64::EPSILON;
    let mut near = _mm256_set1_pd(t_min);
    let mut far = _mm256_set1_pd(t_max);
    let mut outside = _mm256_setzero_pd();
    let zero = _mm256_setzero_pd();
    let (shrink, grow) = (_mm256_set1_pd(1.0 - WIDEN), _mm256_set1_pd(1.0 + WIDEN));
    for k in 0..3 {
        // SAFETY: each row is four f32s, read unaligned.
        let (lo, hi) = unsafe {
            (
                _mm256_cvtps_pd(_mm_loadu_ps(min[k].as_ptr())),
                _mm256_cvtps_pd(_mm_loadu_ps(max[k].as_ptr())),
            )
        };
        let o = _mm256_set1_pd(ray.origin[k]);
        if ray.parallel[k] {
            // Outside the slab: o < lo or o > hi (NaN-free: the boxes and the ray are finite).
            let out = _mm256_or_pd(
                _mm256_cmp_pd::<_CMP_LT_OQ>(o, lo),
                _mm256_cmp_pd::<_CMP_GT_OQ>(o, hi),
            );
            outside = _mm256_or_pd(outside, out);
            continue;
        }
        let inv = _mm256_set1_pd(ray.inverse_dir[k]);
        let (entry, exit) = if ray.inverse_dir[k] >= 0.0 {
            (lo, hi)
        } else {
            (hi, lo)
        };
        let t0 = _mm256_mul_pd(_mm256_sub_pd(entry, o), inv);
        let t1 = _mm256_mul_pd(_mm256_sub_pd(exit, o), inv);
        let t0_positive = _mm256_cmp_pd::<_CMP_GE_OQ>(t0, zero);
        let t1_positive = _mm256_cmp_pd::<_CMP_GE_OQ>(t1, zero);
        let t0 = _mm256_mul_pd(t0, _mm256_blendv_pd(grow, shrink, t0_positive));
        let t1 = _mm256_mul_pd(t1, _mm256_blendv_pd(shrink, grow, t1_positive));
        near = _mm256_max_pd(near, t0);
        far = _mm256_min_pd(far, t1);
    }
    let reached = _mm256_and_pd(
        _mm256_cmp_pd::<_CMP_LE_OQ>(near, far),
        _mm256_cmp_pd::<_CMP_LT_OQ>(near, _mm256_set1_pd(f64::INFINITY)),
    );
    let hit = _mm256_andnot_pd(outside, reached);
    let near = _mm256_blendv_pd(_mm256_set1_pd(f64::INFINITY), near, hit);
    let mut nears = [0.0; 4];
    // SAFETY: four f64s into a four-f64 array.
    unsafe { _mm256_storeu_pd(nears.as_mut_ptr(), near) };
    (_mm256_movemask_pd(hit) as u32, nears)
}
