//! The one traversal of a [`Bvh`], for every kind of query: one ray's nearest hit, an any-hit
//! (shadow) query, and a packet of rays together, whose boxes are tested in f64 one ray at a time
//! or in f32 eight rays at once ([`super::narrow`]). What differs between them is behind
//! [`Query`]: which rays still search, how a node's four boxes are tested, what a leaf does. The
//! order of the walk is here alone: nearest child first (pushed farthest first, ties in lane order),
//! a child skipped once every ray that meets its box has a hit before it.
//!
//! The stack is a fixed-size array on the call stack: the build bounds the depth ([`MAX_DEPTH`]),
//! and each visit of a node replaces one entry with at most four.

// The stack's array is left uninitialised: `Stack` keeps the entries below `len` written.
#![allow(unsafe_code)]

use std::mem::MaybeUninit;
use std::ops::Range;

use super::{Bvh, EMPTY, Node, SAH_DEPTH};

/// Inner levels of a 4-wide hierarchy, at most: the binary build splits by SAH down to
/// [`SAH_DEPTH`] and by the median below it, which halves a run of fewer than 2³² slots at most 32
/// times; collapsing to 4-wide nodes moves at least one binary level a wide level, and the root
/// holder (node 0) adds one.
pub(in crate::render) const MAX_DEPTH: usize = SAH_DEPTH + 32 + 1;

/// Entries on the stack, at most: the root, then three more for each inner level.
pub(in crate::render) const STACK: usize = 3 * MAX_DEPTH + 1;

/// A child to visit: an inner node (`count` 0) or a leaf's slots, the rays of the query that meet
/// its box, and the nearest distance at which one of them enters it.
#[derive(Clone, Copy)]
pub(in crate::render) struct Visit<N> {
    child: u32,
    count: u32,
    rays: u32,
    near: N,
}

/// What a node's box test found: per lane, the live rays that meet the child's box (0: none, or
/// an empty lane) and the nearest distance at which one of them enters it.
pub(in crate::render) struct Met<N> {
    pub(in crate::render) rays: [u32; 4],
    pub(in crate::render) near: [N; 4],
}

/// A query the traversal carries: up to 32 rays, as a bit set.
pub(in crate::render) trait Query {
    /// A distance along the rays: f64, or f32 for the f32 box test.
    type Near: Copy + PartialOrd;
    /// Of `rays`, those whose search is still open at a box they enter at `near` (a ray with a hit
    /// before it has nothing left to find there).
    fn live(&self, rays: u32, near: Self::Near) -> u32;
    /// Tests `node`'s four boxes against the `live` rays (counting the box tests).
    fn boxes(&mut self, node: &Node, live: u32) -> Met<Self::Near>;
    /// Tests a leaf's slots for the `live` rays (counting the triangle tests).
    fn leaf(&mut self, slots: Range<usize>, live: u32);
    /// Called for each child as it is pushed: a query may ask for its memory early.
    #[inline(always)]
    fn will_visit(&self, _child: u32, _count: u32) {}
}

impl Bvh {
    /// Walks the hierarchy for `query`'s rays `rays`, from distance `start`.
    #[inline(always)]
    pub(in crate::render) fn visit<Q: Query>(&self, query: &mut Q, rays: u32, start: Q::Near) {
        self.visit_from(query, (0, 0), 0, rays, start);
    }

    /// [`Bvh::visit`] from below node 0, whose one box (the whole mesh's) is not tested. A
    /// skipped box test only culls less; it never changes what is found. It pays where that box
    /// culls nothing: a packet that reaches a mesh through the object index, which tested the
    /// mesh's box, or a room's rays, which start inside its walls' box. Rays that miss the whole
    /// mesh test the boxes below it instead (the sphere's 4x4 packet rows read the same).
    #[inline(always)]
    #[cfg_attr(
        not(target_arch = "x86_64"),
        allow(dead_code, reason = "used by the x86-64 packet walk only")
    )]
    pub(in crate::render) fn visit_below_root<Q: Query>(
        &self,
        query: &mut Q,
        rays: u32,
        start: Q::Near,
    ) {
        let Some(root) = self.nodes.first() else {
            return;
        };
        let from = match root.child.map(|c| c != super::EMPTY) {
            [true, false, false, false] => (root.child[0], root.count[0]),
            _ => (0, 0),
        };
        self.visit_from(query, from, 0, rays, start);
    }

    /// [`Bvh::visit`] from inner node `near` (one a last walk found a hit below), then, while some
    /// ray of `rays` is still live at `start`, each ancestor's other children in turn, up to node
    /// 0: the whole hierarchy in the end, each node at most once, the part around `near` first.
    /// For an any-hit query of rays beside the last ones, which most often end near where those
    /// did. The boxes of `near` and its ancestors are not tested, only those of their children (a
    /// skipped box test only culls less).
    #[inline(always)]
    #[cfg_attr(
        not(target_arch = "x86_64"),
        allow(dead_code, reason = "used by the x86-64 packet walk only")
    )]
    pub(in crate::render) fn visit_climbing<Q: Query>(
        &self,
        query: &mut Q,
        near: u32,
        rays: u32,
        start: Q::Near,
    ) {
        let mut node = near;
        self.visit_from(query, (node, 0), 0, rays, start);
        while query.live(rays, start) != 0 {
            let Some(parent) = self.climb.parent(node) else {
                return;
            };
            let below = super::climb::lanes_holding(&self.nodes[parent as usize], node);
            self.visit_from(query, (parent, 0), below, rays, start);
            node = parent;
        }
    }

    /// Walks from `(child, count)`: an inner node, or a leaf's slots; an inner node's lanes in
    /// `skip` (a bit each) are left out of it (not of the nodes below it).
    #[inline(always)]
    fn visit_from<Q: Query>(
        &self,
        query: &mut Q,
        (child, count): (u32, u32),
        skip: u32,
        rays: u32,
        start: Q::Near,
    ) {
        if self.nodes.is_empty() || rays == 0 {
            return;
        }
        let mut stack = Stack::new();
        stack.push(Visit {
            child,
            count,
            rays,
            near: start,
        });
        // The first node's lanes to leave out; none below it.
        let mut skip = skip;
        while let Some(entry) = stack.pop() {
            let live = query.live(entry.rays, entry.near);
            if live == 0 {
                continue;
            }
            if entry.count > 0 {
                query.leaf(
                    entry.child as usize..(entry.child + entry.count) as usize,
                    live,
                );
                continue;
            }
            let node = &self.nodes[entry.child as usize];
            let mut met = query.boxes(node, live);
            for (lane, rays) in met.rays.iter_mut().enumerate() {
                if skip & 1 << lane != 0 {
                    *rays = 0;
                }
            }
            skip = 0;
            for lane in farthest_first(&met) {
                query.will_visit(node.child[lane], node.count[lane]);
                stack.push(Visit {
                    child: node.child[lane],
                    count: node.count[lane],
                    rays: met.rays[lane],
                    near: met.near[lane],
                });
            }
        }
    }
}

/// The lanes some ray meets, farthest entry first (so the nearest is popped next); equal entries
/// keep lane order.
#[inline(always)]
fn farthest_first<N: Copy + PartialOrd>(met: &Met<N>) -> impl Iterator<Item = usize> {
    // The lanes met, as bits (without a branch per lane, which a processor mispredicts often),
    // then listed lowest first.
    let mut met_lanes = 0u32;
    for lane in 0..4 {
        met_lanes |= u32::from(met.rays[lane] != 0) << lane;
    }
    let mut lanes = [0usize; 4];
    let mut n = 0;
    while met_lanes != 0 {
        lanes[n] = met_lanes.trailing_zeros() as usize;
        met_lanes &= met_lanes - 1;
        n += 1;
    }
    // At most four: an insertion sort.
    for i in 1..n {
        let mut j = i;
        while j > 0 && met.near[lanes[j - 1]] < met.near[lanes[j]] {
            lanes.swap(j - 1, j);
            j -= 1;
        }
    }
    lanes.into_iter().take(n)
}

/// The number of non-empty children of `node`: the box tests one ray makes there.
#[inline(always)]
pub(in crate::render) fn children(node: &Node) -> u64 {
    node.child.iter().filter(|c| **c != EMPTY).count() as u64
}

/// The traversal stack: [`STACK`] entries on the call stack, the first `len` written.
struct Stack<N> {
    entries: [MaybeUninit<Visit<N>>; STACK],
    len: usize,
}

impl<N: Copy> Stack<N> {
    #[inline(always)]
    fn new() -> Self {
        Stack {
            entries: [const { MaybeUninit::uninit() }; STACK],
            len: 0,
        }
    }

    /// Pushes `visit`; more than [`STACK`] entries would mean a hierarchy deeper than the build
    /// makes, a bug, and panics (the index is checked).
    #[inline(always)]
    fn push(&mut self, visit: Visit<N>) {
        self.entries[self.len] = MaybeUninit::new(visit);
        self.len += 1;
    }

    #[inline(always)]
    fn pop(&mut self) -> Option<Visit<N>> {
        self.len = self.len.checked_sub(1)?;
        // SAFETY: the entries below the old `len` were written by `push`.
        Some(unsafe { self.entries[self.len].assume_init() })
    }
}
