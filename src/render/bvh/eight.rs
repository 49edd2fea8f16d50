//! The hierarchy made eight wide for one ray's any-hit walk ([`super::narrow::occluded_one_ray`]):
//! eight boxes tested with one 256-bit operation a plane, fewer nodes on the way down than four
//! wide. The boxes are made as the 4-wide nodes' are (each binary node's padded box rounded
//! outward to f32), so the walk's bound holds as it does for them. Packets keep the 4-wide nodes.
//!
//! Three choices, each measured on the camera rays' any-hit queries of the 81 920-triangle sphere
//! and the 41 200-triangle box seen from inside (one thread, alternating binaries):
//! - **Packed leaves.** A part of the binary build of four references or fewer is one leaf, its
//!   triangles packed into one quad appended to the hierarchy's slots; a larger binary leaf keeps
//!   its own 4-wide run. Each 4-wide leaf starts a quad of its own, so the sphere's leaves of one
//!   to three triangles filled 2.2 of a quad's four lanes. Packed, the sphere took 6% less time.
//! - **Children planned** ([`Plan`]) for the least summed box area, not opened largest first as
//!   the 4-wide nodes are: half the sphere's 8-wide nodes had two children.
//! - **The smallest box first.** A node's children are sorted by area, the walk taking the
//!   smallest first (after the boxes the ray starts in). In the plan's own order the box from
//!   inside took 21% less time and the sphere 5% more: that order visits the far side of each
//!   split first, which suits a camera inside a mesh looking one way and not one outside looking
//!   the same way. Sorted by area, neither depends on where the camera looks.
//!
//! Together: the sphere 8% less time and the box 9% less than opening largest first with the
//! 4-wide leaves.

// Built and walked on x86-64 only: elsewhere nothing reads them.
#![cfg_attr(
    not(target_arch = "x86_64"),
    allow(dead_code, reason = "walked by the x86-64 kernels only")
)]

use super::{BinaryNode, Leaves, Slots, WideNode};

/// Eight child boxes a node (256 bytes); an inner lane's child is a node of [`Eight::nodes`].
pub(in crate::render) type Node8 = WideNode<8>;

/// A part of the binary build with this many references or fewer is one leaf of the 8-wide walk,
/// its triangles packed into one quad.
const PACKED: usize = 4;

/// The 8-wide nodes and where a walk starts.
#[derive(Clone, Debug, Default)]
pub(in crate::render) struct Eight {
    pub(in crate::render) nodes: Vec<Node8>,
    /// The whole mesh, as `(child, count)`: node 0 here, or the one leaf of a small mesh; `None`
    /// for an empty hierarchy.
    pub(in crate::render) start: Option<(u32, u32)>,
    /// Each node's parent ([`NO_PARENT`] for the first): where a walk that found nothing near the
    /// last blocker looks next.
    pub(in crate::render) parents: Vec<u32>,
}

/// The parent of a node that has none.
pub(in crate::render) const NO_PARENT: u32 = u32::MAX;

impl Eight {
    /// The 8-wide nodes over the binary build `binary` (its root first), whose references are
    /// `leaves`, `slots` holding each binary leaf's run of slots. A binary leaf keeps its run; a
    /// larger part of four references or fewer is packed into slots appended to `packs`.
    pub(super) fn of(
        binary: &[BinaryNode],
        (leaves, slots): (&Leaves, &[(u32, u32)]),
        packs: Slots,
    ) -> Eight {
        if binary.is_empty() {
            return Eight::default();
        }
        let runs = reference_runs(binary);
        let whole = |c: usize| binary[c].count > 0 || runs[c].len() <= PACKED;
        let (order, vertices) = packs;
        // A binary leaf's slots, or the part's triangles packed at the end.
        let mut leaf = |c: usize| match binary[c].count {
            0 => leaves.append(runs[c].clone(), (&mut *order, &mut *vertices)),
            _ => slots[c],
        };
        let plan = Plan::of(binary, &whole);
        let mut eight = Eight {
            nodes: Vec::with_capacity(binary.len() / 8 + 1),
            start: None,
            parents: Vec::with_capacity(binary.len() / 8 + 1),
        };
        eight.start = Some(if whole(0) {
            leaf(0)
        } else {
            (eight.collapse(binary, (&plan, &whole), &mut leaf, 0), 0)
        });
        eight.nodes.shrink_to_fit();
        eight.parents.shrink_to_fit();
        eight
    }

    /// Adds the 8-wide node for binary inner node `index` (and those below it), its children as
    /// `plan` chose them; returns its index. `whole(c)` says that binary node `c` is a leaf here,
    /// `leaf(c)` gives its slots.
    fn collapse(
        &mut self,
        binary: &[BinaryNode],
        (plan, whole): (&Plan, &dyn Fn(usize) -> bool),
        leaf: &mut dyn FnMut(usize) -> (u32, u32),
        index: usize,
    ) -> u32 {
        let at = self.nodes.len();
        self.nodes.push(Node8::empty());
        self.parents.push(NO_PARENT);
        let mut children = Vec::with_capacity(8);
        plan.children(binary, index, &mut children);
        // The walk visits the last lane first (after the boxes the ray starts in): the smallest
        // box, which a ray that meets it is likeliest to find a triangle in.
        // Areas equal to 2⁻²⁰ (the top 20 bits of the mantissa) count as equal, and of those the
        // box reaching farthest to +x, +y and +z comes last, so first: a ray through a vertex or
        // along an edge of a regular grid (whose cells' areas differ only by rounding) is the tie
        // rule's on that side (see `crack_free`). Told apart by their rounding, the box from
        // inside tested 6.09 triangles a ray, and now 4.79; the sphere's order is unchanged.
        let area = |c: &usize| binary[*c].bounds.half_area().to_bits() >> 32;
        let reach = |c: &usize| binary[*c].bounds.max.iter().sum::<f64>();
        children.sort_by(|a, b| area(b).cmp(&area(a)).then(reach(a).total_cmp(&reach(b))));
        for (lane, &c) in children.iter().enumerate() {
            let (child, count) = match whole(c) {
                true => leaf(c),
                false => {
                    let child = self.collapse(binary, (plan, whole), leaf, c);
                    self.parents[child as usize] = at as u32;
                    (child, 0)
                }
            };
            let (min, max) = binary[c].bounds.to_f32();
            let node = &mut self.nodes[at];
            for k in 0..3 {
                node.min[k][lane] = min[k];
                node.max[k][lane] = max[k];
            }
            node.child[lane] = child;
            node.count[lane] = count;
        }
        at as u32
    }

    /// The bytes it holds (its packed slots are the hierarchy's).
    pub(in crate::render) fn held_bytes(&self) -> u64 {
        (std::mem::size_of::<Node8>() * self.nodes.capacity()
            + std::mem::size_of::<u32>() * self.parents.capacity()) as u64
    }
}

/// Per binary node, the references below it: the build partitions them in place, so a node's are
/// one run, its left child's then its right child's. (Children come after their parent.)
fn reference_runs(binary: &[BinaryNode]) -> Vec<std::ops::Range<usize>> {
    let mut runs = vec![0..0; binary.len()];
    for (index, node) in binary.iter().enumerate().rev() {
        runs[index] = if node.count > 0 {
            node.first..node.first + node.count
        } else {
            runs[node.first].start..runs[node.right].end
        };
    }
    runs
}

/// Which binary nodes become each 8-wide node's children: the split of each part among at most
/// eight children that needs the least expected cost, chosen bottom-up (the dynamic program of
/// Ylitie, Karras and Laine, "Efficient Incoherent Ray Traversal on GPUs Through Compressed Wide
/// BVHs", 2017). A ray meets a box with odds in proportion to its area; the leaves are fixed (a
/// binary leaf, or a part packed into a quad), so the cost is the summed area of the 8-wide nodes'
/// boxes, one box test a node. Opening the largest box first, as the 4-wide nodes do, left half
/// of the 81 920-triangle sphere's 8-wide nodes with two children (12 854 nodes; 7 794 planned).
struct Plan {
    /// Per binary node, `cost[n][i − 1]`: the least cost of its part as at most i children of a
    /// node (i from 1 to 8); one child is the part as a leaf, or as an 8-wide node of its own.
    cost: Vec<[f32; 8]>,
    /// Per binary node and i from 2 to 8, how its part becomes at most i children: 0 as at most
    /// i − 1, else k: at most k children of its left part and i − k of its right.
    split: Vec<[u8; 8]>,
    /// Per binary inner node, how many of its 8-wide node's children may come from its left part.
    left: Vec<u8>,
}

impl Plan {
    fn of(binary: &[BinaryNode], whole: &dyn Fn(usize) -> bool) -> Plan {
        let mut plan = Plan {
            cost: vec![[0.0; 8]; binary.len()],
            split: vec![[0; 8]; binary.len()],
            left: vec![0; binary.len()],
        };
        // Children come after their parent, so from the last node back each node's children are
        // planned before it. A leaf's cost is 0 whatever it is a child of.
        for (n, node) in binary.iter().enumerate().rev().filter(|(n, _)| !whole(*n)) {
            let (l, r) = (node.first, node.right);
            // The least cost of the two parts as at most i children together, and its split.
            let both = |plan: &Plan, i: usize| {
                (1..i)
                    .map(|k| (plan.cost[l][k - 1] + plan.cost[r][i - k - 1], k as u8))
                    .min_by(|a, b| a.0.total_cmp(&b.0))
                    .unwrap_or((f32::INFINITY, 0))
            };
            let (below, k) = both(&plan, 8);
            plan.left[n] = k;
            plan.cost[n][0] = node.bounds.half_area() as f32 + below;
            for i in 2..=8 {
                let (split, k) = both(&plan, i);
                let fewer = plan.cost[n][i - 2];
                (plan.cost[n][i - 1], plan.split[n][i - 1]) = match split < fewer {
                    true => (split, k),
                    false => (fewer, 0),
                };
            }
        }
        plan
    }

    /// The children of the 8-wide node for binary inner node `n`.
    fn children(&self, binary: &[BinaryNode], n: usize, children: &mut Vec<usize>) {
        let k = usize::from(self.left[n]);
        self.roots(binary, binary[n].first, k, children);
        self.roots(binary, binary[n].right, 8 - k, children);
    }

    /// The at most `i` children that binary node `n`'s part becomes.
    fn roots(&self, binary: &[BinaryNode], n: usize, i: usize, roots: &mut Vec<usize>) {
        match i {
            1 => roots.push(n),
            _ => match usize::from(self.split[n][i - 1]) {
                0 => self.roots(binary, n, i - 1, roots),
                k => {
                    self.roots(binary, binary[n].first, k, roots);
                    self.roots(binary, binary[n].right, i - k, roots);
                }
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use std::collections::{HashMap, HashSet};

    use super::*;
    use crate::math::linalg::V3;
    use crate::render::bvh::{Bvh, EMPTY};
    use crate::render::generate::irregular_sphere;
    use crate::render::objects::PreparedTriangle;

    /// A triangle's vertices as bits, to find one triangle in two places.
    type Bits = [[u64; 3]; 3];

    fn bits(vertices: &[V3<f64>; 3]) -> Bits {
        vertices.map(|p| p.map(f64::to_bits))
    }

    /// Every leaf of the 4-wide hierarchy, as the triangles it holds.
    fn leaves4(bvh: &Bvh, (child, count): (u32, u32), found: &mut Vec<Vec<Bits>>) {
        if count > 0 {
            let slots = child as usize..(child + count) as usize;
            found.push(slots.map(|slot| bits(&bvh.slot_vertices(slot))).collect());
            return;
        }
        let node = &bvh.nodes[child as usize];
        for lane in (0..4).filter(|&lane| node.child[lane] != EMPTY) {
            leaves4(bvh, (node.child[lane], node.count[lane]), found);
        }
    }

    /// The same of the 8-wide nodes, returning the nodes reached; also checks that each inner
    /// lane's box holds its node's boxes (a box that lost part of what is below it would cull a
    /// hit), and that each leaf starts a quad.
    fn leaves8(bvh: &Bvh, (child, count): (u32, u32), found: &mut Vec<Vec<Bits>>) -> usize {
        if count > 0 {
            assert!(child.is_multiple_of(4), "a leaf at slot {child}");
            let slots = child as usize..(child + count) as usize;
            found.push(slots.map(|slot| bits(&bvh.slot_vertices(slot))).collect());
            return 0;
        }
        let eight = &bvh.eight;
        let node = &eight.nodes[child as usize];
        let mut nodes = 1;
        for lane in (0..8).filter(|&lane| node.child[lane] != EMPTY) {
            if node.count[lane] == 0 {
                let below = &eight.nodes[node.child[lane] as usize];
                for inner in (0..8).filter(|&i| below.child[i] != EMPTY) {
                    for k in 0..3 {
                        assert!(node.min[k][lane] <= below.min[k][inner]);
                        assert!(node.max[k][lane] >= below.max[k][inner]);
                    }
                }
            }
            nodes += leaves8(bvh, (node.child[lane], node.count[lane]), found);
        }
        nodes
    }

    /// The grid box of `cells` cells a side seen from inside (its camera's image is `side` pixels
    /// square).
    fn grid_box_seen_from_inside(cells: usize) -> (crate::render::Prepared, usize) {
        use crate::render::generate::{grid_box, mesh_scene};
        let (camera, side, triangles) = grid_box(cells);
        (mesh_scene(&triangles, camera, side, side), side)
    }

    /// The hierarchy of a one-mesh scene.
    fn mesh_hierarchy(prepared: &crate::render::Prepared) -> &Bvh {
        crate::render::generate::mesh_hierarchy(prepared).expect("a mesh scene has a hierarchy")
    }

    /// The box seen from inside, every camera ray along an edge or through a vertex of its
    /// regular grid, whose cells' boxes have equal areas but for rounding. The tie rule gives each
    /// ray to the triangle on its +x, +y side in the ray's sheared plane; among boxes of equal
    /// area the walk visits first the one reaching farthest to +x, +y and +z, so it finds the
    /// winner in the first leaf it tests more often.
    #[test]
    fn on_a_regular_grid_the_walk_meets_the_tie_winner_first() {
        let avx2 = crate::render::kernels::avx2_or_skip!();
        for cells in [8, 24, 48] {
            let (prepared, side) = grid_box_seen_from_inside(cells);
            let bvh = mesh_hierarchy(&prepared);
            let (mut boxes, mut tested, mut occluded) = (0, 0, 0);
            for row in 0..side {
                for column in 0..side {
                    // The walk alone, not the quad that blocked the last ray.
                    Bvh::forget_last_blocker();
                    let ray = prepared.ray(row, column);
                    let range = (0.0, f64::INFINITY);
                    occluded +=
                        usize::from(bvh.occluded(Some(avx2), &ray, range, &mut boxes, &mut tested));
                }
            }
            assert_eq!(
                occluded,
                side * side,
                "{cells} cells: every ray meets the box"
            );
            // Areas told apart by their rounding: 5.41, 5.53 and 5.93 tests a ray.
            let per_ray = tested as f64 / (side * side) as f64;
            assert!(
                per_ray < 5.0,
                "{cells} cells: {per_ray} triangle tests a ray"
            );
        }
    }

    /// The same for 4x4 packets through the 4-wide nodes: the grid's cells are entered at the
    /// same distance, and of boxes entered together the walk takes first the one reaching
    /// farthest to +x, +y and +z.
    #[test]
    fn on_a_regular_grid_packets_meet_the_tie_winner_first() {
        use crate::render::Ray;
        let avx2 = crate::render::kernels::avx2_or_skip!();
        for cells in [8, 24, 48] {
            let (prepared, side) = grid_box_seen_from_inside(cells);
            let bvh = mesh_hierarchy(&prepared);
            let (mut boxes, mut tested, mut occluded, mut rays) = (0, 0, 0, 0);
            for top in (0..side - 3).step_by(4) {
                for left in (0..side - 3).step_by(4) {
                    // The walk from the top, not from where the last tile's hit was found.
                    Bvh::forget_last_blocker();
                    let tile: [Ray; 16] =
                        std::array::from_fn(|k| prepared.ray(top + k / 4, left + k % 4));
                    let limits = [f64::INFINITY; 16];
                    let found =
                        bvh.occluded_packet(Some(avx2), &tile, limits, &mut boxes, &mut tested);
                    occluded += found.count_ones() as usize;
                    rays += 16;
                }
            }
            assert_eq!(occluded, rays, "{cells} cells: every ray meets the box");
            // Entered together in the build's lane order: 6.92, 6.59 and 6.29 tests a ray.
            let per_ray = tested as f64 / rays as f64;
            assert!(
                per_ray < 5.0,
                "{cells} cells: {per_ray} triangle tests a ray"
            );
        }
    }

    /// The hierarchy over the irregular sphere of `level` (seed 7).
    fn sphere_hierarchy(level: u32) -> Bvh {
        let triangles: Vec<PreparedTriangle> = irregular_sphere(level, 7)
            .into_iter()
            .map(PreparedTriangle::new)
            .collect();
        Bvh::build(&triangles)
    }

    /// Each node's parent is the node whose lane holds it, once; only the first node has none (the
    /// any-hit walk climbs these to the top, and a wrong one would leave part of the mesh unwalked).
    #[test]
    fn every_node_but_the_first_has_the_parent_that_holds_it() {
        for level in [0, 3, 5] {
            let eight = &sphere_hierarchy(level).eight;
            assert_eq!(eight.parents.len(), eight.nodes.len(), "level {level}");
            let mut held = vec![0; eight.nodes.len()];
            for (at, node) in eight.nodes.iter().enumerate() {
                for lane in (0..8).filter(|&l| node.count[l] == 0 && node.child[l] != EMPTY) {
                    let child = node.child[lane] as usize;
                    held[child] += 1;
                    assert_eq!(
                        eight.parents[child], at as u32,
                        "level {level}, node {child}"
                    );
                }
            }
            assert_eq!(eight.parents[0], NO_PARENT, "level {level}");
            assert!(
                held[0] == 0 && held[1..].iter().all(|&h| h == 1),
                "level {level}"
            );
        }
    }

    #[test]
    fn the_eight_wide_leaves_hold_the_four_wide_leaves_whole_through_fewer_nodes() {
        for level in [0, 3, 5] {
            let bvh = sphere_hierarchy(level);
            let root = &bvh.nodes[0];
            let mut four = Vec::new();
            leaves4(&bvh, (root.child[0], root.count[0]), &mut four);
            let mut eight = Vec::new();
            let start = bvh.eight.start.expect("a mesh with triangles has a start");
            let reached = leaves8(&bvh, start, &mut eight);
            assert_eq!(
                reached,
                bvh.eight.nodes.len(),
                "level {level}: a node no walk reaches"
            );
            // Which 8-wide leaves hold each triangle (a triangle split in pieces may be in several).
            let mut held_by: HashMap<Bits, HashSet<usize>> = HashMap::new();
            for (leaf, held) in eight.iter().enumerate() {
                let once: HashSet<&Bits> = held.iter().collect();
                assert_eq!(
                    once.len(),
                    held.len(),
                    "level {level}: a triangle twice in a leaf"
                );
                for triangle in held {
                    held_by.entry(*triangle).or_default().insert(leaf);
                }
            }
            // Each 4-wide leaf's triangles are all in one 8-wide leaf, and the 8-wide leaves hold
            // no triangle that no 4-wide leaf holds.
            let mut in_four = HashSet::new();
            for leaf in &four {
                let mut together = held_by.get(&leaf[0]).cloned().unwrap_or_default();
                for triangle in leaf {
                    in_four.insert(*triangle);
                    together.retain(|l| held_by.get(triangle).is_some_and(|h| h.contains(l)));
                }
                assert!(
                    !together.is_empty(),
                    "level {level}: a 4-wide leaf split up"
                );
            }
            assert_eq!(in_four.len(), held_by.len(), "level {level}");
            assert!(eight.len() <= four.len(), "level {level}");
            // A leaf of more than four triangles is a 4-wide leaf as it was.
            let sorted = |leaf: &Vec<Bits>| {
                let mut leaf = leaf.clone();
                leaf.sort_unstable();
                leaf
            };
            let four_leaves: HashSet<Vec<Bits>> = four.iter().map(sorted).collect();
            for held in eight.iter().filter(|held| held.len() > PACKED) {
                assert!(
                    four_leaves.contains(&sorted(held)),
                    "level {level}: a leaf of {} triangles that no 4-wide leaf holds",
                    held.len()
                );
            }
            let lanes: usize = bvh
                .eight
                .nodes
                .iter()
                .map(|n| n.child.iter().filter(|&&c| c != EMPTY).count())
                .sum();
            // Planned: fewer nodes than four wide, and most of them full (opening the largest box
            // first left about four lanes a node).
            if level > 0 {
                assert!(bvh.eight.nodes.len() < bvh.nodes.len(), "level {level}");
                assert!(
                    lanes > 5 * bvh.eight.nodes.len(),
                    "level {level}: {lanes} lanes, {} nodes",
                    bvh.eight.nodes.len()
                );
            }
            // Each node's lanes from the largest box to the smallest, which the walk takes first.
            for node in &bvh.eight.nodes {
                let area = |lane: usize| {
                    let e: [f32; 3] =
                        std::array::from_fn(|k| node.max[k][lane] - node.min[k][lane]);
                    e[0] * e[1] + e[1] * e[2] + e[2] * e[0]
                };
                let used = node.child.iter().filter(|&&c| c != EMPTY).count();
                assert!(
                    (1..used).all(|lane| area(lane - 1) >= area(lane) * (1.0 - 1e-5)),
                    "level {level}: lanes out of order"
                );
            }
        }
    }
}
