//! The crack-free test of [`crate::render::crack_free`] four lanes at once, with AVX2 on four f64
//! lanes: one ray and four triangles (a BVH leaf's, [`intersect4`]), or one triangle and four rays
//! of a packet whose sheared axes are the same ([`intersect_rays4`]), which takes fewer tests
//! where a packet's rays reach a leaf of one or two triangles together.
//!
//! Each lane does the one-triangle test's arithmetic in the same order, without fused multiply-adds,
//! so it gets the same numbers. Where all three edge functions are clear of their rounding bounds
//! their float signs are the exact signs, and the lane is decided here exactly as the one-triangle
//! test decides it; two clear edge functions of opposite signs are a miss whatever the third. Every
//! other lane (an edge function near zero, a zero determinant, a t that is not finite) is handed back
//! to be tested by [`ShearedRay::intersect`] itself. So the decisions, and the hits' numbers, are the
//! one-triangle test's to the bit.

// The kernels are x86-64 only: elsewhere (the web page) the one-ray paths serve.
#![cfg_attr(
    not(target_arch = "x86_64"),
    allow(dead_code, unused_imports, reason = "used by the x86-64 kernels only")
)]
// The AVX2 kernel: its unsafe blocks say in SAFETY comments why they are sound.
#![allow(unsafe_code)]

use super::Avx2;
use crate::math::linalg::V3;
use crate::render::TriangleHit;
use crate::render::crack_free::ShearedRay;

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

impl QuadHits {
    /// Lane `lane`'s hit as the one-triangle test gives it: β = V / det, γ = W / det, and t.
    #[inline(always)]
    pub fn hit(&self, lane: usize) -> TriangleHit {
        let det = self.det[lane];
        TriangleHit {
            beta: self.v[lane] / det,
            gamma: self.w[lane] / det,
            t: self.t[lane],
        }
    }
}

/// Four lanes of f64 (x86-64 only).
#[cfg(target_arch = "x86_64")]
type F4 = std::arch::x86_64::__m256d;

/// An edge function's lanes: its float value, the lanes where it is clear of its rounding bound,
/// and its two products.
#[cfg(target_arch = "x86_64")]
#[derive(Clone, Copy)]
struct Edge {
    value: F4,
    clear: F4,
    left: F4,
    right: F4,
}

/// The lanes' test, whichever way they were filled: each lane's vertices (`[vertex][axis]`, on the
/// axes that become x, y and z: `[[F4; 3]; 3]`), moved and sheared by its ray's `origin` and
/// `shear` (`[F4; 3]` each), then decided; a `QuadHits`. A macro, not a function, so that each
/// kernel has it inlined (as a function it was left out of line, and the any-hit walk lost 4%);
/// expanded in a function compiled with AVX2 and FMA.
#[cfg(target_arch = "x86_64")]
macro_rules! decide {
    ($origin:expr, $shear:expr, $vertices:expr, $t_min:expr, $lanes:expr) => {{
        use std::arch::x86_64::*;
        let (origin, shear, vertices, t_min, lanes): ([F4; 3], [F4; 3], [[F4; 3]; 3], f64, u32) =
            ($origin, $shear, $vertices, $t_min, $lanes);
        // As `ShearedRay::shear`: x' = (x − ox) − sx·z, y' = (y − oy) − sy·z, z' = sz·z with
        // z = z − oz.
        let sheared = |p: &[F4; 3]| {
            let z = _mm256_sub_pd(p[2], origin[2]);
            [
                _mm256_sub_pd(_mm256_sub_pd(p[0], origin[0]), _mm256_mul_pd(shear[0], z)),
                _mm256_sub_pd(_mm256_sub_pd(p[1], origin[1]), _mm256_mul_pd(shear[1], z)),
                _mm256_mul_pd(shear[2], z),
            ]
        };
        let (a, b, c) = (
            sheared(&vertices[0]),
            sheared(&vertices[1]),
            sheared(&vertices[2]),
        );
        let magnitude = |x: F4| _mm256_andnot_pd(_mm256_set1_pd(-0.0), x);
        // As `edge_sign_and_value`: P × Q, and whether it is clear of its rounding bound.
        let edge = |p: &[F4; 3], q: &[F4; 3]| {
            let left = _mm256_mul_pd(p[0], q[1]);
            let right = _mm256_mul_pd(p[1], q[0]);
            let value = _mm256_sub_pd(left, right);
            let sum = _mm256_add_pd(magnitude(left), magnitude(right));
            let bound = _mm256_mul_pd(_mm256_set1_pd(2.0 * f64::EPSILON), sum);
            let clear = _mm256_and_pd(
                _mm256_cmp_pd::<_CMP_GT_OQ>(magnitude(value), bound),
                _mm256_cmp_pd::<_CMP_GT_OQ>(sum, _mm256_set1_pd(crate::render::crack_free::TINY)),
            );
            Edge {
                value,
                clear,
                left,
                right,
            }
        };
        let edges = [edge(&c, &b), edge(&a, &c), edge(&b, &a)];
        let all_clear = _mm256_and_pd(
            _mm256_and_pd(edges[0].clear, edges[1].clear),
            edges[2].clear,
        );
        if (_mm256_movemask_pd(all_clear) as u32 & lanes) != lanes {
            // SAFETY: this function is compiled with AVX2 and FMA and runs only where they are.
            return unsafe { settle_exactly(&[a, b, c], &edges, t_min, lanes) };
        }
        // Every edge function clear of its bound: its float sign is its exact sign.
        let zero = _mm256_setzero_pd();
        let positive = |e: &Edge| _mm256_cmp_pd::<_CMP_GT_OQ>(e.value, zero);
        let negative = |e: &Edge| _mm256_cmp_pd::<_CMP_LT_OQ>(e.value, zero);
        let all_pos = _mm256_and_pd(
            _mm256_and_pd(positive(&edges[0]), positive(&edges[1])),
            positive(&edges[2]),
        );
        let all_neg = _mm256_and_pd(
            _mm256_and_pd(negative(&edges[0]), negative(&edges[1])),
            negative(&edges[2]),
        );
        let inside = _mm256_or_pd(all_pos, all_neg);
        // SAFETY: as above.
        unsafe {
            finish(
                &[a, b, c],
                &edges,
                inside,
                _mm256_xor_pd(inside, all_clear),
                t_min,
                lanes,
            )
        }
    }};
}

/// Tests the lanes in `lanes` (a bit each) of `quad` against `ray`.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
pub fn intersect4(_: Avx2, ray: &ShearedRay, quad: &Quad, t_min: f64, lanes: u32) -> QuadHits {
    // SAFETY: an `Avx2` exists only on a processor with AVX2 and FMA.
    unsafe { intersect4_unchecked(ray, quad, t_min, lanes) }
}

/// [`intersect4`] without the proof.
///
/// # Safety
/// Only call on a processor with AVX2 and FMA (the function is compiled for them).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,popcnt,bmi1")]
#[inline]
unsafe fn intersect4_unchecked(ray: &ShearedRay, quad: &Quad, t_min: f64, lanes: u32) -> QuadHits {
    use std::arch::x86_64::*;
    let (origin, [kx, ky, kz], [sx, sy, sz]) = ray.parts();
    let origin = [
        _mm256_set1_pd(origin[kx]),
        _mm256_set1_pd(origin[ky]),
        _mm256_set1_pd(origin[kz]),
    ];
    // Each broadcast from its own f64. (Read as copies, sy and sz were loaded as one 16-byte
    // pair, which waited on the two 8-byte stores of a sheared ray made just before: 2% of a
    // shadow ray's time.)
    let shear = [sx, sy, sz].map(|s| _mm256_broadcast_sd(s));
    // Written out, not mapped over arrays: the closures were left uninlined.
    // SAFETY: each row is four f64s in a 32-byte aligned struct.
    let load =
        |vertex: usize, axis: usize| unsafe { _mm256_load_pd(quad.v[vertex][axis].as_ptr()) };
    let vertex = |v: usize| [load(v, kx), load(v, ky), load(v, kz)];
    let vertices = [vertex(0), vertex(1), vertex(2)];
    decide!(origin, shear, vertices, t_min, lanes)
}

/// Four rays' sheared forms as lanes, for one triangle tested against them together
/// ([`intersect_rays4`]): rays whose sheared axes are the same (a packet's neighbours).
#[derive(Clone, Copy, Debug, Default)]
#[repr(C, align(32))]
pub struct RayQuad {
    /// Per lane, the origin's coordinates on the axes that become x, y and z.
    origin: [[f64; 4]; 3],
    /// Per lane, the shear constants sx, sy, sz.
    shear: [[f64; 4]; 3],
}

impl RayQuad {
    /// Sets four rays' lanes: their origins' and shears' rows (x, y, z on each ray's sheared
    /// axes).
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    pub fn store(&mut self, origin: [F4; 3], shear: [F4; 3]) {
        use std::arch::x86_64::*;
        // SAFETY: each row is four f64s in a 32-byte aligned struct.
        unsafe {
            for (row, lanes) in self.origin.iter_mut().zip(origin) {
                _mm256_store_pd(row.as_mut_ptr(), lanes);
            }
            for (row, lanes) in self.shear.iter_mut().zip(shear) {
                _mm256_store_pd(row.as_mut_ptr(), lanes);
            }
        }
    }

    /// Lane `lane`'s origin on its ray's sheared axes (for tests).
    #[cfg(test)]
    pub fn origin_lane(&self, lane: usize) -> [f64; 3] {
        self.origin.map(|row| row[lane])
    }

    /// Lane `lane`'s shear constants (for tests).
    #[cfg(test)]
    pub fn shear_lane(&self, lane: usize) -> [f64; 3] {
        self.shear.map(|row| row[lane])
    }

    /// Puts `ray` in `lane`.
    #[inline(always)]
    pub fn set(&mut self, lane: usize, ray: &ShearedRay) {
        let (origin, [kx, ky, kz], shear) = ray.parts();
        for (row, o) in self
            .origin
            .iter_mut()
            .zip([origin[kx], origin[ky], origin[kz]])
        {
            row[lane] = o;
        }
        for (row, s) in self.shear.iter_mut().zip(shear) {
            row[lane] = *s;
        }
    }
}

/// Up to sixteen rays of a packet whose sheared axes are the same, four to a [`RayQuad`] (ray r in
/// lane r % 4 of quad r / 4): what [`intersect_rays4`] takes for a leaf's triangles.
#[derive(Clone, Debug, Default)]
pub struct RaysTogether {
    /// The axes that become x, y and z for every ray put in.
    pub axes: [usize; 3],
    /// The rays put in, a bit each.
    pub rays: u32,
    pub quads: [RayQuad; 4],
}

impl RaysTogether {
    /// Puts ray `r` (below sixteen) in its lane when its axes are those of the first ray put in.
    #[inline(always)]
    pub fn offer(&mut self, r: usize, ray: &ShearedRay) {
        let axes = ray.parts().1;
        if self.rays == 0 {
            self.axes = axes;
        }
        if key(axes) == key(self.axes) {
            self.rays |= 1 << r;
            self.quads[r / 4].set(r % 4, ray);
        }
    }

    /// Puts in the rays of `lanes` (a bit each, below four) of quarter `quarter` (rays 4q to
    /// 4q + 3) whose `axes` are those of the first ray put in, their lanes already written in
    /// the quarter's quad ([`RayQuad::store`]).
    #[inline(always)]
    pub fn take_quarter(&mut self, quarter: usize, axes: &[[usize; 3]; 4], lanes: u32) {
        let mut each = lanes;
        while each != 0 {
            let lane = each.trailing_zeros() as usize;
            each &= each - 1;
            if self.rays == 0 {
                self.axes = axes[lane];
            }
            if key(axes[lane]) == key(self.axes) {
                self.rays |= 1 << (4 * quarter + lane);
            }
        }
    }
}

/// Sheared axes as one number, compared axis by axis: compared as arrays, axes just stored one
/// by one were read back as one wide load, which waited for the stores (5% of a packet of glass
/// rays' time).
#[inline(always)]
fn key([x, y, z]: [usize; 3]) -> usize {
    x | y << 2 | z << 4
}

/// Tests triangle `triangle` of `quad` against the rays of `rays` in `lanes` (a bit each), whose
/// sheared axes are all `axes`: each lane decides as [`ShearedRay::intersect`] would for its ray,
/// with the same arithmetic as [`intersect4`]'s lanes.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
pub fn intersect_rays4(
    _: Avx2,
    (axes, rays): ([usize; 3], &RayQuad),
    (quad, triangle): (&Quad, usize),
    t_min: f64,
    lanes: u32,
) -> QuadHits {
    // SAFETY: an `Avx2` exists only on a processor with AVX2 and FMA.
    unsafe { intersect_rays4_unchecked(axes, rays, (quad, triangle), t_min, lanes) }
}

/// [`intersect_rays4`] without the proof.
///
/// # Safety
/// Only call on a processor with AVX2 and FMA (the function is compiled for them).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,popcnt,bmi1")]
#[inline]
unsafe fn intersect_rays4_unchecked(
    [kx, ky, kz]: [usize; 3],
    rays: &RayQuad,
    (quad, triangle): (&Quad, usize),
    t_min: f64,
    lanes: u32,
) -> QuadHits {
    use std::arch::x86_64::*;
    // Written out, not mapped over arrays: the closures were left uninlined.
    // SAFETY: each row is four f64s in a 32-byte aligned struct.
    let load = |row: &[f64; 4]| unsafe { _mm256_load_pd(row.as_ptr()) };
    let origin = [
        load(&rays.origin[0]),
        load(&rays.origin[1]),
        load(&rays.origin[2]),
    ];
    let shear = [
        load(&rays.shear[0]),
        load(&rays.shear[1]),
        load(&rays.shear[2]),
    ];
    let lane = triangle % 4;
    let broadcast = |vertex: usize, axis: usize| _mm256_set1_pd(quad.v[vertex][axis][lane]);
    let vertex = |v: usize| [broadcast(v, kx), broadcast(v, ky), broadcast(v, kz)];
    let vertices = [vertex(0), vertex(1), vertex(2)];
    decide!(origin, shear, vertices, t_min, lanes)
}

/// The hits of the lanes found `inside`; lanes neither inside nor `missed`, and inside lanes whose
/// t the division does not give (a zero determinant, a t that is not finite), go back to the
/// one-triangle test.
///
/// # Safety
/// Only call on a processor with AVX2 and FMA.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,popcnt,bmi1")]
#[inline]
unsafe fn finish(
    [a, b, c]: &[[F4; 3]; 3],
    edges: &[Edge; 3],
    inside: F4,
    missed: F4,
    t_min: f64,
    lanes: u32,
) -> QuadHits {
    use std::arch::x86_64::*;
    let (u, v, w) = (edges[0].value, edges[1].value, edges[2].value);
    // As the one-triangle test: det = U + V + W, t = (U·Az + V·Bz + W·Cz) / det.
    let det = _mm256_add_pd(_mm256_add_pd(u, v), w);
    let scaled_t = _mm256_add_pd(
        _mm256_add_pd(_mm256_mul_pd(u, a[2]), _mm256_mul_pd(v, b[2])),
        _mm256_mul_pd(w, c[2]),
    );
    let t = _mm256_div_pd(scaled_t, det);
    let magnitude = _mm256_andnot_pd(_mm256_set1_pd(-0.0), t);
    let usable = _mm256_and_pd(
        _mm256_cmp_pd::<_CMP_NEQ_OQ>(det, _mm256_setzero_pd()),
        _mm256_cmp_pd::<_CMP_LT_OQ>(magnitude, _mm256_set1_pd(f64::INFINITY)),
    );
    let decided = _mm256_and_pd(inside, usable);
    let hit = _mm256_and_pd(
        decided,
        _mm256_cmp_pd::<_CMP_GT_OQ>(t, _mm256_set1_pd(t_min)),
    );
    let hit = _mm256_movemask_pd(hit) as u32 & lanes;
    let settled = _mm256_movemask_pd(_mm256_or_pd(decided, missed)) as u32;
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

/// The lanes where an edge function is within its rounding bound of zero: its exact sign, then
/// the one-triangle test's decision: one sign only, and each zero edge counted by the tie rule.
/// The exact signs come from the float values where those are exact ([`settle_float_exact`]: on
/// the grid box, 99% of the quads, at 174 instructions a quad against 288), else from the
/// error-free expansion of `exact_cross_sign` ([`settle_by_expansion`]). Out of line: most rays
/// graze no edge.
///
/// # Safety
/// Only call on a processor with AVX2 and FMA.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,popcnt,bmi1")]
#[inline(never)]
unsafe fn settle_exactly(
    vertices: &[[F4; 3]; 3],
    edges: &[Edge; 3],
    t_min: f64,
    lanes: u32,
) -> QuadHits {
    // SAFETY: these functions are compiled with AVX2 and FMA and run only where they are.
    unsafe {
        settle_float_exact(vertices, edges, t_min, lanes)
            .unwrap_or_else(|| settle_by_expansion(vertices, edges, t_min, lanes))
    }
}

/// [`settle_exactly`] for lanes whose float values are not all exact: each such edge function's
/// sign by the error-free expansion, where its products fit (other lanes go back to the
/// one-triangle test). Out of line, so that the common path keeps its registers (inlined, the
/// short path spilled two dozen registers to the stack for it).
///
/// # Safety
/// Only call on a processor with AVX2 and FMA.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,popcnt,bmi1")]
#[inline(never)]
unsafe fn settle_by_expansion(
    vertices: &[[F4; 3]; 3],
    edges: &[Edge; 3],
    t_min: f64,
    lanes: u32,
) -> QuadHits {
    use std::arch::x86_64::*;
    #[cfg(test)]
    tests::EXPANSIONS.with(|n| n.set(n.get() + 1));
    let [a, b, c] = vertices;
    let zero = _mm256_setzero_pd();
    let magnitude = |x: F4| _mm256_andnot_pd(_mm256_set1_pd(-0.0), x);
    let finite = |x: F4| _mm256_cmp_pd::<_CMP_LT_OQ>(magnitude(x), _mm256_set1_pd(f64::INFINITY));
    let is_zero = |x: F4| _mm256_cmp_pd::<_CMP_EQ_OQ>(x, zero);
    let above = |x: F4| _mm256_cmp_pd::<_CMP_GT_OQ>(x, zero);
    let below = |x: F4| _mm256_cmp_pd::<_CMP_LT_OQ>(x, zero);
    let (and, or) = (
        |x: F4, y: F4| _mm256_and_pd(x, y),
        |x: F4, y: F4| _mm256_or_pd(x, y),
    );
    // Knuth's two-sum: s + e = x + y exactly.
    let two_sum = |x: F4, y: F4| {
        let s = _mm256_add_pd(x, y);
        let yv = _mm256_sub_pd(s, x);
        let xv = _mm256_sub_pd(s, yv);
        (s, _mm256_add_pd(_mm256_sub_pd(x, xv), _mm256_sub_pd(y, yv)))
    };
    // (a1 + a0) − b as three nonoverlapping terms, largest first.
    let two_one_diff = |a1: F4, a0: F4, b: F4| {
        let (i, x0) = two_sum(a0, _mm256_xor_pd(b, _mm256_set1_pd(-0.0)));
        let (x2, x1) = two_sum(a1, i);
        (x2, x1, x0)
    };
    // Masks of the lanes where P × Q's exact sign is positive, negative, and known.
    let signs = |e: &Edge, p: &[F4; 3], q: &[F4; 3]| {
        let tiny = _mm256_set1_pd(crate::render::crack_free::TINY);
        // a·b = left + le and c·d = right + re exactly, where the products fit.
        let le = _mm256_fmsub_pd(p[0], q[1], e.left);
        let re = _mm256_fmsub_pd(p[1], q[0], e.right);
        let fits = |x: F4, y: F4, product: F4| {
            or(
                or(is_zero(x), is_zero(y)),
                and(
                    _mm256_cmp_pd::<_CMP_GT_OQ>(magnitude(product), tiny),
                    finite(product),
                ),
            )
        };
        let operands = and(
            and(finite(p[0]), finite(q[1])),
            and(finite(p[1]), finite(q[0])),
        );
        let fit = and(
            operands,
            and(fits(p[0], q[1], e.left), fits(p[1], q[0], e.right)),
        );
        // Where the products' errors are equal the exact value is left − right, whose rounded
        // difference has its sign: the float value's sign is exact. On rays through the grid
        // box's vertices nearly every edge function near zero is such a one.
        let float_exact = or(e.clear, and(fit, _mm256_cmp_pd::<_CMP_EQ_OQ>(le, re)));
        let sign_of = if _mm256_movemask_pd(float_exact) as u32 & lanes == lanes {
            e.value
        } else {
            // (left + le) − (right + re) as four nonoverlapping terms, largest first; its sign is
            // its largest nonzero term's.
            let (j, k, x0) = two_one_diff(e.left, le, re);
            let (x3, x2, x1) = two_one_diff(j, k, e.right);
            let lead = _mm256_blendv_pd(
                x3,
                _mm256_blendv_pd(x2, _mm256_blendv_pd(x1, x0, is_zero(x1)), is_zero(x2)),
                is_zero(x3),
            );
            _mm256_blendv_pd(lead, e.value, float_exact)
        };
        let known = or(e.clear, fit);
        (
            and(known, above(sign_of)),
            and(known, below(sign_of)),
            known,
        )
    };
    let (u_pos, u_neg, u_known) = signs(&edges[0], c, b);
    let (v_pos, v_neg, v_known) = signs(&edges[1], a, c);
    let (w_pos, w_neg, w_known) = signs(&edges[2], b, a);
    let any_pos = or(or(u_pos, v_pos), w_pos);
    let any_neg = or(or(u_neg, v_neg), w_neg);
    // Two exact signs that differ: a miss whatever the third.
    let outside = and(any_pos, any_neg);
    let known = and(and(u_known, v_known), w_known);
    let one_sign = _mm256_xor_pd(any_pos, any_neg);
    // A zero edge counts only when its perturbed sign (−sign Δy, or sign Δx where Δy = 0) is the
    // triangle's orientation.
    let tie_ok = |positive: F4, negative: F4, p: &[F4; 3], q: &[F4; 3]| {
        let zero_edge = _mm256_andnot_pd(or(positive, negative), known);
        let dx = _mm256_sub_pd(q[0], p[0]);
        let dy = _mm256_sub_pd(q[1], p[1]);
        let dy_zero = is_zero(dy);
        let perturbed_pos = _mm256_blendv_pd(below(dy), above(dx), dy_zero);
        let perturbed_neg = _mm256_blendv_pd(above(dy), below(dx), dy_zero);
        let agrees = or(and(any_pos, perturbed_pos), and(any_neg, perturbed_neg));
        or(_mm256_andnot_pd(zero_edge, known), agrees)
    };
    let ties = and(
        and(tie_ok(u_pos, u_neg, c, b), tie_ok(v_pos, v_neg, a, c)),
        tie_ok(w_pos, w_neg, b, a),
    );
    let inside = and(and(known, one_sign), ties);
    let missed = or(outside, _mm256_andnot_pd(and(one_sign, ties), known));
    // SAFETY: this function is compiled with AVX2 and FMA and runs only where they are.
    unsafe { finish(vertices, edges, inside, missed, t_min, lanes) }
}

/// The least nonzero size of a sheared coordinate whose products [`settle_float_exact`] takes as
/// exact: 2⁻⁴⁶⁰ (a power of two 2ᵉ is its biased exponent, 1023 + e, shifted into place).
const SMALLEST: f64 = f64::from_bits((1023 - 460) << 52);
/// The greatest: 2⁵⁰⁰.
const LARGEST: f64 = f64::from_bits((1023 + 500) << 52);
// A product of two coordinates in the range is above `TINY`, and finite.
const _: () = assert!(SMALLEST * SMALLEST > crate::render::crack_free::TINY);
const _: () = assert!(LARGEST * LARGEST < f64::MAX);

/// [`settle_exactly`] where every edge function of every lane has its exact sign in its float
/// value: each is clear of its rounding bound, or its two products are exact as `left + le` and
/// `right + re` with `le = re` (so the exact value is `left − right`, whose rounded difference has
/// its sign). The products are exact where every sheared x and y is zero or between 2⁻⁴⁶⁰ and
/// 2⁵⁰⁰: a nonzero product then lies between 2⁻⁹²⁰ (above `TINY`) and 2¹⁰⁰⁰, as
/// `exact_cross_sign` asks. Rays through the grid box's vertices end here nearly always, at
/// 60% of the full settling's work; `None` sends the lanes to the full settling.
///
/// # Safety
/// Only call on a processor with AVX2 and FMA.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,popcnt,bmi1")]
#[inline]
unsafe fn settle_float_exact(
    vertices: &[[F4; 3]; 3],
    edges: &[Edge; 3],
    t_min: f64,
    lanes: u32,
) -> Option<QuadHits> {
    use std::arch::x86_64::*;
    let [a, b, c] = vertices;
    let zero = _mm256_setzero_pd();
    let (and, or) = (
        |x: F4, y: F4| _mm256_and_pd(x, y),
        |x: F4, y: F4| _mm256_or_pd(x, y),
    );
    // Zero, or SMALLEST ≤ |x| ≤ LARGEST (false for NaN).
    let in_range = |x: F4| {
        let size = _mm256_andnot_pd(_mm256_set1_pd(-0.0), x);
        or(
            and(
                _mm256_cmp_pd::<_CMP_GE_OQ>(size, _mm256_set1_pd(SMALLEST)),
                _mm256_cmp_pd::<_CMP_LE_OQ>(size, _mm256_set1_pd(LARGEST)),
            ),
            _mm256_cmp_pd::<_CMP_EQ_OQ>(x, zero),
        )
    };
    let fit = and(
        and(and(in_range(a[0]), in_range(a[1])), in_range(b[0])),
        and(and(in_range(b[1]), in_range(c[0])), in_range(c[1])),
    );
    let exact = |e: &Edge, p: &[F4; 3], q: &[F4; 3]| {
        let le = _mm256_fmsub_pd(p[0], q[1], e.left);
        let re = _mm256_fmsub_pd(p[1], q[0], e.right);
        or(e.clear, _mm256_cmp_pd::<_CMP_EQ_OQ>(le, re))
    };
    let all = and(
        and(fit, exact(&edges[0], c, b)),
        and(exact(&edges[1], a, c), exact(&edges[2], b, a)),
    );
    if _mm256_movemask_pd(all) as u32 & lanes != lanes {
        return None;
    }
    let above = |x: F4| _mm256_cmp_pd::<_CMP_GT_OQ>(x, zero);
    let below = |x: F4| _mm256_cmp_pd::<_CMP_LT_OQ>(x, zero);
    let (u, v, w) = (edges[0].value, edges[1].value, edges[2].value);
    let any_pos = or(or(above(u), above(v)), above(w));
    let any_neg = or(or(below(u), below(v)), below(w));
    let one_sign = _mm256_xor_pd(any_pos, any_neg);
    // As the full settling's tie rule: a zero edge counts only when its perturbed sign is the
    // triangle's orientation. Written again here, with every sign known: one function for both
    // (tried) spilled registers on this path, and the box's packets took 16% longer.
    let tie_ok = |value: F4, p: &[F4; 3], q: &[F4; 3]| {
        let dx = _mm256_sub_pd(q[0], p[0]);
        let dy = _mm256_sub_pd(q[1], p[1]);
        let dy_zero = _mm256_cmp_pd::<_CMP_EQ_OQ>(dy, zero);
        let perturbed_pos = _mm256_blendv_pd(below(dy), above(dx), dy_zero);
        let perturbed_neg = _mm256_blendv_pd(above(dy), below(dx), dy_zero);
        let agrees = or(and(any_pos, perturbed_pos), and(any_neg, perturbed_neg));
        or(_mm256_cmp_pd::<_CMP_NEQ_OQ>(value, zero), agrees)
    };
    let ties = and(and(tie_ok(u, c, b), tie_ok(v, a, c)), tie_ok(w, b, a));
    let inside = and(one_sign, ties);
    let missed = _mm256_xor_pd(inside, _mm256_castsi256_pd(_mm256_set1_epi64x(-1)));
    // SAFETY: this function is compiled with AVX2 and FMA and runs only where they are.
    Some(unsafe { finish(vertices, edges, inside, missed, t_min, lanes) })
}

#[cfg(all(test, target_arch = "x86_64"))]
mod tests {
    use super::*;
    use crate::render::camera_ray;
    use crate::render::generate::grid_box;

    #[test]
    fn the_short_paths_range_is_two_to_the_minus_460_and_500() {
        assert_eq!(SMALLEST, 2f64.powi(-460));
        assert_eq!(LARGEST, 2f64.powi(500));
    }

    thread_local! {
        /// How many quads this thread's tests sent to [`settle_by_expansion`].
        pub(super) static EXPANSIONS: std::cell::Cell<usize> = const { std::cell::Cell::new(0) };
    }

    /// Where the float values are not exact (rays aimed at an edge, whose products round), or the
    /// coordinates are outside the short path's range (scaled by 2⁻⁵⁴⁰ and 2⁵²⁰), the lanes are
    /// settled by the expansion, and decide as the one-triangle test does. Fans of four random
    /// triangles around a shared edge, each ray aimed at the edge's midpoint from a random origin.
    #[test]
    fn lanes_whose_floats_are_not_exact_are_settled_by_the_expansion() {
        use rand::{Rng, SeedableRng};
        let avx2 = crate::render::kernels::avx2_or_skip!();
        let mut random = rand_pcg::Pcg64::seed_from_u64(25);
        let mut point =
            |r: f64| -> [f64; 3] { std::array::from_fn(|_| random.random_range(-r..r)) };
        let (mut settled, mut hits) = (0, 0);
        let mut expansions = Vec::new();
        for scale in [1.0, 2f64.powi(-540), 2f64.powi(520)] {
            let before = EXPANSIONS.with(std::cell::Cell::get);
            for _ in 0..400 {
                let shared = point(1.0);
                let other = point(1.0);
                let fan: Vec<[[f64; 3]; 3]> = (0..4)
                    .map(|_| [shared, other, point(1.0)])
                    .map(|t| t.map(|v| v.map(|x| x * scale)))
                    .collect();
                let origin = point(4.0).map(|x| x * scale);
                // A point of the fan's shared edge, rounded: off the edge by a rounding.
                let aim: [f64; 3] = std::array::from_fn(|k| (fan[0][0][k] + fan[0][1][k]) / 2.0);
                let dir: [f64; 3] = std::array::from_fn(|k| aim[k] - origin[k]);
                let Some(ray) = ShearedRay::new(&origin, &dir) else {
                    continue;
                };
                let found = intersect4(avx2, &ray, &Quad::new(&fan), 0.0, 0b1111);
                for (lane, triangle) in fan.iter().enumerate() {
                    if found.again & (1 << lane) != 0 {
                        continue;
                    }
                    settled += 1;
                    let got = (found.hit & (1 << lane) != 0)
                        .then(|| found.hit(lane))
                        .map(|h| [h.beta, h.gamma, h.t].map(f64::to_bits));
                    let expected = ray
                        .intersect(triangle, 0.0)
                        .map(|h| [h.beta, h.gamma, h.t].map(f64::to_bits));
                    assert_eq!(got, expected, "scale {scale:e}, lane {lane}");
                    hits += usize::from(got.is_some());
                }
            }
            expansions.push(EXPANSIONS.with(std::cell::Cell::get) - before);
        }
        // Unscaled, some quads take the short path and some the expansion; scaled, every quad
        // takes the expansion (which hands its lanes back: their products do not fit).
        assert!(
            (100..300).contains(&expansions[0]) && expansions[1..] == [400, 400],
            "{expansions:?}"
        );
        assert!(settled >= 1500 && hits > 500, "{settled} {hits}");
    }

    /// Four at a time decides every lane it settles as the one-triangle test does, to the bit, on
    /// the grid box whose every camera ray runs along an edge or through a vertex (the exact signs
    /// and the tie rule), and on rays nudged off the grid (clear signs).
    #[test]
    fn four_at_a_time_decides_as_one_at_a_time() {
        let avx2 = crate::render::kernels::avx2_or_skip!();
        let (camera, side, triangles) = grid_box(6);
        let (mut settled, mut hits) = (0, 0);
        for row in 0..side {
            for column in 0..side {
                let crate::render::Ray { origin, dir } =
                    camera_ray(&camera, side, side, row, column);
                for nudge in [0.0, 1e-3] {
                    let dir = [dir[0] + nudge, dir[1], dir[2] - nudge];
                    let Some(ray) = ShearedRay::new(&origin, &dir) else {
                        continue;
                    };
                    for group in triangles.chunks(4) {
                        let lanes = (1u32 << group.len()) - 1;
                        let found = intersect4(avx2, &ray, &Quad::new(group), 0.0, lanes);
                        for (lane, triangle) in group.iter().enumerate() {
                            if found.again & (1 << lane) != 0 {
                                continue;
                            }
                            settled += 1;
                            let got = (found.hit & (1 << lane) != 0)
                                .then(|| found.hit(lane))
                                .map(|h| [h.beta, h.gamma, h.t]);
                            let expected =
                                ray.intersect(triangle, 0.0).map(|h| [h.beta, h.gamma, h.t]);
                            let bits = |v: Option<[f64; 3]>| v.map(|v| v.map(f64::to_bits));
                            assert_eq!(bits(got), bits(expected), "({row}, {column}) {lane}");
                            hits += got.is_some() as usize;
                        }
                    }
                }
            }
        }
        assert!(settled > 50_000 && hits > 300, "{settled} {hits}");
    }

    /// One triangle against four rays decides every lane it settles as the one-triangle test does,
    /// to the bit, on the same grid box and nudged rays: neighbouring camera rays, four to a
    /// group, with their sheared axes the same.
    #[test]
    fn four_rays_at_a_time_decide_as_one_at_a_time() {
        let avx2 = crate::render::kernels::avx2_or_skip!();
        let (camera, side, triangles) = grid_box(6);
        let quads: Vec<Quad> = triangles.chunks(4).map(Quad::new).collect();
        let (mut settled, mut hits, mut exact) = (0, 0, 0);
        for nudge in [0.0, 1e-3] {
            let rays: Vec<ShearedRay> = (0..side * side)
                .filter_map(|pixel| {
                    let ray = camera_ray(&camera, side, side, pixel / side, pixel % side);
                    let dir = [ray.dir[0] + nudge, ray.dir[1], ray.dir[2] - nudge];
                    ShearedRay::new(&ray.origin, &dir)
                })
                .collect();
            for group in rays.chunks(4) {
                let axes = group[0].parts().1;
                let mut lanes = RayQuad::default();
                let mut taking = 0;
                for (lane, ray) in group.iter().enumerate() {
                    if ray.parts().1 == axes {
                        lanes.set(lane, ray);
                        taking |= 1 << lane;
                    }
                }
                for (slot, triangle) in triangles.iter().enumerate() {
                    let quad = (&quads[slot / 4], slot % 4);
                    let found = intersect_rays4(avx2, (axes, &lanes), quad, 0.0, taking);
                    for (lane, ray) in group.iter().enumerate() {
                        if taking & (1 << lane) == 0 {
                            continue;
                        }
                        if found.again & (1 << lane) != 0 {
                            exact += 1;
                            continue;
                        }
                        settled += 1;
                        let got = (found.hit & (1 << lane) != 0)
                            .then(|| found.hit(lane))
                            .map(|h| [h.beta, h.gamma, h.t]);
                        let expected = ray.intersect(triangle, 0.0).map(|h| [h.beta, h.gamma, h.t]);
                        let bits = |v: Option<[f64; 3]>| v.map(|v| v.map(f64::to_bits));
                        assert_eq!(bits(got), bits(expected), "ray {lane} of a group, {slot}");
                        hits += got.is_some() as usize;
                    }
                }
            }
        }
        assert!(settled > 50_000 && hits > 300, "{settled} {hits} {exact}");
    }
}
