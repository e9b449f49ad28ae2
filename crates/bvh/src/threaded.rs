//! One threading's nodes re-laid in that threading's own pre-order, box and miss link in one
//! 32-byte record: the layout the GPU's stackless kernels walk.
//!
//! In every threading a hit link is the next node of the order's pre-order ([`crate::mtbvh`]),
//! so once the nodes are stored in that pre-order the hit link is implicit (the next record)
//! and a step of the walk reads one record instead of a node and a separate link pair. The
//! nodes visited, in their order, are those of the links' walk: same work, same answers.
//! The price is memory: one 32-byte record a node per threading, where the links were 8 bytes.

use bytemuck::{Pod, Zeroable};

use crate::mtbvh::LINK_END;
use crate::pack::{BvhNode, Links};

/// A node in one threading's pre-order (32 bytes, two 16-byte rows as WGSL reads them).
///
/// ```text
/// bytes  0..12  min    f32 × 3
/// bytes 12..16  miss   u32   position of the record after this node's subtree, or LINK_END
/// bytes 16..28  max    f32 × 3
/// bytes 28..32  leaf   u32   a leaf's index in PackedBvh::nodes (its triangles); LINK_END
///                            for an internal node
/// ```
/// When the ray enters the box the walk goes on at the next record; past the last it ends.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct ThreadedNode {
    /// Smallest corner of the node's box.
    pub min: [f32; 3],
    /// Where the walk goes when the ray misses the box: a position in the same pre-order.
    pub miss: u32,
    /// Largest corner of the node's box.
    pub max: [f32; 3],
    /// For a leaf, its index in the shared node array; [`LINK_END`] otherwise.
    pub leaf: u32,
}

const _: () = assert!(size_of::<ThreadedNode>() == 32);

/// Records of all seven threadings (the six MTBVH directions and the TBVH) over `node_count`
/// nodes: one a node each.
pub fn record_count(node_count: usize) -> usize {
    (crate::DIRECTION_COUNT + 1) * node_count
}

/// The records of the threading with `links` over `nodes`, starting at `root`
/// ([`LINK_END`] for an empty tree): record `p` is the `p`-th node the order's pre-order meets.
///
/// # Panics
/// If the hit links do not walk every node once (`links` is not a threading of `nodes`).
pub fn threaded_nodes(nodes: &[BvhNode], links: &[Links], root: u32) -> Vec<ThreadedNode> {
    assert_eq!(nodes.len(), links.len(), "one link pair per node");
    // The pre-order is the chain of hit links from the root.
    let mut order = Vec::with_capacity(nodes.len());
    let mut node = root;
    while node != LINK_END {
        order.push(node);
        node = links[node as usize].hit;
    }
    assert_eq!(
        order.len(),
        nodes.len(),
        "the hit links walk every node once"
    );
    let mut position = vec![LINK_END; nodes.len()];
    for (p, &node) in order.iter().enumerate() {
        position[node as usize] = p as u32;
    }
    order
        .iter()
        .map(|&index| {
            let node = &nodes[index as usize];
            let miss = links[index as usize].miss;
            ThreadedNode {
                min: node.min,
                miss: if miss == LINK_END {
                    LINK_END
                } else {
                    position[miss as usize]
                },
                max: node.max,
                leaf: if node.triangle_count > 0 {
                    index
                } else {
                    LINK_END
                },
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::BuildOptions;
    use crate::pack::PackedBvh;
    use crate::testing::random_soup;

    /// Walks `records` with the box test replaced by `enters(node index)`, returning the nodes
    /// (shared indices) met; the same walk over `links` must meet the same nodes.
    fn walk_records(
        records: &[ThreadedNode],
        order: &[u32],
        enters: &impl Fn(u32) -> bool,
    ) -> Vec<u32> {
        let mut met = Vec::new();
        let mut p = 0u32;
        while (p as usize) < records.len() {
            let node = order[p as usize];
            met.push(node);
            p = if enters(node) {
                p + 1
            } else {
                records[p as usize].miss
            };
        }
        met
    }

    fn walk_links(links: &[Links], root: u32, enters: &impl Fn(u32) -> bool) -> Vec<u32> {
        let mut met = Vec::new();
        let mut node = root;
        while node != LINK_END {
            met.push(node);
            let link = links[node as usize];
            node = if enters(node) { link.hit } else { link.miss };
        }
        met
    }

    #[test]
    fn records_walk_the_links_nodes_in_every_threading() {
        for seed in 0..8u64 {
            let soup = random_soup(seed, 40 + 30 * seed as usize);
            let bvh = PackedBvh::build(&soup, &BuildOptions::default());
            let mut sets = vec![(bvh.tbvh_links.as_slice(), bvh.tbvh_root)];
            for d in 0..crate::DIRECTION_COUNT {
                sets.push((bvh.direction_links(d), bvh.mtbvh_roots[d]));
            }
            for (links, root) in sets {
                let records = threaded_nodes(&bvh.nodes, links, root);
                let order = walk_links(links, root, &|_| true);
                for (p, record) in records.iter().enumerate() {
                    let node = &bvh.nodes[order[p] as usize];
                    assert_eq!((record.min, record.max), (node.min, node.max));
                    assert_eq!(record.leaf != LINK_END, node.triangle_count > 0);
                    if record.leaf != LINK_END {
                        assert_eq!(record.leaf, order[p]);
                    }
                }
                // Pseudo-random box outcomes, so misses skip subtrees of every depth.
                for salt in 0..16u32 {
                    let enters = |n: u32| !(n.wrapping_mul(2_654_435_761) ^ salt).is_multiple_of(3);
                    assert_eq!(
                        walk_records(&records, &order, &enters),
                        walk_links(links, root, &enters)
                    );
                }
            }
        }
    }

    #[test]
    fn an_empty_tree_has_no_records() {
        assert!(threaded_nodes(&[], &[], LINK_END).is_empty());
    }
}
