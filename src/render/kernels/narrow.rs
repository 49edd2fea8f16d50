//! The packet traversal's fast path: sixteen neighbouring rays traverse together, each child box
//! tested against eight rays at once in f32 with AVX2 (SIMD across rays). A leaf is tested with the
//! crack-free test four lanes at a time, whichever way takes fewer tests: each triangle against four
//! rays (the rays sharing their sheared axes), or each ray against four triangles. The hits are
//! the same as the one-ray traversal's: the box test only culls, and it is conservative, and each
//! lane of the leaf test decides as the one-triangle test does. One ray's any-hit walk
//! ([`occluded_one_ray`]) takes the same f32 test across the eight boxes of the hierarchy's 8-wide
//! nodes ([`crate::render::bvh::eight`]) instead of across rays, each lane's numbers made as a
//! packet's lane's are, so the same bound holds.
//!
//! **Why no hit is lost.** A slab distance (box − o)/d is computed as box·(1/d) − o/d, one fused
//! multiply-add from 1/d and o/d rounded to f32. Rounding 1/d and o/d (through f64) and the result
//! each err by at most 2⁻²⁴(1 + 2⁻²⁸) relative, so with |box/d| ≤ |t| + |o/d| the computed t is
//! within 2⁻²²·⁹(|t| + |o/d|) + 2⁻¹⁴⁰ of the exact one. The entry distance (a maximum over the axes
//! and 0) is lowered by [`RELATIVE`]·|t| and the ray's slack (the largest over its axes of
//! 2⁻²¹·|o/d| + 2⁻¹²⁰, rounded up); the exit distance (a minimum, with the ray's t_max rounded up)
//! is raised by as much; the margin left over covers the rounding of the widening itself. A ray
//! takes this path only when, on every axis, 2⁻⁶⁰ ≤ |1/d| ≤ 2⁶⁰ and |o/d| ≤ 2¹⁰⁰, and the
//! hierarchy only when its boxes are within [`BOX_LIMIT`] (2⁶²): every product stays below 2¹²⁷, no
//! f32 is subnormal where it matters, nothing overflows or is NaN. Other packets take the one-ray
//! box test.

// The kernels are x86-64 only: elsewhere (the web page) the one-ray paths serve.
#![cfg_attr(
    not(target_arch = "x86_64"),
    allow(dead_code, unused_imports, reason = "used by the x86-64 kernels only")
)]
// The AVX2 kernel: each unsafe block says in a SAFETY comment why it is sound.
#![allow(unsafe_code)]

use std::mem::MaybeUninit;

use super::Avx2;
use crate::render::Ray;
use crate::render::bvh::climb::lanes_holding;
use crate::render::bvh::eight::{NO_PARENT, Node8};
use crate::render::bvh::traverse::{Met, Query, children};
use crate::render::bvh::{Bvh, EMPTY, Nearest, Node, WideNode, close_found};
use crate::render::crack_free::ShearedRay;
use crate::render::kernels::crack_free4::{RayQuad, RaysTogether};

/// Rays in a packet: two groups of eight f32 lanes.
pub const RAYS: usize = 16;
/// Box coordinates up to this magnitude (2⁶²) allow the f32 test.
pub const BOX_LIMIT: f64 = 4.611_686_018_427_388e18;
/// The relative widening of the distances, 2⁻¹⁹.
const RELATIVE: f32 = 1.0 / 524_288.0;

/// The packet's rays as f32 lanes (lane r is ray r).
#[repr(C, align(64))]
struct Lanes {
    /// 1/d per axis (its sign bit also picks each slab's entry face).
    inverse: [[f32; RAYS]; 3],
    /// o/d per axis.
    offset: [[f32; RAYS]; 3],
    /// The largest slack over the axes.
    slack: [f32; RAYS],
    /// t_max rounded up.
    t_max: [f32; RAYS],
    /// −1 where d is zero on the axis (the ray is parallel to its slabs), else 0; 1/d and o/d
    /// are then 0, and the slab is (−∞, ∞) when o is between its faces, else empty.
    parallel: [[f32; RAYS]; 3],
    /// o rounded down and up to f32 (below and above o), for the parallel axes.
    origin_down: [[f32; RAYS]; 3],
    origin_up: [[f32; RAYS]; 3],
    /// Per axis, whether any ray is parallel to it.
    any_parallel: [bool; 3],
}

/// A non-negative f64 rounded up to f32 (or above): nearest, raised by 2⁻²⁰ relative and 10⁻³⁷.
#[inline(always)]
fn up(x: f64) -> f32 {
    (x as f32) * (1.0 + 1.0 / 1_048_576.0) + 1e-37
}

impl Lanes {
    /// Every lane zero.
    const ZERO: Lanes = Lanes {
        inverse: [[0.0; RAYS]; 3],
        offset: [[0.0; RAYS]; 3],
        slack: [0.0; RAYS],
        t_max: [0.0; RAYS],
        parallel: [[0.0; RAYS]; 3],
        origin_down: [[0.0; RAYS]; 3],
        origin_up: [[0.0; RAYS]; 3],
        any_parallel: [false; 3],
    };

    /// Fills the [`Lanes::ZERO`] `lanes` with the rays of `taking` (a bit set); false when one of
    /// those rays' numbers is outside the range the error bound holds in. (Filled in place: made
    /// and returned in an `Option`, the kilobyte was copied out, 2.5% of a mirror ray's
    /// instructions.)
    ///
    /// # Safety
    /// Only call on a processor with AVX2 and FMA.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma,popcnt,bmi1")]
    #[inline]
    unsafe fn fill(
        lanes: &mut Lanes,
        (rays, taking): (&[Ray; RAYS], u32),
        t_max: &[f64; RAYS],
    ) -> bool {
        use std::arch::x86_64::*;
        let mut valid = _mm256_castsi256_pd(_mm256_set1_epi64x(-1));
        let mut slack = [_mm256_setzero_pd(); RAYS / 4];
        // Lanes parallel to every axis so far, over every quarter taken: a zero direction is
        // refused only when its lane is zero in each of them (elsewhere its ray meets nothing,
        // having no sheared form).
        let mut all_parallel = _mm256_castsi256_pd(_mm256_set1_epi64x(-1));
        for k in 0..3 {
            for (quarter, slack) in slack.iter_mut().enumerate() {
                let r = 4 * quarter;
                // Four lanes no ray takes are left zero: whatever their box tests say is masked
                // off (a packet of a hit's four shadow rays fills one quarter).
                if (taking >> r) & 0b1111 == 0 {
                    continue;
                }
                let dir = _mm256_setr_pd(
                    rays[r].dir[k],
                    rays[r + 1].dir[k],
                    rays[r + 2].dir[k],
                    rays[r + 3].dir[k],
                );
                let origin = _mm256_setr_pd(
                    rays[r].origin[k],
                    rays[r + 1].origin[k],
                    rays[r + 2].origin[k],
                    rays[r + 3].origin[k],
                );
                let slabs = slabs4(origin, dir);
                all_parallel = _mm256_and_pd(all_parallel, slabs.parallel);
                valid = _mm256_and_pd(valid, slabs.in_range);
                let at = |row: &mut [f32; RAYS]| {
                    // SAFETY: lane r, a multiple of four below 16, of a 16-f32 row.
                    unsafe { row.as_mut_ptr().add(r) }
                };
                let parallel = _mm256_movemask_pd(slabs.parallel) != 0;
                // The parallel rows are read only for parallel lanes (the box test masks the
                // rest): where none of the four rays is parallel, they keep the zeros a
                // non-parallel lane would be given. (Skipping them, a fill takes 935
                // instructions, not 1 099, on the Cornell box's glass rays.)
                if parallel {
                    let parallel_lanes =
                        _mm256_cvtpd_ps(_mm256_and_pd(slabs.parallel, _mm256_set1_pd(-1.0)));
                    // SAFETY: four f32s at lane r of 16-f32 rows.
                    unsafe {
                        _mm_storeu_ps(at(&mut lanes.parallel[k]), parallel_lanes);
                        _mm_storeu_ps(at(&mut lanes.origin_down[k]), slabs.origin_down);
                        _mm_storeu_ps(at(&mut lanes.origin_up[k]), slabs.origin_up);
                    }
                }
                // SAFETY: as above.
                unsafe {
                    _mm_storeu_ps(at(&mut lanes.inverse[k]), slabs.inverse);
                    _mm_storeu_ps(at(&mut lanes.offset[k]), slabs.offset);
                }
                lanes.any_parallel[k] |= parallel;
                *slack = _mm256_max_pd(*slack, slabs.slack);
            }
        }
        if _mm256_movemask_pd(valid) != 0b1111 || _mm256_movemask_pd(all_parallel) != 0 {
            return false;
        }
        for (quarter, slack) in slack.iter().enumerate() {
            // Rounded to nearest, then raised by 2⁻²⁰ relative: at least the f64 slack (≥ 2⁻¹²⁰,
            // a normal f32).
            let raised = _mm_mul_ps(
                _mm256_cvtpd_ps(*slack),
                _mm_set1_ps(1.0 + 1.0 / 1_048_576.0),
            );
            // SAFETY: four f32s at lane 4·quarter of a 16-f32 row.
            unsafe { _mm_storeu_ps(lanes.slack.as_mut_ptr().add(4 * quarter), raised) };
        }
        lanes.t_max = t_max.map(up);
        true
    }
}

/// Four lanes' numbers for the f32 box test, made alike for a packet's rays ([`Lanes::fill`]) and
/// a ray's axes ([`OneRay::new`]), so the module's bound holds for both.
#[cfg(target_arch = "x86_64")]
struct Slabs4 {
    /// All ones where d = 0.
    parallel: std::arch::x86_64::__m256d,
    /// All ones where the error bound holds: 2⁻⁶⁰ ≤ |1/d| ≤ 2⁶⁰ (or d = 0), |o/d| ≤ 2¹⁰⁰ and
    /// |o| ≤ 2¹⁰⁰ (false for NaN).
    in_range: std::arch::x86_64::__m256d,
    /// 1/d (0 where d = 0) and o/d, rounded to f32.
    inverse: std::arch::x86_64::__m128,
    offset: std::arch::x86_64::__m128,
    /// o rounded to nearest (within 2⁻²⁴|o|), moved down and up by 2⁻²²|o| + 10⁻³⁷.
    origin_down: std::arch::x86_64::__m128,
    origin_up: std::arch::x86_64::__m128,
    /// The slack of each lane in f64: 2⁻²¹·|o/d| + 7.6·10⁻³⁷.
    slack: std::arch::x86_64::__m256d,
}

/// The numbers of four lanes of origins and directions.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,popcnt,bmi1")]
#[inline]
fn slabs4(origin: std::arch::x86_64::__m256d, dir: std::arch::x86_64::__m256d) -> Slabs4 {
    use std::arch::x86_64::*;
    let magnitude = _mm256_set1_pd(-0.0);
    let parallel = _mm256_cmp_pd::<_CMP_EQ_OQ>(dir, _mm256_setzero_pd());
    let inverse = _mm256_andnot_pd(parallel, _mm256_div_pd(_mm256_set1_pd(1.0), dir));
    let offset = _mm256_mul_pd(origin, inverse);
    let inverse_size = _mm256_andnot_pd(magnitude, inverse);
    let offset_size = _mm256_andnot_pd(magnitude, offset);
    let origin_size = _mm256_andnot_pd(magnitude, origin);
    let inverse_in_range = _mm256_and_pd(
        _mm256_cmp_pd::<_CMP_GE_OQ>(inverse_size, _mm256_set1_pd(8.673_617_379_884_035e-19)),
        _mm256_cmp_pd::<_CMP_LE_OQ>(inverse_size, _mm256_set1_pd(1.152_921_504_606_847e18)),
    );
    let in_range = _mm256_and_pd(
        _mm256_or_pd(parallel, inverse_in_range),
        _mm256_and_pd(
            _mm256_cmp_pd::<_CMP_LE_OQ>(offset_size, _mm256_set1_pd(1.27e30)),
            _mm256_cmp_pd::<_CMP_LE_OQ>(origin_size, _mm256_set1_pd(1.27e30)),
        ),
    );
    let near_origin = _mm256_cvtpd_ps(origin);
    let widen = _mm_fmadd_ps(
        _mm_andnot_ps(_mm_set1_ps(-0.0), near_origin),
        _mm_set1_ps(1.0 / 4_194_304.0),
        _mm_set1_ps(1e-37),
    );
    Slabs4 {
        parallel,
        in_range,
        inverse: _mm256_cvtpd_ps(inverse),
        offset: _mm256_cvtpd_ps(offset),
        origin_down: _mm_sub_ps(near_origin, widen),
        origin_up: _mm_add_ps(near_origin, widen),
        slack: _mm256_add_pd(
            _mm256_mul_pd(offset_size, _mm256_set1_pd(1.0 / 2_097_152.0)),
            _mm256_set1_pd(7.6e-37),
        ),
    }
}

/// The nearest crack-free hits of sixteen rays (those of `taking`, a bit set) in `bvh`, written into
/// `best`, or with `ANY` a hit before each ray's t_max (a ray leaves the walk at its first); false
/// when their numbers do not allow the f32 box test (the caller then takes the one-ray box test).
/// Each node's boxes are tested against eight rays at a time, or all sixteen at once where `avx2`
/// says the processor has AVX-512 ([`boxes_avx512`]).
///
/// # Safety
/// Compiled with AVX2 and FMA: safe to call from code compiled with them (the packet traversal);
/// `avx2` proves the processor has them.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,popcnt,bmi1")]
pub fn traverse<const ANY: bool>(
    avx2: Avx2,
    bvh: &Bvh,
    (rays, taking): (&[Ray; RAYS], u32),
    t_max: [f64; RAYS],
    (box_tests, triangle_tests): (&mut u64, &mut u64),
    best: &mut [Nearest; RAYS],
) -> bool {
    let mut lanes = Lanes::ZERO;
    // SAFETY: an `Avx2` exists only on a processor with AVX2 and FMA.
    if !(unsafe { Lanes::fill(&mut lanes, (rays, taking), &t_max) }) {
        return false;
    }
    let mut together = RaysTogether::default();
    let mut query = Narrow::<ANY> {
        avx2,
        bvh,
        rays,
        lanes: &mut lanes,
        together: &mut together,
        taking: taking & ((1 << RAYS) - 1),
        made: 0,
        t_max,
        open: t_max,
        sheared: [None; RAYS],
        found_in: None,
        box_tests,
        triangle_tests,
        best,
    };
    let taking = taking & ((1 << RAYS) - 1);
    // An any-hit packet starts where the last one's hit was found (see `BLOCKERS`).
    match ANY.then(|| last_packet_node(bvh)).flatten() {
        Some(near) => bvh.visit_climbing(&mut query, near, taking, 0.0),
        None => bvh.visit_below_root(&mut query, taking, 0.0),
    }
    if ANY {
        let holder = query.found_in.and_then(|first| bvh.climb.holder(first));
        remember_packet_node(
            bvh,
            holder.map(|node| bvh.climb.ancestor(node, PACKET_START_UP)),
        );
    }
    true
}

/// The query of sixteen rays with the f32 box test.
struct Narrow<'a, const ANY: bool> {
    avx2: Avx2,
    bvh: &'a Bvh,
    rays: &'a [Ray; RAYS],
    /// Borrowed from the caller's frame, not moved into the query: moving its kilobyte cost the
    /// packets 5–9% (timed against the loop before the rewrite, alternating in one process).
    lanes: &'a mut Lanes,
    /// The rays that share the first ray's sheared axes, as lanes for the leaves' one triangle,
    /// four rays test (borrowed as `lanes` is).
    together: &'a mut RaysTogether,
    /// The rays the walk takes (a bit each).
    taking: u32,
    /// The rays whose quarter's sheared lanes have been made ([`Narrow::put_together`]).
    made: u32,
    /// Each ray's nearest hit so far (`lanes.t_max` holds it rounded up).
    t_max: [f64; RAYS],
    /// Each ray's t_max at the start (an any-hit query's limit).
    open: [f64; RAYS],
    /// Each ray's sheared form, made when the ray is first tested alone ([`Bvh::packet_leaf`],
    /// or an undecided lane of [`Bvh::leaf_rays4`]): `None` until then, and for a ray with no
    /// direction.
    sheared: [Option<ShearedRay>; RAYS],
    /// With `ANY`, the first slot of the last leaf in which a ray found its hit.
    found_in: Option<usize>,
    box_tests: &'a mut u64,
    triangle_tests: &'a mut u64,
    best: &'a mut [Nearest; RAYS],
}

#[cfg(target_arch = "x86_64")]
impl<const ANY: bool> Query for Narrow<'_, ANY> {
    type Near = f32;

    #[inline(always)]
    fn live(&self, rays: u32, near: f32) -> u32 {
        let _ = self.avx2;
        // SAFETY: an `Avx2` exists only on a processor with AVX2 and FMA.
        unsafe { live_unchecked(self.lanes, rays, near) }
    }

    #[inline(always)]
    fn boxes(&mut self, node: &Node, live: u32) -> Met<f32> {
        *self.box_tests += children(node) * u64::from(live.count_ones());
        // Where the processor has AVX-512, each node's boxes against all sixteen rays at once.
        match self.avx2.avx512() {
            // SAFETY: an `Avx512` exists only on a processor with AVX-512F, AVX2 and FMA.
            // (A call: the walk is compiled once, for AVX2. Compiled a second time with AVX-512,
            // its leaf kernels were no longer inlined into either copy, and the AVX2 walk took 5%
            // more instructions; with the call, 1.9% more, for the branch here.)
            Some(_) => unsafe { boxes_avx512(self.lanes, node, live) },
            // SAFETY: as in `live`. (Rays parallel to no axis, the most, skip the test for
            // them: a branch a box and axis, and the mask it makes.)
            None if self.lanes.any_parallel == [false; 3] => unsafe {
                boxes_unchecked::<false>(self.lanes, node, live)
            },
            // SAFETY: as in `live`.
            None => unsafe { boxes_unchecked::<true>(self.lanes, node, live) },
        }
    }

    #[inline(always)]
    fn leaf(&mut self, slots: std::ops::Range<usize>, live: u32) {
        let first = slots.start;
        self.put_together(live & !self.made);
        let lanes = &mut *self.lanes;
        let mut lowered = |r: usize, t_max: f64| lanes.t_max[r] = up(t_max);
        let together = live & self.together.rays;
        let alone = if together != 0 && together_pays(together, slots.len()) {
            *self.triangle_tests += (slots.len() * together.count_ones() as usize) as u64;
            let rays = (together, &*self.together, (&mut self.sheared, self.rays));
            let hits = (&mut self.t_max, &mut *self.best);
            self.bvh
                .leaf_rays4(self.avx2, slots.clone(), rays, hits, &mut lowered);
            live & !together
        } else {
            live
        };
        if alone != 0 {
            let hits = (&mut self.t_max, &mut *self.best);
            let rays = (&mut self.sheared, self.rays);
            let tests = &mut *self.triangle_tests;
            self.bvh
                .packet_leaf(self.avx2, slots, alone, rays, hits, tests, &mut lowered);
        }
        if ANY {
            let mut found = false;
            close_found(live, self.best, &self.open, &mut self.t_max, |r| {
                lanes.t_max[r] = f32::NEG_INFINITY;
                found = true;
            });
            if found {
                self.found_in = Some(first);
            }
        }
    }

    #[inline(always)]
    fn will_visit(&self, child: u32, count: u32) {
        prefetch(self.bvh, &self.bvh.nodes, child, count);
    }
}

#[cfg(target_arch = "x86_64")]
impl<const ANY: bool> Narrow<'_, ANY> {
    /// Puts the rays of `fresh` (reaching their first leaf), and the rays taken beside them in
    /// their quarters, in [`Narrow::together`] when they share the packet's sheared axes: their
    /// sheared forms made as lanes, four at once. (A ray tested alone makes its own
    /// [`ShearedRay`] when it first needs it, in [`Bvh::packet_leaf`] or [`Bvh::leaf_rays4`].)
    #[inline(always)]
    fn put_together(&mut self, fresh: u32) {
        for quarter in 0..RAYS / 4 {
            if (fresh >> (4 * quarter)) & 0b1111 == 0 {
                continue;
            }
            let taken = (self.taking >> (4 * quarter)) & 0b1111;
            self.made |= taken << (4 * quarter);
            let quad = &mut self.together.quads[quarter];
            // SAFETY: an `Avx2` exists only on a processor with AVX2 and FMA; the quarter holds
            // a ray taken, so `Lanes::fill` found all four of its rays finite.
            let (axes, aimed) = unsafe { sheared_quarter(self.rays, quarter, quad) };
            // A ray with no direction has no sheared form (`ShearedRay::new` says `None`): it
            // meets nothing, and is not put in.
            self.together.take_quarter(quarter, &axes, taken & aimed);
        }
    }
}

/// The sheared axes of a ray by its main axis z (0, 1, 2) and whether it goes down it: those
/// of [`ShearedRay::new`].
const SHEARED_AXES: [[[usize; 3]; 2]; 3] = [
    [[1, 2, 0], [2, 1, 0]],
    [[2, 0, 1], [0, 2, 1]],
    [[0, 1, 2], [1, 0, 2]],
];

/// The sheared forms of rays 4q to 4q + 3 of a packet, four lanes at once, written into `quad`:
/// as [`ShearedRay::new`] makes each, to the bit (the same compares pick each ray's axes, and the
/// same division and products make its shear). Returns each ray's axes and the lanes whose ray
/// has a direction (a bit each): a ray without one has no sheared form, and its lane's numbers
/// mean nothing.
///
/// # Safety
/// Only call on a processor with AVX2 and FMA, for a quarter whose four rays are finite (as
/// [`Lanes::fill`] checks).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,popcnt,bmi1")]
#[inline]
unsafe fn sheared_quarter(
    rays: &[Ray; RAYS],
    quarter: usize,
    quad: &mut RayQuad,
) -> ([[usize; 3]; 4], u32) {
    use std::arch::x86_64::*;
    let [a, b, c, d] = [0, 1, 2, 3].map(|lane| &rays[4 * quarter + lane]);
    // Written out, not mapped over arrays: the closures were left uninlined.
    let dir = [
        _mm256_setr_pd(a.dir[0], b.dir[0], c.dir[0], d.dir[0]),
        _mm256_setr_pd(a.dir[1], b.dir[1], c.dir[1], d.dir[1]),
        _mm256_setr_pd(a.dir[2], b.dir[2], c.dir[2], d.dir[2]),
    ];
    let origin = [
        _mm256_setr_pd(a.origin[0], b.origin[0], c.origin[0], d.origin[0]),
        _mm256_setr_pd(a.origin[1], b.origin[1], c.origin[1], d.origin[1]),
        _mm256_setr_pd(a.origin[2], b.origin[2], c.origin[2], d.origin[2]),
    ];
    let sign = _mm256_set1_pd(-0.0);
    let size = [
        _mm256_andnot_pd(sign, dir[0]),
        _mm256_andnot_pd(sign, dir[1]),
        _mm256_andnot_pd(sign, dir[2]),
    ];
    // As `ShearedRay::new`: z is x where |x| ≥ |y| and |x| ≥ |z|, else y where |y| ≥ |z|, else z.
    let z_is_x = _mm256_and_pd(
        _mm256_cmp_pd::<_CMP_GE_OQ>(size[0], size[1]),
        _mm256_cmp_pd::<_CMP_GE_OQ>(size[0], size[2]),
    );
    let y_over_z = _mm256_cmp_pd::<_CMP_GE_OQ>(size[1], size[2]);
    // Each lane's coordinate on its z axis, and on the two axes after it (z + 1 and z + 2,
    // mod 3), of the rows `$v`: a macro, expanded in place for the directions and the origins.
    macro_rules! on_axes {
        ($v:expr) => {{
            let v = $v;
            let pick = |when_x, when_y, when_z| {
                _mm256_blendv_pd(_mm256_blendv_pd(when_z, when_y, y_over_z), when_x, z_is_x)
            };
            (
                pick(v[0], v[1], v[2]),
                pick(v[1], v[2], v[0]),
                pick(v[2], v[0], v[1]),
            )
        }};
    }
    let (d_z, d_next, d_after) = on_axes!(dir);
    let (o_z, o_next, o_after) = on_axes!(origin);
    // Down the main axis, x and y swap (keeping the winding): the sign bit of d_z picks.
    let sz = _mm256_div_pd(_mm256_set1_pd(1.0), d_z);
    let sx = _mm256_mul_pd(_mm256_blendv_pd(d_next, d_after, d_z), sz);
    let sy = _mm256_mul_pd(_mm256_blendv_pd(d_after, d_next, d_z), sz);
    let ox = _mm256_blendv_pd(o_next, o_after, d_z);
    let oy = _mm256_blendv_pd(o_after, o_next, d_z);
    quad.store([ox, oy, o_z], [sx, sy, sz]);
    let (x, y) = (
        _mm256_movemask_pd(z_is_x) as usize,
        _mm256_movemask_pd(y_over_z) as usize,
    );
    let down = _mm256_movemask_pd(d_z) as usize;
    let axes_of = |lane: usize| {
        let main = if (x >> lane) & 1 == 1 {
            0
        } else if (y >> lane) & 1 == 1 {
            1
        } else {
            2
        };
        SHEARED_AXES[main][(down >> lane) & 1]
    };
    let axes = [axes_of(0), axes_of(1), axes_of(2), axes_of(3)];
    // d_z is the direction's largest coordinate: zero only where the direction is.
    let aimless = _mm256_cmp_pd::<_CMP_EQ_OQ>(d_z, _mm256_setzero_pd());
    let aimed = !_mm256_movemask_pd(aimless) as u32 & 0b1111;
    (axes, aimed)
}

/// True when a leaf of `triangles` costs fewer four-lane tests taken a triangle against four of
/// the rays `together` at a time than a ray against four triangles at a time.
#[inline(always)]
fn together_pays(together: u32, triangles: usize) -> bool {
    // The groups of four lanes holding one of the rays.
    let mut groups = together | (together >> 1);
    groups |= groups >> 2;
    let groups = (groups & 0x1111).count_ones() as usize;
    triangles * groups < together.count_ones() as usize * triangles.div_ceil(4)
}

/// Reads eight f32s at lane 0 or 8 of a 16-f32 row of the 64-byte aligned [`Lanes`].
/// A macro, not a closure, so that it is always inlined.
#[cfg(target_arch = "x86_64")]
macro_rules! load {
    ($row:expr, $group:expr) => {
        // SAFETY: eight f32s at lane 0 or 8 of a 16-f32 row of the 64-byte aligned `Lanes`
        // (each row starts 64 bytes after the last), so in bounds and 32-byte aligned.
        unsafe { std::arch::x86_64::_mm256_load_ps($row.as_ptr().add(8 * $group)) }
    };
}

/// Of `rays`, those whose nearest hit so far is not before `near`.
///
/// # Safety
/// Only call on a processor with AVX2 and FMA.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,popcnt,bmi1")]
#[inline]
unsafe fn live_unchecked(lanes: &Lanes, rays: u32, near: f32) -> u32 {
    use std::arch::x86_64::*;
    let mut live = 0;
    for group in 0..2 {
        let reached = _mm256_cmp_ps::<_CMP_GE_OQ>(load!(lanes.t_max, group), _mm256_set1_ps(near));
        live |= (_mm256_movemask_ps(reached) as u32) << (8 * group);
    }
    live & rays
}

/// Which of `node`'s boxes each `live` ray meets, and the nearest (lowered) entry among them.
/// `PARALLEL` false skips the parallel rays' test: only for lanes where no ray is parallel to an
/// axis (`any_parallel` all false), where it would find nothing.
///
/// # Safety
/// Only call on a processor with AVX2 and FMA.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,popcnt,bmi1")]
#[inline]
unsafe fn boxes_unchecked<const PARALLEL: bool>(lanes: &Lanes, node: &Node, live: u32) -> Met<f32> {
    use std::arch::x86_64::*;
    let shrink = _mm256_set1_ps(1.0 - RELATIVE);
    let relative = _mm256_set1_ps(RELATIVE);
    let zero = _mm256_setzero_ps();
    let infinity = _mm256_set1_ps(f32::INFINITY);
    let sign = _mm256_set1_ps(-0.0);
    let mut met = Met {
        rays: [0u32; 4],
        near: [0.0f32; 4],
    };
    // Each group's live rays as lanes of all ones, made once for the node's four boxes (made a
    // box at a time, they took three instructions of forty).
    let bits = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
    let first = _mm256_set1_epi32((live & 0xff) as i32);
    let second = _mm256_set1_epi32(((live >> 8) & 0xff) as i32);
    let live_lanes = [
        _mm256_castsi256_ps(_mm256_cmpgt_epi32(
            _mm256_and_si256(first, bits),
            _mm256_setzero_si256(),
        )),
        _mm256_castsi256_ps(_mm256_cmpgt_epi32(
            _mm256_and_si256(second, bits),
            _mm256_setzero_si256(),
        )),
    ];
    for lane in 0..4 {
        if node.child[lane] == EMPTY {
            continue;
        }
        // Written out, not mapped through closures, which may be left uninlined.
        let lo = [
            _mm256_set1_ps(node.min[0][lane]),
            _mm256_set1_ps(node.min[1][lane]),
            _mm256_set1_ps(node.min[2][lane]),
        ];
        let hi = [
            _mm256_set1_ps(node.max[0][lane]),
            _mm256_set1_ps(node.max[1][lane]),
            _mm256_set1_ps(node.max[2][lane]),
        ];
        let mut hit = 0u32;
        let mut nearest = infinity;
        for (group, live_lanes) in live_lanes.iter().enumerate() {
            let active = (live >> (8 * group)) & 0xff;
            if active == 0 {
                continue;
            }
            let mut near = zero;
            let mut far = load!(lanes.t_max, group);
            let mut outside = zero;
            for k in 0..3 {
                let inverse = load!(lanes.inverse[k], group);
                let offset = load!(lanes.offset[k], group);
                // The entry face is the low one where 1/d ≥ 0 (its sign bit picks).
                let entry_face = _mm256_blendv_ps(lo[k], hi[k], inverse);
                let exit_face = _mm256_blendv_ps(hi[k], lo[k], inverse);
                let mut t0 = _mm256_fmsub_ps(entry_face, inverse, offset);
                let mut t1 = _mm256_fmsub_ps(exit_face, inverse, offset);
                if PARALLEL && lanes.any_parallel[k] {
                    // Parallel lanes: the whole line, or nothing when o is outside.
                    let parallel = load!(lanes.parallel[k], group);
                    let minus_infinity = _mm256_set1_ps(f32::NEG_INFINITY);
                    t0 = _mm256_blendv_ps(t0, minus_infinity, parallel);
                    t1 = _mm256_blendv_ps(t1, infinity, parallel);
                    let up = load!(lanes.origin_up[k], group);
                    let down = load!(lanes.origin_down[k], group);
                    let beyond = _mm256_or_ps(
                        _mm256_cmp_ps::<_CMP_LT_OQ>(up, lo[k]),
                        _mm256_cmp_ps::<_CMP_GT_OQ>(down, hi[k]),
                    );
                    let is_parallel = _mm256_cmp_ps::<_CMP_LT_OQ>(parallel, zero);
                    outside = _mm256_or_ps(outside, _mm256_and_ps(is_parallel, beyond));
                }
                near = _mm256_max_ps(near, t0);
                far = _mm256_min_ps(far, t1);
            }
            // near ≥ 0: lowered as near·(1 − 2⁻¹⁹) − slack; far raised by as much.
            let slack = load!(lanes.slack, group);
            let near = _mm256_fmsub_ps(near, shrink, slack);
            let far_size = _mm256_andnot_ps(sign, far);
            let far = _mm256_fmadd_ps(relative, far_size, _mm256_add_ps(far, slack));
            let mut meets = _mm256_and_ps(*live_lanes, _mm256_cmp_ps::<_CMP_LE_OQ>(near, far));
            if PARALLEL {
                meets = _mm256_andnot_ps(outside, meets);
            }
            let meets_mask = _mm256_movemask_ps(meets) as u32;
            if meets_mask == 0 {
                continue;
            }
            hit |= meets_mask << (8 * group);
            nearest = _mm256_min_ps(nearest, _mm256_blendv_ps(infinity, near, meets));
        }
        if hit != 0 {
            met.rays[lane] = hit;
            met.near[lane] = horizontal_min(nearest);
        }
    }
    met
}

/// [`boxes_unchecked`] with all sixteen rays in one AVX-512 register: per lane the same operations
/// (a sign-bit blend, fused multiply-subtracts, max and min, the same widening), so the same rays
/// meet each box with the same nearest entry, to the bit. (The Cornell box's glass rays take 10%
/// less time on one thread than with the AVX2 test, its mirror rays 11%, its primary rays 8%:
/// `AVX512=0` in `examples/ray_kind_loop.rs` times the two in one build.)
///
/// # Safety
/// Only call on a processor with AVX-512F, AVX2 and FMA.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,popcnt,bmi1,avx512f")]
#[inline]
unsafe fn boxes_avx512(lanes: &Lanes, node: &Node, live: u32) -> Met<f32> {
    use std::arch::x86_64::*;
    let shrink = _mm512_set1_ps(1.0 - RELATIVE);
    let relative = _mm512_set1_ps(RELATIVE);
    let zero = _mm512_setzero_ps();
    let infinity = _mm512_set1_ps(f32::INFINITY);
    // A 16-ray packet: the low sixteen bits.
    let live = live as __mmask16;
    // SAFETY: a 16-f32 row of the 64-byte aligned `Lanes` (each row starts 64 bytes after the
    // last), so in bounds and aligned.
    let row = |row: &[f32; RAYS]| unsafe { _mm512_load_ps(row.as_ptr()) };
    let mut met = Met {
        rays: [0u32; 4],
        near: [0.0f32; 4],
    };
    for lane in 0..4 {
        if node.child[lane] == EMPTY {
            continue;
        }
        let mut near = zero;
        let mut far = row(&lanes.t_max);
        let mut outside: __mmask16 = 0;
        for k in 0..3 {
            let lo = _mm512_set1_ps(node.min[k][lane]);
            let hi = _mm512_set1_ps(node.max[k][lane]);
            let inverse = row(&lanes.inverse[k]);
            let offset = row(&lanes.offset[k]);
            // The entry face is the low one where 1/d ≥ 0: the sign bit picks, as blendv's does.
            let negative =
                _mm512_cmplt_epi32_mask(_mm512_castps_si512(inverse), _mm512_setzero_si512());
            let entry_face = _mm512_mask_blend_ps(negative, lo, hi);
            let exit_face = _mm512_mask_blend_ps(negative, hi, lo);
            let mut t0 = _mm512_fmsub_ps(entry_face, inverse, offset);
            let mut t1 = _mm512_fmsub_ps(exit_face, inverse, offset);
            if lanes.any_parallel[k] {
                // Parallel lanes: the whole line, or nothing when o is outside.
                let parallel = _mm512_cmp_ps_mask::<_CMP_LT_OQ>(row(&lanes.parallel[k]), zero);
                t0 = _mm512_mask_blend_ps(parallel, t0, _mm512_set1_ps(f32::NEG_INFINITY));
                t1 = _mm512_mask_blend_ps(parallel, t1, infinity);
                let beyond = _mm512_cmp_ps_mask::<_CMP_LT_OQ>(row(&lanes.origin_up[k]), lo)
                    | _mm512_cmp_ps_mask::<_CMP_GT_OQ>(row(&lanes.origin_down[k]), hi);
                outside |= parallel & beyond;
            }
            near = _mm512_max_ps(near, t0);
            far = _mm512_min_ps(far, t1);
        }
        // near ≥ 0: lowered as near·(1 − 2⁻¹⁹) − slack; far raised by as much.
        let slack = row(&lanes.slack);
        let near = _mm512_fmsub_ps(near, shrink, slack);
        let far = _mm512_fmadd_ps(relative, _mm512_abs_ps(far), _mm512_add_ps(far, slack));
        let meets = _mm512_mask_cmp_ps_mask::<_CMP_LE_OQ>(live & !outside, near, far);
        if meets != 0 {
            met.rays[lane] = u32::from(meets);
            met.near[lane] = _mm512_mask_reduce_min_ps(meets, near);
        }
    }
    met
}

/// Asks the processor to start loading a child the traversal will visit: an inner node of `nodes`
/// (its cache lines), or a leaf's first four triangles. The children found are pushed farthest
/// first and popped nearest first, so the loads of all but the nearest overlap the work on it.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn prefetch<const W: usize>(bvh: &Bvh, nodes: &[WideNode<W>], child: u32, count: u32) {
    use std::mem::size_of;
    // The cache lines a node and a quad of triangles span (a fixed count, so the loop below
    // unrolls: the range's iterator cost more than the prefetches).
    let node_lines = const { size_of::<WideNode<W>>().div_ceil(64) };
    const QUAD_LINES: usize = size_of::<super::crack_free4::Quad>().div_ceil(64);
    use super::prefetch_lines as lines;
    if count == 0 {
        lines(nodes.as_ptr().wrapping_add(child as usize), node_lines);
    } else {
        lines(
            bvh.quads.as_ptr().wrapping_add(child as usize / 4),
            QUAD_LINES,
        );
    }
}

/// The smallest of eight f32s.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,popcnt,bmi1")]
#[inline]
fn horizontal_min(x: std::arch::x86_64::__m256) -> f32 {
    use std::arch::x86_64::*;
    let halves = _mm_min_ps(_mm256_castps256_ps128(x), _mm256_extractf128_ps::<1>(x));
    let pairs = _mm_min_ps(halves, _mm_movehl_ps(halves, halves));
    let one = _mm_min_ss(pairs, _mm_shuffle_ps::<1>(pairs, pairs));
    _mm_cvtss_f32(one)
}

/// One ray's numbers for the f32 box test of an 8-wide node's eight boxes at once
/// ([`crate::render::bvh::eight`]): the numbers a lane of [`Lanes`] holds, made the same way (the
/// same operations, four axes in the lanes where [`Lanes::fill`] has four rays), so the same bound
/// holds (see the module's note). Each is held broadcast to the eight lanes of a node's boxes.
#[cfg(target_arch = "x86_64")]
struct OneRay {
    /// 1/d and o/d per axis.
    inverse: [std::arch::x86_64::__m256; 3],
    offset: [std::arch::x86_64::__m256; 3],
    /// Per axis, where a node's entry and exit faces are, in f32s from the node's start (its
    /// minima, then its maxima): the low face is the entry where 1/d ≥ 0.
    entry_row: [usize; 3],
    exit_row: [usize; 3],
    slack: std::arch::x86_64::__m256,
    t_max: std::arch::x86_64::__m256,
    /// Per axis, whether d is zero there, and whether it is on any axis.
    parallel: [bool; 3],
    any_parallel: bool,
    /// o rounded down and up to f32 (below and above o), for the parallel axes.
    origin_down: [std::arch::x86_64::__m256; 3],
    origin_up: [std::arch::x86_64::__m256; 3],
}

#[cfg(target_arch = "x86_64")]
impl OneRay {
    /// The numbers of `ray` looking up to `t_max`, or `None` when they are outside the range the
    /// error bound holds in (as [`Lanes::fill`] refuses a packet).
    ///
    /// # Safety
    /// Only call on a processor with AVX2 and FMA.
    #[target_feature(enable = "avx2,fma,popcnt,bmi1")]
    #[inline]
    unsafe fn new(ray: &Ray, t_max: f64) -> Option<OneRay> {
        use std::arch::x86_64::*;
        // Lane k is axis k; lane 3 a stand-in (d = 1, o = 0) that passes every check.
        let dir = _mm256_setr_pd(ray.dir[0], ray.dir[1], ray.dir[2], 1.0);
        let origin = _mm256_setr_pd(ray.origin[0], ray.origin[1], ray.origin[2], 0.0);
        let slabs = slabs4(origin, dir);
        let parallel_axes = _mm256_movemask_pd(slabs.parallel) as u32;
        if _mm256_movemask_pd(slabs.in_range) != 0b1111 || parallel_axes == 0b0111 {
            return None;
        }
        let axis_slack = slabs.slack;
        // The largest over the axes (lane 3's is the least a slack can be).
        let halves = _mm_max_pd(
            _mm256_castpd256_pd128(axis_slack),
            _mm256_extractf128_pd::<1>(axis_slack),
        );
        let slack = _mm_max_sd(halves, _mm_unpackhi_pd(halves, halves));
        // Rounded to nearest, then raised by 2⁻²⁰ relative: at least the f64 slack.
        let slack = _mm_mul_ss(
            _mm_cvtsd_ss(_mm_setzero_ps(), slack),
            _mm_set1_ps(1.0 + 1.0 / 1_048_576.0),
        );
        let negative = _mm_movemask_ps(slabs.inverse) as usize & 0b111;
        let parallel = std::array::from_fn(|k| (parallel_axes >> k) & 1 == 1);
        let any_parallel = parallel_axes != 0;
        // Only the parallel axes' test reads these.
        let (origin_down, origin_up) = match any_parallel {
            true => (each_axis(slabs.origin_down), each_axis(slabs.origin_up)),
            false => ([_mm256_setzero_ps(); 3], [_mm256_setzero_ps(); 3]),
        };
        Some(OneRay {
            inverse: each_axis(slabs.inverse),
            offset: each_axis(slabs.offset),
            entry_row: ENTRY_ROWS[negative],
            exit_row: ENTRY_ROWS[negative ^ 0b111],
            slack: _mm256_broadcastss_ps(slack),
            t_max: _mm256_set1_ps(up(t_max)),
            parallel,
            any_parallel,
            origin_down,
            origin_up,
        })
    }
}

/// Per axis, where a node's entry faces are (in f32s from the node's start: the minima's rows at
/// 8k, the maxima's at 24 + 8k), for each set of axes whose 1/d is negative (bit k for axis k):
/// there the maximum is the entry. Its exit faces are the other set's.
const ENTRY_ROWS: [[usize; 3]; 8] = {
    let mut rows = [[0; 3]; 8];
    let mut negative = 0;
    while negative < 8 {
        let mut k = 0;
        while k < 3 {
            rows[negative][k] = 8 * k + 24 * ((negative >> k) & 1);
            k += 1;
        }
        negative += 1;
    }
    rows
};

/// Lanes 0, 1 and 2 of `lanes` (x, y, z), each broadcast to eight lanes.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,popcnt,bmi1")]
#[inline]
fn each_axis(lanes: std::arch::x86_64::__m128) -> [std::arch::x86_64::__m256; 3] {
    use std::arch::x86_64::{_mm_permute_ps, _mm256_broadcastss_ps};
    [
        _mm256_broadcastss_ps(lanes),
        _mm256_broadcastss_ps(_mm_permute_ps::<0x55>(lanes)),
        _mm256_broadcastss_ps(_mm_permute_ps::<0xaa>(lanes)),
    ]
}

/// Whether the crack-free test finds a triangle of `bvh` that `ray` meets at 0 < t < t_max: what
/// [`Bvh::occluded`] answers from t_min = 0, one ray through the f32 box test of an 8-wide node's
/// eight boxes at once (fewer nodes on the way down than four wide: 6–14% less time on the
/// Cornell box's shadow and occlusion rays); `None` when the ray's numbers do not allow the f32
/// test (the caller then takes the f64 walk). The first hit found ends the walk, and any hit
/// before t_max answers, so the order of a node's children is free: the boxes the ray starts in
/// are visited last, as they hold the surface a shadow ray leaves, which it cannot hit; the others
/// smallest first, as the build sorts each node's lanes (see `bvh::eight`). On the
/// Cornell box's shadow rays that a mesh blocks, the node's own order tested 2.8 leaves a walk.
/// Nearest first (tried) tested 3.2, farthest first 2.0, but farthest first sent a camera ray to
/// the back of the 81 920-triangle sphere and took 35% more time there. The boxes started in
/// last test nearly as few triangles as farthest first on the Cornell box (2.02 M against 1.99 M
/// for its 1.53 M shadow rays, 2.61 M in the node's order), and the sphere's camera rays, which
/// start in no box, test the same boxes as before. Before the walk, the quad that blocked the
/// last blocked ray on this hierarchy in this thread's lane ([`in_blocker_lane`]) may be tested
/// (`BLOCKERS`); in lane 0, whose rays come one beside the other, the walk then starts at the node
/// that ray's walk found its quad in (the quads beside it), and only if nothing there blocks, from
/// the top. On the peer bench's box seen from inside, one ray at a time, 6% less time and 16.1
/// box tests a ray against 23.5 (19.6 against 28.9 and 7% less time at 363 600 triangles; the
/// sphere, whose rays mostly miss or meet its far side, 28.0 against 29.8 and the same time).
/// When nothing below that node blocks, the walk climbs: each ancestor's other children in turn
/// (the nodes beside it, then farther), up to the first node; and a ray nothing blocks sends the
/// next one straight to the top. On the same rays (callgrind, two casts on one thread): the box
/// 5.8% fewer instructions than walking from the top after the near node, the finer box 6.1%, the
/// sphere 11.1% (its missing rays no longer walk near an old blocker first); box tests a ray
/// 9.93 on the box (from 16.1) and 21.6 on the sphere (from 28.0).
///
/// # Safety
/// Compiled with AVX2 and FMA: safe to call from code compiled with them; `avx2` proves the
/// processor has them.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,popcnt,bmi1")]
pub fn occluded_one_ray(
    avx2: Avx2,
    bvh: &Bvh,
    ray: &Ray,
    t_max: f64,
    (box_tests, triangle_tests): (&mut u64, &mut u64),
) -> Option<bool> {
    use crate::render::bvh::traverse::MAX_DEPTH;
    /// An 8-wide node on the path pushes at most seven children besides the one visited next, and
    /// the path is no deeper than the 4-wide one.
    const STACK: usize = 7 * MAX_DEPTH + 1;
    if !bvh.narrow {
        return None;
    }
    // No start: the hierarchy holds no triangle.
    let Some((start, start_count)) = bvh.eight.start else {
        return Some(false);
    };
    // SAFETY: compiled with AVX2 and FMA, which `avx2` proves the processor has.
    let one = unsafe { OneRay::new(ray, t_max) }?;
    let mut sheared: Option<Option<ShearedRay>> = None;
    // This thread's last blocker first (see `BLOCKERS`).
    let quads = bvh.quads.as_ptr() as usize;
    let mut last_blocker_tests = 0;
    let (lane, last) = BLOCKERS.with(|blockers| {
        let lane = blockers.lane.get();
        (lane, blockers.last[lane].get())
    });
    if last.whose == quads && last.quad < bvh.quads.len() && (lane == 0 || last.worth_testing) {
        last_blocker_tests = 4;
        let quad = last.quad;
        if let Some(first) = sheared.insert(ShearedRay::new(&ray.origin, &ray.dir))
            && bvh
                .blocking_quad(avx2, first, 4 * quad..4 * quad + 4, t_max)
                .is_some()
        {
            *triangle_tests += last_blocker_tests;
            return Some(true);
        }
        if lane > 0 {
            let failed = LastBlocker {
                worth_testing: false,
                ..last
            };
            BLOCKERS.with(|blockers| blockers.last[lane].set(failed));
        }
    }
    // Counted here and added once (a store through the references at each node took more
    // instructions).
    let (mut boxes, mut triangles) = (0u64, 0u64);
    // One walk from `top` (a node's `(child, 0)`, or the mesh's start), leaving out the top
    // node's lanes in `skip` (a bit each): the quad that blocks the ray and the node the walk was
    // in when it found it, `Some(None)` when none does, `None` when the ray has no sheared form
    // (then nothing blocks it).
    let mut walk_from = |top: (u32, u32), skip: u32| -> Option<Option<(usize, u32)>> {
        // (child, count) of the children still to visit; the build bounds the depth, so `STACK`
        // entries suffice (the index is checked: more would be a bug, and panics).
        let mut stack = [const { MaybeUninit::<(u32, u32)>::uninit() }; STACK];
        let mut len = 0;
        let mut node_in = top.0;
        // Pushes the children of inner node `child` whose boxes the ray meets, less the lanes of
        // `skip`. A macro, so that the top node's copy alone takes the mask.
        macro_rules! push_children {
            ($child:expr, $skip:expr) => {{
                let node = &bvh.eight.nodes[$child as usize];
                // SAFETY: compiled with AVX2 and FMA, which `avx2` proves the processor has.
                let (met, tested, starts_in) = unsafe { one_ray_boxes8(&one, node) };
                boxes += u64::from(tested);
                let (met, starts_in) = (met & !$skip, starts_in & !$skip);
                // The boxes the ray starts in (the low byte) are pushed first, so visited last.
                let mut order = starts_in | (met & !starts_in) << 8;
                while order != 0 {
                    let lane = order.trailing_zeros() as usize & 7;
                    order &= order - 1;
                    prefetch(bvh, &bvh.eight.nodes, node.child[lane], node.count[lane]);
                    stack[len].write((node.child[lane], node.count[lane]));
                    len += 1;
                }
            }};
        }
        match top {
            (child, 0) => push_children!(child, skip),
            leaf => {
                stack[0].write(leaf);
                len = 1;
            }
        }
        while len > 0 {
            len -= 1;
            // SAFETY: the entries below `len` were written.
            let (child, count) = unsafe { stack[len].assume_init() };
            if count > 0 {
                triangles += u64::from(count);
                let ray = sheared.get_or_insert_with(|| ShearedRay::new(&ray.origin, &ray.dir));
                let ray = ray.as_ref()?;
                let slots = child as usize..(child + count) as usize;
                if let Some(quad) = bvh.blocking_quad(avx2, ray, slots, t_max) {
                    return Some(Some((quad, node_in)));
                }
                continue;
            }
            node_in = child;
            push_children!(child, 0u32);
        }
        Some(None)
    };
    // Lane 0's rays come one beside the other: the node its last blocked ray's walk found the
    // blocker in holds the quads beside that one. Walked first; then, while nothing blocks, each
    // ancestor's other children in turn (the nodes beside it, then farther), up to the mesh's
    // first node, whose own box is not tested, as the object index has mostly tested that box
    // already (a skipped box test only culls less, never answers).
    let near_last = (lane == 0 && last.whose == quads && start_count == 0)
        .then_some(last.node)
        .filter(|&node| node != start && (node as usize) < bvh.eight.nodes.len());
    let blocker = match near_last {
        Some(mut node) => {
            let mut blocker = walk_from((node, 0), 0);
            while blocker == Some(None) {
                let parent = bvh.eight.parents[node as usize];
                if parent == NO_PARENT {
                    break;
                }
                let below = lanes_holding(&bvh.eight.nodes[parent as usize], node);
                blocker = walk_from((parent, 0), below);
                node = parent;
            }
            blocker
        }
        None => walk_from((start, start_count), 0),
    };
    let found = match blocker {
        Some(Some((quad, node))) => {
            BLOCKERS.with(|blockers| {
                let last = blockers.last[lane].get();
                blockers.last[lane].set(LastBlocker {
                    whose: quads,
                    quad,
                    node,
                    // The same quad blocked the lane's last blocked ray on this hierarchy too.
                    worth_testing: last.whose == quads && last.quad == quad,
                });
            });
            true
        }
        _ => {
            // Nothing blocks this ray (a ray past the mesh's edge): the next ray walks from the
            // top, not near a blocker that the rays since may have left behind.
            if near_last.is_some() {
                BLOCKERS.with(|blockers| {
                    let last = blockers.last[lane].get();
                    blockers.last[lane].set(LastBlocker {
                        node: LastBlocker::NONE.node,
                        ..last
                    });
                });
            }
            false
        }
    };
    *box_tests += boxes;
    *triangle_tests += triangles + last_blocker_tests;
    Some(found)
}

/// A thread's last blocker (see `BLOCKERS`).
#[derive(Clone, Copy)]
struct LastBlocker {
    /// The address of the hierarchy's quads.
    whose: usize,
    /// The quad (slot / 4) that blocked the thread's last blocked ray on that hierarchy.
    quad: usize,
    /// The 8-wide node that ray's walk was in when it found that quad.
    node: u32,
    /// Whether a packet's lane tests it first: the same quad blocked the lane's last two blocked
    /// rays, or the last test of it blocked its ray. (Lane 0 tests it whatever this says.)
    worth_testing: bool,
}

impl LastBlocker {
    const NONE: LastBlocker = LastBlocker {
        whose: 0,
        quad: usize::MAX,
        node: u32::MAX,
        worth_testing: false,
    };
}

thread_local! {
    /// This thread's last blockers: for each lane, the quad in which the lane's last any-hit walk
    /// that found a hit found it, and whose it is. Lane 0 holds rays cast one after another
    /// beside each other (a row's camera rays); lane r + 1 a packet's ray r, which in a render's
    /// packets is the same light's shadow ray, or the same occlusion ray, hit after hit
    /// ([`in_blocker_lane`]). The next walk on the same hierarchy in the same lane tests that quad
    /// first: neighbouring rays are most often blocked by the same few triangles. A packet's lane
    /// stops testing it once a test fails, until two of its blocked rays in a row are blocked by
    /// the same quad: the Cornell box's occlusion rays, each hit's eight going every way, were
    /// blocked by it too seldom for its four tests a ray (`ray_kind_loop`). It only chooses what
    /// is tested first, so no answer depends on it: a quad of another hierarchy is never tested (a
    /// hierarchy built where a dropped one was may share its address, but then a quad past its end
    /// is not tested either, and any quad of its own holds its own triangles). On the camera rays
    /// of the peer bench, a walk 24–27% less time on the sphere and 16–18% on the box seen from
    /// inside.
    static BLOCKERS: Blockers = const {
        Blockers {
            lane: std::cell::Cell::new(0),
            last: [const { std::cell::Cell::new(LastBlocker::NONE) }; RAYS + 1],
            packet: std::cell::Cell::new(NO_PACKET_NODE),
        }
    };
}

/// A thread's last blockers, one a lane (see `BLOCKERS`), and the lane its walks use now.
struct Blockers {
    lane: std::cell::Cell<usize>,
    last: [std::cell::Cell<LastBlocker>; RAYS + 1],
    /// The 4-wide node that held the leaf of the last any-hit packet's last hit, and whose (the
    /// address of the hierarchy's quads): the next packet on that hierarchy starts its walk there
    /// ([`Bvh::visit_climbing`]). Packets of neighbouring rays, one after the other (the peer
    /// bench's 4x4 tiles), most often end in the same part of the mesh.
    packet: std::cell::Cell<(usize, u32)>,
}

/// No node to start an any-hit packet's walk from (see [`Blockers::packet`]): of no hierarchy.
const NO_PACKET_NODE: (usize, u32) = (0, NO_PARENT);

/// How many levels above the node holding the last packet's hit the next packet's walk starts.
/// Started lower, a packet's rays along an edge tested the neighbouring leaves there before the
/// tie rule's own; higher, it tested more boxes. In instructions against the walk from the top
/// (`examples/any_hit_loop`, `TEST=packets`), started at the holder itself: the box seen from
/// inside +0.7%, the finer box −4.9%, the sphere −19%; three levels up: −9.8%, −14.8% and
/// −11.9%. Two levels up saved less on the boxes, four less on the sphere.
const PACKET_START_UP: u32 = 3;

/// This thread's node to start an any-hit packet's walk on `bvh` from, if it has one (see
/// [`Blockers::packet`]). Any node would do: the climb from it covers the whole hierarchy.
fn last_packet_node(bvh: &Bvh) -> Option<u32> {
    let (whose, node) = BLOCKERS.with(|blockers| blockers.packet.get());
    (whose == bvh.quads.as_ptr() as usize && (node as usize) < bvh.nodes.len()).then_some(node)
}

/// Keeps `node` as this thread's node to start `bvh`'s next any-hit packet from; `None` (a
/// packet in which no ray found a hit) starts the next from the top.
fn remember_packet_node(bvh: &Bvh, node: Option<u32>) {
    let kept = match node {
        Some(node) => (bvh.quads.as_ptr() as usize, node),
        None => NO_PACKET_NODE,
    };
    BLOCKERS.with(|blockers| blockers.packet.set(kept));
}

/// Runs `walks` with this thread's any-hit walks testing first and keeping the last blocker of a
/// packet's ray `r` (below [`RAYS`]), then gives the walks that follow the lane they had.
pub fn in_blocker_lane<T>(r: usize, walks: impl FnOnce() -> T) -> T {
    let lane = (r + 1).min(RAYS);
    let before = BLOCKERS.with(|blockers| blockers.lane.replace(lane));
    let answer = walks();
    BLOCKERS.with(|blockers| blockers.lane.set(before));
    answer
}

/// Forgets this thread's last blockers (see `BLOCKERS`): the next any-hit walk starts from
/// the top, as every walk did before there was one (for measuring the walk alone).
pub fn forget_last_blocker() {
    BLOCKERS.with(|blockers| {
        blockers
            .last
            .iter()
            .for_each(|one| one.set(LastBlocker::NONE));
        blockers.packet.set(NO_PACKET_NODE);
    });
}

/// Which of an 8-wide node's boxes `one` meets (a bit per lane), how many boxes it has, and which
/// of the met boxes it enters at t ≤ 0 (the lowered entry): the operations of the packet test
/// ([`boxes_unchecked`]) with the ray's numbers in every lane and a box a lane.
///
/// # Safety
/// Only call on a processor with AVX2 and FMA.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,popcnt,bmi1")]
#[inline]
unsafe fn one_ray_boxes8(one: &OneRay, node: &Node8) -> (u32, u32, u32) {
    use std::arch::x86_64::*;
    const { assert!(std::mem::offset_of!(Node8, max) == 24 * size_of::<f32>()) };
    let faces = std::ptr::from_ref(node).cast::<f32>();
    // SAFETY: a row starts at a multiple of eight f32s below 48, the node's 48 box f32s, and the
    // node is aligned to 64 bytes.
    let row = |at: usize| unsafe { _mm256_load_ps(faces.add(at)) };
    let mut near = _mm256_setzero_ps();
    let mut far = one.t_max;
    let mut outside = _mm256_setzero_ps();
    if one.any_parallel {
        for k in 0..3 {
            if one.parallel[k] {
                // The whole line, or nothing when o is outside the slab.
                let beyond = _mm256_or_ps(
                    _mm256_cmp_ps::<_CMP_LT_OQ>(one.origin_up[k], row(8 * k)),
                    _mm256_cmp_ps::<_CMP_GT_OQ>(one.origin_down[k], row(24 + 8 * k)),
                );
                outside = _mm256_or_ps(outside, beyond);
            } else {
                let entry = _mm256_fmsub_ps(row(one.entry_row[k]), one.inverse[k], one.offset[k]);
                let exit = _mm256_fmsub_ps(row(one.exit_row[k]), one.inverse[k], one.offset[k]);
                near = _mm256_max_ps(near, entry);
                far = _mm256_min_ps(far, exit);
            }
        }
    } else {
        for k in 0..3 {
            let entry = _mm256_fmsub_ps(row(one.entry_row[k]), one.inverse[k], one.offset[k]);
            let exit = _mm256_fmsub_ps(row(one.exit_row[k]), one.inverse[k], one.offset[k]);
            near = _mm256_max_ps(near, entry);
            far = _mm256_min_ps(far, exit);
        }
    }
    // near ≥ 0: lowered as near·(1 − 2⁻¹⁹) − slack; far raised by as much.
    let near = _mm256_fmsub_ps(near, _mm256_set1_ps(1.0 - RELATIVE), one.slack);
    let far_size = _mm256_andnot_ps(_mm256_set1_ps(-0.0), far);
    let far = _mm256_fmadd_ps(
        _mm256_set1_ps(RELATIVE),
        far_size,
        _mm256_add_ps(far, one.slack),
    );
    let meets = _mm256_andnot_ps(outside, _mm256_cmp_ps::<_CMP_LE_OQ>(near, far));
    // SAFETY: eight u32s.
    let child = unsafe { _mm256_loadu_si256(node.child.as_ptr().cast()) };
    let empty = _mm256_movemask_ps(_mm256_castsi256_ps(_mm256_cmpeq_epi32(
        child,
        _mm256_set1_epi32(-1),
    )));
    let boxes = !empty as u32 & 0xff;
    let met = _mm256_movemask_ps(meets) as u32 & boxes;
    // Entered at t ≤ 0 (lowered): boxes the ray may start in.
    let starts_in = _mm256_movemask_ps(_mm256_cmp_ps::<_CMP_LE_OQ>(near, _mm256_setzero_ps()));
    (met, boxes.count_ones(), met & starts_in as u32)
}

#[cfg(all(test, target_arch = "x86_64"))]
mod tests {
    use super::*;

    /// Four rays sheared at once are each the ray [`ShearedRay::new`] makes, to the bit (origin,
    /// axes and shear), and their lanes for [`RaysTogether`] hold each ray's origin and shear on
    /// its own axes; a ray with no direction has none: over random rays whose directions often
    /// tie in size on two or three axes (where the order of the compares picks the axes), have
    /// zeros of either sign, point down an axis, or are zero.
    #[test]
    fn four_rays_sheared_at_once_are_each_sheared_alone() {
        use rand::{Rng, SeedableRng};
        let _avx2 = crate::render::kernels::avx2_or_skip!();
        let mut rng = rand::rngs::StdRng::seed_from_u64(25);
        let component = |rng: &mut rand::rngs::StdRng, size: f64| match rng.random_range(0..6) {
            0 => 0.0,
            1 => -0.0,
            2 => size,
            3 => -size,
            _ => rng.random_range(-3.0..3.0),
        };
        for case in 0..4000 {
            let size = rng.random_range(0.1..2.0);
            let rays: [Ray; RAYS] = std::array::from_fn(|_| {
                let origin = [0; 3].map(|_| rng.random_range(-5.0..5.0));
                Ray::new(origin, [0; 3].map(|_| component(&mut rng, size)))
            });
            let quarter = case % 4;
            // SAFETY: `_avx2` proves AVX2 and FMA; every ray is finite.
            let mut quad = RayQuad::default();
            let (axes, aimed) = unsafe { sheared_quarter(&rays, quarter, &mut quad) };
            for lane in 0..4 {
                let ray = &rays[4 * quarter + lane];
                let Some(alone) = ShearedRay::new(&ray.origin, &ray.dir) else {
                    assert_eq!(ray.dir, [0.0; 3], "case {case}");
                    assert_eq!((aimed >> lane) & 1, 0, "case {case}, {ray:?}");
                    continue;
                };
                assert_eq!((aimed >> lane) & 1, 1, "case {case}, {ray:?}");
                let (origin, alone_axes, alone_shear) = alone.parts();
                assert_eq!(alone_axes, axes[lane], "case {case}, {ray:?}");
                let bits = |x: [f64; 3]| x.map(f64::to_bits);
                let lane_shear = quad.shear_lane(lane);
                assert_eq!(bits(*alone_shear), bits(lane_shear), "case {case}, {ray:?}");
                let mut quads = RaysTogether::default();
                quads.take_quarter(0, &axes, 1 << lane);
                let mut one = RaysTogether::default();
                one.offer(lane, &alone);
                assert_eq!(quads.axes, alone_axes);
                let [kx, ky, kz] = alone_axes;
                let moved = [origin[kx], origin[ky], origin[kz]];
                assert_eq!(bits(moved), bits(quad.origin_lane(lane)), "case {case}");
                assert_eq!(bits(lane_shear), bits(quad.shear_lane(lane)), "case {case}");
                assert_eq!(
                    bits(one.quads[0].origin_lane(lane)),
                    bits(quad.origin_lane(lane))
                );
            }
        }
    }

    /// The box tests of sixteen rays give the same answers to the bit: the AVX2 one without the
    /// parallel rays' test as with it, where no ray is parallel to an axis, and the AVX-512 one (on
    /// a processor that has it) as the AVX2 one: which rays meet each box and the nearest entry,
    /// over random packets (in three of four, some rays parallel to an axis; some fours taken by no
    /// ray; limits from a quarter to +∞), random boxes (some flat, some lanes empty) and random
    /// live rays.
    #[test]
    fn the_box_tests_of_sixteen_rays_agree() {
        use rand::{Rng, SeedableRng};
        let avx2 = crate::render::kernels::avx2_or_skip!();
        let avx512 = avx2.avx512().is_some();
        if !avx512 {
            eprintln!("this processor has no AVX-512F: the AVX2 test is checked against itself");
        }
        let same = |a: &Met<f32>, b: &Met<f32>, case: usize| {
            assert_eq!(a.rays, b.rays, "case {case}");
            for lane in (0..4).filter(|&lane| a.rays[lane] != 0) {
                assert_eq!(
                    a.near[lane].to_bits(),
                    b.near[lane].to_bits(),
                    "case {case}"
                );
            }
        };
        let mut random = rand_pcg::Pcg64::seed_from_u64(512);
        let coordinate = |random: &mut rand_pcg::Pcg64| random.random_range(-3.0..3.0f64);
        let (mut met_some, mut parallel_met, mut none_parallel_met) = (0, 0, 0);
        for i in 0..10_000 {
            let rays: [Ray; RAYS] = std::array::from_fn(|r| {
                let origin = std::array::from_fn(|_| coordinate(&mut random));
                let mut dir: [f64; 3] = std::array::from_fn(|_| coordinate(&mut random));
                if (r + i) % 5 == 0 && i % 4 != 3 {
                    dir[(r + i) % 3] = 0.0;
                }
                Ray::new(origin, dir)
            });
            let t_max: [f64; RAYS] =
                std::array::from_fn(|r| [f64::INFINITY, 1.0, 2.0, 0.25][(r + i) % 4]);
            let taking = if i % 3 == 0 {
                0xffff
            } else {
                random.random::<u32>() & 0xffff
            };
            let mut lanes = Lanes::ZERO;
            // SAFETY: the processor has AVX2 and FMA (detected above).
            assert!(unsafe { Lanes::fill(&mut lanes, (&rays, taking), &t_max) });
            let node = Node {
                min: std::array::from_fn(|_| {
                    std::array::from_fn(|_| coordinate(&mut random) as f32)
                }),
                max: [[0.0; 4]; 3],
                child: std::array::from_fn(|lane| if (lane + i) % 6 == 5 { EMPTY } else { 1 }),
                count: [0; 4],
            };
            let node = Node {
                max: std::array::from_fn(|k| {
                    std::array::from_fn(|lane| {
                        let low = node.min[k][lane];
                        if i % 7 == 0 {
                            low
                        } else {
                            low + random.random_range(0.0..6.0f32)
                        }
                    })
                }),
                ..node
            };
            let live = taking & random.random::<u32>();
            // The live rays parallel to some axis (their slabs take the parallel rows).
            let parallel: u32 = (0..RAYS)
                .filter(|&r| rays[r].dir.contains(&0.0))
                .fold(0, |set, r| set | 1 << r);
            // SAFETY: the processor has AVX2 and FMA (detected above).
            let eight = unsafe { boxes_unchecked::<true>(&lanes, &node, live) };
            let met: u32 = eight.rays.iter().map(|rays| rays.count_ones()).sum();
            met_some += met;
            parallel_met += eight
                .rays
                .iter()
                .map(|rays| (rays & parallel).count_ones())
                .sum::<u32>();
            if lanes.any_parallel == [false; 3] {
                // SAFETY: as above; no ray is parallel to an axis.
                let without = unsafe { boxes_unchecked::<false>(&lanes, &node, live) };
                same(&without, &eight, i);
                none_parallel_met += met;
            }
            if avx512 {
                // SAFETY: the processor has AVX2, FMA and AVX-512F (detected above).
                let sixteen = unsafe { boxes_avx512(&lanes, &node, live) };
                same(&sixteen, &eight, i);
            }
        }
        assert!(
            met_some > 8_000 && parallel_met > 1_000 && none_parallel_met > 2_000,
            "{met_some} {parallel_met} {none_parallel_met}"
        );
    }

    /// The last blocker changes no answer, and spares the walk: the camera rays of the grid box and
    /// of a sphere, cast one after another through both hierarchies in turn (each query follows one
    /// on the other hierarchy every other ray, and a hierarchy dropped after blocking the last
    /// ray), each answered as the f64 walk answers it, to its nearest hit and to the float below
    /// it; and on the box, cast in order alone, at most 60% of the box tests of walks from the top.
    #[test]
    fn the_last_blocker_changes_no_answer_and_spares_the_walk() {
        use crate::render::generate::{irregular_sphere, mesh_hierarchy, mesh_scene};
        let avx2 = crate::render::kernels::avx2_or_skip!();
        fn hierarchy(prepared: &crate::render::Prepared) -> &Bvh {
            mesh_hierarchy(prepared).expect("a mesh scene has a hierarchy")
        }
        let (grid, sphere, side) = grid_and_sphere();
        let camera = sphere_camera();
        let (grid_bvh, sphere_bvh) = (hierarchy(&grid), hierarchy(&sphere));
        let (mut blocked, mut open) = (0, 0);
        for row in 0..side {
            for column in 0..side {
                for (prepared, bvh) in [(&grid, &grid_bvh), (&sphere, &sphere_bvh)] {
                    let ray = prepared.ray(row, column);
                    let nearest =
                        bvh.nearest_crack_free(None, &ray, (0.0, f64::INFINITY), &mut 0, &mut 0);
                    let limits = match nearest {
                        Some((_, hit)) => vec![hit.t, hit.t.next_up(), f64::INFINITY],
                        None => vec![f64::INFINITY],
                    };
                    for t_max in limits {
                        let f64_walk = bvh.occluded(None, &ray, (0.0, t_max), &mut 0, &mut 0);
                        let with_memory =
                            bvh.occluded(Some(avx2), &ray, (0.0, t_max), &mut 0, &mut 0);
                        assert_eq!(with_memory, f64_walk, "{ray:?} to {t_max}");
                        blocked += usize::from(f64_walk);
                        open += usize::from(!f64_walk);
                    }
                }
            }
        }
        assert!(blocked > 500 && open > 500, "{blocked} {open}");
        // The last blocker is a quad of a larger hierarchy; a smaller one built after it is
        // dropped answers as before.
        let big = mesh_scene(&irregular_sphere(5, 3), camera.clone(), 8, 8);
        let ray = sphere.ray(side / 2, side / 2);
        assert!(hierarchy(&big).occluded(Some(avx2), &ray, (0.0, f64::INFINITY), &mut 0, &mut 0));
        drop(big);
        let again = mesh_scene(&irregular_sphere(3, 12), camera, side, side);
        let small = hierarchy(&again);
        for column in 0..side {
            let ray = sphere.ray(side / 2, column);
            let f64_walk = small.occluded(None, &ray, (0.0, f64::INFINITY), &mut 0, &mut 0);
            let with_memory =
                small.occluded(Some(avx2), &ray, (0.0, f64::INFINITY), &mut 0, &mut 0);
            assert_eq!(with_memory, f64_walk, "{ray:?}");
        }
        // The box's rays in order: with the last blocker, and each walk from the top.
        let mut boxes = [0u64; 2];
        for (forget, boxes) in [false, true].into_iter().zip(&mut boxes) {
            Bvh::forget_last_blocker();
            for row in 0..side {
                for column in 0..side {
                    if forget {
                        Bvh::forget_last_blocker();
                    }
                    let ray = grid.ray(row, column);
                    let range = (0.0, f64::INFINITY);
                    assert!(grid_bvh.occluded(Some(avx2), &ray, range, boxes, &mut 0));
                }
            }
        }
        // 6 430 against 15 734 (8 102 with the last quad alone, before the walk from its node).
        assert!(2 * boxes[0] <= boxes[1], "box tests: {boxes:?}");
    }

    /// A packet's lanes each keep their own last blocker, tested first while it blocks: on the
    /// grid box, a ray blocked twice in lane 0 is then answered by its quad alone (no box tested),
    /// though lane 1 was blocked elsewhere between; once a lane's blocker fails a ray, the lane
    /// walks from the top until the same quad blocks two rays in a row. Every answer is the f64
    /// walk's.
    #[test]
    fn each_packet_lane_keeps_its_own_last_blocker() {
        use crate::render::generate::{grid_box, mesh_hierarchy, mesh_scene};
        let avx2 = crate::render::kernels::avx2_or_skip!();
        let (camera, side, triangles) = grid_box(12);
        let grid = mesh_scene(&triangles, camera, side, side);
        let bvh = mesh_hierarchy(&grid).expect("a mesh scene has a hierarchy");
        let (a, b) = (
            grid.ray(side / 3, side / 3),
            grid.ray(2 * side / 3, 2 * side / 3),
        );
        // (box tests, triangle tests) of one query of `ray` in `lane`, checked against the f64 walk.
        let cast = |lane: Option<usize>, ray: &Ray| {
            let (mut boxes, mut triangles) = (0, 0);
            let range = (0.0, f64::INFINITY);
            let mut query = || bvh.occluded(Some(avx2), ray, range, &mut boxes, &mut triangles);
            let found = match lane {
                Some(r) => Bvh::in_blocker_lane(r, query),
                None => query(),
            };
            assert_eq!(found, bvh.occluded(None, ray, range, &mut 0, &mut 0));
            assert!(found, "{ray:?}");
            (boxes, triangles)
        };
        Bvh::forget_last_blocker();
        cast(Some(0), &a);
        cast(Some(0), &a);
        cast(Some(1), &b);
        cast(Some(1), &b);
        assert_eq!(
            cast(Some(0), &a),
            (0, 4),
            "lane 0 tests its own blocker first"
        );
        assert_eq!(
            cast(Some(1), &b),
            (0, 4),
            "lane 1 tests its own blocker first"
        );
        // Lane 0's blocker fails ray b, which walks from the top. The next ray in lane 0, b again,
        // walks too, though b's quad is the lane's blocker now: one blocked ray is not enough.
        // After two in a row, the lane tests it first again.
        assert!(cast(Some(0), &b).0 > 0);
        assert!(cast(Some(0), &b).0 > 0);
        assert_eq!(cast(Some(0), &b), (0, 4));
        // Rays cast one after another (no lane) test their last blocker whatever happened
        // before: one blocked ray is enough.
        cast(None, &b);
        assert!(cast(None, &a).0 > 0);
        assert_eq!(cast(None, &a), (0, 4));
    }

    /// A packet's any-hit walk that starts at any node and climbs answers as the walk from the
    /// top: on the grid box and the sphere (rays that miss among them), 4x4 tiles of camera rays,
    /// some limited to their nearest hit (not blocked there) or just past it, each tile walked
    /// from every node of the hierarchy and from the node the tile before left. Every answer is
    /// the f64 one-ray walk's. Along a row of tiles, starting where the last tile's hit was found
    /// tests fewer boxes than from the top.
    #[test]
    fn a_packet_walk_from_any_node_answers_as_from_the_top() {
        use crate::render::generate::mesh_hierarchy;
        let avx2 = crate::render::kernels::avx2_or_skip!();
        let (grid, sphere, side) = grid_and_sphere();
        let (mut blocked, mut open) = (0, 0);
        for prepared in [&grid, &sphere] {
            let bvh = mesh_hierarchy(prepared).expect("a mesh scene has a hierarchy");
            let mut boxes = [0u64; 2];
            for (top, boxes) in [true, false].into_iter().zip(&mut boxes) {
                Bvh::forget_last_blocker();
                for (row, column) in (0..side / 4).flat_map(|r| (0..side / 4).map(move |c| (r, c)))
                {
                    let rays: [Ray; RAYS] =
                        std::array::from_fn(|k| prepared.ray(4 * row + k / 4, 4 * column + k % 4));
                    let t_max: [f64; RAYS] = std::array::from_fn(|k| {
                        let range = (0.0, f64::INFINITY);
                        let nearest = bvh.nearest_crack_free(None, &rays[k], range, &mut 0, &mut 0);
                        match (nearest, k % 3) {
                            (Some((_, hit)), 1) => hit.t,
                            (Some((_, hit)), 2) => hit.t.next_up(),
                            _ => f64::INFINITY,
                        }
                    });
                    let expected = (0..RAYS).fold(0, |bits, k| {
                        let range = (0.0, t_max[k]);
                        let found = bvh.occluded(None, &rays[k], range, &mut 0, &mut 0);
                        bits | u32::from(found) << k
                    });
                    blocked += expected.count_ones();
                    open += RAYS as u32 - expected.count_ones();
                    if top {
                        // From every node, and from the top.
                        for node in (0..bvh.nodes.len() as u32).map(Some).chain([None]) {
                            remember_packet_node(bvh, node);
                            let found =
                                bvh.occluded_packet(Some(avx2), &rays, t_max, &mut 0, &mut 0);
                            assert_eq!(found, expected, "tile {row}, {column} from {node:?}");
                        }
                        remember_packet_node(bvh, None);
                        bvh.occluded_packet(Some(avx2), &rays, t_max, boxes, &mut 0);
                    } else {
                        // From where the tile before left.
                        let found = bvh.occluded_packet(Some(avx2), &rays, t_max, boxes, &mut 0);
                        assert_eq!(found, expected, "tile {row}, {column}");
                    }
                }
            }
            eprintln!("box tests from the top, then climbing: {boxes:?}");
            assert!(
                boxes[1] < boxes[0],
                "box tests from the top, then climbing: {boxes:?}"
            );
        }
        assert!(blocked > 500 && open > 500, "{blocked} {open}");
    }

    /// The camera the sphere of the last-blocker tests is seen from.
    fn sphere_camera() -> crate::scene::render::Camera {
        crate::scene::render::Camera::Pinhole {
            position: [0.3, -3.6, 0.5],
            target: [0.0, 0.0, 0.0],
            fov_y: 40.0,
        }
    }

    /// The grid box of 12 cells a side seen from inside, and the sphere of level 3 seen from
    /// outside on an image of the same size (some of its rays miss), and that size.
    fn grid_and_sphere() -> (crate::render::Prepared, crate::render::Prepared, usize) {
        use crate::render::generate::{grid_box, irregular_sphere, mesh_scene};
        let (camera, side, triangles) = grid_box(12);
        let grid = mesh_scene(&triangles, camera, side, side);
        let sphere = mesh_scene(&irregular_sphere(3, 12), sphere_camera(), side, side);
        (grid, sphere, side)
    }

    /// A node whose lanes hold `boxes` (min, max), the rest empty.
    fn node(boxes: &[([f32; 3], [f32; 3])]) -> Node8 {
        let mut node = Node8::empty();
        for (lane, (min, max)) in boxes.iter().enumerate() {
            for k in 0..3 {
                node.min[k][lane] = min[k];
                node.max[k][lane] = max[k];
            }
            node.child[lane] = lane as u32;
        }
        node
    }

    /// The boxes a ray starts in are told apart from those ahead of it, which the any-hit walk
    /// visits first (a shadow ray cannot hit the surface it leaves, in the box it starts in).
    #[test]
    fn a_node_tells_the_boxes_a_ray_starts_in_from_those_ahead() {
        let _ = crate::render::kernels::avx2_or_skip!();
        let boxes = node(&[
            ([-1.0, -1.0, -1.0], [1.0, 1.0, 1.0]),
            ([2.0, -1.0, -1.0], [3.0, 1.0, 1.0]),
            ([-3.0, -1.0, -1.0], [-2.0, 1.0, 1.0]),
            ([0.5, -0.5, -0.5], [4.0, 0.5, 0.5]),
        ]);
        let cases = [
            // From inside the first and the last box, along +x: it starts in both, and meets the
            // second ahead; the third is behind it.
            ([0.6, 0.0, 0.0], [1.0, 0.01, 0.02], 0b1011, 0b1001),
            // From outside them all: every met box is ahead.
            ([-5.0, 0.0, 0.0], [1.0, 0.0, 0.0], 0b1111, 0b0000),
            // Going −x from inside the first box only.
            ([0.0, 0.9, 0.0], [-1.0, 0.0, 0.0], 0b0101, 0b0001),
        ];
        for (origin, dir, met, starts_in) in cases {
            let ray = Ray { origin, dir };
            // SAFETY: the processor has AVX2 and FMA (detected above).
            let one = unsafe { OneRay::new(&ray, f64::INFINITY) }.expect("ordinary numbers");
            // SAFETY: as above.
            let (found, tested, started) = unsafe { one_ray_boxes8(&one, &boxes) };
            assert_eq!((found, tested, started), (met, 4, starts_in), "{ray:?}");
        }
    }
}
