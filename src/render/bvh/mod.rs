//! A bounding volume hierarchy over a mesh's triangles: built by binned SAH (the surface area
//! heuristic) over references to the triangles, a long thin triangle split into several
//! ([`split`]), collapsed to 4-wide nodes whose four child boxes are tested together, traversed
//! nearest child first with an early exit past the nearest hit so far.
//!
//! Boxes are stored in f32, rounded outward from padded f64 boxes, and tested in f64 with the slab
//! distances widened by a few ulps (as pbrt does), so the test is conservative: it never culls a
//! triangle the exact test would hit. A direction component that is zero is handled without 0 · ∞, and
//! a ray that would enter a box only at t = ∞ (an overflow) misses it. Triangles with a non-finite
//! coordinate are left out: no method hits them.
//!
//! The renderer's packets of sixteen neighbouring rays go through [`narrow`] where the processor has
//! AVX2 and the rays' numbers allow: each child box tested against eight rays at once in f32, with a
//! proven widening in place of the f64 test. Leaves start at multiples of four slots, so their
//! triangles are tested four at a time with one ray ([`crack_free4`]), with the one-triangle test's
//! decisions and numbers to the bit. Every query walks the nodes through one loop, [`traverse`].

// The AVX2 box tests: each unsafe block says in a SAFETY comment why it is sound (the CPU feature
// was checked, or the caller was compiled for it).
#![allow(unsafe_code)]

use super::crack_free::ShearedRay;
use traverse::{Met, Query, children};

pub(in crate::render) mod climb;
pub(in crate::render) mod eight;
mod split;
pub(in crate::render) mod traverse;
use super::kernels::{Avx2, Isa, Scalar, crack_free4::Quad, narrow};
#[cfg(target_arch = "x86_64")]
use super::kernels::{boxes4, crack_free4};
use super::objects::PreparedTriangle;
use crate::math::linalg::V3;
use crate::render::{Ray, TriangleHit};
use rayon::prelude::*;

/// Triangles per leaf, at most.
const MAX_LEAF: usize = 8;
/// Triangles a task when the build makes its references on every thread.
const REFERENCES_A_TASK: usize = 4096;
/// SAH bins per axis.
const BINS: usize = 16;
/// Below this depth of the binary build, SAH chooses splits; deeper, the median does, which bounds
/// the depth (and so the traversal stack) whatever the mesh.
const SAH_DEPTH: usize = 40;
/// The cost of a box test relative to a triangle test, for the SAH. (Pricing a leaf by its quads
/// instead, as the four-triangle test costs the same for one to four, filled the leaves: the
/// 512-triangle sphere's any-hit rays took 2.5% fewer instructions, its primary-ray packets 18%
/// more, each ray testing the larger leaves' quads. Left out.)
const BOX_COST: f64 = 1.0;
/// Marks an unused child slot.
pub(in crate::render) const EMPTY: u32 = u32::MAX;

/// An axis-aligned box in f64, during the build.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Bounds {
    min: V3<f64>,
    max: V3<f64>,
}

impl Bounds {
    const EMPTY: Bounds = Bounds {
        min: [f64::INFINITY; 3],
        max: [f64::NEG_INFINITY; 3],
    };

    fn grow(self, p: &V3<f64>) -> Bounds {
        Bounds {
            min: std::array::from_fn(|k| lesser(self.min[k], p[k])),
            max: std::array::from_fn(|k| greater(self.max[k], p[k])),
        }
    }

    fn of(triangle: &[V3<f64>; 3]) -> Bounds {
        triangle.iter().fold(Bounds::EMPTY, Bounds::grow)
    }

    fn union(self, other: Bounds) -> Bounds {
        Bounds {
            min: std::array::from_fn(|k| lesser(self.min[k], other.min[k])),
            max: std::array::from_fn(|k| greater(self.max[k], other.max[k])),
        }
    }

    /// The part of this box within `other`.
    fn and_within(self, other: Bounds) -> Bounds {
        Bounds {
            min: std::array::from_fn(|k| self.min[k].max(other.min[k])),
            max: std::array::from_fn(|k| self.max[k].min(other.max[k])),
        }
    }

    fn is_empty(&self) -> bool {
        (0..3).any(|k| self.min[k] > self.max[k])
    }

    /// Half the surface area (0 for an empty box).
    fn half_area(&self) -> f64 {
        if self.is_empty() {
            return 0.0;
        }
        let [x, y, z] = std::array::from_fn(|k| self.max[k] - self.min[k]);
        x * y + y * z + z * x
    }

    /// Widened by a relative margin, then rounded outward to f32: (min, max).
    fn to_f32(self) -> ([f32; 3], [f32; 3]) {
        if self.is_empty() {
            return ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]);
        }
        let margin = (0..3)
            .map(|k| self.max[k] - self.min[k])
            .fold(0.0f64, f64::max)
            * 1e-9
            + 1e-300;
        (
            self.min.map(|c| round_down(c - margin)),
            self.max.map(|c| round_up(c + margin)),
        )
    }
}

/// The lesser of two numbers that are not NaN (the build's boxes are finite or ±∞): one
/// instruction, where `f64::min` also orders NaN (the build spends most of its time in these).
#[inline(always)]
fn lesser(a: f64, b: f64) -> f64 {
    if b < a { b } else { a }
}

/// The greater of two numbers that are not NaN.
#[inline(always)]
fn greater(a: f64, b: f64) -> f64 {
    if b > a { b } else { a }
}

/// The largest f32 not above x.
fn round_down(x: f64) -> f32 {
    let f = x as f32;
    if f as f64 > x { f.next_down() } else { f }
}

/// The smallest f32 not below x.
fn round_up(x: f64) -> f32 {
    let f = x as f32;
    if (f as f64) < x { f.next_up() } else { f }
}

/// The binary build's triangle order, and the triangles, for laying out the leaves.
struct Leaves<'a> {
    /// Slot → triangle (a triangle split in pieces may have several slots).
    order: &'a [u32],
    triangles: &'a [PreparedTriangle],
}

/// Where a leaf's triangles go: the slot order and the slots' vertices.
type Slots<'a> = (&'a mut Vec<u32>, &'a mut Vec<[V3<f64>; 3]>);

impl Leaves<'_> {
    /// Appends the triangles of references `run` to `slots` at the next multiple of four, each
    /// once (two pieces of one triangle in one leaf: test it once), then pads to the next multiple
    /// of four; returns the leaf's (first slot, triangles held). The 4-wide leaves and the 8-wide
    /// walk's packed leaves are made by it.
    fn append(&self, run: std::ops::Range<usize>, (order, vertices): Slots) -> (u32, u32) {
        let start = order.len();
        for &triangle in &self.order[run] {
            if !order[start..].contains(&triangle) {
                order.push(triangle);
                vertices.push(self.triangles[triangle as usize].vertices);
            }
        }
        let held = (order.len() - start) as u32;
        while !order.len().is_multiple_of(4) {
            order.push(order[start]);
            vertices.push(vertices[start]);
        }
        (start as u32, held)
    }
}

/// A node of the binary build: a box and either two children or a run of slots.
struct BinaryNode {
    bounds: Bounds,
    /// Leaf: first slot; inner: the left child.
    first: usize,
    /// Leaf: slots; inner: 0 (then `right` is the right child).
    count: usize,
    right: usize,
}

/// A `W`-wide node: `W` child boxes (lanes), each an inner node, a leaf (a run of slots), or empty.
/// Aligned to a cache line: a 4-wide node (128 bytes) is read in two lines, not three.
#[derive(Clone, Debug)]
#[repr(C, align(64))]
pub(in crate::render) struct WideNode<const W: usize> {
    /// Box minima per axis, one lane per child.
    pub(in crate::render) min: [[f32; W]; 3],
    /// Box maxima per axis.
    pub(in crate::render) max: [[f32; W]; 3],
    /// Inner: the node's index; leaf: its first slot; empty: [`EMPTY`].
    pub(in crate::render) child: [u32; W],
    /// Leaf: its slot count; inner and empty: 0.
    pub(in crate::render) count: [u32; W],
}

impl<const W: usize> WideNode<W> {
    /// A node with every lane empty.
    pub(in crate::render) fn empty() -> WideNode<W> {
        WideNode {
            min: [[f32::INFINITY; W]; 3],
            max: [[f32::NEG_INFINITY; W]; 3],
            child: [EMPTY; W],
            count: [0; W],
        }
    }
}

/// The hierarchy's nodes, four boxes each (the packets' and the portable walks').
pub(in crate::render) type Node = WideNode<4>;

/// A ray's nearest hit in a hierarchy: the triangle's index and its (β, γ, t).
#[cfg_attr(
    not(target_arch = "x86_64"),
    allow(dead_code, unused_imports, reason = "used by the x86-64 kernels only")
)]
pub(in crate::render) type Nearest = Option<(usize, TriangleHit)>;

/// The hierarchy: 4-wide nodes (the root first), and the triangles in leaf order ("slots").
#[derive(Clone, Debug)]
pub struct Bvh {
    pub(in crate::render) nodes: Vec<Node>,
    /// Slot → triangle index.
    order: Vec<u32>,
    /// Slot → the triangle's vertices while the build places the leaves, in leaf order so a leaf's
    /// triangles are contiguous; empty once [`Bvh::quads`] holds them (a second copy cost 72
    /// bytes a slot). Each leaf starts at a multiple of four; the slots between leaves repeat a
    /// triangle and belong to no leaf. After the 4-wide leaves come the 8-wide walk's packed
    /// leaves ([`eight`]).
    build_vertices: Vec<[V3<f64>; 3]>,
    /// The slots' vertices four at a time (slot / 4), for the four-triangle test; one slot's are
    /// read back by [`Bvh::slot_vertices`].
    pub(in crate::render) quads: Vec<Quad>,
    /// Triangles held (those with finite coordinates).
    triangles: usize,
    /// True when every box is within the f32 packet test's range ([`narrow::BOX_LIMIT`]).
    pub(in crate::render) narrow: bool,
    /// The nodes merged eight wide, for one ray's any-hit walk ([`narrow::occluded_one_ray`]).
    pub(in crate::render) eight: eight::Eight,
    /// The 4-wide nodes' parents and leaves' holders, for a packet's any-hit walk.
    pub(in crate::render) climb: climb::Climb,
}

/// Per-ray constants of the box test.
pub(in crate::render) struct BoxRay {
    pub(in crate::render) origin: V3<f64>,
    pub(in crate::render) inverse_dir: V3<f64>,
    /// True where the direction component is zero (or so small its inverse overflows).
    pub(in crate::render) parallel: [bool; 3],
}

/// What a `width`-wide node for binary inner node `index` holds: its two children, the largest
/// inner one opened in its place while there are fewer than `width` (or only leaves are left).
fn widest_children(binary: &[BinaryNode], index: usize, width: usize) -> Vec<usize> {
    let mut children = vec![index];
    while children.len() < width {
        let openable = children
            .iter()
            .enumerate()
            .filter(|(_, c)| binary[**c].count == 0)
            .max_by(|a, b| {
                let area = |i: usize| binary[i].bounds.half_area();
                area(*a.1).total_cmp(&area(*b.1))
            })
            .map(|(slot, _)| slot);
        let Some(slot) = openable else { break };
        let opened = children.swap_remove(slot);
        children.push(binary[opened].first);
        children.push(binary[opened].right);
    }
    children
}

/// A packet's rays' sheared forms, each made when the ray first needs one, and the rays.
pub(in crate::render) type Sheared<'a, const P: usize> =
    (&'a mut [Option<ShearedRay>; P], &'a [Ray; P]);

/// Ray `r`'s sheared form, made the first time it is asked for; `None` for a ray with none (no
/// direction, or a number not finite).
#[inline(always)]
fn sheared_when_needed<'a, const P: usize>(
    (sheared, rays): (&'a mut [Option<ShearedRay>; P], &[Ray; P]),
    r: usize,
) -> Option<&'a ShearedRay> {
    if sheared[r].is_none() {
        sheared[r] = ShearedRay::new(&rays[r].origin, &rays[r].dir);
    }
    sheared[r].as_ref()
}

impl Bvh {
    /// Builds the hierarchy over `triangles`.
    pub fn build(triangles: &[PreparedTriangle]) -> Bvh {
        let finite: Vec<u32> = (0..triangles.len() as u32)
            .filter(|&i| {
                let v = &triangles[i as usize].vertices;
                v.iter().flatten().all(|c| c.is_finite())
            })
            .collect();
        // The builder's references: each a triangle, or a piece of a long thin one (made on
        // every thread, in the triangles' order).
        let references: Vec<Reference> = finite
            .par_chunks(REFERENCES_A_TASK)
            .flat_map_iter(|chunk| {
                let mut references = Vec::with_capacity(chunk.len());
                let mut boxes = Vec::new();
                for &triangle in chunk {
                    boxes.clear();
                    split::pieces(&triangles[triangle as usize].vertices, &mut boxes);
                    references.extend(boxes.iter().map(|&bounds| Reference {
                        bounds,
                        centroid: std::array::from_fn(|k| {
                            bounds.min[k] * 0.5 + bounds.max[k] * 0.5
                        }),
                        triangle,
                    }));
                }
                references
            })
            .collect();
        let mut references = references;
        let mut binary = Vec::with_capacity(2 * references.len());
        if !references.is_empty() {
            let mut builder = Builder { nodes: &mut binary };
            builder.split(&mut references, 0, 0);
        }
        // Slot → triangle, in the order the build left the references.
        let order: Vec<u32> = references.iter().map(|r| r.triangle).collect();
        let mut bvh = Bvh {
            nodes: Vec::with_capacity(binary.len() / 2 + 1),
            order: Vec::with_capacity(order.len() + order.len() / 2),
            build_vertices: Vec::with_capacity(order.len() + order.len() / 2),
            quads: Vec::new(),
            triangles: finite.len(),
            narrow: true,
            eight: eight::Eight::default(),
            climb: climb::Climb::default(),
        };
        if !binary.is_empty() {
            // Node 0 holds the whole mesh's box as its one child: a ray that misses the mesh costs
            // one box test.
            bvh.nodes.push(Node::empty());
            let mut root = Node::empty();
            let leaves = Leaves {
                order: &order,
                triangles,
            };
            let mut slots = vec![(0, 0); binary.len()];
            bvh.place(&binary, (&leaves, &mut slots), 0, &mut root, 0);
            bvh.nodes[0] = root;
            // Only the x86-64 kernels walk them (the web page would hold them for nothing).
            if cfg!(target_arch = "x86_64") {
                let packs = (&mut bvh.order, &mut bvh.build_vertices);
                bvh.eight = eight::Eight::of(&binary, (&leaves, &slots), packs);
            }
        }
        bvh.quads = bvh.build_vertices.par_chunks(4).map(Quad::new).collect();
        bvh.build_vertices = Vec::new();
        if cfg!(target_arch = "x86_64") {
            bvh.climb = climb::Climb::of(&bvh.nodes);
        }
        // The vectors grew while the size was unknown: hold no more than they use.
        bvh.nodes.shrink_to_fit();
        bvh.order.shrink_to_fit();
        bvh
    }

    /// Slot `slot`'s triangle, as the four-triangle test reads it.
    #[inline(always)]
    fn slot_vertices(&self, slot: usize) -> [V3<f64>; 3] {
        let (quad, lane) = (&self.quads[slot / 4], slot % 4);
        std::array::from_fn(|vertex| std::array::from_fn(|axis| quad.v[vertex][axis][lane]))
    }

    /// Puts binary node `index` into lane `lane` of `node`: its box, and its slots or its wide node.
    /// `slots` takes each binary leaf's `(first slot, count)` (the 8-wide nodes point to them).
    fn place(
        &mut self,
        binary: &[BinaryNode],
        (leaves, slots): (&Leaves, &mut [(u32, u32)]),
        index: usize,
        node: &mut Node,
        lane: usize,
    ) {
        let (min, max) = binary[index].bounds.to_f32();
        let within = |c: &f32| f64::from(c.abs()) <= narrow::BOX_LIMIT;
        self.narrow &= min.iter().chain(&max).all(within);
        for k in 0..3 {
            node.min[k][lane] = min[k];
            node.max[k][lane] = max[k];
        }
        if binary[index].count > 0 {
            let run = binary[index].first..binary[index].first + binary[index].count;
            let (first, held) = leaves.append(run, (&mut self.order, &mut self.build_vertices));
            slots[index] = (first, held);
            node.child[lane] = first;
            node.count[lane] = held;
        } else {
            let inner = self.collapse(binary, (leaves, slots), index);
            self.nodes.push(inner);
            node.child[lane] = (self.nodes.len() - 1) as u32;
        }
    }

    /// The wide node for binary inner node `index`: its children, opened (largest box first) until
    /// there are four or only leaves are left ([`widest_children`]). Returns the node; its inner
    /// children are pushed.
    fn collapse(
        &mut self,
        binary: &[BinaryNode],
        (leaves, slots): (&Leaves, &mut [(u32, u32)]),
        index: usize,
    ) -> Node {
        let mut children = widest_children(binary, index, 4);
        // The walks take the nearer box first, and of boxes entered at the same distance the
        // last lane first: the one reaching farthest to +x, +y and +z, as the 8-wide nodes order
        // boxes of equal area (see `eight`).
        let reach = |c: &usize| binary[*c].bounds.max.iter().sum::<f64>();
        children.sort_by(|a, b| reach(a).total_cmp(&reach(b)));
        let mut node = Node::empty();
        for (lane, &c) in children.iter().enumerate() {
            self.place(binary, (leaves, &mut *slots), c, &mut node, lane);
        }
        node
    }

    /// How many triangles the hierarchy holds (those with finite coordinates).
    pub fn len(&self) -> usize {
        self.triangles
    }

    /// The bytes it holds (its vectors' capacities).
    pub fn held_bytes(&self) -> u64 {
        fn held<T>(v: &Vec<T>) -> u64 {
            (std::mem::size_of::<T>() * v.capacity()) as u64
        }
        held(&self.nodes)
            + held(&self.order)
            + held(&self.build_vertices)
            + held(&self.quads)
            + self.eight.held_bytes()
            + self.climb.held_bytes()
    }

    /// True when it holds no triangle.
    pub fn is_empty(&self) -> bool {
        self.triangles == 0
    }

    /// Visits the triangles whose boxes the ray o + t d meets for t from `t_min` to the nearest hit
    /// so far, nearer boxes first. `test(triangle)` returns the triangle's t when it is hit;
    /// `box_tests` counts box tests (one per child box looked at).
    pub fn traverse(
        &self,
        ray: &Ray,
        t_min: f64,
        t_max: f64,
        box_tests: &mut u64,
        mut test: impl FnMut(usize) -> Option<f64>,
    ) {
        self.walk(
            Scalar,
            ray,
            (t_min, t_max),
            box_tests,
            |slots, mut t_max| {
                for slot in slots {
                    if let Some(t) = test(self.order[slot] as usize) {
                        t_max = t_max.min(t);
                    }
                }
                t_max
            },
        );
    }

    /// The nearest triangle the crack-free watertight test hits with `t_min < t ≤ t_max` (ties to
    /// the lower triangle index): its index and (β, γ, t). Counts box and triangle tests.
    pub fn nearest_crack_free(
        &self,
        simd: Option<Avx2>,
        ray: &Ray,
        range: (f64, f64),
        box_tests: &mut u64,
        triangle_tests: &mut u64,
    ) -> Nearest {
        self.one_ray::<false>(simd, ray, range, (box_tests, triangle_tests))
    }

    /// True when the crack-free test hits some triangle with `t_min < t < t_max` (an any-hit, or
    /// shadow, query: the traversal stops at the first such hit, nearest boxes first). Counts box
    /// and triangle tests. True exactly when [`Bvh::nearest_crack_free`] finds its nearest hit
    /// before `t_max`. Where the processor has AVX2, the quad that blocked this thread's last
    /// blocked ray on this hierarchy is tested first ([`Bvh::forget_last_blocker`]).
    pub fn occluded(
        &self,
        simd: Option<Avx2>,
        ray: &Ray,
        (t_min, t_max): (f64, f64),
        box_tests: &mut u64,
        triangle_tests: &mut u64,
    ) -> bool {
        #[cfg(target_arch = "x86_64")]
        if let Some(avx2) = simd
            && t_min == 0.0
            // SAFETY: an `Avx2` exists only on a processor with AVX2 and FMA.
            && let Some(found) = unsafe {
                narrow::occluded_one_ray(avx2, self, ray, t_max, (box_tests, triangle_tests))
            }
        {
            return found;
        }
        let counts = (box_tests, triangle_tests);
        let found = self.one_ray::<true>(simd, ray, (t_min, t_max), counts);
        found.is_some_and(|(_, hit)| hit.t < t_max)
    }

    /// Forgets the quad that blocked this thread's last blocked any-hit ray, which
    /// [`Bvh::occluded`] tests first on the same hierarchy, and the node an any-hit packet's walk
    /// starts from ([`Bvh::occluded_packet`]): the next query walks from the top. No answer
    /// changes; only the tests counted and the time do (for measuring the walk alone).
    pub fn forget_last_blocker() {
        #[cfg(target_arch = "x86_64")]
        narrow::forget_last_blocker();
    }

    /// Runs `queries` with this thread's [`Bvh::occluded`] queries testing first and keeping the
    /// last blocker of ray `r` of a packet whose rays are walked one at a time (in a render, the
    /// same light's shadow ray or the same occlusion ray hit after hit), not the one of rays cast
    /// one after another beside each other. No answer changes.
    pub fn in_blocker_lane<T>(r: usize, queries: impl FnOnce() -> T) -> T {
        #[cfg(target_arch = "x86_64")]
        return narrow::in_blocker_lane(r, queries);
        #[cfg(not(target_arch = "x86_64"))]
        {
            let _ = r;
            queries()
        }
    }

    /// One ray's crack-free query: the nearest hit, or with `ANY` a hit before t_max as soon as
    /// one is found.
    ///
    /// Compiled twice: with AVX2 and FMA where `simd` proves the processor has them (the same
    /// arithmetic, as Rust never fuses a multiply and an add on its own, so the same answers),
    /// else for the baseline.
    fn one_ray<const ANY: bool>(
        &self,
        simd: Option<Avx2>,
        ray: &Ray,
        range: (f64, f64),
        counts: (&mut u64, &mut u64),
    ) -> Nearest {
        match simd {
            #[cfg(target_arch = "x86_64")]
            // SAFETY: an `Avx2` exists only on a processor with AVX2 and FMA.
            Some(avx2) => unsafe { self.one_ray_avx2::<ANY>(avx2, ray, range, counts) },
            _ => self.one_ray_in::<ANY, _>(Scalar, ray, range, counts),
        }
    }

    /// [`Bvh::one_ray`] compiled with AVX2 and FMA.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma,popcnt,bmi1")]
    fn one_ray_avx2<const ANY: bool>(
        &self,
        avx2: Avx2,
        ray: &Ray,
        range: (f64, f64),
        counts: (&mut u64, &mut u64),
    ) -> Nearest {
        self.one_ray_in::<ANY, _>(avx2, ray, range, counts)
    }

    /// The traversal and tests themselves, inlined into each of the two builds above.
    #[inline(always)]
    fn one_ray_in<const ANY: bool, I: Isa>(
        &self,
        isa: I,
        ray: &Ray,
        (t_min, t_max): (f64, f64),
        (box_tests, triangle_tests): (&mut u64, &mut u64),
    ) -> Nearest {
        let sheared = ShearedRay::new(&ray.origin, &ray.dir)?;
        let mut best: Nearest = None;
        self.walk(isa, ray, (t_min, t_max), box_tests, |slots, limit| {
            *triangle_tests += slots.len() as u64;
            let limit = self.leaf_crack_free(isa, &sheared, slots, t_min, limit, &mut best);
            // An any-hit query is done at its first hit before t_max: a limit below every box
            // ends the walk.
            if ANY && best.is_some_and(|(_, hit)| hit.t < t_max) {
                f64::NEG_INFINITY
            } else {
                limit
            }
        });
        best
    }

    /// Tests a leaf's slots with the crack-free test, keeping in `best` the nearest hit with
    /// t_min < t ≤ `limit` (ties to the lower triangle index); returns the new limit. With
    /// [`Avx2`] (inlined into a function compiled with AVX2 and FMA) four triangles at a time, with
    /// the same decisions and numbers (see [`crack_free4`]).
    #[inline(always)]
    pub(in crate::render) fn leaf_crack_free<I: Isa>(
        &self,
        isa: I,
        ray: &ShearedRay,
        slots: std::ops::Range<usize>,
        t_min: f64,
        mut limit: f64,
        best: &mut Nearest,
    ) -> f64 {
        let mut offer = |slot: usize, hit: TriangleHit, limit: &mut f64| {
            self.offer(slot, hit, (limit, &mut *best));
        };
        #[cfg(target_arch = "x86_64")]
        if let Some(avx2) = isa.avx2() {
            // Leaves start at multiples of four (see `append_leaf`).
            for first in slots.clone().step_by(4) {
                let lanes = (1u32 << (slots.end - first).min(4)) - 1;
                let found =
                    crack_free4::intersect4(avx2, ray, &self.quads[first / 4], t_min, lanes);
                let mut hit = found.hit;
                while hit != 0 {
                    let lane = hit.trailing_zeros() as usize;
                    hit &= hit - 1;
                    offer(first + lane, found.hit(lane), &mut limit);
                }
                let mut again = found.again;
                while again != 0 {
                    let lane = again.trailing_zeros() as usize;
                    again &= again - 1;
                    if let Some(hit) = ray.intersect(&self.slot_vertices(first + lane), t_min) {
                        offer(first + lane, hit, &mut limit);
                    }
                }
            }
            return limit;
        }
        #[cfg(not(target_arch = "x86_64"))]
        let _ = isa;
        for slot in slots {
            if let Some(hit) = ray.intersect(&self.slot_vertices(slot), t_min) {
                offer(slot, hit, &mut limit);
            }
        }
        limit
    }

    /// Keeps `hit` of `slot` in `best` when it is nearer (ties to the lower triangle index), or,
    /// with no hit yet, when its t is not past `limit`; the limit becomes the hit's t.
    #[inline(always)]
    fn offer(&self, slot: usize, hit: TriangleHit, (limit, best): (&mut f64, &mut Nearest)) {
        let index = self.order[slot] as usize;
        let closer = match *best {
            None => hit.t <= *limit,
            Some((b, bh)) => hit.t < bh.t || (hit.t == bh.t && index < b),
        };
        if closer {
            *best = Some((index, hit));
            *limit = hit.t;
        }
    }

    /// [`Bvh::leaf_crack_free`] from t_min = 0 for a packet's rays of `taking` at once, each
    /// triangle against four rays together ([`crack_free4::intersect_rays4`]): the rays' lanes in
    /// `together`, all of whose rays share their sheared axes. Each ray's t_max is lowered to its
    /// nearest hit, and `lowered(r, t_max)` told of it.
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    pub(in crate::render) fn leaf_rays4<const P: usize>(
        &self,
        avx2: Avx2,
        slots: std::ops::Range<usize>,
        (taking, together, (sheared, packet)): (u32, &crack_free4::RaysTogether, Sheared<'_, P>),
        (t_max, best): (&mut [f64; P], &mut [Nearest; P]),
        mut lowered: impl FnMut(usize, f64),
    ) {
        for slot in slots {
            let quad = (&self.quads[slot / 4], slot % 4);
            for (group, rays) in together.quads.iter().enumerate() {
                let lanes = (taking >> (4 * group)) & 0b1111;
                if lanes == 0 {
                    continue;
                }
                let found =
                    crack_free4::intersect_rays4(avx2, (together.axes, rays), quad, 0.0, lanes);
                let mut hit = found.hit;
                while hit != 0 {
                    let lane = hit.trailing_zeros() as usize;
                    hit &= hit - 1;
                    let r = 4 * group + lane;
                    self.offer(slot, found.hit(lane), (&mut t_max[r], &mut best[r]));
                }
                let mut again = found.again;
                while again != 0 {
                    let lane = again.trailing_zeros() as usize;
                    again &= again - 1;
                    let r = 4 * group + lane;
                    let Some(ray) = sheared_when_needed((sheared, packet), r) else {
                        continue;
                    };
                    if let Some(hit) = ray.intersect(&self.slot_vertices(slot), 0.0) {
                        self.offer(slot, hit, (&mut t_max[r], &mut best[r]));
                    }
                }
            }
        }
        let mut each = taking;
        while each != 0 {
            let r = each.trailing_zeros() as usize;
            each &= each - 1;
            lowered(r, t_max[r]);
        }
    }

    /// The quad (slot / 4) of a leaf's slots in which the crack-free test finds a hit with
    /// 0 < t < t_max, if any: whether [`Bvh::leaf_crack_free`] from t_min = 0 would keep a hit
    /// before t_max, decided without working out β and γ.
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    pub(in crate::render) fn blocking_quad(
        &self,
        avx2: Avx2,
        ray: &ShearedRay,
        slots: std::ops::Range<usize>,
        t_max: f64,
    ) -> Option<usize> {
        // Leaves start at multiples of four (see `append_leaf`).
        for first in slots.clone().step_by(4) {
            let lanes = (1u32 << (slots.end - first).min(4)) - 1;
            let found = crack_free4::intersect4(avx2, ray, &self.quads[first / 4], 0.0, lanes);
            let mut hit = found.hit;
            while hit != 0 {
                let lane = hit.trailing_zeros() as usize;
                hit &= hit - 1;
                if found.t[lane] < t_max {
                    return Some(first / 4);
                }
            }
            let mut again = found.again;
            while again != 0 {
                let lane = again.trailing_zeros() as usize;
                again &= again - 1;
                let vertices = self.slot_vertices(first + lane);
                if ray
                    .intersect(&vertices, 0.0)
                    .is_some_and(|hit| hit.t < t_max)
                {
                    return Some(first / 4);
                }
            }
        }
        None
    }

    /// Tests a leaf's slots for each of a packet's `live` rays, lowering its t_max to its nearest
    /// hit (`lowered(r, t_max)` is told of each ray's new t_max). A ray's sheared form is made when
    /// it first reaches a leaf; a ray without one (no direction, a number not finite) finds
    /// nothing.
    #[allow(
        clippy::too_many_arguments,
        reason = "a packet's parallel arrays, each by name"
    )]
    #[inline(always)]
    pub(in crate::render) fn packet_leaf<I: Isa, const P: usize>(
        &self,
        isa: I,
        slots: std::ops::Range<usize>,
        live: u32,
        (sheared, rays): Sheared<'_, P>,
        (t_max, best): (&mut [f64; P], &mut [Nearest; P]),
        triangle_tests: &mut u64,
        mut lowered: impl FnMut(usize, f64),
    ) {
        let mut each = live;
        while each != 0 {
            let r = each.trailing_zeros() as usize;
            each &= each - 1;
            let Some(ray) = sheared_when_needed((sheared, rays), r) else {
                continue;
            };
            *triangle_tests += slots.len() as u64;
            t_max[r] = self.leaf_crack_free(isa, ray, slots.clone(), 0.0, t_max[r], &mut best[r]);
            lowered(r, t_max[r]);
        }
    }

    /// [`Bvh::nearest_crack_free`] for `P` rays at once (neighbouring pixels), each with its own
    /// t_max: the same answers, one traversal, written into `best` (the renderer's packets pass
    /// their own, so the hits are not copied on the way out). A node's boxes are tested for every
    /// ray still in play; a child is visited when any of them meets its box, with those rays only.
    /// Box and triangle tests are counted per ray, as if each ray had made them alone.
    pub fn nearest_crack_free_packet<const P: usize>(
        &self,
        simd: Option<Avx2>,
        rays: &[Ray; P],
        t_max: [f64; P],
        box_tests: &mut u64,
        triangle_tests: &mut u64,
        best: &mut [Nearest; P],
    ) {
        let every = crate::render::ray::all_rays::<P>();
        self.nearest_crack_free_packet_of(
            simd,
            (rays, every),
            t_max,
            box_tests,
            triangle_tests,
            best,
        );
    }

    /// [`Bvh::nearest_crack_free_packet`] for the rays of `taking` alone (a bit set): the others
    /// fill the packet's lanes (each must still be a ray, finite, with a direction, or the packet
    /// takes the one-ray box test) and are never tested; their hits are `None`.
    pub fn nearest_crack_free_packet_of<const P: usize>(
        &self,
        simd: Option<Avx2>,
        (rays, taking): (&[Ray; P], u32),
        t_max: [f64; P],
        box_tests: &mut u64,
        triangle_tests: &mut u64,
        best: &mut [Nearest; P],
    ) {
        let counts = (box_tests, triangle_tests);
        self.packet::<P, false>(simd, (rays, taking), t_max, counts, best);
    }

    /// [`Bvh::occluded`] for `P` rays at once (neighbouring pixels, or the shadow rays of their
    /// hits), each with its own t_max and t_min = 0: a bit set of the rays with a crack-free hit at
    /// 0 < t < t_max. A ray leaves the packet at its first such hit; the walk ends when none is
    /// left. Counts box and triangle tests per ray. With AVX2, the walk starts a few levels above
    /// the node where this thread's last packet on this hierarchy found a hit, and climbs from
    /// there (`Bvh::visit_climbing`): packets of neighbouring rays cast one after another end
    /// near one another.
    pub fn occluded_packet<const P: usize>(
        &self,
        simd: Option<Avx2>,
        rays: &[Ray; P],
        t_max: [f64; P],
        box_tests: &mut u64,
        triangle_tests: &mut u64,
    ) -> u32 {
        let every = crate::render::ray::all_rays::<P>();
        self.occluded_packet_of(simd, (rays, every), t_max, box_tests, triangle_tests)
    }

    /// [`Bvh::occluded_packet`] for the rays of `taking` alone (a bit set): the others fill the
    /// packet's lanes (each must still be a ray, finite, with a direction, or the packet takes the
    /// one-ray box test) and are never tested or reported.
    pub fn occluded_packet_of<const P: usize>(
        &self,
        simd: Option<Avx2>,
        (rays, taking): (&[Ray; P], u32),
        t_max: [f64; P],
        box_tests: &mut u64,
        triangle_tests: &mut u64,
    ) -> u32 {
        let mut best = [None; P];
        let counts = (box_tests, triangle_tests);
        self.packet::<P, true>(simd, (rays, taking), t_max, counts, &mut best);
        let mut occluded = 0;
        for (r, found) in best.iter().enumerate() {
            if found.is_some_and(|(_, hit)| hit.t < t_max[r]) {
                occluded |= 1 << r;
            }
        }
        occluded & taking
    }

    /// The packet queries' entry: the nearest hits, or with `ANY` hits before t_max.
    #[inline(always)]
    fn packet<const P: usize, const ANY: bool>(
        &self,
        simd: Option<Avx2>,
        (rays, taking): (&[Ray; P], u32),
        t_max: [f64; P],
        (box_tests, triangle_tests): (&mut u64, &mut u64),
        best: &mut [Nearest; P],
    ) {
        const { assert!(P <= 32, "a packet is a 32-bit set") };
        *best = [None; P];
        match simd {
            #[cfg(target_arch = "x86_64")]
            // SAFETY: an `Avx2` exists only on a processor with AVX2 and FMA.
            Some(avx2) => unsafe {
                let counts = (box_tests, triangle_tests);
                self.packet_avx2::<P, ANY>(avx2, (rays, taking), t_max, counts, best)
            },
            _ => {
                let counts = (box_tests, triangle_tests);
                self.packet_in::<P, ANY, _>(Scalar, (rays, taking), t_max, counts, best)
            }
        }
    }

    /// The packet traversal compiled with AVX2 and FMA: sixteen rays whose numbers allow it take
    /// [`narrow`]'s f32 box test of eight rays at once.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma,popcnt,bmi1")]
    fn packet_avx2<const P: usize, const ANY: bool>(
        &self,
        avx2: Avx2,
        (rays, taking): (&[Ray; P], u32),
        t_max: [f64; P],
        (box_tests, triangle_tests): (&mut u64, &mut u64),
        best: &mut [Nearest; P],
    ) {
        if P == narrow::RAYS && self.narrow && !self.nodes.is_empty() {
            let packet = <&[Ray; narrow::RAYS]>::try_from(rays.as_slice());
            let limits = <[f64; narrow::RAYS]>::try_from(t_max.as_slice());
            let found = match (
                packet,
                limits,
                <&mut [Nearest; narrow::RAYS]>::try_from(&mut best[..]),
            ) {
                (Ok(packet), Ok(limits), Ok(out)) => {
                    let tests = (&mut *box_tests, &mut *triangle_tests);
                    narrow::traverse::<ANY>(avx2, self, (packet, taking), limits, tests, out)
                }
                _ => false,
            };
            if found {
                return;
            }
        }
        let counts = (box_tests, triangle_tests);
        self.packet_in::<P, ANY, _>(avx2, (rays, taking), t_max, counts, best)
    }

    /// The packet traversal itself, inlined into each of the two builds above.
    #[inline(always)]
    fn packet_in<const P: usize, const ANY: bool, I: Isa>(
        &self,
        isa: I,
        (rays, taking): (&[Ray; P], u32),
        t_max: [f64; P],
        (box_tests, triangle_tests): (&mut u64, &mut u64),
        best: &mut [Nearest; P],
    ) {
        let sheared: [Option<ShearedRay>; P] =
            std::array::from_fn(|r| ShearedRay::new(&rays[r].origin, &rays[r].dir));
        // Rays with a direction and finite numbers take part (ShearedRay checks both).
        let mut all = 0u32;
        for (r, ray) in sheared.iter().enumerate() {
            if ray.is_some() {
                all |= 1 << r;
            }
        }
        let mut query = Packet::<I, P, ANY> {
            bvh: self,
            isa,
            rays,
            sheared,
            box_rays: std::array::from_fn(|r| BoxRay::new(&rays[r])),
            t_max,
            open: t_max,
            box_tests,
            triangle_tests,
            best,
        };
        self.visit(&mut query, all & taking, 0.0);
    }

    /// One ray's walk: `leaf(slots, t_max)` tests a leaf's slots and returns the new t_max. With
    /// [`Avx2`], boxes are tested with AVX2 intrinsics (inlined into a function compiled with them).
    #[inline(always)]
    fn walk<I: Isa>(
        &self,
        isa: I,
        ray: &Ray,
        (t_min, t_max): (f64, f64),
        box_tests: &mut u64,
        leaf: impl FnMut(std::ops::Range<usize>, f64) -> f64,
    ) {
        if !ray.is_finite() {
            return;
        }
        let mut query = OneRay {
            isa,
            ray: BoxRay::new(ray),
            t_min,
            t_max,
            box_tests,
            leaf,
        };
        self.visit(&mut query, 1, t_min);
    }
}

/// One ray's query: its box test and its nearest hit so far (`t_max`), which `leaf` lowers.
struct OneRay<'a, I, L> {
    isa: I,
    ray: BoxRay,
    t_min: f64,
    t_max: f64,
    box_tests: &'a mut u64,
    leaf: L,
}

impl<I: Isa, L: FnMut(std::ops::Range<usize>, f64) -> f64> Query for OneRay<'_, I, L> {
    type Near = f64;

    #[inline(always)]
    fn live(&self, rays: u32, near: f64) -> u32 {
        if near > self.t_max { 0 } else { rays }
    }

    #[inline(always)]
    fn boxes(&mut self, node: &Node, _: u32) -> Met<f64> {
        let (hit, near) = node.test(self.isa, &self.ray, self.t_min, self.t_max);
        *self.box_tests += children(node);
        Met {
            rays: std::array::from_fn(|lane| (hit >> lane) & 1),
            near,
        }
    }

    #[inline(always)]
    fn leaf(&mut self, slots: std::ops::Range<usize>, _: u32) {
        self.t_max = (self.leaf)(slots, self.t_max);
    }
}

/// A packet's query with the f64 box test, one ray at a time: each ray's sheared ray, box ray and
/// nearest hit so far.
struct Packet<'a, I, const P: usize, const ANY: bool> {
    bvh: &'a Bvh,
    isa: I,
    rays: &'a [Ray; P],
    sheared: [Option<ShearedRay>; P],
    box_rays: [BoxRay; P],
    t_max: [f64; P],
    /// Each ray's t_max at the start (an any-hit query's limit).
    open: [f64; P],
    box_tests: &'a mut u64,
    triangle_tests: &'a mut u64,
    best: &'a mut [Nearest; P],
}

impl<I: Isa, const P: usize, const ANY: bool> Query for Packet<'_, I, P, ANY> {
    type Near = f64;

    #[inline(always)]
    fn live(&self, rays: u32, near: f64) -> u32 {
        let mut rays_in = rays;
        let mut live = 0u32;
        while rays_in != 0 {
            let r = rays_in.trailing_zeros() as usize;
            rays_in &= rays_in - 1;
            if near <= self.t_max[r] {
                live |= 1 << r;
            }
        }
        live
    }

    #[inline(always)]
    fn boxes(&mut self, node: &Node, live: u32) -> Met<f64> {
        let mut met = Met {
            rays: [0u32; 4],
            near: [f64::INFINITY; 4],
        };
        let mut each = live;
        while each != 0 {
            let r = each.trailing_zeros() as usize;
            each &= each - 1;
            let (hit, nears) = node.test(self.isa, &self.box_rays[r], 0.0, self.t_max[r]);
            *self.box_tests += children(node);
            // Lanes the ray misses enter at +∞ (see `test`), so `min` needs no branch.
            for (lane, near) in nears.iter().enumerate() {
                met.rays[lane] |= ((hit >> lane) & 1) << r;
                met.near[lane] = met.near[lane].min(*near);
            }
        }
        met
    }

    #[inline(always)]
    fn leaf(&mut self, slots: std::ops::Range<usize>, live: u32) {
        let hits = (&mut self.t_max, &mut *self.best);
        let rays = (&mut self.sheared, self.rays);
        let tests = &mut *self.triangle_tests;
        self.bvh
            .packet_leaf(self.isa, slots, live, rays, hits, tests, |_, _| {});
        if ANY {
            close_found(live, self.best, &self.open, &mut self.t_max, |_| {});
        }
    }
}

/// An any-hit packet's rays of `live` that have found a hit before their `open` limit are done:
/// their t_max becomes −∞, which no box is entered before, so the walk passes them by.
/// `closed(r)` is told of each.
#[inline(always)]
pub(in crate::render) fn close_found<const P: usize>(
    live: u32,
    best: &[Nearest; P],
    open: &[f64; P],
    t_max: &mut [f64; P],
    mut closed: impl FnMut(usize),
) {
    let mut each = live;
    while each != 0 {
        let r = each.trailing_zeros() as usize;
        each &= each - 1;
        if best[r].is_some_and(|(_, hit)| hit.t < open[r]) {
            t_max[r] = f64::NEG_INFINITY;
            closed(r);
        }
    }
}

impl BoxRay {
    /// The box test's constants for `ray`.
    #[inline(always)]
    pub(in crate::render) fn new(ray: &Ray) -> BoxRay {
        let inverse_dir = ray.dir.map(|d| 1.0 / d);
        BoxRay {
            origin: ray.origin,
            inverse_dir,
            parallel: inverse_dir.map(|i| !i.is_finite()),
        }
    }
}

impl Node {
    /// Which of the four boxes the ray meets within [t_min, t_max] (a bit a lane), and where it enters
    /// each (+∞ for the boxes it misses).
    #[inline(always)]
    fn test<I: Isa>(&self, isa: I, ray: &BoxRay, t_min: f64, t_max: f64) -> (u32, [f64; 4]) {
        #[cfg(target_arch = "x86_64")]
        if let Some(avx2) = isa.avx2() {
            return boxes4::test(avx2, (&self.min, &self.max), ray, t_min, t_max);
        }
        #[cfg(not(target_arch = "x86_64"))]
        let _ = isa;
        self.test_portable(ray, t_min, t_max)
    }

    /// The box test in portable code, which [`boxes4`] does four lanes at once.
    #[inline(always)]
    fn test_portable(&self, ray: &BoxRay, t_min: f64, t_max: f64) -> (u32, [f64; 4]) {
        // Widen the distances by 2γ₃ so a rounded slab cannot cut off a touching ray; by multiplying,
        // so an infinite distance stays infinite.
        const WIDEN: f64 = 2.0 * 3.0 * f64::EPSILON;
        let mut near = [t_min; 4];
        let mut far = [t_max; 4];
        for k in 0..3 {
            let o = ray.origin[k];
            let lo = self.min[k].map(f64::from);
            let hi = self.max[k].map(f64::from);
            if ray.parallel[k] {
                // Parallel to this slab: inside it or never.
                for lane in 0..4 {
                    if !(o >= lo[lane] && o <= hi[lane]) {
                        near[lane] = f64::INFINITY;
                    }
                }
                continue;
            }
            let inv = ray.inverse_dir[k];
            let (entry, exit) = if inv >= 0.0 { (lo, hi) } else { (hi, lo) };
            for lane in 0..4 {
                let t0 = (entry[lane] - o) * inv;
                let t1 = (exit[lane] - o) * inv;
                let t0 = t0 * if t0 >= 0.0 { 1.0 - WIDEN } else { 1.0 + WIDEN };
                let t1 = t1 * if t1 >= 0.0 { 1.0 + WIDEN } else { 1.0 - WIDEN };
                near[lane] = near[lane].max(t0);
                far[lane] = far[lane].min(t1);
            }
        }
        // An empty lane has min = +∞ > max = −∞, so its near exceeds its far. A box entered only at
        // t = ∞ (distances that overflowed) is never reached.
        let mut hit = 0;
        for lane in 0..4 {
            if near[lane] <= far[lane] && near[lane] < f64::INFINITY {
                hit |= 1 << lane;
            } else {
                near[lane] = f64::INFINITY;
            }
        }
        (hit, near)
    }
}

/// The binary binned-SAH build over `order`'s slots.
/// What the build sorts: a triangle, or a piece of one, with its box and the box's centre. Kept by
/// value, so each pass over a run of them reads memory in order.
#[derive(Clone, Copy)]
struct Reference {
    bounds: Bounds,
    centroid: V3<f64>,
    triangle: u32,
}

struct Builder<'a> {
    nodes: &'a mut Vec<BinaryNode>,
}

/// Whether a run is worth building on another thread (below this, the join costs more than it
/// saves).
fn run_len_is_large(len: usize) -> bool {
    len >= 16_384
}

impl Builder<'_> {
    /// Adds the node for `order[start..end]` and, below it, its children; returns its index.
    fn split(&mut self, run: &mut [Reference], start: usize, depth: usize) -> usize {
        let end = start + run.len();
        // The run's box and its centroids' box, in one pass.
        let (bounds, spread) = run
            .iter()
            .fold((Bounds::EMPTY, Bounds::EMPTY), |(b, s), r| {
                (b.union(r.bounds), s.grow(&r.centroid))
            });
        let index = self.nodes.len();
        self.nodes.push(BinaryNode {
            bounds,
            first: start,
            count: end - start,
            right: 0,
        });
        if end - start == 1 {
            return index;
        }
        let middle = match self.choose_split(run, (&bounds, &spread), depth) {
            Some(middle) => middle,
            None => return index,
        };
        let (left_run, right_run) = run.split_at_mut(middle);
        let (left, right) = if run_len_is_large(end - start) {
            // Large runs build their two halves on two threads, each into its own list.
            let (left_nodes, right_nodes) = rayon::join(
                || Builder::subtree(left_run, start, depth + 1),
                || Builder::subtree(right_run, start + middle, depth + 1),
            );
            (self.append(left_nodes), self.append(right_nodes))
        } else {
            let left = self.split(left_run, start, depth + 1);
            (left, self.split(right_run, start + middle, depth + 1))
        };
        let node = &mut self.nodes[index];
        node.first = left;
        node.count = 0;
        node.right = right;
        index
    }

    /// The nodes of the subtree over `run` (whose first slot is `start`), its root first.
    fn subtree(run: &mut [Reference], start: usize, depth: usize) -> Vec<BinaryNode> {
        let mut nodes = Vec::with_capacity(2 * run.len());
        Builder { nodes: &mut nodes }.split(run, start, depth);
        nodes
    }

    /// Appends a subtree's nodes (their child indices moved past the nodes already here) and
    /// returns its root's index.
    fn append(&mut self, subtree: Vec<BinaryNode>) -> usize {
        let offset = self.nodes.len();
        self.nodes.extend(subtree.into_iter().map(|mut node| {
            if node.count == 0 {
                node.first += offset;
                node.right += offset;
            }
            node
        }));
        offset
    }

    /// Partitions `run` and returns where its right part starts, or `None` to make it a leaf.
    /// `spread` is the box of the run's centroids.
    fn choose_split(
        &self,
        run: &mut [Reference],
        (bounds, spread): (&Bounds, &Bounds),
        depth: usize,
    ) -> Option<usize> {
        let n = run.len();
        let axis = (0..3)
            .max_by(|&a, &b| {
                let extent = |k: usize| spread.max[k] - spread.min[k];
                extent(a).total_cmp(&extent(b))
            })
            .unwrap_or(0);
        let flat = spread.max[axis] <= spread.min[axis];
        if depth >= SAH_DEPTH || flat {
            // Median split (all centroids equal: split the run in two as it is).
            if n <= MAX_LEAF {
                return None;
            }
            let middle = n / 2;
            if !flat {
                run.select_nth_unstable_by(middle, |a, b| {
                    a.centroid[axis].total_cmp(&b.centroid[axis])
                });
            }
            return Some(middle);
        }
        let (axis, bin, cost) = self.best_bins(run, spread, bounds.half_area());
        // Cost of a leaf: testing every triangle; of a split: the box tests and the children's.
        let leaf_cost = n as f64;
        if n <= MAX_LEAF && cost >= leaf_cost {
            return None;
        }
        let low = spread.min[axis];
        let scale = BINS as f64 / (spread.max[axis] - low);
        let bin_of = |r: &Reference| (((r.centroid[axis] - low) * scale) as usize).min(BINS - 1);
        let mut middle = 0;
        for k in 0..n {
            if bin_of(&run[k]) <= bin {
                run.swap(k, middle);
                middle += 1;
            }
        }
        if middle == 0 || middle == n {
            middle = n / 2;
        }
        Some(middle)
    }

    /// The best SAH split over every axis's bins: (axis, last bin of the left part, cost). The
    /// three axes are binned in one pass over the run.
    fn best_bins(&self, run: &[Reference], spread: &Bounds, parent: f64) -> (usize, usize, f64) {
        let parent = parent.max(f64::MIN_POSITIVE);
        let low = spread.min;
        let extent: V3<f64> = std::array::from_fn(|k| spread.max[k] - low[k]);
        // A flat axis's bins are filled (all in bin 0) and then skipped.
        let scale: V3<f64> = std::array::from_fn(|k| match extent[k] > 0.0 {
            true => BINS as f64 / extent[k],
            false => 0.0,
        });
        let mut boxes = [[Bounds::EMPTY; BINS]; 3];
        let mut counts = [[0usize; BINS]; 3];
        for r in run {
            for axis in 0..3 {
                let bin = (((r.centroid[axis] - low[axis]) * scale[axis]) as usize).min(BINS - 1);
                boxes[axis][bin] = boxes[axis][bin].union(r.bounds);
                counts[axis][bin] += 1;
            }
        }
        let mut best = (0, 0, f64::INFINITY);
        for axis in 0..3 {
            if extent[axis] <= 0.0 {
                continue;
            }
            let (boxes, counts) = (&boxes[axis], &counts[axis]);
            // Areas and counts of every prefix and suffix of bins.
            let mut right_area = [0.0; BINS];
            let mut right_count = [0usize; BINS];
            let (mut b, mut c) = (Bounds::EMPTY, 0);
            for k in (1..BINS).rev() {
                b = b.union(boxes[k]);
                c += counts[k];
                right_area[k] = b.half_area();
                right_count[k] = c;
            }
            let (mut b, mut c) = (Bounds::EMPTY, 0);
            for k in 0..BINS - 1 {
                b = b.union(boxes[k]);
                c += counts[k];
                if c == 0 || right_count[k + 1] == 0 {
                    continue;
                }
                let cost = BOX_COST
                    + (b.half_area() * c as f64 + right_area[k + 1] * right_count[k + 1] as f64)
                        / parent;
                if cost < best.2 {
                    best = (axis, k, cost);
                }
            }
        }
        best
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::loading::assets::{Embedded, load_mesh};

    fn ray_of(origin: V3<f64>, dir: V3<f64>) -> BoxRay {
        let inverse_dir = dir.map(|d| 1.0 / d);
        BoxRay {
            origin,
            inverse_dir,
            parallel: inverse_dir.map(|i| !i.is_finite()),
        }
    }

    #[test]
    fn boxes_are_rounded_outward_and_tested_conservatively() {
        let exact = Bounds {
            min: [0.1, 0.2, 0.3],
            max: [0.7, 0.8, 0.9],
        };
        let (min, max) = exact.to_f32();
        for k in 0..3 {
            assert!((min[k] as f64) < exact.min[k] && (max[k] as f64) > exact.max[k]);
        }
        let mut node = Node::empty();
        for k in 0..3 {
            node.min[k][1] = min[k];
            node.max[k][1] = max[k];
        }
        // Along the box's face (a zero direction component), through it, and past it.
        let (hit, _) = node.test(
            Scalar,
            &ray_of([0.1, 0.5, -1.0], [0.0, 0.0, 1.0]),
            0.0,
            f64::INFINITY,
        );
        assert_eq!(hit, 0b10);
        let (hit, _) = node.test(Scalar, &ray_of([0.0, 0.0, 0.0], [1.0, 1.0, 1.0]), 0.0, 0.2);
        assert_eq!(hit, 0);
        let (hit, _) = node.test(
            Scalar,
            &ray_of([5.0, 0.5, 0.5], [-1.0, 0.0, 0.0]),
            0.0,
            10.0,
        );
        assert_eq!(hit, 0b10);
    }

    /// The AVX2 box test decides as the portable one, on random boxes, rays along axes included.
    #[cfg(target_arch = "x86_64")]
    #[test]
    fn the_avx2_box_test_agrees_with_the_portable_one() {
        use rand::{Rng, SeedableRng};
        let avx2 = crate::render::kernels::avx2_or_skip!();
        let mut random = rand_pcg::Pcg64::seed_from_u64(7);
        for i in 0..20_000 {
            let mut node = Node::empty();
            for lane in 0..(1 + i % 4) {
                let b = Bounds::EMPTY
                    .grow(&std::array::from_fn(|_| random.random_range(-2.0..2.0)))
                    .grow(&std::array::from_fn(|_| random.random_range(-2.0..2.0)));
                let (min, max) = b.to_f32();
                for k in 0..3 {
                    node.min[k][lane] = min[k];
                    node.max[k][lane] = max[k];
                }
            }
            let origin: V3<f64> = std::array::from_fn(|_| random.random_range(-3.0..3.0));
            let mut dir: V3<f64> = std::array::from_fn(|_| random.random_range(-1.0..1.0));
            if i % 3 == 0 {
                dir[i % 2] = 0.0;
            }
            let ray = ray_of(origin, dir);
            let t_max = if i % 5 == 0 { 1.0 } else { f64::INFINITY };
            let (hit, near) = node.test(Scalar, &ray, 0.0, t_max);
            let (hit_avx, near_avx) = node.test(avx2, &ray, 0.0, t_max);
            assert_eq!(hit, hit_avx, "{origin:?} {dir:?}");
            for lane in 0..4 {
                if hit & (1 << lane) != 0 {
                    assert_eq!(near[lane], near_avx[lane]);
                }
            }
        }
    }

    /// A ray from 1e308 whose slab distances overflow to ∞ visits no triangle.
    #[test]
    fn overflowing_slab_distances_test_no_triangle() {
        let mesh = load_mesh(&Embedded, "meshes/octasphere.obj").unwrap();
        let bvh = Bvh::build(&mesh);
        let mut tested = 0;
        let mut box_tests = 0;
        let origin = [-1e308, -1e308, -1e308];
        bvh.traverse(
            &Ray::new(origin, [1e-300, 1.0, 1e-300]),
            0.0,
            f64::INFINITY,
            &mut box_tests,
            |_| {
                tested += 1;
                None
            },
        );
        assert_eq!(tested, 0);
        assert!(box_tests <= 4 * bvh.nodes.len() as u64);
    }

    /// Whatever the numbers (NaN, ∞, zero and huge components in the mesh and the ray), the traversal
    /// ends after at most one visit per node, and NaN rays visit nothing.
    #[test]
    fn traversal_ends_whatever_the_numbers() {
        let values = [
            0.0,
            -0.0,
            1.0,
            -1.0,
            1e-310,
            1e308,
            -1e308,
            f64::INFINITY,
            f64::NAN,
        ];
        let mut triangles = Vec::new();
        for (i, &a) in values.iter().enumerate() {
            for &b in &values {
                let c = values[(i * 5 + 3) % values.len()];
                triangles.push(PreparedTriangle::new([[a, b, c], [b, c, a], [c, a, b]]));
            }
        }
        let bvh = Bvh::build(&triangles);
        for &o in &values {
            for &d in &values {
                let mut box_tests = 0;
                let mut tests = 0;
                bvh.traverse(
                    &Ray::new([o, 0.5, -o], [d, 1.0, -d]),
                    0.0,
                    f64::INFINITY,
                    &mut box_tests,
                    |_| {
                        tests += 1;
                        Some(1.0)
                    },
                );
                assert!(
                    box_tests <= 4 * bvh.nodes.len() as u64,
                    "{o} {d}: {box_tests}"
                );
                assert!(tests <= triangles.len(), "{o} {d}");
                if o.is_nan() || d.is_nan() {
                    assert_eq!(tests, 0);
                }
            }
        }
    }

    /// How many leaves hold each triangle (a leaf holds a triangle at most once).
    fn leaves_holding(bvh: &Bvh, triangles: usize) -> Vec<usize> {
        let mut seen = vec![0; triangles];
        for node in &bvh.nodes {
            for lane in 0..4 {
                let (c, n) = (node.child[lane] as usize, node.count[lane] as usize);
                if n == 0 {
                    continue;
                }
                let leaf = &bvh.order[c..c + n];
                for (k, &i) in leaf.iter().enumerate() {
                    assert!(!leaf[..k].contains(&i), "a leaf holds {i} twice");
                    seen[i as usize] += 1;
                }
            }
        }
        seen
    }

    /// Every triangle of a large random soup is in a leaf (in one, or in several where it was
    /// split, but in no leaf twice).
    #[test]
    fn every_finite_triangle_is_in_a_leaf() {
        use rand::{Rng, SeedableRng};
        let mut random = rand_pcg::Pcg64::seed_from_u64(5);
        let triangles: Vec<PreparedTriangle> = (0..5000)
            .map(|_| {
                let c: V3<f64> = std::array::from_fn(|_| random.random_range(-10.0..10.0));
                PreparedTriangle::new(std::array::from_fn(|_| {
                    std::array::from_fn(|k| c[k] + random.random_range(-0.3..0.3))
                }))
            })
            .collect();
        let bvh = Bvh::build(&triangles);
        let seen = leaves_holding(&bvh, triangles.len());
        assert!(seen.iter().all(|s| (1..=4).contains(s)));
        assert!(seen.iter().filter(|s| **s == 1).count() > 2500);
        assert_eq!(bvh.len(), triangles.len());
    }

    /// The build makes its references and its two halves of large runs on several threads: the
    /// hierarchy is the same, to the bit, on one thread and on three (a mesh large enough that the
    /// references come in several tasks and the top splits run on two threads).
    #[test]
    fn the_build_is_the_same_on_any_number_of_threads() {
        use crate::render::generate::irregular_sphere;
        let mesh: Vec<PreparedTriangle> = irregular_sphere(5, 3)
            .into_iter()
            .map(PreparedTriangle::new)
            .collect();
        assert!(mesh.len() > 4 * REFERENCES_A_TASK && run_len_is_large(mesh.len()));
        let built_on = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .expect("a pool");
            format!("{:?}", pool.install(|| Bvh::build(&mesh)))
        };
        let one = built_on(1);
        assert!(one == built_on(3), "the hierarchy depends on the threads");
    }

    /// A closed hedgehog: a sphere whose vertices are pushed out to radii between 1 and 12 (each
    /// vertex the same way in every triangle that has it), so its triangles are long spikes that
    /// the build splits. Rays from outside towards its vertices, its edges' midpoints and points
    /// inside its triangles all hit it (no ray slips through a seam), and the hierarchy's hits,
    /// one ray at a time and in packets, are a brute-force loop's.
    #[test]
    fn split_spikes_lose_no_hit() {
        use crate::render::generate::irregular_sphere;
        let spike = |v: V3<f64>| {
            let bits = v.iter().fold(0u64, |h, c| {
                (h ^ c.to_bits()).wrapping_mul(0x9E37_79B9_7F4A_7C15)
            });
            let radius = 1.0 + 11.0 * ((bits >> 11) as f64 / (1u64 << 53) as f64);
            v.map(|c| c * radius)
        };
        let mesh: Vec<PreparedTriangle> = irregular_sphere(2, 7)
            .into_iter()
            .map(|t| PreparedTriangle::new(t.map(spike)))
            .collect();
        let bvh = Bvh::build(&mesh);
        let split_up = mesh
            .iter()
            .filter(|t| {
                let mut boxes = Vec::new();
                split::pieces(&t.vertices, &mut boxes);
                boxes.len() > 1
            })
            .count();
        let seen = leaves_holding(&bvh, mesh.len());
        let in_several = seen.iter().filter(|s| **s > 1).count();
        assert!(split_up > 40 && in_several > 40, "{split_up} {in_several}");
        let brute = |origin: V3<f64>, dir: V3<f64>| {
            let ray = ShearedRay::new(&origin, &dir)?;
            let mut best: Nearest = None;
            for (i, t) in mesh.iter().enumerate() {
                if let Some(hit) = ray.intersect(&t.vertices, 0.0)
                    && best.is_none_or(|(_, b)| hit.t < b.t)
                {
                    best = Some((i, hit));
                }
            }
            best
        };
        let mut targets: Vec<V3<f64>> = Vec::new();
        for t in &mesh {
            let v = t.vertices;
            targets.push(v[0]);
            targets.push(std::array::from_fn(|k| v[0][k] * 0.5 + v[1][k] * 0.5));
            targets.push(std::array::from_fn(|k| (v[0][k] + v[1][k] + v[2][k]) / 3.0));
        }
        // From outside, and from the centre: the hedgehog is star-shaped about its centre (its
        // vertices moved along their radii), so a ray from there leaves it once, at the target.
        for origin in [[0.3, -9.0, 0.5], [0.0; 3]] {
            let rays: Vec<Ray> = targets
                .iter()
                .map(|p| Ray::new(origin, std::array::from_fn(|k| p[k] - origin[k])))
                .collect();
            for packet in rays.chunks_exact(16) {
                let packet: &[Ray; 16] = packet.try_into().unwrap();
                let mut found = [None; 16];
                bvh.nearest_crack_free_packet(
                    Avx2::detect(),
                    packet,
                    [f64::INFINITY; 16],
                    &mut 0,
                    &mut 0,
                    &mut found,
                );
                for (r, ray) in packet.iter().enumerate() {
                    let alone =
                        bvh.nearest_crack_free(None, ray, (0.0, f64::INFINITY), &mut 0, &mut 0);
                    assert_eq!(found[r], alone, "{ray:?}");
                    assert_eq!(alone, brute(ray.origin, ray.dir), "{ray:?}");
                    if origin == [0.0; 3] {
                        let t = alone.map(|(_, hit)| hit.t);
                        assert!(t.is_some_and(|t| (t - 1.0).abs() < 1e-9), "{ray:?} {t:?}");
                    }
                }
            }
        }
    }

    /// Packets of sixteen rays (across whose rays the f32 box test runs where their numbers allow
    /// it) find exactly what each ray finds alone: rows of neighbouring rays, scattered rays, rays
    /// through the mesh's vertices and edge midpoints (on its boxes' faces and corners), with and
    /// without a t_max (one at the ray's nearest hit), packets with a zero direction component in
    /// every ray, and packets with one in some groups of four rays only (whose other groups keep
    /// no parallel rows). The any-hit packet answers as each ray's any-hit query does, on the f32
    /// path and the scalar one.
    #[test]
    fn packets_find_what_single_rays_find() {
        use rand::{Rng, SeedableRng};
        let mesh = load_mesh(&Embedded, "meshes/octasphere.obj").unwrap();
        let bvh = Bvh::build(&mesh);
        let mut random = rand_pcg::Pcg64::seed_from_u64(11);
        let (mut hits, mut blocked) = (0, 0);
        for p in 0..750 {
            let origin: V3<f64> = [
                random.random_range(-0.5..0.5),
                -3.0,
                random.random_range(-0.5..0.5),
            ];
            let base = [
                random.random_range(-0.4..0.4),
                random.random_range(-0.4..0.4),
            ];
            let rays: [Ray; 16] = std::array::from_fn(|r| {
                let target: V3<f64> = match p % 5 {
                    0 => [base[0] + r as f64 / 64.0, 0.0, base[1]],
                    1 => std::array::from_fn(|_| random.random_range(-1.2..1.2)),
                    2 => {
                        let t = &mesh[random.random_range(0..mesh.len())].vertices;
                        let (a, b) = (t[r % 3], t[(r + 1) % 3]);
                        if r % 2 == 0 {
                            a
                        } else {
                            std::array::from_fn(|k| a[k] * 0.5 + b[k] * 0.5)
                        }
                    }
                    // Through x = 0 exactly: a zero direction component.
                    3 => [0.0, 0.0, base[1] + r as f64 / 32.0],
                    // The same in the first and third four rays, not in the others.
                    _ => [
                        if (r / 4) % 2 == 0 { 0.0 } else { 0.125 },
                        0.0,
                        base[1] + r as f64 / 32.0,
                    ],
                };
                let origin = if p % 5 >= 3 {
                    [0.0, -3.0, origin[2]]
                } else {
                    origin
                };
                Ray::new(origin, std::array::from_fn(|k| target[k] - origin[k]))
            });
            // Some rays end before the mesh, some exactly at their nearest hit.
            let t_max: [f64; 16] = std::array::from_fn(|r| match r % 5 {
                0 => 2.9,
                1 => bvh
                    .nearest_crack_free(None, &rays[r], (0.0, f64::INFINITY), &mut 0, &mut 0)
                    .map_or(f64::INFINITY, |(_, hit)| hit.t),
                _ => f64::INFINITY,
            });
            let mut packet = [None; 16];
            bvh.nearest_crack_free_packet(
                Avx2::detect(),
                &rays,
                t_max,
                &mut 0,
                &mut 0,
                &mut packet,
            );
            for (r, ray) in rays.iter().enumerate() {
                let alone = bvh.nearest_crack_free(None, ray, (0.0, t_max[r]), &mut 0, &mut 0);
                assert_eq!(packet[r], alone, "packet {p}, ray {r}: {ray:?}");
                hits += alone.is_some() as usize;
            }
            // The any-hit packet, through the f32 test and through the scalar path.
            for simd in [Avx2::detect(), None] {
                let occluded = bvh.occluded_packet(simd, &rays, t_max, &mut 0, &mut 0);
                for (r, ray) in rays.iter().enumerate() {
                    let alone = bvh.occluded(None, ray, (0.0, t_max[r]), &mut 0, &mut 0);
                    let what = format!("packet {p}, ray {r}, {simd:?}: {ray:?}");
                    assert_eq!((occluded >> r) & 1 == 1, alone, "{what}");
                }
                blocked += occluded.count_ones();
            }
        }
        assert!(hits > 4000 && blocked > 4000, "{hits} {blocked}");
    }

    /// The any-hit query is true exactly when the nearest-hit query finds a hit before t_max, on
    /// random rays (seams and vertices included) with finite and infinite t_max.
    #[test]
    fn occluded_agrees_with_the_nearest_hit() {
        use rand::{Rng, SeedableRng};
        let mesh = load_mesh(&Embedded, "meshes/octasphere.obj").unwrap();
        let bvh = Bvh::build(&mesh);
        let mut random = rand_pcg::Pcg64::seed_from_u64(13);
        let (mut occluded, mut open) = (0, 0);
        for i in 0..20_000 {
            let origin: V3<f64> = std::array::from_fn(|_| random.random_range(-3.0..3.0));
            let target: V3<f64> = if i % 3 == 0 {
                mesh[random.random_range(0..mesh.len())].vertices[i % 3]
            } else {
                std::array::from_fn(|_| random.random_range(-1.2..1.2))
            };
            let dir = std::array::from_fn(|k| target[k] - origin[k]);
            let t_max = [f64::INFINITY, 1.0, 0.999_999, 0.5][i % 4];
            let ray = Ray::new(origin, dir);
            let nearest = bvh.nearest_crack_free(None, &ray, (0.0, f64::INFINITY), &mut 0, &mut 0);
            let expected = nearest.is_some_and(|(_, hit)| hit.t < t_max);
            assert_eq!(
                bvh.occluded(Avx2::detect(), &ray, (0.0, t_max), &mut 0, &mut 0),
                expected,
                "{origin:?} {dir:?} {t_max}"
            );
            occluded += expected as usize;
            open += !expected as usize;
        }
        assert!(occluded > 3000 && open > 3000, "{occluded} {open}");
    }

    /// The one-ray any-hit walk through f32 boxes ([`narrow::occluded_one_ray`]) answers as the f64
    /// walk does: rays leaving the surface of the sphere and of a flat grid (whose boxes are flat
    /// in z), in random and axis-parallel directions, looking to a random distance, to their
    /// nearest hit exactly and to the float below it.
    #[test]
    fn the_f32_any_hit_walk_answers_as_the_f64_walk() {
        use rand::{Rng, SeedableRng};
        let avx2 = crate::render::kernels::avx2_or_skip!();
        let sphere = load_mesh(&Embedded, "meshes/octasphere.obj").unwrap();
        // A 16x16 grid of squares in the plane z = 0.3, two triangles each.
        let grid: Vec<PreparedTriangle> = (0..256)
            .flat_map(|i| {
                let (x, y) = (f64::from(i % 16) / 8.0 - 1.0, f64::from(i / 16) / 8.0 - 1.0);
                let corner = |dx: f64, dy: f64| [x + dx / 8.0, y + dy / 8.0, 0.3];
                [
                    [corner(0.0, 0.0), corner(1.0, 0.0), corner(1.0, 1.0)],
                    [corner(0.0, 0.0), corner(1.0, 1.0), corner(0.0, 1.0)],
                ]
            })
            .map(PreparedTriangle::new)
            .collect();
        let mut random = rand_pcg::Pcg64::seed_from_u64(25);
        let (mut blocked, mut open) = (0, 0);
        for mesh in [&sphere, &grid] {
            let bvh = Bvh::build(mesh);
            for i in 0..20_000 {
                // A point on a random triangle, or anywhere near the mesh.
                let v = &mesh[random.random_range(0..mesh.len())].vertices;
                let (b, c) = (random.random_range(0.0..0.5), random.random_range(0.0..0.5));
                let origin: V3<f64> = if i % 5 == 4 {
                    std::array::from_fn(|_| random.random_range(-1.5..1.5))
                } else {
                    std::array::from_fn(|k| {
                        v[0][k] + b * (v[1][k] - v[0][k]) + c * (v[2][k] - v[0][k])
                    })
                };
                let mut dir: V3<f64> = std::array::from_fn(|_| random.random_range(-1.0..1.0));
                // Parallel to one axis's slabs, or to two.
                match i % 7 {
                    0 => dir[i % 3] = 0.0,
                    1 => (dir[i % 3], dir[(i + 1) % 3]) = (0.0, 0.0),
                    _ => {}
                }
                let ray = Ray::new(origin, dir);
                let nearest =
                    bvh.nearest_crack_free(None, &ray, (0.0, f64::INFINITY), &mut 0, &mut 0);
                let t_max = match (i % 4, nearest) {
                    (0, Some((_, hit))) => hit.t,
                    (1, Some((_, hit))) => hit.t.next_up(),
                    (2, _) => random.random_range(0.0..2.0),
                    _ => f64::INFINITY,
                };
                let f64_walk = bvh.occluded(None, &ray, (0.0, t_max), &mut 0, &mut 0);
                // SAFETY: an `Avx2` exists only on a processor with AVX2 and FMA.
                let found =
                    unsafe { narrow::occluded_one_ray(avx2, &bvh, &ray, t_max, (&mut 0, &mut 0)) };
                assert!(found.is_some(), "the f32 walk refused {ray:?}");
                assert_eq!(found, Some(f64_walk), "{ray:?} to {t_max}");
                blocked += usize::from(f64_walk);
                open += usize::from(!f64_walk);
            }
        }
        assert!(blocked > 10_000 && open > 10_000, "{blocked} {open}");
    }

    /// Every triangle a brute-force loop hits first is the one the BVH finds first (ties to the lower
    /// index, as the renderer breaks them), with the exact-deciding test and with the crack-free one.
    #[test]
    fn the_bvh_finds_what_brute_force_finds() {
        use crate::intersect::{Case, Method};
        let mesh = load_mesh(&Embedded, "meshes/octasphere.obj").unwrap();
        let bvh = Bvh::build(&mesh);
        let nearest = |origin: V3<f64>, dir: V3<f64>, through_bvh: bool| {
            let mut best: Option<(f64, usize)> = None;
            let mut test = |i: usize| {
                let case = Case {
                    tri: mesh[i].vertices,
                    origin,
                    dir,
                };
                let answer = Method::Watertight.run(&case);
                let t = answer.values.filter(|_| answer.hit)?[0];
                if best.is_none_or(|(b, bi)| t < b || (t == b && i < bi)) {
                    best = Some((t, i));
                }
                Some(t)
            };
            if through_bvh {
                bvh.traverse(&Ray::new(origin, dir), 0.0, f64::INFINITY, &mut 0, test);
            } else {
                (0..mesh.len()).for_each(|i| {
                    test(i);
                });
            }
            best
        };
        let crack_free = |origin: V3<f64>, dir: V3<f64>| {
            let ray = ShearedRay::new(&origin, &dir)?;
            let mut best: Option<(f64, usize)> = None;
            for (i, t) in mesh.iter().enumerate() {
                if let Some(TriangleHit { t, .. }) = ray.intersect(&t.vertices, 0.0)
                    && best.is_none_or(|(b, bi)| t < b || (t == b && i < bi))
                {
                    best = Some((t, i));
                }
            }
            best
        };
        let mut hits = 0;
        for i in 0..40 {
            for j in 0..40 {
                let origin = [0.0, -3.0, 0.0];
                // Includes rays exactly along the x = 0 and z = 0 seams (i, j = 20).
                let dir = [(i as f64 - 20.0) / 40.0, 1.0, (j as f64 - 20.0) / 40.0];
                let brute = nearest(origin, dir, false);
                assert_eq!(nearest(origin, dir, true), brute, "ray {dir:?}");
                let fast = bvh
                    .nearest_crack_free(
                        None,
                        &Ray::new(origin, dir),
                        (0.0, f64::INFINITY),
                        &mut 0,
                        &mut 0,
                    )
                    .map(|(i, hit)| (hit.t, i));
                assert_eq!(fast, crack_free(origin, dir), "ray {dir:?}");
                assert_eq!(fast.is_some(), brute.is_some(), "ray {dir:?}");
                hits += brute.is_some() as usize;
            }
        }
        assert!(hits > 400, "{hits}");
    }

    /// Inner levels below `node` (0 for a node whose children are all leaves or empty).
    fn depth(bvh: &Bvh, node: usize) -> usize {
        let inner = (0..4).filter(|&lane| {
            let n = &bvh.nodes[node];
            n.child[lane] != EMPTY && n.count[lane] == 0
        });
        let deepest = inner.map(|lane| depth(bvh, bvh.nodes[node].child[lane] as usize));
        1 + deepest.max().unwrap_or(0)
    }

    /// Triangles spaced ever wider apart (x = 1.05ⁱ) make SAH cut a few off at a time, so the
    /// hierarchy is far deeper than a balanced one (5 levels for 1 500 triangles): its depth stays
    /// within [`traverse::MAX_DEPTH`], which sizes the traversal's fixed stack, and rays through
    /// them all find the nearest.
    #[test]
    fn the_depth_stays_within_the_traversal_stack() {
        let triangles: Vec<PreparedTriangle> = (0..1500)
            .map(|i| {
                let x = 1.05f64.powi(i);
                PreparedTriangle::new([[x, -1.0, -1.0], [x, 2.0, -1.0], [x, -1.0, 2.0]])
            })
            .collect();
        let bvh = Bvh::build(&triangles);
        let levels = depth(&bvh, 0);
        assert!(levels >= 20, "{levels}");
        assert!(levels <= traverse::MAX_DEPTH, "{levels}");
        for (origin, dir, nearest) in [
            ([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], 0),
            ([1e33, 0.0, 0.0], [-1.0, 0.0, 0.0], 1499),
        ] {
            let found = bvh.nearest_crack_free(
                Avx2::detect(),
                &Ray::new(origin, dir),
                (0.0, f64::INFINITY),
                &mut 0,
                &mut 0,
            );
            assert_eq!(found.map(|(i, _)| i), Some(nearest));
        }
    }
}
