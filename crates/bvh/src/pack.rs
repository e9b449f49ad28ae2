//! The GPU layout: nodes, links and triangles as `#[repr(C)]` plain-old-data arrays.
//!
//! Memory, as the talk counts it: every triangle is 3 vertices × 2 vec4 (96 bytes); every node
//! a 32-byte box shared by all threadings, plus 8 bytes of links per threading. The TBVH keeps
//! one link set, the MTBVH six. See [`PackedBvh::memory`]. The GPU kernels walk the threadings
//! as [`crate::threaded`] records instead (32 bytes a node per threading, one load a step),
//! counted apart as [`Memory::gpu_threaded_bytes`].

use std::mem::size_of;

use bytemuck::{Pod, Zeroable};
use glam::Vec3;
use rayon::prelude::*;
use scene::Triangle;

pub use crate::packed_triangle::{PackedTriangle, PackedVertex};

use crate::build_sah::BuildOptions;
use crate::mtbvh::{DIRECTION_COUNT, thread_all};
use crate::probe::build_chosen;
use crate::threaded::{self, ThreadedNode};
use crate::tree::Bvh;

/// One node's box and contents, shared by the stack traversal and all seven threadings.
///
/// Layout (32 bytes, two 16-byte rows as WGSL reads `vec3<f32>` + `u32`):
/// ```text
/// bytes  0..12  min             f32 × 3
/// bytes 12..16  first_or_right  u32
/// bytes 16..28  max             f32 × 3
/// bytes 28..32  triangle_count  u32   (0 = internal node)
/// ```
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct BvhNode {
    /// Smallest corner of the box around everything below the node.
    pub min: [f32; 3],
    /// Leaf (`triangle_count > 0`): index in [`PackedBvh::triangles`] of its first triangle.
    /// Internal (`triangle_count == 0`): index of its right (second) child; its left child is
    /// the next node (`index + 1`). Only the stack traversal reads it for internal nodes.
    pub first_or_right: u32,
    /// Largest corner of the box.
    pub max: [f32; 3],
    /// Leaf: its number of triangles, `triangles[first_or_right..][..triangle_count]`.
    /// Internal node: 0.
    pub triangle_count: u32,
}

const _: () = assert!(size_of::<BvhNode>() == 32);

/// A node's two links in one threading. Values are node indices or
/// [`crate::mtbvh::LINK_END`]; see [`crate::mtbvh`] for what they mean.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
pub struct Links {
    /// Next node when the ray hits this node's box (next in the order's pre-order).
    pub hit: u32,
    /// Next node when the ray misses it (the node after its subtree).
    pub miss: u32,
}

const _: () = assert!(size_of::<Links>() == 8);

/// The tree, its seven threadings and its triangles, ready to upload.
///
/// The six MTBVH link sets lie one after another, direction-major:
/// `mtbvh_links[d * nodes.len() + node]`. Rays in one GPU wave tend to share a major direction
/// (all primary rays of a tile, photons leaving a small light), so with one direction's links
/// contiguous a 64-byte cache line carries 8 nodes' links that the wave will use, where an
/// interleaved `[Links; 6]` per node would bring 48 bytes a node of which it uses 8. A
/// direction's set is also one contiguous range, so it can be bound on its own should the
/// whole array pass a device's storage-binding limit.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PackedBvh {
    /// Boxes and contents, depth-first (left-first) order; node 0 is the root.
    pub nodes: Vec<BvhNode>,
    /// The TBVH's links (left child first), one per node; its hit links are `index + 1`.
    pub tbvh_links: Vec<Links>,
    /// First node of the TBVH traversal: 0, or `LINK_END` for an empty tree.
    pub tbvh_root: u32,
    /// The six directions' links, `DIRECTION_COUNT × nodes.len()`, direction-major.
    pub mtbvh_links: Vec<Links>,
    /// First node per direction (index = [`direction_index`]); 0 in this layout, where every
    /// order starts at the shared root, or `LINK_END` for an empty tree.
    pub mtbvh_roots: [u32; DIRECTION_COUNT],
    /// Triangles in leaf order.
    pub triangles: Vec<PackedTriangle>,
    /// `triangle_ids[i]` = index in the input slice of `triangles[i]`.
    pub triangle_ids: Vec<u32>,
}

/// Device memory of a [`PackedBvh`], in bytes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Memory {
    /// Packed triangles.
    pub triangle_bytes: usize,
    /// Node boxes (shared by both traversals).
    pub node_bytes: usize,
    /// One set of links (one threading).
    pub link_set_bytes: usize,
    /// Triangles + nodes + one link set + one root.
    pub tbvh_bytes: usize,
    /// Triangles + nodes + six link sets + six roots.
    pub mtbvh_bytes: usize,
    /// What the GPU's stack, TBVH and MTBVH kernels read: triangles + nodes + the seven
    /// threadings as threaded records ([`crate::threaded`], 32 bytes a node each), which trade
    /// the links' 8 bytes for one load a traversal step.
    pub gpu_threaded_bytes: usize,
}

impl PackedBvh {
    /// Builds (with split triangles where they pay: [`crate::probe`]), threads and packs a
    /// tree over `triangles`.
    ///
    /// # Panics
    /// With more triangles than [`crate::build_sah::MAX_TRIANGLES`] or a material index of
    /// [`PackedTriangle::MAX_MATERIAL`] or more.
    pub fn build(triangles: &[Triangle], options: &BuildOptions) -> PackedBvh {
        build_chosen(triangles, options).1
    }

    /// Threads and packs `bvh`, built over `triangles`.
    pub fn from_bvh(triangles: &[Triangle], bvh: &Bvh) -> PackedBvh {
        let nodes = bvh
            .nodes
            .par_iter()
            .map(|n| BvhNode {
                min: n.bounds.min.to_array(),
                first_or_right: n.first_or_right,
                max: n.bounds.max.to_array(),
                triangle_count: n.triangle_count,
            })
            .collect();
        let packed = bvh
            .triangle_order
            .par_iter()
            .map(|&id| PackedTriangle::pack(&triangles[id as usize]))
            .collect();
        let threadings = thread_all(bvh);
        PackedBvh {
            nodes,
            tbvh_links: threadings.tbvh,
            tbvh_root: threadings.root,
            mtbvh_links: threadings.mtbvh,
            mtbvh_roots: [threadings.root; DIRECTION_COUNT],
            triangles: packed,
            triangle_ids: bvh.triangle_order.clone(),
        }
    }

    /// Direction `d`'s links, one per node.
    pub fn direction_links(&self, direction: usize) -> &[Links] {
        let count = self.nodes.len();
        &self.mtbvh_links[direction * count..(direction + 1) * count]
    }

    /// What the arrays take on the device.
    pub fn memory(&self) -> Memory {
        let triangle_bytes = self.triangles.len() * size_of::<PackedTriangle>();
        let node_bytes = self.nodes.len() * size_of::<BvhNode>();
        let link_set_bytes = self.nodes.len() * size_of::<Links>();
        Memory {
            triangle_bytes,
            node_bytes,
            link_set_bytes,
            tbvh_bytes: triangle_bytes + node_bytes + link_set_bytes + size_of::<u32>(),
            mtbvh_bytes: triangle_bytes
                + node_bytes
                + DIRECTION_COUNT * link_set_bytes
                + size_of::<[u32; DIRECTION_COUNT]>(),
            gpu_threaded_bytes: triangle_bytes
                + node_bytes
                + threaded::record_count(self.nodes.len()) * size_of::<ThreadedNode>(),
        }
    }
}

/// The major direction of `direction`: 0:+X 1:−X 2:+Y 3:−Y 4:+Z 5:−Z.
///
/// The major axis is the component of largest magnitude (ties: x before y before z); the sign
/// is that component's (+0 and −0 count as positive). Any answer gives the same hits, since
/// every threading visits every node; the right one culls the most.
pub fn direction_index(direction: Vec3) -> usize {
    let a = direction.abs();
    let axis = if a.x >= a.y && a.x >= a.z {
        0
    } else if a.y >= a.z {
        1
    } else {
        2
    };
    2 * axis + usize::from(direction[axis] < 0.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn direction_index_picks_major_axis_and_sign() {
        assert_eq!(direction_index(Vec3::new(1.0, 0.5, -0.5)), 0);
        assert_eq!(direction_index(Vec3::new(-1.0, 0.5, -0.5)), 1);
        assert_eq!(direction_index(Vec3::new(0.1, 0.5, -0.2)), 2);
        assert_eq!(direction_index(Vec3::new(0.1, -0.5, -0.2)), 3);
        assert_eq!(direction_index(Vec3::new(0.1, 0.5, 2.0)), 4);
        assert_eq!(direction_index(Vec3::new(0.1, 0.5, -2.0)), 5);
        assert_eq!(direction_index(Vec3::new(1.0, -1.0, 1.0)), 0);
    }

    #[test]
    fn memory_counts_six_link_sets_for_the_mtbvh() {
        let triangles = crate::testing::random_soup(7, 50);
        let packed = PackedBvh::build(&triangles, &BuildOptions::default());
        let m = packed.memory();
        let nodes = packed.nodes.len();
        // Split triangles are packed once per piece.
        let triangles = packed.triangles.len();
        assert!(triangles >= 50);
        assert_eq!(m.triangle_bytes, triangles * 96);
        assert_eq!(m.tbvh_bytes, triangles * 96 + nodes * 32 + nodes * 8 + 4);
        assert_eq!(
            m.mtbvh_bytes,
            triangles * 96 + nodes * 32 + 6 * nodes * 8 + 24
        );
        assert_eq!(packed.mtbvh_links.len(), 6 * nodes);
        assert_eq!(
            m.gpu_threaded_bytes,
            triangles * 96 + nodes * 32 + 7 * nodes * 32
        );
    }

    #[test]
    fn tbvh_hit_links_are_the_next_node() {
        let triangles = crate::testing::random_soup(3, 40);
        let packed = PackedBvh::build(&triangles, &BuildOptions::default());
        for (i, links) in packed.tbvh_links.iter().enumerate() {
            let next = if i + 1 == packed.nodes.len() {
                u32::MAX
            } else {
                i as u32 + 1
            };
            assert_eq!(links.hit, next);
        }
    }
}
