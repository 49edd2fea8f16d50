//! The hierarchy collapsed eight wide for one ray's any-hit walk ([`super::narrow::occluded_one_ray`]):
//! the binary build's nodes opened, the largest box first, until a node holds eight children, as the
//! 4-wide nodes hold four ([`super::widest_children`]). The walk then tests eight boxes with one
//! 256-bit operation a plane and visits fewer nodes. The boxes are made as the 4-wide nodes' are
//! (each binary node's padded box rounded outward to f32), so the walk's bound holds as it does for
//! them, and the leaves are the 4-wide nodes' own runs of slots. Packets keep the 4-wide nodes.

// Built and walked on x86-64 only: elsewhere nothing reads them.
#![cfg_attr(
    not(target_arch = "x86_64"),
    allow(dead_code, reason = "walked by the x86-64 kernels only")
)]

use super::{BinaryNode, WideNode, widest_children};

/// Eight child boxes a node (256 bytes); an inner lane's child is a node of [`Eight::nodes`].
pub(in crate::render) type Node8 = WideNode<8>;

/// The 8-wide nodes and where a walk starts.
#[derive(Clone, Debug, Default)]
pub(in crate::render) struct Eight {
    pub(in crate::render) nodes: Vec<Node8>,
    /// The whole mesh, as `(child, count)`: node 0 here, or the one leaf of a small mesh; `None`
    /// for an empty hierarchy.
    pub(in crate::render) start: Option<(u32, u32)>,
}

impl Eight {
    /// The 8-wide nodes over the binary build `binary` (its root first), `slots` holding each
    /// binary leaf's run of slots.
    pub(super) fn of(binary: &[BinaryNode], slots: &[(u32, u32)]) -> Eight {
        let Some(root) = binary.first() else {
            return Eight::default();
        };
        if root.count > 0 {
            return Eight {
                nodes: Vec::new(),
                start: Some(slots[0]),
            };
        }
        let mut eight = Eight {
            nodes: Vec::with_capacity(binary.len() / 8 + 1),
            start: None,
        };
        let root = eight.collapse(binary, slots, 0);
        eight.start = Some((root, 0));
        eight.nodes.shrink_to_fit();
        eight
    }

    /// Adds the 8-wide node for binary inner node `index` (and those below it); returns its index.
    fn collapse(&mut self, binary: &[BinaryNode], slots: &[(u32, u32)], index: usize) -> u32 {
        let at = self.nodes.len();
        self.nodes.push(Node8::empty());
        for (lane, &c) in widest_children(binary, index, 8).iter().enumerate() {
            let (child, count) = match binary[c].count {
                0 => (self.collapse(binary, slots, c), 0),
                _ => slots[c],
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

    /// The bytes it holds.
    pub(in crate::render) fn held_bytes(&self) -> u64 {
        (std::mem::size_of::<Node8>() * self.nodes.capacity()) as u64
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::bvh::{Bvh, EMPTY, Node};
    use crate::render::generate::irregular_sphere;
    use crate::render::objects::PreparedTriangle;

    /// Every leaf of a 4-wide hierarchy, as `(first slot, count)`.
    fn leaves4(nodes: &[Node], (child, count): (u32, u32), found: &mut Vec<(u32, u32)>) {
        if count > 0 {
            found.push((child, count));
            return;
        }
        let node = &nodes[child as usize];
        for lane in (0..4).filter(|&lane| node.child[lane] != EMPTY) {
            leaves4(nodes, (node.child[lane], node.count[lane]), found);
        }
    }

    /// The same of the 8-wide nodes; also checks that each inner lane's box holds its node's boxes
    /// (a box that lost part of what is below it would cull a hit).
    fn leaves8(eight: &Eight, (child, count): (u32, u32), found: &mut Vec<(u32, u32)>) -> usize {
        if count > 0 {
            found.push((child, count));
            return 0;
        }
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
            nodes += leaves8(eight, (node.child[lane], node.count[lane]), found);
        }
        nodes
    }

    #[test]
    fn the_eight_wide_nodes_reach_every_leaf_once_through_fewer_nodes() {
        for level in [0, 3, 5] {
            let triangles: Vec<PreparedTriangle> = irregular_sphere(level, 7)
                .into_iter()
                .map(PreparedTriangle::new)
                .collect();
            let bvh = Bvh::build(&triangles);
            let root = &bvh.nodes[0];
            let mut four = Vec::new();
            leaves4(&bvh.nodes, (root.child[0], root.count[0]), &mut four);
            let mut eight = Vec::new();
            let start = bvh.eight.start.expect("a mesh with triangles has a start");
            let reached = leaves8(&bvh.eight, start, &mut eight);
            assert_eq!(
                reached,
                bvh.eight.nodes.len(),
                "level {level}: a node no walk reaches"
            );
            four.sort_unstable();
            eight.sort_unstable();
            assert_eq!(four, eight, "level {level}");
            let lanes: usize = bvh
                .eight
                .nodes
                .iter()
                .map(|n| n.child.iter().filter(|&&c| c != EMPTY).count())
                .sum();
            // Opened until eight children (or only leaves): fewer nodes than four wide.
            if level > 0 {
                assert!(bvh.eight.nodes.len() < bvh.nodes.len(), "level {level}");
                assert!(
                    lanes > 3 * bvh.eight.nodes.len(),
                    "level {level}: {lanes} lanes"
                );
            }
        }
    }
}
