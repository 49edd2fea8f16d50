//! What an any-hit walk climbs by: each 4-wide node's parent, and the node that holds each leaf.
//! A packet of rays beside the last packet most often ends where that one did, so its walk starts
//! in the node the last packet's hit was found in, and climbs from there
//! ([`Bvh::visit_climbing`](super::Bvh::visit_climbing)); the 8-wide walk of one ray keeps its own
//! parents ([`super::eight::Eight`]).

use super::{Node, WideNode};

pub(in crate::render) use super::eight::NO_PARENT;

/// The links of a hierarchy's 4-wide nodes.
#[derive(Clone, Debug, Default)]
pub(in crate::render) struct Climb {
    /// Each node's parent ([`NO_PARENT`] for node 0).
    pub(in crate::render) parents: Vec<u32>,
    /// By quad (slot / 4): the node whose lane holds the leaf starting there ([`NO_PARENT`] where
    /// no 4-wide leaf starts; each leaf starts at a multiple of four).
    holders: Vec<u32>,
}

impl Climb {
    /// The links of `nodes`.
    pub(in crate::render) fn of(nodes: &[Node]) -> Climb {
        // The 4-wide leaves come before the 8-wide walk's packed ones: no holder past them.
        let leaves_end = nodes
            .iter()
            .flat_map(|node| {
                (0..4)
                    .filter(|&lane| node.count[lane] > 0)
                    .map(|lane| node.child[lane] + node.count[lane])
            })
            .max()
            .unwrap_or(0);
        let mut climb = Climb {
            parents: vec![NO_PARENT; nodes.len()],
            holders: vec![NO_PARENT; (leaves_end as usize).div_ceil(4)],
        };
        for (at, node) in nodes.iter().enumerate() {
            for lane in 0..4 {
                let (child, count) = (node.child[lane] as usize, node.count[lane]);
                match count {
                    0 if child < nodes.len() => climb.parents[child] = at as u32,
                    0 => {}
                    _ => {
                        if let Some(holder) = climb.holders.get_mut(child / 4) {
                            *holder = at as u32;
                        }
                    }
                }
            }
        }
        climb
    }

    /// The node whose lane holds the leaf starting at slot `first`, if one does.
    #[inline(always)]
    #[cfg_attr(
        not(target_arch = "x86_64"),
        allow(dead_code, reason = "used by the x86-64 packet walk only")
    )]
    pub(in crate::render) fn holder(&self, first: usize) -> Option<u32> {
        self.holders
            .get(first / 4)
            .copied()
            .filter(|&node| node != NO_PARENT)
    }

    /// `node`'s parent, if it has one (node 0, and a node the links do not know, have none).
    #[inline(always)]
    pub(in crate::render) fn parent(&self, node: u32) -> Option<u32> {
        self.parents
            .get(node as usize)
            .copied()
            .filter(|&parent| parent != NO_PARENT)
    }

    /// `node`'s ancestor `levels` up, or node 0 if it is fewer levels deep.
    #[cfg_attr(
        not(target_arch = "x86_64"),
        allow(dead_code, reason = "used by the x86-64 packet walk only")
    )]
    pub(in crate::render) fn ancestor(&self, mut node: u32, levels: u32) -> u32 {
        for _ in 0..levels {
            match self.parent(node) {
                Some(parent) => node = parent,
                None => break,
            }
        }
        node
    }

    /// The bytes it holds.
    pub(in crate::render) fn held_bytes(&self) -> u64 {
        (std::mem::size_of::<u32>() * (self.parents.capacity() + self.holders.capacity())) as u64
    }
}

/// The lanes (a bit each) of `parent` whose child is inner node `node`.
#[inline(always)]
pub(in crate::render) fn lanes_holding<const W: usize>(parent: &WideNode<W>, node: u32) -> u32 {
    let mut lanes = 0;
    for lane in 0..W {
        if parent.child[lane] == node && parent.count[lane] == 0 {
            lanes |= 1 << lane;
        }
    }
    lanes
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::generate::{grid_box, mesh_hierarchy, mesh_scene};

    /// Each node's parent holds it in a lane, node 0 has none, and every 4-wide leaf's holder
    /// holds it; climbing from any node reaches node 0.
    #[test]
    fn every_node_and_leaf_knows_what_holds_it() {
        if !cfg!(target_arch = "x86_64") {
            return;
        }
        let (camera, side, triangles) = grid_box(12);
        let prepared = mesh_scene(&triangles, camera, side, side);
        let bvh = mesh_hierarchy(&prepared).expect("a mesh scene has a hierarchy");
        let (nodes, climb) = (&bvh.nodes, &bvh.climb);
        assert_eq!(climb.parents.len(), nodes.len());
        assert_eq!(climb.parents[0], NO_PARENT);
        let mut leaves = 0;
        for at in 1..nodes.len() {
            let parent = &nodes[climb.parents[at] as usize];
            assert_eq!(
                lanes_holding(parent, at as u32).count_ones(),
                1,
                "node {at}"
            );
            assert_eq!(climb.ancestor(at as u32, MAX_LEVELS), 0, "node {at}");
        }
        for (at, node) in nodes.iter().enumerate() {
            for lane in (0..4).filter(|&lane| node.count[lane] > 0) {
                assert_eq!(climb.holder(node.child[lane] as usize), Some(at as u32));
                leaves += 1;
            }
        }
        assert!(leaves > 100, "{leaves} leaves");
    }

    /// More levels than any hierarchy has.
    const MAX_LEVELS: u32 = 100;
}
