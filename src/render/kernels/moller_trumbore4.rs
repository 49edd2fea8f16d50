//! Four rays at once (AVX2, one f64 lane a ray) through a lone triangle's Möller–Trumbore test: the
//! one-ray code's arithmetic in the same order, with no fused multiply-add, so the same numbers and
//! decisions to the bit.

// The AVX2 kernels: each unsafe block says in a SAFETY comment why it is sound.
#![allow(unsafe_code)]

#[cfg(target_arch = "x86_64")]
use std::arch::x86_64::*;

use super::Avx2;
use crate::math::linalg::V3;

/// Four rays, as `[axis][lane]`.
pub struct Rays4 {
    /// Origins.
    pub origin: [[f64; 4]; 3],
    /// Directions.
    pub dir: [[f64; 4]; 3],
}

/// Three lanes of f64 (x86-64 only): a vector's components for four rays or triangles.
#[cfg(target_arch = "x86_64")]
pub(super) type Lanes3 = [__m256d; 3];

/// `a × b` as [`crate::math::linalg::cross`] computes it.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,popcnt,bmi1")]
#[inline]
fn cross4(a: &Lanes3, b: &Lanes3) -> Lanes3 {
    let c =
        |i: usize, j: usize| _mm256_sub_pd(_mm256_mul_pd(a[i], b[j]), _mm256_mul_pd(a[j], b[i]));
    [c(1, 2), c(2, 0), c(0, 1)]
}

/// `a · b` as [`crate::math::linalg::dot`] computes it (a fold from zero).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,popcnt,bmi1")]
#[inline]
fn dot4(a: &Lanes3, b: &Lanes3) -> __m256d {
    let mut sum = _mm256_setzero_pd();
    for k in 0..3 {
        sum = _mm256_add_pd(sum, _mm256_mul_pd(a[k], b[k]));
    }
    sum
}

/// One vector in every lane.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,popcnt,bmi1")]
#[inline]
pub(super) fn splat(v: &V3<f64>) -> Lanes3 {
    // Written out: a closure passed to `map` may be left uninlined, outside this AVX2 function.
    [
        _mm256_set1_pd(v[0]),
        _mm256_set1_pd(v[1]),
        _mm256_set1_pd(v[2]),
    ]
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,popcnt,bmi1")]
#[inline]
fn sub4(a: &Lanes3, b: &Lanes3) -> Lanes3 {
    [
        _mm256_sub_pd(a[0], b[0]),
        _mm256_sub_pd(a[1], b[1]),
        _mm256_sub_pd(a[2], b[2]),
    ]
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,popcnt,bmi1")]
#[inline]
fn load(rows: &[[f64; 4]; 3]) -> Lanes3 {
    // SAFETY: each row is four f64s, read unaligned.
    unsafe {
        [
            _mm256_loadu_pd(rows[0].as_ptr()),
            _mm256_loadu_pd(rows[1].as_ptr()),
            _mm256_loadu_pd(rows[2].as_ptr()),
        ]
    }
}

/// Four lanes out to an array.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,popcnt,bmi1")]
#[inline]
pub(super) fn store(x: __m256d) -> [f64; 4] {
    let mut out = [0.0; 4];
    // SAFETY: four f64s into a four-f64 array.
    unsafe { _mm256_storeu_pd(out.as_mut_ptr(), x) };
    out
}

/// [`crate::intersect::moller_trumbore::hit`] for four rays: a bit per ray that hits, and each
/// ray's (t, β, γ) as `[value][lane]`.
#[inline(always)]
pub fn moller_trumbore(avx2: Avx2, triangle: &[V3<f64>; 3], rays: &Rays4) -> (u32, [[f64; 4]; 3]) {
    #[cfg(target_arch = "x86_64")]
    {
        let _ = avx2;
        // SAFETY: an `Avx2` exists only on a processor with AVX2 and FMA.
        unsafe { moller_trumbore4(triangle, rays) }
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        let _ = (triangle, rays);
        avx2.unreachable()
    }
}

/// [`moller_trumbore`] with AVX2.
///
/// # Safety
/// Only call on a processor with AVX2 and FMA.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,popcnt,bmi1")]
#[inline]
unsafe fn moller_trumbore4([a, b, c]: &[V3<f64>; 3], rays: &Rays4) -> (u32, [[f64; 4]; 3]) {
    let (a, b, c) = (splat(a), splat(b), splat(c));
    let (origin, dir) = (load(&rays.origin), load(&rays.dir));
    let e1 = sub4(&b, &a);
    let e2 = sub4(&c, &a);
    let p = cross4(&dir, &e2);
    let det = dot4(&e1, &p);
    let zero = _mm256_setzero_pd();
    let nonzero = _mm256_cmp_pd::<_CMP_NEQ_OQ>(det, zero);
    let inv_det = _mm256_div_pd(_mm256_set1_pd(1.0), det);
    let s = sub4(&origin, &a);
    let beta = _mm256_mul_pd(dot4(&s, &p), inv_det);
    let q = cross4(&s, &e1);
    let gamma = _mm256_mul_pd(dot4(&dir, &q), inv_det);
    let t = _mm256_mul_pd(dot4(&e2, &q), inv_det);
    // `decide`: β ≥ 0, γ ≥ 0, β + γ ≤ 1, t > 0.
    let inside = _mm256_and_pd(
        _mm256_and_pd(
            _mm256_cmp_pd::<_CMP_GE_OQ>(beta, zero),
            _mm256_cmp_pd::<_CMP_GE_OQ>(gamma, zero),
        ),
        _mm256_and_pd(
            _mm256_cmp_pd::<_CMP_LE_OQ>(_mm256_add_pd(beta, gamma), _mm256_set1_pd(1.0)),
            _mm256_cmp_pd::<_CMP_GT_OQ>(t, zero),
        ),
    );
    let hit = _mm256_movemask_pd(_mm256_and_pd(nonzero, inside)) as u32;
    if hit == 0 {
        return (0, [[0.0; 4]; 3]);
    }
    (hit, [store(t), store(beta), store(gamma)])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::intersect::moller_trumbore;
    use rand::SeedableRng;

    /// The four-ray Möller–Trumbore decides as the one-ray code, bit for bit: its hits and
    /// (t, β, γ), on random rays near a triangle's edges.
    #[test]
    fn four_rays_at_once_decide_as_one_at_a_time() {
        let avx2 = crate::render::kernels::avx2_or_skip!();
        let mut random = rand_pcg::Pcg64::seed_from_u64(3);
        let mut hits = 0;
        for i in 0..20_000 {
            let draws: [[V3<f64>; 5]; 4] = std::array::from_fn(|_| {
                crate::geometry::parallelogram::lean::random_ray_near_edges(&mut random, 1e-12)
            });
            let [corner, e1, e2, _, _] = draws[i % 4];
            let four = Rays4 {
                origin: std::array::from_fn(|k| draws.map(|d| d[3][k])),
                dir: std::array::from_fn(|k| draws.map(|d| d[4][k])),
            };
            let triangle = [
                corner,
                std::array::from_fn(|k| corner[k] + e1[k]),
                std::array::from_fn(|k| corner[k] + e2[k]),
            ];
            let (hit, values) = moller_trumbore(avx2, &triangle, &four);
            for lane in 0..4 {
                let (origin, dir) = (draws[lane][3], draws[lane][4]);
                let expected = moller_trumbore::hit(&triangle, &origin, &dir);
                let got = (hit & (1 << lane) != 0).then(|| values.map(|row| row[lane]));
                let bits = |v: Option<[f64; 3]>| v.map(|v| v.map(f64::to_bits));
                assert_eq!(bits(got), bits(expected), "{i} {lane}");
                hits += got.is_some() as usize;
            }
        }
        assert!(hits > 2_000, "{hits}");
    }
}
