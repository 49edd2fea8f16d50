//! Four rays at once (AVX2, one f64 lane a ray) through seed 001's lean parallelogram solver,
//! [`crate::geometry::parallelogram::lean::solve_inside`]: the same float operations in the same
//! order (no fused multiply-add), so the same (α, β, t) and verdicts to the bit. A lane whose ray
//! takes one of the solver's rare paths (a non-finite input, a zero direction, a direction nearly
//! in the plane, whose check needs the norms) is marked for the one-ray solver. A lane whose t is
//! negative, not finite or beyond the ray's nearest hit so far is dropped before its α and β are
//! divided out: the solver's t is computed first, to the bit, so this cull needs no margin. An
//! any-hit query first drops the rays whose plane test, with a bound on its rounding and the
//! solver's, shows the solver's t to be negative or past the ray's end (`out_of_reach`): the
//! floor an occlusion ray leaves, a wall behind it. A lone any-hit ray
//! ([`Parallelogram4::blocks_one`]) takes one lane of the same arithmetic in scalar f64.

// The AVX2 kernel: each unsafe block says in a SAFETY comment why it is sound.
#![allow(unsafe_code)]

#[cfg(target_arch = "x86_64")]
use std::arch::x86_64::*;

use super::Avx2;
#[cfg(target_arch = "x86_64")]
use super::moller_trumbore4::{Lanes3, splat, store};
use crate::math::linalg::V3;
use crate::math::linalg::other_two;
use crate::render::Ray;

/// Four rays (origin, direction), one a lane.
pub type Rays4 = [Ray; 4];

/// What four rays found: lanes are bits (lane i is bit i), values are `[lane]`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Found4 {
    /// The lanes the solver calls a hit (α, β in [0, 1], finite t ≥ 0) with t ≤ the lane's `t_max`.
    pub hit: u32,
    /// The lanes left to the one-ray solver: their `hit` bit is clear and their values mean nothing.
    pub rare: u32,
    /// The solver's t.
    pub t: [f64; 4],
    /// The solver's α.
    pub alpha: [f64; 4],
    /// The solver's β.
    pub beta: [f64; 4],
}

/// What the four-lane solver needs of one parallelogram beyond its corner and edges, found once,
/// when the scene is prepared: what it derives from e1 × e2.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Parallelogram4Parts {
    /// The largest |component| of e1 × e2 (for the solver's near-parallel check).
    normal_largest: f64,
    /// n = e1 × e2 rounded, and per component the sum of its two products' magnitudes (what
    /// bounds n's rounding and the solver's): for [`out_of_reach`].
    normal: V3<f64>,
    normal_sizes: V3<f64>,
}

impl Parallelogram4Parts {
    /// `None` when the parallelogram takes one of the solver's rare paths whatever the ray
    /// (non-finite, or edges that may be parallel): then every ray goes to the one-ray solver.
    pub fn of(shape @ [_, e1, e2]: [&V3<f64>; 3]) -> Option<Parallelogram4Parts> {
        // n_k = e1_a·e2_b − e1_b·e2_a, (a, b) following k around the axes: n = e1 × e2.
        let product = |k: usize| {
            let (a, b) = ((k + 1) % 3, (k + 2) % 3);
            (e1[a] * e2[b], e1[b] * e2[a])
        };
        Some(Parallelogram4Parts {
            normal_largest: normal_largest(shape)?,
            normal: std::array::from_fn(|k| product(k).0 - product(k).1),
            normal_sizes: std::array::from_fn(|k| product(k).0.abs() + product(k).1.abs()),
        })
    }
}

/// The solver for one parallelogram, four rays at a time: its corner, edges and parts, borrowed
/// from the prepared scene. (Made afresh for each packet, by value, its copies' stores were read
/// back as wider loads the processor could not forward them to: 5% of the samples of the
/// ambient-occlusion scene's occlusion rays.)
#[derive(Clone, Copy)]
pub struct Parallelogram4<'a> {
    /// The proof that the processor runs the kernel.
    avx2: Avx2,
    corner: &'a V3<f64>,
    e1: &'a V3<f64>,
    e2: &'a V3<f64>,
    parts: &'a Parallelogram4Parts,
}

impl std::ops::Deref for Parallelogram4<'_> {
    type Target = Parallelogram4Parts;

    fn deref(&self) -> &Parallelogram4Parts {
        self.parts
    }
}

impl<'a> Parallelogram4<'a> {
    /// The solver for parallelogram `[corner, e1, e2]`, whose parts were found once, when it was
    /// prepared. `None` without `simd` (a processor without AVX2).
    #[inline]
    pub fn new(
        simd: Option<Avx2>,
        [corner, e1, e2]: [&'a V3<f64>; 3],
        parts: &'a Parallelogram4Parts,
    ) -> Option<Parallelogram4<'a>> {
        Some(Parallelogram4 {
            avx2: simd?,
            corner,
            e1,
            e2,
            parts,
        })
    }

    /// The solver's answers for four rays (in the parallelogram's space), keeping only hits with
    /// t ≤ `t_max` (per lane).
    #[inline]
    pub fn solve(&self, rays: &Rays4, t_max: &[f64; 4]) -> Found4 {
        self.solve_lanes::<false>(rays, 0b1111, t_max)
    }

    /// An any-hit query's answers for the rays of `lanes` (a bit set; the other lanes' rays are
    /// neither solved nor reported, and may hold anything): the hits with 0 < t < `t_end` (per
    /// lane), the open range a shadow or occlusion ray asks about.
    #[inline]
    pub fn solve_between(&self, rays: &Rays4, lanes: u32, t_end: &[f64; 4]) -> Found4 {
        self.solve_lanes::<true>(rays, lanes, t_end)
    }

    /// [`Parallelogram4::solve_between`] for one ray: `Some(true)` when it is hit with
    /// 0 < t < `t_end`, `None` when the one-ray solver must decide (a rare path). One lane of the
    /// kernel in scalar f64: the same operations in the same order, so the same decisions, but
    /// α and β are divided out only once t is in range. (The kernel with the ray in all four
    /// lanes took as many instructions, but the one-light scene's shadow rays, which leave its
    /// floor, took 1.0 ms a cast against 0.8 ms on one thread.)
    #[inline]
    pub fn blocks_one(&self, ray: &Ray, t_end: f64) -> Option<bool> {
        let (origin, d) = (&ray.origin, &ray.dir);
        let (e1, e2, corner) = (self.e1, self.e2, self.corner);
        // M = [e1 e2 −d] by columns; y = o − c.
        let m = [
            [e1[0], e2[0], -d[0]],
            [e1[1], e2[1], -d[1]],
            [e1[2], e2[2], -d[2]],
        ];
        let y = [
            origin[0] - corner[0],
            origin[1] - corner[1],
            origin[2] - corner[2],
        ];
        // |minor(row, col)| as `det2`: ad − bc.
        let minor = |row: usize, col: usize| {
            let ([r0, r1], [k0, k1]) = (other_two(row), other_two(col));
            m[r0][k0] * m[r1][k1] - m[r0][k1] * m[r1][k0]
        };
        // |M| = ((0 + m₀₀|A|) − m₀₁|B|) + m₀₂|C|, along the first row.
        let det = ((0.0 + m[0][0] * minor(0, 0)) - m[0][1] * minor(0, 1)) + m[0][2] * minor(0, 2);
        // The kernel's usual rays: finite, a nonzero direction, a finite |M| surely not negligible.
        let finite_ray = origin.iter().chain(d).all(|x| x.is_finite());
        let zero_dir = d.iter().all(|&x| x == 0.0);
        let dir_largest = d[0].abs().max(d[1].abs()).max(d[2].abs());
        let product = self.normal_largest * dir_largest;
        let bound = <f64 as crate::math::real::Real>::TOLERANCE * 6.0 * product;
        let in_range = (product * 4.0).is_finite() && bound > 1e-280;
        let surely_above = in_range && det.abs() > bound;
        if zero_dir || !(finite_ray && det.is_finite() && surely_above) {
            return None;
        }
        // Row i of M⁻¹ y: ((0 + (adj[i][0] / |M|) y₀) + (adj[i][1] / |M|) y₁) + (adj[i][2] / |M|) y₂,
        // with adj[i][j] = (−1)^(i+j) |minor(j, i)|.
        let solved = |i: usize| {
            let adjugate = |j: usize| {
                let cofactor = minor(j, i);
                if (i + j) % 2 == 1 {
                    -cofactor
                } else {
                    cofactor
                }
            };
            (0..3).fold(0.0, |sum, j| sum + (adjugate(j) / det) * y[j])
        };
        let unit = |x: f64| (0.0..=1.0).contains(&x);
        let t = solved(2);
        Some(t.is_finite() && t > 0.0 && t < t_end && unit(solved(0)) && unit(solved(1)))
    }

    /// [`Parallelogram4::solve`] (`OPEN` false) or [`Parallelogram4::solve_between`] (true).
    #[inline]
    fn solve_lanes<const OPEN: bool>(&self, rays: &Rays4, lanes: u32, limit: &[f64; 4]) -> Found4 {
        let _: Avx2 = self.avx2;
        #[cfg(target_arch = "x86_64")]
        // SAFETY: `self` holds an `Avx2`, which exists only on a processor with AVX2 and FMA.
        return unsafe { solve_four::<OPEN>(self, rays, lanes, limit) };
        #[cfg(not(target_arch = "x86_64"))]
        {
            // Never built: no `Avx2` exists off x86-64.
            let _ = (
                rays,
                limit,
                self.corner,
                self.e1,
                self.e2,
                self.normal_largest,
                self.normal,
                self.normal_sizes,
            );
            Found4 {
                rare: lanes,
                ..Found4::default()
            }
        }
    }
}

/// The largest |component| of the parallelogram's normal e1 × e2 when it passes the solver's
/// refusals that do not depend on the ray ([`regular_normal`]): what [`Parallelogram4`] needs of
/// it. `None` when the four-lane solver leaves every ray to the one-ray solver.
///
/// [`regular_normal`]: crate::geometry::parallelogram::lean::regular_normal
pub fn normal_largest(shape: [&V3<f64>; 3]) -> Option<f64> {
    crate::geometry::parallelogram::lean::regular_normal(shape).map(|normal| largest(&normal))
}

/// As the solver's `surely_above` takes it: the largest |component|.
fn largest(v: &V3<f64>) -> f64 {
    v[0].abs().max(v[1].abs()).max(v[2].abs())
}

/// Four numbers into lanes, read one by one: the caller has just written them one by one, and a
/// 256-bit load of four scalar stores would wait for them (no store forwarding).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,popcnt,bmi1")]
#[inline]
fn gather(x: [f64; 4]) -> __m256d {
    _mm256_set_pd(x[3], x[2], x[1], x[0])
}

/// The rays' origins (`which` 0) or directions (1) as `[axis]` lanes.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,popcnt,bmi1")]
#[inline]
fn rays_lanes(rays: &Rays4, which: usize) -> Lanes3 {
    let part = |lane: usize| {
        if which == 0 {
            &rays[lane].origin
        } else {
            &rays[lane].dir
        }
    };
    let axis = |k: usize| [part(0)[k], part(1)[k], part(2)[k], part(3)[k]];
    [gather(axis(0)), gather(axis(1)), gather(axis(2))]
}

/// −x, as the solver's `neg`: the sign bit flipped.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,popcnt,bmi1")]
#[inline]
fn negate(x: __m256d) -> __m256d {
    _mm256_xor_pd(x, _mm256_set1_pd(-0.0))
}

/// |x|.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,popcnt,bmi1")]
#[inline]
fn abs(x: __m256d) -> __m256d {
    _mm256_andnot_pd(_mm256_set1_pd(-0.0), x)
}

/// All ones where x is finite (not NaN, not ±∞).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,popcnt,bmi1")]
#[inline]
fn finite(x: __m256d) -> __m256d {
    _mm256_cmp_pd::<_CMP_LT_OQ>(abs(x), _mm256_set1_pd(f64::INFINITY))
}

/// a ∧ b ∧ c, lane by lane.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,popcnt,bmi1")]
#[inline]
fn all3(a: __m256d, b: __m256d, c: __m256d) -> __m256d {
    _mm256_and_pd(_mm256_and_pd(a, b), c)
}

/// All ones where x = 0 (either sign).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,popcnt,bmi1")]
#[inline]
fn is_zero(x: __m256d) -> __m256d {
    _mm256_cmp_pd::<_CMP_EQ_OQ>(x, _mm256_setzero_pd())
}

/// All ones where 0 ≤ x ≤ 1 (the solver's `in_unit`).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,popcnt,bmi1")]
#[inline]
fn in_unit(x: __m256d) -> __m256d {
    _mm256_and_pd(
        _mm256_cmp_pd::<_CMP_GE_OQ>(x, _mm256_setzero_pd()),
        _mm256_cmp_pd::<_CMP_LE_OQ>(x, _mm256_set1_pd(1.0)),
    )
}

/// The 2x2 determinant `ad − bc`, as `det2`.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,popcnt,bmi1")]
#[inline]
fn det2(m: &[[__m256d; 2]; 2]) -> __m256d {
    _mm256_sub_pd(
        _mm256_mul_pd(m[0][0], m[1][1]),
        _mm256_mul_pd(m[0][1], m[1][0]),
    )
}

/// The minor of a 3x3 matrix without `row` and `col`, as `minor3`.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,popcnt,bmi1")]
#[inline]
fn minor3(m: &[Lanes3; 3], row: usize, col: usize) -> [[__m256d; 2]; 2] {
    let (rows, cols) = (other_two(row), other_two(col));
    [
        [m[rows[0]][cols[0]], m[rows[0]][cols[1]]],
        [m[rows[1]][cols[0]], m[rows[1]][cols[1]]],
    ]
}

/// The adjugate as `adjugate3`: adj[i][j] = (−1)^(i+j) |minor(j, i)|.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,popcnt,bmi1")]
#[inline]
fn adjugate(m: &[Lanes3; 3]) -> [Lanes3; 3] {
    let entry = |i: usize, j: usize| {
        let cofactor = det2(&minor3(m, j, i));
        if (i + j) % 2 == 1 {
            negate(cofactor)
        } else {
            cofactor
        }
    };
    [
        [entry(0, 0), entry(0, 1), entry(0, 2)],
        [entry(1, 0), entry(1, 1), entry(1, 2)],
        [entry(2, 0), entry(2, 1), entry(2, 2)],
    ]
}

/// Row i of the solver's M⁻¹ (o − c): ((0 + (adj[i][0] / |M|) y₀) + (adj[i][1] / |M|) y₁) +
/// (adj[i][2] / |M|) y₂, as `dot(&adjugate[i].map(|x| x / det), &y)`.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,popcnt,bmi1")]
#[inline]
fn solved_row(adjugate_row: &Lanes3, det: __m256d, y: &Lanes3) -> __m256d {
    let mut sum = _mm256_setzero_pd();
    for (entry, y) in adjugate_row.iter().zip(y) {
        sum = _mm256_add_pd(sum, _mm256_mul_pd(_mm256_div_pd(*entry, det), *y));
    }
    sum
}

/// [`solve4`] for four rays, a lane each.
///
/// # Safety
/// Only call on a processor with AVX2 and FMA.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,popcnt,bmi1")]
#[inline]
unsafe fn solve_four<const OPEN: bool>(
    shape: &Parallelogram4<'_>,
    rays: &Rays4,
    lanes: u32,
    limit: &[f64; 4],
) -> Found4 {
    let (origin, dir) = (rays_lanes(rays, 0), rays_lanes(rays, 1));
    let limit = gather(*limit);
    // An any-hit query first drops the rays the plane keeps from a hit (the floor under an
    // occlusion ray's origin, a wall behind it or out of its reach), and is done if none is left.
    let lanes = match OPEN {
        true => lanes & !out_of_reach(shape, &[origin, dir], limit),
        false => lanes,
    };
    if lanes == 0 {
        return Found4::default();
    }
    solve4::<OPEN>(shape, [origin, dir], lanes, limit)
}

/// The solver's near-parallel bound on |det| for each lane's direction (6 × tolerance × the
/// largest |component| of the normal and of d), and the lanes where that bound is taken: the
/// product finite with room to spare, the bound not negligible.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,popcnt,bmi1")]
#[inline]
fn near_parallel_bound(shape: &Parallelogram4<'_>, dir: &Lanes3) -> (__m256d, __m256d) {
    let dir_largest = _mm256_max_pd(_mm256_max_pd(abs(dir[0]), abs(dir[1])), abs(dir[2]));
    let product = _mm256_mul_pd(_mm256_set1_pd(shape.normal_largest), dir_largest);
    let factor = <f64 as crate::math::real::Real>::TOLERANCE * 6.0;
    let bound = _mm256_mul_pd(_mm256_set1_pd(factor), product);
    let in_range = _mm256_and_pd(
        finite(_mm256_mul_pd(product, _mm256_set1_pd(4.0))),
        _mm256_cmp_pd::<_CMP_GT_OQ>(bound, _mm256_set1_pd(1e-280)),
    );
    (bound, in_range)
}

/// The lanes whose rays the solver surely finds no hit for with 0 < t < `t_end` because of where
/// the parallelogram's plane is: the ray leaves the plane (an occlusion ray from a floor, or away
/// from a wall it stands in front of), or meets it only at |t| ≥ `t_end`. The plane's
/// t = −((o − c)·n) / (d·n) is known here to within a bound on the rounding of both this sum and
/// the solver's (16 ε times the sums of the products' magnitudes), so a lane is dropped only where
/// the solver's own t, to the bit, is < 0 or beyond `t_end`, and only where d·n is far enough from
/// zero that the solver takes its usual path. Lanes near the plane's line, parallel to it, with a
/// number not finite (the bounds are then ∞ or NaN, and every comparison false), or with t near 0
/// or near `t_end` are solved. No answer changes.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,popcnt,bmi1")]
#[inline]
fn out_of_reach(shape: &Parallelogram4<'_>, [origin, dir]: &[Lanes3; 2], t_end: __m256d) -> u32 {
    let corner = splat(shape.corner);
    let (normal, sizes) = (splat(&shape.normal), splat(&shape.normal_sizes));
    // y = o − c as the solver rounds it.
    let y = [0, 1, 2].map(|k| _mm256_sub_pd(origin[k], corner[k]));
    let dot = |v: &Lanes3| {
        let term = |k: usize| _mm256_mul_pd(v[k], normal[k]);
        _mm256_add_pd(_mm256_add_pd(term(0), term(1)), term(2))
    };
    // 16 ε · Σ |v_k| · (|a_k| + |b_k|): more than this sum's rounding and n's, and the solver's
    // rounding of its t's numerator (v = y) or of its determinant (v = d), together.
    let error = |v: &Lanes3| {
        let term = |k: usize| _mm256_mul_pd(abs(v[k]), sizes[k]);
        let sum = _mm256_add_pd(_mm256_add_pd(term(0), term(1)), term(2));
        _mm256_mul_pd(_mm256_set1_pd(16.0 * f64::EPSILON), sum)
    };
    let (towards, across) = (dot(&y), dot(dir));
    let (towards_error, across_error) = (error(&y), error(dir));
    let (towards_size, across_size) = (abs(towards), abs(across));
    // The solver's usual path, surely: |det| = |d·n| (within its rounding) above the solver's
    // near-parallel bound, in the range that bound is taken in.
    let (bound, in_range) = near_parallel_bound(shape, dir);
    let usual = _mm256_and_pd(
        in_range,
        _mm256_cmp_pd::<_CMP_GT_OQ>(_mm256_sub_pd(across_size, across_error), bound),
    );
    // (o − c)·n and d·n of one sign, the first clear of its rounding: t < 0.
    let leaves = _mm256_and_pd(
        _mm256_cmp_pd::<_CMP_GT_OQ>(_mm256_mul_pd(towards, across), _mm256_setzero_pd()),
        _mm256_cmp_pd::<_CMP_GT_OQ>(towards_size, towards_error),
    );
    // |t| > t_end: the bounds (each at least 16 ε of its sum) also cover the division's rounding.
    let reach = _mm256_mul_pd(t_end, _mm256_add_pd(across_size, across_error));
    let beyond = _mm256_cmp_pd::<_CMP_GT_OQ>(_mm256_sub_pd(towards_size, towards_error), reach);
    _mm256_movemask_pd(_mm256_and_pd(usual, _mm256_or_pd(leaves, beyond))) as u32
}

/// [`Parallelogram4::solve`] with AVX2, the rays' origins and directions in lanes.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,popcnt,bmi1")]
#[inline]
fn solve4<const OPEN: bool>(
    shape: &Parallelogram4<'_>,
    [origin, dir]: [Lanes3; 2],
    lanes: u32,
    limit: __m256d,
) -> Found4 {
    let (e1, e2) = (splat(shape.e1), splat(shape.e2));
    let minus_d = [negate(dir[0]), negate(dir[1]), negate(dir[2])];
    // M = [e1 e2 −d] by columns; y = o − c.
    let m: [Lanes3; 3] = [
        [e1[0], e2[0], minus_d[0]],
        [e1[1], e2[1], minus_d[1]],
        [e1[2], e2[2], minus_d[2]],
    ];
    let corner = splat(shape.corner);
    let y = [
        _mm256_sub_pd(origin[0], corner[0]),
        _mm256_sub_pd(origin[1], corner[1]),
        _mm256_sub_pd(origin[2], corner[2]),
    ];
    // |M| = ((0 + m₀₀|A|) − m₀₁|B|) + m₀₂|C|, along the first row.
    let mut det = _mm256_setzero_pd();
    for col in 0..3 {
        let product = _mm256_mul_pd(m[0][col], det2(&minor3(&m, 0, col)));
        det = if col == 1 {
            _mm256_sub_pd(det, product)
        } else {
            _mm256_add_pd(det, product)
        };
    }
    // The rays the kernel solves as the solver would: finite, a nonzero direction, a finite |M|
    // surely not negligible (the solver's `surely_above(&[det, 0, 0], &normal, dir)`).
    let zero = _mm256_setzero_pd();
    let finite_ray = _mm256_and_pd(
        all3(finite(origin[0]), finite(origin[1]), finite(origin[2])),
        all3(finite(dir[0]), finite(dir[1]), finite(dir[2])),
    );
    let zero_dir = all3(is_zero(dir[0]), is_zero(dir[1]), is_zero(dir[2]));
    let (bound, in_range) = near_parallel_bound(shape, &dir);
    let surely_above = _mm256_and_pd(in_range, _mm256_cmp_pd::<_CMP_GT_OQ>(abs(det), bound));
    let usual = _mm256_andnot_pd(zero_dir, all3(finite_ray, finite(det), surely_above));
    let rare = lanes & !(_mm256_movemask_pd(usual) as u32);
    let mut found = Found4 {
        rare,
        ..Found4::default()
    };
    let adj = adjugate(&m);
    // t first: a hit needs a finite t ≥ 0, and only t ≤ t_max can be kept (or, `OPEN`, only
    // 0 < t < t_end). (A division-free cull by N = adj · y against |M| with a margin, before
    // this, measured no faster.)
    let t = solved_row(&adj[2], det, &y);
    let near = if OPEN {
        _mm256_and_pd(
            _mm256_cmp_pd::<_CMP_GT_OQ>(t, zero),
            _mm256_cmp_pd::<_CMP_LT_OQ>(t, limit),
        )
    } else {
        _mm256_and_pd(
            _mm256_cmp_pd::<_CMP_GE_OQ>(t, zero),
            _mm256_cmp_pd::<_CMP_LE_OQ>(t, limit),
        )
    };
    let mut keep = all3(usual, finite(t), near);
    let kept = |keep: __m256d| lanes & _mm256_movemask_pd(keep) as u32;
    if kept(keep) == 0 {
        return found;
    }
    let alpha = solved_row(&adj[0], det, &y);
    keep = _mm256_and_pd(keep, in_unit(alpha));
    if kept(keep) == 0 {
        return found;
    }
    let beta = solved_row(&adj[1], det, &y);
    keep = _mm256_and_pd(keep, in_unit(beta));
    found.hit = kept(keep);
    found.t = store(t);
    found.alpha = store(alpha);
    found.beta = store(beta);
    found
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::parallelogram::lean::{
        Inside, random_ray_at, random_ray_near_edges, solve_inside,
    };
    use crate::math::linalg::cross;
    use rand::{Rng, SeedableRng};

    /// What one ray at a time keeps: the solver's hit with t ≤ t_max, as (t, α, β).
    fn one_at_a_time(
        shape: [&V3<f64>; 3],
        origin: &V3<f64>,
        dir: &V3<f64>,
        t_max: f64,
    ) -> Option<[f64; 3]> {
        let Inside {
            alpha_beta_t: [alpha, beta, t],
            hit,
        } = solve_inside(shape, origin, dir)?;
        (hit && t <= t_max).then_some([t, alpha, beta])
    }

    /// A ray made unusual on some draws: the solver's rare paths (zero, non-finite, nearly in the
    /// plane, near its thresholds), behind, or left as it is.
    fn vary(i: usize, [e1, e2]: [&V3<f64>; 2], origin: &mut V3<f64>, dir: &mut V3<f64>) {
        let n = cross(e1, e2);
        match i % 40 {
            0 => *dir = std::array::from_fn(|k| e1[k] + 1e-17 * n[k]),
            1 => *dir = [0.0; 3],
            2 => dir[1] = f64::NAN,
            3 => dir[2] = f64::INFINITY,
            4 => origin[0] = f64::NEG_INFINITY,
            5 => *dir = dir.map(|x| -x),
            6 => *dir = std::array::from_fn(|k| e2[k] + 3e-15 * n[k] * (i % 7) as f64),
            7 => *dir = dir.map(|x| x * 1e-300),
            8 => *origin = std::array::from_fn(|k| origin[k] + 1e-3 * n[k] * (i % 3) as f64),
            _ => {}
        }
    }

    /// The t_max a lane is given: none, the solver's own t (a tie), just either side of it, or any.
    fn t_max_for(random: &mut rand_pcg::Pcg64, t: Option<f64>) -> f64 {
        let t = t.unwrap_or(1.0);
        match random.random_range(0..6) {
            0 => f64::INFINITY,
            1 => t,
            2 => t.next_down(),
            3 => t.next_up(),
            4 => 0.0,
            _ => random.random_range(0.0..20.0),
        }
    }

    /// Four lanes decide and compute as the one-ray solver does, to the bit: random parallelograms
    /// (scaled far from 1 on some draws), four rays aimed near their edges and corners, rays on the
    /// solver's rare paths, and t_max at, just before and just past the solver's t. A lane the kernel
    /// leaves to the one-ray solver must be rare: only on the draws made unusual. An any-hit query
    /// ([`Parallelogram4::solve_between`]) of some of the lanes answers as one ray, 0 < t < t_max,
    /// and so does each ray alone ([`Parallelogram4::blocks_one`]).
    #[test]
    fn four_lanes_solve_as_one_ray_at_a_time() {
        let avx2 = crate::render::kernels::avx2_or_skip!();
        let mut random = rand_pcg::Pcg64::seed_from_u64(12);
        let (mut hits, mut culled, mut rare, mut between_hits) = (0, 0, 0, 0);
        for i in 0..40_000 {
            let [corner, e1, e2, origin, dir] = random_ray_near_edges(&mut random, 1e-13);
            let mut rays = [[origin, dir]; 4];
            for ray in &mut rays[1..] {
                *ray = random_ray_at(&mut random, [&corner, &e1, &e2], 1e-13);
            }
            let mut unusual = 0;
            for (lane, [origin, dir]) in rays.iter_mut().enumerate() {
                let draw = 4 * i + lane;
                vary(draw, [&e1, &e2], origin, dir);
                unusual |= u32::from(draw % 40 < 9) << lane;
            }
            let scale = [1e-150, 1e100, 1e153, 1.0, 1.0, 1.0][i % 6];
            let (corner, e1) = (corner.map(|x| x * scale), e1.map(|x| x * scale));
            let rays = rays.map(|ray| ray.map(|v| v.map(|x| x * scale)));
            let shape = [&corner, &e1, &e2];
            let t_max: [f64; 4] = std::array::from_fn(|lane| {
                let t = solve_inside(shape, &rays[lane][0], &rays[lane][1]);
                t_max_for(&mut random, t.map(|x| x.alpha_beta_t[2]))
            });
            let Some(parts) = Parallelogram4Parts::of(shape) else {
                panic!("{shape:?}: a usual parallelogram left to the one-ray solver");
            };
            let solver = Parallelogram4::new(Some(avx2), shape, &parts).unwrap();
            let four = rays.map(|[o, d]| Ray::new(o, d));
            let found = solver.solve(&four, &t_max);
            assert_eq!(found.hit & found.rare, 0);
            // An any-hit query of some lanes: the one-ray hits with 0 < t < t_max, those lanes'.
            let lanes = random.random_range(1..16u32);
            let between = solver.solve_between(&four, lanes, &t_max);
            assert_eq!(between.rare, found.rare & lanes, "{i}");
            assert_eq!(between.hit & !(lanes & !between.rare), 0, "{i}");
            for lane in (0..4).filter(|lane| found.rare & (1 << lane) != 0) {
                assert_eq!(
                    solver.blocks_one(&four[lane], t_max[lane]),
                    None,
                    "{i} {lane}"
                );
            }
            for (lane, [origin, dir]) in rays.iter().enumerate() {
                if (lanes & !between.rare) & (1 << lane) == 0 {
                    continue;
                }
                let [t, ..] = one_at_a_time(shape, origin, dir, t_max[lane].next_down())
                    .unwrap_or([f64::NAN; 3]);
                let expected = t > 0.0;
                let got = between.hit & (1 << lane) != 0;
                assert_eq!(got, expected, "{i} {lane}: {shape:?} {origin:?} {dir:?}");
                between_hits += usize::from(got);
                // The same ray alone, in every lane.
                let alone = solver.blocks_one(&four[lane], t_max[lane]);
                assert_eq!(alone, Some(expected), "{i} {lane}: {origin:?} {dir:?}");
            }
            if scale == 1.0 {
                assert_eq!(found.rare & !unusual, 0, "{i}: {rays:?} left to one ray");
            }
            rare += found.rare.count_ones();
            for (lane, [origin, dir]) in rays.iter().enumerate() {
                if found.rare & (1 << lane) != 0 {
                    continue;
                }
                let expected = one_at_a_time(shape, origin, dir, t_max[lane]);
                let got = (found.hit & (1 << lane) != 0)
                    .then(|| [found.t[lane], found.alpha[lane], found.beta[lane]]);
                let bits = |v: Option<[f64; 3]>| v.map(|v| v.map(f64::to_bits));
                assert_eq!(
                    bits(got),
                    bits(expected),
                    "{i} {lane}: {shape:?} {origin:?} {dir:?}"
                );
                hits += got.is_some() as usize;
                culled += (expected.is_none()
                    && one_at_a_time(shape, origin, dir, f64::INFINITY).is_some())
                    as usize;
            }
        }
        assert!(
            hits > 8_000 && culled > 4_000 && rare > 30_000 && between_hits > 3_000,
            "{hits} {culled} {rare} {between_hits}"
        );
    }

    /// The plane's cull ([`out_of_reach`]) drops only rays the solver finds no hit for with
    /// 0 < t < t_end: random parallelograms turned every way, rays from just off their planes
    /// (10⁻¹⁴ to 1 along the normal, either side, over the parallelogram or beside it) going every
    /// way, some nearly along the plane, and t_end at, just before and just past the plane's t, or
    /// unlimited. Each lane of an any-hit query answers as the one-ray solver, and the cull must
    /// have dropped many lanes, on both of its grounds.
    #[test]
    fn the_plane_cull_drops_only_rays_the_solver_finds_no_hit_for() {
        let avx2 = crate::render::kernels::avx2_or_skip!();
        let mut random = rand_pcg::Pcg64::seed_from_u64(15);
        let mut unit = || random.random_range(-1.0..1.0);
        let (mut behind, mut beyond, mut hits) = (0, 0, 0);
        for i in 0..40_000 {
            let corner: V3<f64> = std::array::from_fn(|_| 3.0 * unit());
            let e1: V3<f64> = std::array::from_fn(|_| 2.0 * unit());
            let e2: V3<f64> = std::array::from_fn(|_| 2.0 * unit());
            let shape = [&corner, &e1, &e2];
            let Some(parts) = Parallelogram4Parts::of(shape) else {
                continue;
            };
            let solver = Parallelogram4::new(Some(avx2), shape, &parts).unwrap();
            let n = cross(&e1, &e2);
            let size = n.iter().map(|x| x * x).sum::<f64>().sqrt();
            let mut rays = [Ray::new([0.0; 3], [1.0, 0.0, 0.0]); 4];
            let mut t_end = [f64::INFINITY; 4];
            for lane in 0..4 {
                let (a, b) = (1.4 * unit() - 0.2, 1.4 * unit() - 0.2);
                let off = [1e-14, 1e-9, 1e-6, 1e-3, 1.0][(4 * i + lane) % 5] * unit();
                let origin: V3<f64> =
                    std::array::from_fn(|k| corner[k] + a * e1[k] + b * e2[k] + off * n[k] / size);
                let mut dir: V3<f64> = std::array::from_fn(|_| unit());
                if lane == 3 {
                    // Nearly along the plane.
                    let along: V3<f64> = std::array::from_fn(|k| e1[k] + 1e-12 * unit() * n[k]);
                    dir = along;
                }
                rays[lane] = Ray::new(origin, dir);
                // The plane's t, as the solver may find it (or not).
                let t = solve_inside(shape, &origin, &dir).map(|x| x.alpha_beta_t[2]);
                t_end[lane] = match (i + lane) % 4 {
                    0 => f64::INFINITY,
                    _ => t.map_or(1.0, |t| {
                        t.abs() * (1.0 + [0.0, 1e-15, -1e-15][(i + lane) % 3])
                    }),
                };
            }
            let lanes = 0b1111;
            // SAFETY: `avx2` proves the processor runs AVX2 and FMA.
            let dropped = unsafe {
                let (origin, dir) = (rays_lanes(&rays, 0), rays_lanes(&rays, 1));
                out_of_reach(&solver, &[origin, dir], gather(t_end))
            };
            let found = solver.solve_between(&rays, lanes, &t_end);
            for lane in 0..4 {
                let Ray { origin, dir, .. } = rays[lane];
                let expected = one_at_a_time(shape, &origin, &dir, t_end[lane].next_down())
                    .is_some_and(|[t, ..]| t > 0.0);
                if found.rare & (1 << lane) == 0 {
                    let got = found.hit & (1 << lane) != 0;
                    assert_eq!(got, expected, "{i} {lane}: {shape:?} {origin:?} {dir:?}");
                    hits += usize::from(got);
                }
                if dropped & (1 << lane) != 0 {
                    assert!(!expected && found.rare & (1 << lane) == 0, "{i} {lane}");
                    let towards: f64 = (0..3).map(|k| (origin[k] - corner[k]) * n[k]).sum();
                    let across: f64 = (0..3).map(|k| dir[k] * n[k]).sum();
                    match towards * across > 0.0 {
                        true => behind += 1,
                        false => beyond += 1,
                    }
                }
            }
        }
        assert!(
            behind > 50_000 && beyond > 10_000 && hits > 3_000,
            "{behind} {beyond} {hits}"
        );
    }

    /// A ray leaving a floor from a point on it (the solver's t exactly 0, or −0) is not blocked by
    /// it in an any-hit query, whose range is open at 0; the same ray from just above, going down,
    /// is.
    #[test]
    fn a_ray_leaving_a_floor_is_not_blocked_by_it() {
        let avx2 = crate::render::kernels::avx2_or_skip!();
        let shape = [[-3.0, -3.0, 0.0], [6.0, 0.0, 0.0], [0.0, 6.0, 0.0]];
        let [corner, e1, e2] = &shape;
        let parts = Parallelogram4Parts::of([corner, e1, e2]).unwrap();
        let solver = Parallelogram4::new(Some(avx2), [corner, e1, e2], &parts).unwrap();
        let mut random = rand_pcg::Pcg64::seed_from_u64(14);
        for i in 0..1_000 {
            let (x, y) = (
                random.random_range(-2.9..2.9),
                random.random_range(-2.9..2.9),
            );
            let dir = [
                random.random_range(-1.0..1.0),
                random.random_range(-1.0..1.0),
                0.5,
            ];
            let height = [0.0, 1e-9][i % 2];
            let rays = [
                Ray::new([x, y, 0.0], dir),
                Ray::new([x, y, 0.0], dir.map(|x| -x)),
                Ray::new([x, y, height], [0.0, 0.0, -1.0]),
                Ray::new([x, y, -height], [0.0, 0.0, 1.0]),
            ];
            let found = solver.solve_between(&rays, 0b1111, &[1.0; 4]);
            let expected = if height > 0.0 { 0b1100 } else { 0 };
            assert_eq!((found.hit, found.rare), (expected, 0), "{i}: {rays:?}");
        }
    }

    /// A parallelogram that may take the solver's rare paths whatever the ray (edges parallel or
    /// nearly so, a non-finite corner or edge, edges whose products overflow) is left to the one-ray
    /// solver; a usual one is not.
    #[test]
    fn unusual_parallelograms_are_left_to_one_ray() {
        let mut random = rand_pcg::Pcg64::seed_from_u64(13);
        for i in 0..1_000 {
            let [corner, e1, e2, ..] = random_ray_near_edges(&mut random, 1e-13);
            assert!(Parallelogram4Parts::of([&corner, &e1, &e2]).is_some());
            let unusual: [[V3<f64>; 3]; 5] = [
                [corner, e2.map(|x| x * 3.0), e2],
                [
                    corner,
                    std::array::from_fn(|k| 3.0 * e2[k] + 1e-16 * corner[k]),
                    e2,
                ],
                [[f64::NAN, 0.0, 0.0], e1, e2],
                [corner, e1.map(|x| x * f64::INFINITY), e2],
                [corner, e1.map(|x| x * 1e200), e2.map(|x| x * 1e200)],
            ];
            for [c, a, b] in unusual {
                assert!(
                    Parallelogram4Parts::of([&c, &a, &b]).is_none(),
                    "{i}: {c:?} {a:?} {b:?}"
                );
            }
        }
    }
}
