//! The scene's objects in a hierarchy of world-space boxes (a top-level BVH, as Embree's instances
//! have): a secondary ray tests only the objects whose box it meets, nearest box first, instead of
//! every object of the scene. The Cornell box's shadow and occlusion rays tested all fourteen of its
//! objects (twelve lone triangles, two meshes taken into their own space), now only those whose box
//! they meet.
//!
//! Culling only: an object whose box the ray meets is tested exactly as before, with the same
//! transform, method and t range, and a nearest-hit query keeps the earlier object on a tie, so the
//! hits are the same whatever order the boxes are visited in. The boxes are widened and their
//! distances rounded outward by far more than the objects' own tests can be off (a hit found in an
//! object's space, its t computed there), so no hit is culled.

// The traversal's stack is left uninitialised: entries below its depth are written before read.
#![allow(unsafe_code)]

use std::mem::MaybeUninit;

use glam::DVec3;

use super::cast::bits;
use super::kernels::Avx2;
use super::objects::{Geometry, PreparedObject, PreparedTriangle};
use super::{Prepared, Ray};

/// Scenes with fewer objects test each one (a box per object saves nothing there).
const MIN_OBJECTS: usize = 2;

/// How far a box's distances are moved outward, relative to the distance: far above the relative
/// error of the crack-free test's t (a weighted mean of the vertices' depths, weights of one sign:
/// a few roundings) and of a transform into an object's space.
const T_SLACK: f64 = 1e-5;

/// How far each box is widened, relative to the largest of its coordinates' magnitudes and its size.
const BOX_SLACK: f64 = 1e-7;

/// A box's lowest and highest corners.
type Bounds = ([f64; 3], [f64; 3]);

/// The box that holds no point.
fn empty() -> Bounds {
    ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3])
}

/// The smallest box holding `boxes`.
fn union<'a>(boxes: impl Iterator<Item = &'a Bounds>) -> Bounds {
    boxes.fold(empty(), |(lo, hi), (l, h)| {
        (
            std::array::from_fn(|k| lo[k].min(l[k])),
            std::array::from_fn(|k| hi[k].max(h[k])),
        )
    })
}

/// Half a box's surface area (the chance a ray through its parent meets it, up to a factor).
fn area((lo, hi): &Bounds) -> f64 {
    let [x, y, z] = std::array::from_fn(|k| (hi[k] - lo[k]).max(0.0));
    x * y + y * z + z * x
}

/// The lanes of `node` in `met` that hold something, farthest entry first (equal entries in lane
/// order), and how many.
#[inline(always)]
fn farthest_first(node: &Wide, near: &[f64; 4], met: u32) -> ([usize; 4], usize) {
    let mut lanes = [0usize; 4];
    let mut n = 0;
    for lane in 0..4 {
        if met & (1 << lane) != 0 && node.child[lane] != EMPTY {
            lanes[n] = lane;
            n += 1;
        }
    }
    for i in 1..n {
        let mut j = i;
        while j > 0 && near[lanes[j - 1]] < near[lanes[j]] {
            lanes.swap(j - 1, j);
            j -= 1;
        }
    }
    (lanes, n)
}

/// A node of the binary build: a box, and a leaf's object or an inner node's two children.
#[derive(Clone, Debug)]
struct Binary {
    bounds: Bounds,
    /// A leaf's object, or an inner node's second child (the first follows it).
    object_or_right: u32,
    leaf: bool,
}

/// The walks' stack entries, at most: each node's visit replaces one entry with at most four, and
/// the build keeps a quarter of the objects on each side of a split, so 3 entries for each of
/// log₄⁄₃ 2³² < 78 levels, and the root.
const STACK: usize = 3 * 78 + 1;

/// A lane of a wide node that holds nothing.
const EMPTY: u32 = u32::MAX;
/// Marks a lane's child as an object rather than a node.
const OBJECT: u32 = 1 << 31;

/// A node of the index: up to four children's boxes, axis by axis (so the four are tested
/// together), and what each child is: a node, an object (`OBJECT` set) or nothing (`EMPTY`).
#[derive(Clone, Debug)]
struct Wide {
    lo: [[f64; 4]; 3],
    hi: [[f64; 4]; 3],
    child: [u32; 4],
    /// How many lanes hold something (the first ones; the rest are `EMPTY`): the boxes one ray
    /// tests here.
    held: u64,
}

/// The objects' boxes in a four-wide hierarchy, built once per set of objects.
#[derive(Clone, Debug, Default)]
pub struct ObjectIndex {
    nodes: Vec<Wide>,
    /// Objects without a box (parallelograms, non-finite coordinates): tested by every ray.
    unbounded: Vec<u32>,
    /// True when every object of triangles is an OBJ mesh (watertight by default).
    triangles_all_meshes: bool,
    /// The lone triangles in one hierarchy, for packets of primary rays, when there are any.
    gathered: Option<Gathered>,
    /// Each object's box as a node of one lane (`None` for an object without one): a packet of
    /// nearest-hit rays tests it before walking the object's own hierarchy
    /// ([`ObjectIndex::packet_meets`]).
    #[cfg_attr(
        not(target_arch = "x86_64"),
        allow(dead_code, reason = "read by the x86-64 packets only")
    )]
    own_boxes: Vec<Option<Wide>>,
}

/// The triangles of every object that is [`gathers`]' kind (a triangle or a few, placed in the
/// world without a transform, with no hierarchy of their own) in one BVH, in world space, which is
/// their own: a packet of primary rays walks the Cornell box's twelve walls together, four
/// triangles at a time, rather than testing twelve objects ray by ray. Taken only with the
/// crack-free test ([`Gathered::applies`]), whose decisions are the triangle's alone, so each
/// triangle is decided as it is alone. Triangles are numbered in object order, so the hierarchy's
/// ties (to the lower number) are the objects'. (Secondary rays keep each wall's own box in the
/// index: a shadow ray from the floor meets the floor's flat box and no other, where a leaf of the
/// gathered hierarchy spans two walls; gathered, the Cornell box took 10% more instructions.)
#[derive(Clone, Debug)]
pub struct Gathered {
    /// The hierarchy over the triangles.
    pub bvh: super::bvh::Bvh,
    /// Triangle number → (object, its triangle).
    owners: Vec<(u32, u32)>,
    /// Object → whether its triangles are gathered here ([`gathers`], found once: asked of each
    /// object for every packet, it read each wall's vertices from memory, a cache miss a wall and
    /// 2% of the Cornell box's glass rays' instructions).
    holds: Vec<bool>,
    /// The box holding every gathered triangle.
    bounds: Bounds,
    /// Each gathered triangle's box, widened as an object's is ([`widened`]), when there are
    /// few enough for [`Gathered::beyond_reach`] to test them all.
    reach_boxes: Vec<Bounds>,
}

/// The most gathered triangles whose boxes [`Gathered::beyond_reach`] tests (each costs a packet
/// six compares; the Cornell box has twelve).
const REACH_BOXES_MOST: usize = 32;

impl Gathered {
    /// Triangle `number`'s object and its index there.
    pub fn owner(&self, number: usize) -> (usize, usize) {
        let (object, primitive) = self.owners[number];
        (object as usize, primitive as usize)
    }

    /// True when object `index`'s triangles are gathered here.
    #[inline(always)]
    pub fn holds(&self, index: usize) -> bool {
        self.holds.get(index).is_some_and(|&held| held)
    }

    /// True when `prepared` tests the gathered triangles with the crack-free test: what
    /// [`super::cast::crack_free_applies`] says of their objects, alike in all that decides it
    /// (none is a mesh, so the method is the scene's).
    pub fn applies(&self, prepared: &Prepared) -> bool {
        let (first, _) = self.owner(0);
        super::cast::crack_free_applies(prepared, &prepared.objects[first])
    }

    /// True when every ray starts within the gathered triangles' box: rays inside a room of them
    /// (the Cornell box's walls), where whatever else a ray meets in the room lies before the
    /// walls. A packet's nearest search then walks the walls after the meshes, with the hits
    /// found so far culling their boxes. (Which comes first changes no answer: the nearest hit,
    /// ties to the lower object and triangle, is found either way.)
    pub fn surrounds<const P: usize>(&self, rays: &[Ray; P]) -> bool {
        let (lo, hi) = &self.bounds;
        rays.iter()
            .all(|ray| (0..3).all(|k| lo[k] <= ray.origin[k] && ray.origin[k] <= hi[k]))
    }

    /// True when no gathered triangle can hold a hit of a packet's ray at t ≤ its `t_max` (its
    /// hit so far; the gathered triangles take the crack-free test, whose hits have t > 0): the
    /// box around every ray's segment, from its origin to t_max lengthened by 2·[`T_SLACK`] (far
    /// above the relative error of the test's t, as for the index's distances), widened as an
    /// object's box is, meets no gathered triangle's widened box. The two widenings, 10⁻⁷ of the
    /// coordinates, cover the rounding of the segments' ends, and of a t that errs relative to
    /// the vertices' distances rather than to t. A packet it answers true for need not walk the
    /// gathered triangles at all: 64% of the Cornell box's mirror-ray packets, most of them
    /// reflected inside the glass sphere, which they meet again long before any wall. False when
    /// some ray has no finite reach, or there are too many triangles to test.
    pub fn beyond_reach<const P: usize>(&self, rays: &[Ray; P], t_max: &[f64; P]) -> bool {
        // A ray that has met nothing (t_max = +∞) must walk: answered before any arithmetic.
        if self.reach_boxes.is_empty() || !t_max.iter().all(|t| t.is_finite()) {
            return false;
        }
        let (mut lo, mut hi) = empty();
        let mut finite = true;
        for (ray, &t) in rays.iter().zip(t_max) {
            let reach = t * (1.0 + 2.0 * T_SLACK);
            for k in 0..3 {
                let (origin, end) = (ray.origin[k], ray.origin[k] + reach * ray.dir[k]);
                finite &= end.is_finite();
                // Compares, not `min` and `max`, which pass over a NaN (`finite` catches it).
                let (near, far) = if origin < end {
                    (origin, end)
                } else {
                    (end, origin)
                };
                lo[k] = if near < lo[k] { near } else { lo[k] };
                hi[k] = if far > hi[k] { far } else { hi[k] };
            }
        }
        let Some((lo, hi)) = widened(lo, hi).filter(|_| finite) else {
            return false;
        };
        let meets = |(l, h): &Bounds| (0..3).all(|k| lo[k] <= h[k] && l[k] <= hi[k]);
        !self.reach_boxes.iter().any(meets)
    }
}

/// True for an object whose triangles the index gathers: not a mesh, untransformed, without a
/// hierarchy of its own, every coordinate finite.
pub fn gathers(object: &PreparedObject) -> bool {
    match &object.geometry {
        Geometry::Triangles { triangles, bvh } => {
            !object.is_mesh
                && object.object_from_world.is_none()
                && bvh.is_none()
                && triangles
                    .iter()
                    .all(|t| t.vertices.iter().flatten().all(|x| x.is_finite()))
        }
        Geometry::Parallelogram { .. } => false,
    }
}

/// The gathered triangles of `objects`, when more than one triangle is gathered.
fn gather(objects: &[PreparedObject]) -> Option<Gathered> {
    let mut triangles = Vec::new();
    let mut owners = Vec::new();
    let mut holds = vec![false; objects.len()];
    for (index, object) in objects.iter().enumerate() {
        if let (true, Geometry::Triangles { triangles: own, .. }) =
            (gathers(object), &object.geometry)
        {
            holds[index] = true;
            for (primitive, triangle) in own.iter().enumerate() {
                triangles.push(triangle.clone());
                owners.push((index as u32, primitive as u32));
            }
        }
    }
    let reach_boxes = match triangles.len() <= REACH_BOXES_MOST {
        true => triangles
            .iter()
            .map(|t| {
                let (lo, hi) = vertex_bounds(std::slice::from_ref(t));
                widened(lo, hi)
            })
            .collect::<Option<_>>()
            .unwrap_or_default(),
        false => Vec::new(),
    };
    (triangles.len() > 1).then(|| Gathered {
        bvh: super::bvh::Bvh::build(&triangles),
        owners,
        holds,
        bounds: vertex_bounds(&triangles),
        reach_boxes,
    })
}

/// A ray's numbers for the box test, worked out once per ray.
#[derive(Clone, Copy)]
struct Slabs {
    origin: [f64; 3],
    /// 1/d per axis; where d is 0 (or 1/d is not finite) ±10³⁰⁰, which puts the slab's planes
    /// at ±∞ on the side of the origin where they lie, at 0 where the origin is on one: a ray
    /// parallel to a slab is in it for all t or for none (or, on its plane, from t = 0 on: the
    /// boxes are widened, so that is only ever a little too much).
    inverse: [f64; 3],
}

impl Slabs {
    fn of(ray: &Ray) -> Slabs {
        Slabs {
            origin: ray.origin,
            inverse: ray.dir.map(|d| {
                let inverse = 1.0 / d;
                if inverse.is_finite() {
                    inverse
                } else {
                    1e300_f64.copysign(d)
                }
            }),
        }
    }

    /// Each lane's distance of entry into its box, rounded down, and whether the ray meets the
    /// box within [t_min, t_max] (its distances rounded outward). The four lanes alike, without
    /// branches (min and max as comparisons), so the compiler tests them in vector registers.
    #[inline(always)]
    fn enter(&self, node: &Wide, (t_min, t_max): (f64, f64)) -> ([f64; 4], u32) {
        let min = |a: f64, b: f64| if a < b { a } else { b };
        let max = |a: f64, b: f64| if a > b { a } else { b };
        let mut near = [t_min; 4];
        let mut far = [f64::INFINITY; 4];
        for k in 0..3 {
            for lane in 0..4 {
                let a = (node.lo[k][lane] - self.origin[k]) * self.inverse[k];
                let b = (node.hi[k][lane] - self.origin[k]) * self.inverse[k];
                near[lane] = max(near[lane], min(a, b));
                far[lane] = min(far[lane], max(a, b));
            }
        }
        let mut met = 0;
        for lane in 0..4 {
            near[lane] -= T_SLACK * near[lane].abs();
            far[lane] += T_SLACK * far[lane].abs();
            let inside = near[lane] <= far[lane] && far[lane] >= t_min && near[lane] <= t_max;
            met |= u32::from(inside) << lane;
        }
        (near, met)
    }

    /// [`Slabs::enter`], compiled with AVX2 where `simd` proves the processor has it (the same
    /// operations, four lanes to a register).
    #[inline(always)]
    fn enter_on(&self, simd: Option<Avx2>, node: &Wide, range: (f64, f64)) -> ([f64; 4], u32) {
        match simd {
            #[cfg(target_arch = "x86_64")]
            // SAFETY: an `Avx2` exists only on a processor with AVX2 and FMA.
            Some(_) => unsafe { self.enter_avx2(node, range) },
            _ => self.enter(node, range),
        }
    }

    /// [`Slabs::enter`] in AVX2 intrinsics: the same operations in the same order, a box a lane
    /// (`_mm256_min_pd(a, b)` is `if a < b { a } else { b }`, NaN included, and `max` alike), so
    /// the same answers. Left to the compiler, the loop took 118 instructions a call.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma,popcnt,bmi1")]
    fn enter_avx2(&self, node: &Wide, (t_min, t_max): (f64, f64)) -> ([f64; 4], u32) {
        use std::arch::x86_64::*;
        // SAFETY: each row is four f64s, read unaligned; the target features are enabled here.
        let row = |row: &[f64; 4]| unsafe { _mm256_loadu_pd(row.as_ptr()) };
        let mut near = _mm256_set1_pd(t_min);
        let mut far = _mm256_set1_pd(f64::INFINITY);
        for k in 0..3 {
            let origin = _mm256_set1_pd(self.origin[k]);
            let inverse = _mm256_set1_pd(self.inverse[k]);
            let a = _mm256_mul_pd(_mm256_sub_pd(row(&node.lo[k]), origin), inverse);
            let b = _mm256_mul_pd(_mm256_sub_pd(row(&node.hi[k]), origin), inverse);
            near = _mm256_max_pd(near, _mm256_min_pd(a, b));
            far = _mm256_min_pd(far, _mm256_max_pd(a, b));
        }
        let sign = _mm256_set1_pd(-0.0);
        let slack = _mm256_set1_pd(T_SLACK);
        near = _mm256_sub_pd(near, _mm256_mul_pd(slack, _mm256_andnot_pd(sign, near)));
        far = _mm256_add_pd(far, _mm256_mul_pd(slack, _mm256_andnot_pd(sign, far)));
        let inside = _mm256_and_pd(
            _mm256_cmp_pd::<_CMP_LE_OQ>(near, far),
            _mm256_and_pd(
                _mm256_cmp_pd::<_CMP_GE_OQ>(far, _mm256_set1_pd(t_min)),
                _mm256_cmp_pd::<_CMP_LE_OQ>(near, _mm256_set1_pd(t_max)),
            ),
        );
        let mut nears = [0.0; 4];
        // SAFETY: four f64s into a four-f64 array.
        unsafe { _mm256_storeu_pd(nears.as_mut_ptr(), near) };
        (nears, _mm256_movemask_pd(inside) as u32)
    }
}

/// A packet's [`Slabs`], a row per axis and a lane per ray, so that one box is tested against
/// four rays at once.
#[cfg(target_arch = "x86_64")]
#[repr(C, align(32))]
struct PacketSlabs<const P: usize> {
    origin: [[f64; P]; 3],
    inverse: [[f64; P]; 3],
}

#[cfg(target_arch = "x86_64")]
impl<const P: usize> PacketSlabs<P> {
    /// [`Slabs::of`] for the rays of `taking`, four at a time in lanes (the same division and the
    /// same stand-in for a 1/d that is not finite, so the same bits); a four that no ray of
    /// `taking` is in is left as it was. Made from the rays, without each ray's [`Slabs`] first:
    /// their transposing cost a shadow ray more than its box tests at the index's root.
    ///
    /// # Safety
    /// Only call on a processor with AVX2 and FMA.
    #[target_feature(enable = "avx2,fma,popcnt,bmi1")]
    fn fill(&mut self, rays: &[Ray; P], taking: u32) {
        use std::arch::x86_64::*;
        let sign = _mm256_set1_pd(-0.0);
        for group in 0..P / 4 {
            let r = 4 * group;
            if (taking >> r) & 0b1111 == 0 {
                continue;
            }
            for k in 0..3 {
                let lane = |i: usize| &rays[r + i];
                let origin = _mm256_setr_pd(
                    lane(0).origin[k],
                    lane(1).origin[k],
                    lane(2).origin[k],
                    lane(3).origin[k],
                );
                let dir = _mm256_setr_pd(
                    lane(0).dir[k],
                    lane(1).dir[k],
                    lane(2).dir[k],
                    lane(3).dir[k],
                );
                let inverse = _mm256_div_pd(_mm256_set1_pd(1.0), dir);
                // Where 1/d is not finite: 10³⁰⁰ with d's sign, as `Slabs::of` puts it.
                let finite = _mm256_cmp_pd::<_CMP_LT_OQ>(
                    _mm256_andnot_pd(sign, inverse),
                    _mm256_set1_pd(f64::INFINITY),
                );
                let stand_in = _mm256_or_pd(_mm256_and_pd(sign, dir), _mm256_set1_pd(1e300));
                let inverse = _mm256_blendv_pd(stand_in, inverse, finite);
                // SAFETY: four f64s at lane r (a multiple of four, below P) of P-f64 rows.
                unsafe {
                    _mm256_storeu_pd(self.origin[k].as_mut_ptr().add(r), origin);
                    _mm256_storeu_pd(self.inverse[k].as_mut_ptr().add(r), inverse);
                }
            }
        }
    }

    /// Every row zero, for [`PacketSlabs::fill`] (filled in place: returned, its 768 bytes were
    /// copied).
    #[inline(always)]
    fn zero() -> PacketSlabs<P> {
        PacketSlabs {
            origin: [[0.0; P]; 3],
            inverse: [[0.0; P]; 3],
        }
    }

    /// Per lane of `node`, the rays of `live` that meet its box within [t_min, t_max[r]]: what
    /// [`Slabs::enter`] answers for each ray, by the same operations in the same order (a ray a
    /// lane rather than a box a lane), so the same bits; and how many rays `live` holds.
    ///
    /// The rays are taken four at a time: `P` must be a multiple of four (the caller checks), or
    /// the last few would go untested. Only the lanes that hold something are tested: the others
    /// answer no ray (their infinite empty boxes would be met, and are never walked into).
    ///
    /// # Safety
    /// Only call on a processor with AVX2 and FMA.
    #[target_feature(enable = "avx2,fma,popcnt,bmi1")]
    fn enter_avx2(
        &self,
        node: &Wide,
        live: u32,
        (t_min, t_max): (f64, &[f64; P]),
    ) -> ([u32; 4], u64) {
        use std::arch::x86_64::*;
        let sign = _mm256_set1_pd(-0.0);
        let slack = _mm256_set1_pd(T_SLACK);
        let low = _mm256_set1_pd(t_min);
        // The four boxes' rays, sixteen bits each, in one register. (Or-ed into a [u32; 4] on the
        // stack a lane at a time and read back as one wide load, which waited for the four
        // stores: 4% of a Cornell box shadow ray's time.)
        const { assert!(P <= 16, "a box's rays are sixteen bits of one u64") };
        let mut met_by = 0u64;
        for group in 0..P / 4 {
            if (live >> (4 * group)) & 0b1111 == 0 {
                continue;
            }
            let at = 4 * group;
            // SAFETY: four f64s at lane `at` (a multiple of four, below P) of P-f64 rows, read
            // unaligned; the target features are enabled here.
            let row = |row: &[f64; P]| unsafe { _mm256_loadu_pd(row.as_ptr().add(at)) };
            let origin = [0, 1, 2].map(|k| row(&self.origin[k]));
            let inverse = [0, 1, 2].map(|k| row(&self.inverse[k]));
            let high = row(t_max);
            for lane in 0..(node.held as usize).min(4) {
                let mut near = low;
                let mut far = _mm256_set1_pd(f64::INFINITY);
                for k in 0..3 {
                    let lo = _mm256_set1_pd(node.lo[k][lane]);
                    let hi = _mm256_set1_pd(node.hi[k][lane]);
                    let a = _mm256_mul_pd(_mm256_sub_pd(lo, origin[k]), inverse[k]);
                    let b = _mm256_mul_pd(_mm256_sub_pd(hi, origin[k]), inverse[k]);
                    near = _mm256_max_pd(near, _mm256_min_pd(a, b));
                    far = _mm256_min_pd(far, _mm256_max_pd(a, b));
                }
                near = _mm256_sub_pd(near, _mm256_mul_pd(slack, _mm256_andnot_pd(sign, near)));
                far = _mm256_add_pd(far, _mm256_mul_pd(slack, _mm256_andnot_pd(sign, far)));
                let inside = _mm256_and_pd(
                    _mm256_cmp_pd::<_CMP_LE_OQ>(near, far),
                    _mm256_and_pd(
                        _mm256_cmp_pd::<_CMP_GE_OQ>(far, low),
                        _mm256_cmp_pd::<_CMP_LE_OQ>(near, high),
                    ),
                );
                met_by |= (_mm256_movemask_pd(inside) as u64) << (at + 16 * lane);
            }
        }
        let rays = |lane: usize| (met_by >> (16 * lane)) as u32 & 0xffff & live;
        // The count here, where POPCNT is enabled: the caller's took a dozen instructions.
        (
            [rays(0), rays(1), rays(2), rays(3)],
            u64::from(live.count_ones()),
        )
    }
}

impl ObjectIndex {
    /// The index of `objects`' world-space boxes.
    pub fn new(objects: &[PreparedObject]) -> ObjectIndex {
        let mut bounded = Vec::new();
        let mut unbounded = Vec::new();
        for (index, object) in objects.iter().enumerate() {
            match world_box(object) {
                Some(b) => bounded.push((index as u32, b)),
                None => unbounded.push(index as u32),
            }
        }
        let mut own_boxes = vec![None; objects.len()];
        for &(object, bounds) in &bounded {
            let leaf = Binary {
                bounds,
                object_or_right: object,
                leaf: true,
            };
            own_boxes[object as usize] = Some(Wide::of(&[leaf], &[0]));
        }
        let mut binary = Vec::with_capacity(2 * bounded.len());
        if !bounded.is_empty() {
            build(&mut binary, &mut bounded);
        }
        let mut index = ObjectIndex {
            nodes: Vec::with_capacity(bounded.len() / 2 + 1),
            unbounded,
            triangles_all_meshes: objects.iter().all(|object| {
                object.is_mesh || matches!(object.geometry, Geometry::Parallelogram { .. })
            }),
            gathered: gather(objects),
            own_boxes,
        };
        if let Some(root) = binary.first() {
            if root.leaf {
                // One object: a root with one lane.
                index.nodes.push(Wide::of(&binary, &[0]));
            } else {
                index.widen(&binary, 0);
            }
        }
        index
    }

    /// Appends the wide node for binary inner node `at` (its children's children taken up into
    /// it, the largest first, until it has four), then those of its inner children; its index.
    fn widen(&mut self, binary: &[Binary], at: usize) -> u32 {
        let children_of = |at: usize| [at + 1, binary[at].object_or_right as usize];
        let mut lanes: Vec<usize> = children_of(at).to_vec();
        while lanes.len() < 4 {
            let largest = lanes
                .iter()
                .enumerate()
                .filter(|(_, c)| !binary[**c].leaf)
                .max_by(|a, b| area(&binary[*a.1].bounds).total_cmp(&area(&binary[*b.1].bounds)));
            let Some((lane, &child)) = largest else {
                break;
            };
            lanes.splice(lane..=lane, children_of(child));
        }
        let here = self.nodes.len();
        self.nodes.push(Wide::of(binary, &lanes));
        for (lane, &child) in lanes.iter().enumerate() {
            if !binary[child].leaf {
                self.nodes[here].child[lane] = self.widen(binary, child);
            }
        }
        here as u32
    }

    /// Calls `test(object, t_max)` for the objects without a box, then for every object whose box
    /// the ray meets within [t_min, t_max], nearest box first. `test` answers the t_max from then
    /// on: the nearest hit so far, or −∞ to stop (an any-hit query's hit). Counts the box tests.
    /// With `ANY` (an any-hit query, which any hit ends), an index of one node visits last the
    /// boxes the ray starts in (entered at t_min): they hold the surface a shadow ray leaves, which
    /// it cannot hit.
    #[inline(always)]
    pub fn visit<const ANY: bool>(
        &self,
        simd: Option<Avx2>,
        ray: &Ray,
        (t_min, mut t_max): (f64, f64),
        box_tests: &mut u64,
        mut test: impl FnMut(usize, f64) -> f64,
    ) {
        for &object in &self.unbounded {
            if t_max < t_min {
                return;
            }
            t_max = test(object as usize, t_max);
        }
        if self.nodes.is_empty() || t_max < t_min {
            return;
        }
        let slabs = Slabs::of(ray);
        if let [root] = self.nodes.as_slice() {
            // A root that holds every object (a scene of up to four boxes): its objects in
            // order, nearest first, without the stack.
            *box_tests += root.held;
            let (near, met) = slabs.enter_on(simd, root, (t_min, t_max));
            let (lanes, n) = farthest_first(root, &near, met);
            debug_assert!(
                lanes[..n]
                    .iter()
                    .all(|&lane| root.child[lane] & OBJECT != 0)
            );
            // Nearest first the boxes ahead, then (with `ANY`) those the ray starts in.
            let mut deferred = 0u32;
            for &lane in lanes[..n].iter().rev() {
                if ANY && near[lane] <= t_min {
                    deferred |= 1 << lane;
                } else if near[lane] <= t_max {
                    t_max = test((root.child[lane] & !OBJECT) as usize, t_max);
                }
            }
            for &lane in lanes[..n].iter().rev() {
                if deferred & (1 << lane) != 0 && near[lane] <= t_max {
                    t_max = test((root.child[lane] & !OBJECT) as usize, t_max);
                }
            }
            return;
        }
        let mut stack = [const { MaybeUninit::<(u32, f64)>::uninit() }; STACK];
        stack[0] = MaybeUninit::new((0, t_min));
        let mut depth = 1;
        while depth > 0 {
            depth -= 1;
            // SAFETY: the entries below `depth` were written (here or in the loop below).
            let (child, near) = unsafe { stack[depth].assume_init() };
            if near > t_max {
                continue;
            }
            if child & OBJECT != 0 {
                t_max = test((child & !OBJECT) as usize, t_max);
                continue;
            }
            let node = &self.nodes[child as usize];
            *box_tests += node.held;
            let (near, met) = slabs.enter_on(simd, node, (t_min, t_max));
            // Farthest first, so the nearest is popped next.
            let (lanes, n) = farthest_first(node, &near, met);
            for &lane in &lanes[..n] {
                stack[depth] = MaybeUninit::new((node.child[lane], near[lane]));
                depth += 1;
            }
        }
    }
}

/// A packet's rays made ready for the test of single objects' boxes
/// ([`ObjectIndex::packet_meets`]), once for all the objects.
#[cfg(target_arch = "x86_64")]
pub struct PacketBoxes<const P: usize>(PacketSlabs<P>);

#[cfg(target_arch = "x86_64")]
impl<const P: usize> PacketBoxes<P> {
    /// Rows to fill ([`PacketBoxes::fill`]), in the caller's frame: returned filled, their 768
    /// bytes were copied.
    #[inline(always)]
    pub fn zero() -> PacketBoxes<P> {
        PacketBoxes(PacketSlabs::zero())
    }

    /// The packet's rays. `P` must be a multiple of four.
    pub fn fill(&mut self, _: Avx2, rays: &[Ray; P]) {
        const {
            assert!(
                P.is_multiple_of(4) && P <= 32,
                "rays are taken four at a time"
            )
        };
        // SAFETY: an `Avx2` exists only on a processor with AVX2 and FMA.
        unsafe { self.0.fill(rays, super::ray::all_rays::<P>()) };
    }
}

#[cfg(target_arch = "x86_64")]
impl ObjectIndex {
    /// Which of the packet's rays meet object `object`'s box within [0, t_max[r]] (all of them
    /// where the object has no box): the box test the one-ray walk ([`ObjectIndex::visit`]) culls
    /// an object by, so the object holds no hit in that range for the others. The rays' numbers
    /// must be finite. Counts a box test per ray.
    pub fn packet_meets<const P: usize>(
        &self,
        _: Avx2,
        rays: &PacketBoxes<P>,
        object: usize,
        t_max: &[f64; P],
        box_tests: &mut u64,
    ) -> u32 {
        let every = super::ray::all_rays::<P>();
        let Some(Some(own)) = self.own_boxes.get(object) else {
            return every;
        };
        // SAFETY: an `Avx2` exists only on a processor with AVX2 and FMA.
        let (met_by, tested) = unsafe { rays.0.enter_avx2(own, every, (0.0, t_max)) };
        *box_tests += tested;
        met_by[0]
    }
}

impl ObjectIndex {
    /// The lone triangles gathered in one hierarchy, if any.
    pub fn gathered(&self) -> Option<&Gathered> {
        self.gathered.as_ref()
    }

    /// For `P` any-hit queries together (a hit's occlusion or shadow rays): calls
    /// `test(object, rays)` with the rays of `taking` (a bit set) still unblocked whose range
    /// [t_min, t_max[r]] meets the object's box, in no particular order (an any-hit answer does not
    /// depend on it), and first for the objects without a box. `test` answers which of those rays
    /// the object blocks; they leave the walk, which ends when none is left. Each ray's numbers
    /// must be finite. A node's boxes are tested four rays at once where `simd` allows (the same
    /// answers as each ray alone). Counts the box tests, one ray at a time. Returns the rays
    /// blocked.
    #[inline(always)]
    pub fn visit_any<const P: usize>(
        &self,
        simd: Option<Avx2>,
        (rays, taking): (&[Ray; P], u32),
        (t_min, t_max): (f64, &[f64; P]),
        box_tests: &mut u64,
        mut test: impl FnMut(usize, u32) -> u32,
    ) -> u32 {
        let mut open = taking;
        for &object in &self.unbounded {
            if open == 0 {
                return taking;
            }
            open &= !test(object as usize, open);
        }
        if self.nodes.is_empty() {
            return taking & !open;
        }
        #[cfg(target_arch = "x86_64")]
        if simd.is_some() && P.is_multiple_of(4) {
            let mut lanes = PacketSlabs::zero();
            // SAFETY: an `Avx2` exists only on a processor with AVX2 and FMA.
            unsafe { lanes.fill(rays, taking) };
            let boxes = |node: &Wide, live: u32| {
                // SAFETY: as above.
                unsafe { lanes.enter_avx2(node, live, (t_min, t_max)) }
            };
            return taking & !self.walk_any(open, box_tests, boxes, test);
        }
        let unused = Slabs {
            origin: [0.0; 3],
            inverse: [0.0; 3],
        };
        let mut slabs = [unused; P];
        for r in bits(taking) {
            slabs[r] = Slabs::of(&rays[r]);
        }
        let boxes = |node: &Wide, live: u32| {
            let mut met_by = [0u32; 4];
            for r in bits(live) {
                let (_, met) = slabs[r].enter_on(simd, node, (t_min, t_max[r]));
                for (lane, rays) in met_by.iter_mut().enumerate() {
                    *rays |= ((met >> lane) & 1) << r;
                }
            }
            (met_by, u64::from(live.count_ones()))
        };
        taking & !self.walk_any(open, box_tests, boxes, test)
    }

    /// [`ObjectIndex::visit_any`]'s walk from the root, `boxes(node, live)` answering which of the
    /// rays of `live` meet each of a node's boxes, and how many rays `live` holds: the rays of
    /// `open` still open at its end.
    #[inline(always)]
    fn walk_any(
        &self,
        mut open: u32,
        box_tests: &mut u64,
        boxes: impl Fn(&Wide, u32) -> ([u32; 4], u64),
        mut test: impl FnMut(usize, u32) -> u32,
    ) -> u32 {
        let mut stack = [const { MaybeUninit::<(u32, u32)>::uninit() }; STACK];
        stack[0] = MaybeUninit::new((0, open));
        let mut depth = 1;
        while depth > 0 {
            depth -= 1;
            // SAFETY: the entries below `depth` were written (here or in the loop below).
            let (child, rays_in) = unsafe { stack[depth].assume_init() };
            let live = rays_in & open;
            if live == 0 {
                continue;
            }
            if child & OBJECT != 0 {
                open &= !test((child & !OBJECT) as usize, live);
                continue;
            }
            let node = &self.nodes[child as usize];
            let (met_by, rays) = boxes(node, live);
            *box_tests += node.held * rays;
            for (rays, child) in met_by.into_iter().zip(node.child) {
                if rays != 0 && child != EMPTY {
                    stack[depth] = MaybeUninit::new((child, rays));
                    depth += 1;
                }
            }
        }
        open
    }
}

impl Wide {
    /// The wide node over binary nodes `lanes` (leaves become objects; inner nodes are filled in
    /// by the caller).
    fn of(binary: &[Binary], lanes: &[usize]) -> Wide {
        let mut wide = Wide {
            lo: [[f64::INFINITY; 4]; 3],
            hi: [[f64::NEG_INFINITY; 4]; 3],
            child: [EMPTY; 4],
            held: lanes.len() as u64,
        };
        for (lane, &at) in lanes.iter().enumerate() {
            let node = &binary[at];
            for k in 0..3 {
                wide.lo[k][lane] = node.bounds.0[k];
                wide.hi[k][lane] = node.bounds.1[k];
            }
            if node.leaf {
                wide.child[lane] = OBJECT | node.object_or_right;
            }
        }
        wide
    }
}

/// Appends the binary subtree over `items` to `nodes`: a leaf for one object, else split where the
/// two halves' boxes cost least by the surface area heuristic (each axis's order of the boxes'
/// centres, every place in it: the objects are few).
fn build(nodes: &mut Vec<Binary>, items: &mut [(u32, Bounds)]) {
    let at = nodes.len();
    nodes.push(Binary {
        bounds: union(items.iter().map(|(_, b)| b)),
        object_or_right: items[0].0,
        leaf: items.len() == 1,
    });
    if items.len() == 1 {
        return;
    }
    let centre = |b: &Bounds, k: usize| b.0[k] + b.1[k];
    let mut best = (f64::INFINITY, 0, items.len() / 2);
    for axis in 0..3 {
        items.sort_by(|a, b| centre(&a.1, axis).total_cmp(&centre(&b.1, axis)));
        // The area of the first i boxes' union, for every i, then the same from the right.
        let mut left = vec![0.0; items.len()];
        let mut running = empty();
        for (i, item) in items.iter().enumerate() {
            running = union([&running, &item.1].into_iter());
            left[i] = area(&running);
        }
        let mut running = empty();
        // Splits that keep a quarter of the objects on each side at least: the tree's depth stays
        // within log₄⁄₃ n (the traversal's stack is sized by it).
        let n = items.len();
        let keep = (n / 4).max(1);
        for split in (1..n).rev() {
            running = union([&running, &items[split].1].into_iter());
            let cost = left[split - 1] * split as f64 + area(&running) * (n - split) as f64;
            if cost < best.0 && split >= keep && n - split >= keep {
                best = (cost, axis, split);
            }
        }
    }
    let (_, axis, split) = best;
    items.sort_by(|a, b| centre(&a.1, axis).total_cmp(&centre(&b.1, axis)));
    let (left, right) = items.split_at_mut(split);
    build(nodes, left);
    nodes[at].object_or_right = nodes.len() as u32;
    build(nodes, right);
}

/// True when `prepared`'s secondary rays may go through the object index: every triangle takes
/// the crack-free test, whose hit lies on the triangle (its t a weighted mean of the vertices'
/// depths along the ray, the weights of one sign), so in the triangle's box. The float methods
/// may report a ray in a triangle's plane as a hit at any t, far off the triangle, and the bugs
/// accept points off a triangle or t < 0, or change what t means: there every object is tested,
/// as before.
///
/// (What [`super::cast::crack_free_applies`] says of each triangle object, decided once for them all.)
pub fn applies(prepared: &Prepared) -> bool {
    use super::Bug;
    use crate::intersect::Method;
    prepared.objects.len() >= MIN_OBJECTS
        && matches!(prepared.bug, None | Some(Bug::ShadowAcne))
        && match prepared.method {
            Some(method) => method == Method::Watertight,
            // Watertight is the default for meshes alone.
            None => prepared.object_index().triangles_all_meshes,
        }
}

/// The index for `ray`, when the ray may go through it ([`applies`], and every number of the ray
/// finite: a box test on others could cull wrongly); `None` tests every object in turn.
#[inline(always)]
pub fn for_ray<'a>(prepared: &'a Prepared, ray: &Ray) -> Option<&'a ObjectIndex> {
    (ray.is_finite() && applies(prepared)).then(|| prepared.object_index())
}

/// The object's box in world space, widened ([`BOX_SLACK`]); `None` when not finite, and for a
/// parallelogram, whose solver may find a ray nearly in its plane at a t far off it (such a ray's
/// hit is as the solver says, so a parallelogram is tested by every ray).
fn world_box(object: &PreparedObject) -> Option<Bounds> {
    let corners: Vec<DVec3> = match &object.geometry {
        Geometry::Triangles { triangles, .. } => {
            let (lo, hi) = vertex_bounds(triangles);
            box_corners(lo, hi)
        }
        Geometry::Parallelogram { .. } => return None,
    };
    if corners.is_empty() {
        return None;
    }
    // Into world space (M), when the object has a transform.
    let world: Vec<DVec3> = match object.object_from_world {
        Some(_) => corners
            .iter()
            .map(|c| object.world_from_object.transform_point3(*c))
            .collect(),
        None => corners,
    };
    let lo = world.iter().fold(DVec3::INFINITY, |m, c| m.min(*c));
    let hi = world.iter().fold(DVec3::NEG_INFINITY, |m, c| m.max(*c));
    widened(lo.to_array(), hi.to_array())
}

/// The box [lo, hi] widened by [`BOX_SLACK`] of its largest coordinate's magnitude or size;
/// `None` when it is not finite.
fn widened(lo: [f64; 3], hi: [f64; 3]) -> Option<Bounds> {
    let (lo, hi) = (DVec3::from_array(lo), DVec3::from_array(hi));
    if !(lo.is_finite() && hi.is_finite()) {
        return None;
    }
    let pad = BOX_SLACK * lo.abs().max(hi.abs()).max(hi - lo).max_element() + f64::MIN_POSITIVE;
    Some(((lo - pad).to_array(), (hi + pad).to_array()))
}

/// The smallest box holding the triangles' vertices (empty for no triangle).
fn vertex_bounds(triangles: &[PreparedTriangle]) -> Bounds {
    triangles
        .iter()
        .flat_map(|t| &t.vertices)
        .fold(empty(), |(lo, hi), v| {
            (
                std::array::from_fn(|k| lo[k].min(v[k])),
                std::array::from_fn(|k| hi[k].max(v[k])),
            )
        })
}

/// The eight corners of the box [lo, hi] (none for an empty one).
fn box_corners(lo: [f64; 3], hi: [f64; 3]) -> Vec<DVec3> {
    if (0..3).any(|k| lo[k] > hi[k]) {
        return Vec::new();
    }
    (0..8)
        .map(|i| {
            DVec3::new(
                if i & 1 == 0 { lo[0] } else { hi[0] },
                if i & 2 == 0 { lo[1] } else { hi[1] },
                if i & 4 == 0 { lo[2] } else { hi[2] },
            )
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use glam::{DAffine3, DMat3, DQuat};
    use rand::{Rng, SeedableRng};
    use std::sync::Arc;

    #[cfg(target_arch = "x86_64")]
    use super::PacketSlabs;
    use super::{EMPTY, OBJECT, Slabs, Wide};
    use crate::intersect::Method;
    use crate::render::cast::{
        any_hit, any_of_each_object, nearest_hit_between, nearest_of_each_object,
    };
    use crate::render::kernels::parallelogram4::Parallelogram4Parts;
    use crate::render::objects::{Geometry, PreparedObject, PreparedTriangle};
    use crate::render::ray_log::rays_cast;
    use crate::render::{Prepared, Ray, Stats};

    /// Every shipped render scene, shrunk so a debug build logs its rays quickly.
    fn shipped() -> Vec<(String, Prepared)> {
        crate::render::shipped_scenes(24, 16)
    }

    /// The shipped Cornell box, shrunk as [`shipped`] shrinks it.
    fn cornell_box() -> (String, Prepared) {
        shipped()
            .into_iter()
            .find(|(name, _)| name.contains("cornell"))
            .expect("the Cornell box is shipped")
    }

    /// Objects under awkward transforms: rotated, sheared, scaled by 10⁻⁶ and 10⁶, a sliver
    /// triangle and parallelograms, placed at random, some sharing planes and edges.
    fn awkward(seed: u64) -> Prepared {
        let mut random = rand_pcg::Pcg64::seed_from_u64(seed);
        let (_, mut prepared) = shipped().swap_remove(0);
        let mut objects = Vec::new();
        for i in 0..24 {
            let mut point =
                || -> [f64; 3] { std::array::from_fn(|_| random.random_range(-2.0..2.0)) };
            let geometry = if i % 3 == 0 {
                let [corner, e1, e2] = [point(), point(), point()];
                let lanes = Parallelogram4Parts::of([&corner, &e1, &e2]);
                Geometry::Parallelogram {
                    corner,
                    e1,
                    e2,
                    face_normal: [0.0, 0.0, 1.0],
                    lanes,
                }
            } else {
                let (a, b) = (point(), point());
                // Every fourth a sliver along a − b.
                let c = if i % 4 == 1 {
                    std::array::from_fn(|k| a[k] + 1e-9 * b[k])
                } else {
                    point()
                };
                Geometry::Triangles {
                    triangles: Arc::new([PreparedTriangle::new([a, b, c])]),
                    bvh: None,
                }
            };
            let scale = [1e-6, 1.0, 1e6, 3.0][i % 4];
            let world_from_object = DAffine3::from_scale_rotation_translation(
                glam::DVec3::new(scale, scale * 0.5, scale * 2.0),
                DQuat::from_euler(glam::EulerRot::XYZ, i as f64, 0.3 * i as f64, 1.0),
                glam::DVec3::from(point()),
            );
            let moved = i % 2 == 1;
            objects.push(PreparedObject {
                geometry,
                object_from_world: moved.then(|| world_from_object.inverse()),
                world_from_object: if moved {
                    world_from_object
                } else {
                    DAffine3::IDENTITY
                },
                normal_to_world: DMat3::IDENTITY,
                color: [0.5; 3],
                texture: None,
                is_mesh: false,
            });
        }
        prepared.objects = objects.into();
        prepared.index = Default::default();
        prepared.method = Some(Method::Watertight);
        assert!(super::applies(&prepared));
        prepared
    }

    /// Rays at random and along the axes (directions with zero components), from inside and
    /// outside the scene, and rays that run in an object's plane through its corners.
    fn rays(prepared: &Prepared, seed: u64) -> Vec<Ray> {
        let mut random = rand_pcg::Pcg64::seed_from_u64(seed);
        let mut rays = Vec::new();
        for i in 0..3000 {
            let origin: [f64; 3] = std::array::from_fn(|_| random.random_range(-4.0..4.0));
            let mut dir: [f64; 3] = std::array::from_fn(|_| random.random_range(-1.0..1.0));
            if i % 5 == 0 {
                dir[i % 3] = 0.0;
            }
            if i % 7 == 0 {
                dir = [0.0; 3];
                dir[i % 3] = 1.0;
            }
            rays.push(Ray::new(origin, dir));
        }
        // Along the edges and through the corners of every object, in world space.
        for object in prepared.objects.iter() {
            let corners: Vec<[f64; 3]> = match &object.geometry {
                Geometry::Triangles { triangles, .. } => {
                    triangles.iter().take(8).flat_map(|t| t.vertices).collect()
                }
                Geometry::Parallelogram { corner, e1, e2, .. } => {
                    vec![*corner, std::array::from_fn(|k| corner[k] + e1[k] + e2[k])]
                }
            };
            let world: Vec<[f64; 3]> = corners
                .iter()
                .map(|c| {
                    object
                        .world_from_object
                        .transform_point3((*c).into())
                        .to_array()
                })
                .collect();
            for pair in world.windows(2) {
                let dir = std::array::from_fn(|k| pair[1][k] - pair[0][k]);
                let back = std::array::from_fn(|k| pair[0][k] - 0.5 * dir[k]);
                rays.push(Ray::new(back, dir));
            }
        }
        rays
    }

    /// The index's queries against every object tested in turn, on `rays`: the same nearest hit
    /// (object, primitive, t and where on it) and the same answer to every any-hit query.
    fn agree(name: &str, prepared: &Prepared, rays: &[Ray]) -> usize {
        let mut met = 0;
        let mut stats = Stats::default();
        for (i, ray) in rays.iter().enumerate() {
            let nearest = nearest_hit_between(prepared, *ray, (0.0, f64::INFINITY), &mut stats);
            let each = nearest_of_each_object(prepared, *ray, (0.0, f64::INFINITY), &mut stats);
            assert_eq!(nearest, each, "{name}: ray {i} {ray:?}");
            met += usize::from(nearest.is_some());
            // Ending just before, at and past the nearest hit, and at a few lengths.
            let ends = match nearest {
                Some(hit) => vec![hit.t.next_down(), hit.t, hit.t.next_up(), 2.0 * hit.t],
                None => vec![0.5, 3.0, f64::INFINITY],
            };
            for t_max in ends {
                let range = (0.0, t_max);
                let blocked = any_hit(prepared, ray, range, &mut stats);
                assert_eq!(
                    blocked,
                    any_of_each_object(prepared, ray, range, &mut stats),
                    "{name}: ray {i} {ray:?} up to {t_max}"
                );
                // The any-hit query and the nearest hit take their own ways through an object
                // (lone triangles, parallelograms, meshes), to the same decisions.
                assert_eq!(
                    blocked,
                    nearest.is_some_and(|hit| hit.t < t_max),
                    "{name}: ray {i} {ray:?} up to {t_max}, against the nearest hit"
                );
            }
        }
        together(name, prepared, rays);
        met
    }

    /// The queries of rays together against the same rays one at a time: sixteen at a time, the
    /// packet's nearest hits (the gathered lone triangles in one hierarchy) the same to the bit as
    /// [`nearest_hit`]'s, and [`any_hits`] the same answers as testing every object for each ray,
    /// with every ray, every other one, rays of the first four or eight lanes only (which the index
    /// walks as a packet of four or eight) or a single one taking part, and each ray ending just
    /// before, at or past its nearest hit, or at a few lengths.
    fn together(name: &str, prepared: &Prepared, rays: &[Ray]) {
        use crate::render::cast::{
            TOGETHER, any_hits, nearest_hit, nearest_hit_between, nearest_hits,
            nearest_hits_between,
        };
        let mut stats = Stats::default();
        let bits = |h: Option<crate::render::Hit>| {
            h.map(|h| {
                (
                    h.object,
                    h.primitive,
                    h.t.to_bits(),
                    h.coordinates().map(f64::to_bits),
                )
            })
        };
        for (group, chunk) in rays.chunks_exact(TOGETHER).enumerate() {
            let packet: [Ray; TOGETHER] = std::array::from_fn(|r| chunk[r]);
            let mut found = [None; TOGETHER];
            nearest_hits(prepared, &packet, &mut stats, &mut found);
            for (r, ray) in packet.iter().enumerate() {
                let single = nearest_hit(prepared, *ray, &mut stats);
                assert_eq!(
                    bits(found[r]),
                    bits(single),
                    "{name}: group {group}, ray {r}"
                );
            }
            // Sample rays together: the hits of one at a time with t in (0, ∞).
            let mut between = [None; TOGETHER];
            nearest_hits_between(prepared, &packet, &mut stats, &mut between);
            for (r, ray) in packet.iter().enumerate() {
                let single = nearest_hit_between(prepared, *ray, (0.0, f64::INFINITY), &mut stats);
                assert_eq!(
                    bits(between[r]),
                    bits(single),
                    "{name}: group {group}, ray {r} {ray:?}, between"
                );
            }
            for end in 0..4 {
                let t_max: [f64; TOGETHER] = std::array::from_fn(|r| match (end, found[r]) {
                    (0, Some(hit)) => hit.t.next_down(),
                    (1, Some(hit)) => hit.t,
                    (2, Some(hit)) => hit.t.next_up(),
                    (_, Some(hit)) => 2.0 * hit.t,
                    (_, None) => [0.5, 3.0, f64::INFINITY][(r + end) % 3],
                });
                // Every lane, every other, rays in the first four lanes or the first eight only
                // (the index walks four or eight lanes then), one ray.
                let every = crate::render::ray::all_rays::<TOGETHER>();
                let masks = [every, 0x5555, 0b1011, 0b1101_0101, 0b1111_0000];
                let one = 1 << (group % TOGETHER);
                for taking in masks.into_iter().chain([one]) {
                    let blocked = any_hits(prepared, (&packet, taking), &t_max, &mut stats);
                    for (r, ray) in packet.iter().enumerate() {
                        let expected = taking & (1 << r) != 0
                            && any_of_each_object(prepared, ray, (0.0, t_max[r]), &mut stats);
                        assert_eq!(
                            blocked & (1 << r) != 0,
                            expected,
                            "{name}: group {group}, ray {r} {ray:?} up to {}, taking {taking:#x}",
                            t_max[r]
                        );
                    }
                }
            }
        }
    }

    /// The index culls nothing it should not, in every shipped scene (on the rays its tracer casts,
    /// and random and edge-on ones), with each method, and among objects under awkward transforms.
    #[test]
    fn the_index_finds_the_same_hits_as_testing_every_object() {
        let mut met = 0;
        for (name, prepared) in shipped() {
            let mut cast: Vec<Ray> = rays_cast(&prepared).iter().map(|r| r.ray).collect();
            cast.truncate(4000);
            for method in [None, Some(Method::MollerTrumbore), Some(Method::Watertight)] {
                let mut variant = prepared.clone();
                variant.method = method.or(prepared.method);
                met += agree(&name, &variant, &cast);
            }
            met += agree(&name, &prepared, &rays(&prepared, 7));
        }
        for seed in 0..3 {
            let prepared = awkward(seed);
            met += agree(
                &format!("awkward {seed}"),
                &prepared,
                &rays(&prepared, seed),
            );
        }
        assert!(met > 20_000, "{met}");
    }

    /// The gathered hierarchy holds exactly the objects [`gathers`] takes, in every shipped scene
    /// that gathers some (a packet's nearest search skips those objects by it): with one too few,
    /// a wall would be tested twice, which no hit would show.
    #[test]
    fn the_gathered_walls_are_the_objects_gathers_takes() {
        let mut held = 0;
        for (name, prepared) in shipped() {
            let Some(gathered) = prepared.object_index().gathered() else {
                continue;
            };
            for (index, object) in prepared.objects.iter().enumerate() {
                assert_eq!(
                    gathered.holds(index),
                    super::gathers(object),
                    "{name}: object {index}"
                );
                held += usize::from(gathered.holds(index));
            }
            assert!(
                !gathered.holds(prepared.objects.len()),
                "{name}: past the last object"
            );
        }
        assert!(
            held >= 12,
            "the Cornell box's twelve walls at least: {held}"
        );
    }

    /// Packets of mirror, glass and shadow rays, which start inside the Cornell box's room of
    /// gathered walls and so test the walls after the meshes, find the hits each ray finds alone.
    #[test]
    fn rays_inside_a_room_of_walls_find_what_single_rays_find() {
        use crate::render::cast::{TOGETHER, nearest_hit, nearest_hits};
        let (name, prepared) = cornell_box();
        let gathered = prepared
            .object_index()
            .gathered()
            .expect("its walls are gathered");
        let inside: Vec<Ray> = rays_cast(&prepared)
            .iter()
            .filter(|logged| logged.kind.name() != "primary" && logged.kind.name() != "samples")
            .map(|logged| logged.ray)
            .collect();
        // And the mirror and glass rays that meet a sphere, together: those inside the glass
        // sphere skip the walls' walk.
        let meets_a_sphere = |ray: &Ray| {
            nearest_hit(&prepared, *ray, &mut Stats::default())
                .is_some_and(|hit| !gathered.holds(hit.object))
        };
        let bounced: Vec<Ray> = rays_cast(&prepared)
            .iter()
            .filter(|logged| ["reflection", "refraction"].contains(&logged.kind.name()))
            .map(|logged| logged.ray)
            .filter(meets_a_sphere)
            .collect();
        let packets = inside.chunks_exact(TOGETHER).take(400);
        let (mut surrounded, mut met, mut walls_skipped) = (0, 0, 0);
        let mut stats = Stats::default();
        for chunk in packets.chain(bounced.chunks_exact(TOGETHER)) {
            let packet: [Ray; TOGETHER] = std::array::from_fn(|r| chunk[r]);
            surrounded += usize::from(gathered.surrounds(&packet));
            let mut found = [None; TOGETHER];
            nearest_hits(&prepared, &packet, &mut stats, &mut found);
            for (r, ray) in packet.iter().enumerate() {
                let single = nearest_hit(&prepared, *ray, &mut stats);
                assert_eq!(found[r], single, "{name}: ray {r} {ray:?}");
                met += usize::from(single.is_some());
            }
            // Packets whose hits all lie before the walls' boxes, which skipped the walls' walk.
            let hits: [f64; TOGETHER] =
                std::array::from_fn(|r| found[r].map_or(f64::INFINITY, |h| h.t));
            walls_skipped += usize::from(gathered.beyond_reach(&packet, &hits));
        }
        assert!(
            surrounded > 100 && met > 1000 && walls_skipped > 10,
            "{surrounded} {met} {walls_skipped}"
        );
    }

    /// A ray whose nearest hit is a gathered wall's, at t, is never beyond the walls' reach with
    /// t_max = t (where a tie to the lower object would keep the wall), nor is a packet with a
    /// ray looking to +∞ or with a t_max that is NaN; a ray stopped well before the floor is.
    #[test]
    fn a_hit_on_a_wall_is_never_beyond_reach() {
        use crate::render::cast::{TOGETHER, nearest_hit};
        let (name, prepared) = cornell_box();
        let gathered = prepared
            .object_index()
            .gathered()
            .expect("its walls are gathered");
        let mut on_walls = 0;
        for logged in rays_cast(&prepared).iter().take(20_000) {
            let ray = logged.ray;
            let Some(hit) = nearest_hit(&prepared, ray, &mut Stats::default()) else {
                continue;
            };
            if !gathered.holds(hit.object) {
                continue;
            }
            on_walls += 1;
            let packet = [ray; TOGETHER];
            assert!(
                !gathered.beyond_reach(&packet, &[hit.t; TOGETHER]),
                "{name}: {ray:?} meets object {} at {}",
                hit.object,
                hit.t
            );
        }
        assert!(on_walls > 1000, "{on_walls}");
        // Straight down from half a unit above the floor (z = 0), far from every other wall.
        let down = Ray::new([0.1, 1.0, 0.5], [0.0, 0.0, -1.0]);
        let packet = [down; TOGETHER];
        assert!(!gathered.beyond_reach(&packet, &[0.5; TOGETHER]));
        assert!(gathered.beyond_reach(&packet, &[0.49; TOGETHER]));
        for odd in [f64::INFINITY, f64::NAN] {
            let mut t_max = [0.49; TOGETHER];
            t_max[TOGETHER - 1] = odd;
            assert!(!gathered.beyond_reach(&packet, &t_max), "{odd}");
        }
    }

    /// Sample rays cast together meet what they meet alone with t in (0, ∞), also under each
    /// bug (where a primary ray takes hits at t ≤ 0) and from points on a parallelogram, where
    /// a primary ray's hit is at t = 0.
    #[test]
    fn sample_packets_find_what_single_rays_find_past_zero() {
        use crate::render::Bug;
        use crate::render::cast::{TOGETHER, nearest_hit_between, nearest_hits_between};
        let mut zero_hits = 0;
        for (name, prepared) in shipped() {
            let mut rays: Vec<Ray> = rays_cast(&prepared).iter().map(|r| r.ray).collect();
            rays.truncate(320);
            // From the middle of each parallelogram, across it and along it.
            for object in prepared.objects.iter() {
                if let Geometry::Parallelogram { corner, e1, e2, .. } = &object.geometry {
                    let middle = std::array::from_fn(|k| corner[k] + 0.5 * (e1[k] + e2[k]));
                    let across = crate::math::linalg::cross(e1, e2);
                    for dir in [across, across.map(|c| -c), *e1, [0.3, -0.2, 0.9]] {
                        rays.push(Ray::new(middle, dir));
                    }
                }
            }
            let bugs = [
                None,
                Some(Bug::NegativeT),
                Some(Bug::AndForOr),
                Some(Bug::ShadowAcne),
            ];
            for bug in bugs {
                let mut variant = prepared.clone();
                variant.bug = bug;
                let mut stats = Stats::default();
                for chunk in rays.chunks(TOGETHER) {
                    let packet: [Ray; TOGETHER] = std::array::from_fn(|r| chunk[r % chunk.len()]);
                    let mut found = [None; TOGETHER];
                    crate::render::cast::nearest_hits(&variant, &packet, &mut stats, &mut found);
                    zero_hits += found.iter().flatten().filter(|hit| hit.t <= 0.0).count();
                    nearest_hits_between(&variant, &packet, &mut stats, &mut found);
                    for (r, ray) in packet.iter().enumerate() {
                        let alone =
                            nearest_hit_between(&variant, *ray, (0.0, f64::INFINITY), &mut stats);
                        assert_eq!(found[r], alone, "{name} {bug:?}: ray {ray:?}");
                    }
                }
            }
        }
        // The case the packets cast again alone was met.
        assert!(zero_hits > 0);
    }

    /// Case `i`'s node: 1 + i mod 4 random boxes (flat on every axis when 7 divides i), the
    /// other lanes empty.
    fn random_node(random: &mut rand_pcg::Pcg64, i: usize) -> Wide {
        let mut node = Wide {
            lo: [[f64::INFINITY; 4]; 3],
            hi: [[f64::NEG_INFINITY; 4]; 3],
            child: [EMPTY; 4],
            held: (1 + i % 4) as u64,
        };
        for lane in 0..(1 + i % 4) {
            for k in 0..3 {
                let (a, b): (f64, f64) = (
                    random.random_range(-3.0..3.0),
                    random.random_range(-3.0..3.0),
                );
                node.lo[k][lane] = a.min(b);
                node.hi[k][lane] = if i.is_multiple_of(7) {
                    a.min(b)
                } else {
                    a.max(b)
                };
            }
            node.child[lane] = OBJECT | lane as u32;
        }
        node
    }

    /// The AVX2 box test gives the portable one's answers to the bit: random boxes, empty lanes,
    /// boxes the ray starts in or on, and rays parallel to an axis (1/d = ±10³⁰⁰).
    #[test]
    fn the_avx2_box_test_agrees_with_the_portable_one() {
        let Some(simd) = crate::render::kernels::Avx2::detect() else {
            return;
        };
        let mut random = rand_pcg::Pcg64::seed_from_u64(4);
        for i in 0..20_000 {
            let node = random_node(&mut random, i);
            let mut origin: [f64; 3] = std::array::from_fn(|_| random.random_range(-4.0..4.0));
            if i % 5 == 0 {
                origin = std::array::from_fn(|k| node.lo[k][0]);
            }
            let mut dir: [f64; 3] = std::array::from_fn(|_| random.random_range(-1.0..1.0));
            if i % 3 == 0 {
                dir[i % 3] = 0.0;
            }
            let slabs = Slabs::of(&Ray::new(origin, dir));
            let range = [(0.0, f64::INFINITY), (0.0, 1.0), (0.5, 2.0)][i % 3];
            let (near, met) = slabs.enter(&node, range);
            let (near_simd, met_simd) = slabs.enter_on(Some(simd), &node, range);
            assert_eq!(met, met_simd, "case {i}");
            assert_eq!(
                near.map(f64::to_bits),
                near_simd.map(f64::to_bits),
                "case {i}"
            );
        }
    }

    /// The packet's box test (a ray a lane) meets, for each ray it is given, the boxes the one-ray
    /// test meets: random boxes, flat ones, empty lanes, rays from a box's corner and parallel to
    /// an axis (or nearly, a subnormal d), each ray with its own t_max, only the rays asked for.
    /// Its numbers are each ray's, to the bit.
    #[test]
    #[cfg(target_arch = "x86_64")]
    fn the_packet_box_test_agrees_with_each_ray_alone() {
        let Some(_) = crate::render::kernels::Avx2::detect() else {
            return;
        };
        let mut random = rand_pcg::Pcg64::seed_from_u64(5);
        let mut met_some = 0;
        for i in 0..4_000 {
            let node = random_node(&mut random, i);
            let rays: [Ray; 16] = std::array::from_fn(|r| {
                let mut origin: [f64; 3] = std::array::from_fn(|_| random.random_range(-4.0..4.0));
                if r % 5 == 0 {
                    origin = std::array::from_fn(|k| node.lo[k][0]);
                }
                let mut dir: [f64; 3] = std::array::from_fn(|_| random.random_range(-1.0..1.0));
                if r % 3 == 0 {
                    dir[r % 4 % 3] = 0.0;
                }
                if r % 7 == 0 {
                    dir[r % 3] = [-0.0, 1e-310, -1e-320][i % 3];
                }
                Ray::new(origin, dir)
            });
            let slabs = rays.map(|ray| Slabs::of(&ray));
            let t_max: [f64; 16] =
                std::array::from_fn(|r| [f64::INFINITY, 1.0, 2.0, 0.25][(r + i) % 4]);
            let live = random.random::<u32>() & 0xffff;
            // SAFETY: the processor has AVX2 and FMA (detected above).
            let lanes = unsafe {
                let mut lanes = PacketSlabs::zero();
                lanes.fill(&rays, live);
                lanes
            };
            // SAFETY: as above.
            let (met_by, counted) = unsafe { lanes.enter_avx2(&node, live, (0.0, &t_max)) };
            assert_eq!(counted, u64::from(live.count_ones()));
            for r in 0..16 {
                let row = |rows: &[[f64; 16]; 3]| rows.map(|row| row[r].to_bits());
                let alone = |v: [f64; 3]| v.map(f64::to_bits);
                // A four no ray takes is left zero.
                let taken = (live >> (r / 4 * 4)) & 0b1111 != 0;
                let expected = |v: [f64; 3]| if taken { alone(v) } else { [0; 3] };
                assert_eq!(row(&lanes.origin), expected(slabs[r].origin), "case {i}");
                assert_eq!(row(&lanes.inverse), expected(slabs[r].inverse), "case {i}");
                let (_, met) = slabs[r].enter(&node, (0.0, t_max[r]));
                for (lane, rays) in met_by.iter().enumerate() {
                    let held = lane < node.held as usize;
                    let alone = held && live & (1 << r) != 0 && met & (1 << lane) != 0;
                    assert_eq!(
                        rays & (1 << r) != 0,
                        alone,
                        "case {i}, ray {r}, lane {lane}"
                    );
                    met_some += u32::from(alone);
                }
            }
        }
        assert!(met_some > 10_000, "{met_some} boxes met");
    }

    /// A ray with no finite numbers, or none at all, and a box on a ray's plane: nothing panics,
    /// and the index agrees.
    #[test]
    fn rays_parallel_to_a_box_or_on_its_faces_are_culled_only_when_outside() {
        let prepared = awkward(9);
        let inside_a_face = prepared.objects.iter().find_map(|o| match &o.geometry {
            Geometry::Parallelogram { corner, e1, e2, .. } if o.object_from_world.is_none() => {
                Some(Ray::new(
                    *corner,
                    std::array::from_fn(|k| e1[k] + 0.5 * e2[k]),
                ))
            }
            _ => None,
        });
        let mut rays: Vec<Ray> = inside_a_face.into_iter().collect();
        rays.push(Ray::new([0.0; 3], [0.0; 3]));
        rays.push(Ray::new([f64::NAN, 0.0, 0.0], [1.0, 0.0, 0.0]));
        rays.push(Ray::new([0.0; 3], [f64::INFINITY, 1.0, 0.0]));
        rays.push(Ray::new([0.0; 3], [1e-320, 0.0, 1.0]));
        agree("degenerate rays", &prepared, &rays);
    }
}
