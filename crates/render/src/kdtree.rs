//! A kd-tree over one photon pass's photons, for fixed-radius density estimation: the
//! benchmark's alternative to the stochastic spatial hash (issue 6, variant c).
//!
//! The tree is Jensen's left-balanced kd-tree (H. W. Jensen, *Realistic Image Synthesis Using
//! Photon Mapping*, 2001, §6.3): complete, stored in heap order (the children of node `i` are
//! `2i + 1` and `2i + 2`), so it needs no links and its depth is the least possible,
//! ⌊log₂ n⌋ + 1. Each node is one photon, split at its own coordinate along the widest axis of
//! its subtree's bounding box. A node is the photon itself in tree order, 32 bytes
//! ([`KdNode`]), its spare word holding its index and the split axis: measured against 16-byte
//! nodes (position and index) that fetch the photon from the pass's buffer for positions
//! inside the radius, it queries 1.3× (queries in image order) to 2× (random order) faster on
//! the CPU, as it saves a dependent load per photon found.
//!
//! The build selects medians in place ([`slice::select_nth_unstable_by`]) over 16-byte
//! (position, index) entries, subtrees split over rayon, then scatters the photons into heap
//! order. The query ([`PhotonKdTree::query`]) is the twin of `kd_gather` in
//! `gpu/shaders/shared/kdtree.wgsl`:
//! the same stack, the same order (node, near side, far side), so both sum flux in one order.

use bytemuck::{Pod, Zeroable};
use glam::Vec3;
use rayon::prelude::*;

use crate::buffers::Photon;
use crate::packing::unpack_normal;

/// Most photons a tree holds, 2²⁷ − 1: 4 GiB of [`Photon`]s, past any storage binding, so
/// that [`MAX_DEPTH`] and [`STACK_SIZE`] bound every tree that can reach a GPU.
pub const MAX_PHOTONS: usize = (1 << 27) - 1;

/// Levels of the deepest tree, one of [`MAX_PHOTONS`] nodes.
pub const MAX_DEPTH: u32 = 27;

/// Entries of the query's stack. The far child pushed at a node is one level below it, and the
/// entries on the stack belong to distinct levels below the root: at most depth − 1.
pub const STACK_SIZE: usize = MAX_DEPTH as usize - 1;

/// Where the split axis sits in [`KdNode::photon_axis`] (and in the build's entries).
pub const AXIS_SHIFT: u32 = 30;

/// The photon index's bits in [`KdNode::photon_axis`].
pub const PHOTON_MASK: u32 = (1 << AXIS_SHIFT) - 1;

/// Subtrees of at least this many photons are built in parallel (smaller ones are not worth a
/// rayon task).
const PARALLEL_MIN: usize = 4096;

/// One node of the tree: a stored photon (32 bytes, [`Photon`]'s layout with its padding put
/// to use), as uploaded to the GPU (`struct KdNode` in kdtree.wgsl).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct KdNode {
    /// The photon's position; the split plane's point.
    pub position: [f32; 3],
    /// The photon's normal, octahedral-packed ([`Photon::normal`]).
    pub normal: u32,
    /// The photon's flux (RGB), non-zero.
    pub flux: [f32; 3],
    /// Bits 0–29: the photon's index in the pass's photon buffer; bits 30–31: the axis (0 x,
    /// 1 y, 2 z) of the plane through `position` that splits the subtree (0 in leaves). Left
    /// descendants have coordinates ≤ the node's on that axis, right ones ≥.
    pub photon_axis: u32,
}

const _: () = assert!(size_of::<KdNode>() == 32);

impl KdNode {
    /// The photon's index in the photon buffer.
    pub fn photon(&self) -> u32 {
        self.photon_axis & PHOTON_MASK
    }

    /// The split axis, 0 to 2.
    pub fn axis(&self) -> usize {
        (self.photon_axis >> AXIS_SHIFT) as usize
    }
}

/// What the build moves around: a photon's position and its `photon_axis` word (16 bytes, half
/// a node, so the median selections move half the bytes).
#[derive(Clone, Copy, Debug)]
struct Entry {
    position: [f32; 3],
    photon_axis: u32,
}

/// A left-balanced kd-tree over the stored photons of one pass, in heap order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PhotonKdTree {
    nodes: Vec<KdNode>,
}

impl PhotonKdTree {
    /// Builds the tree over the photons of `photons` that are stored (non-zero flux); the
    /// nodes refer to them by their index in `photons`. The same input gives the same nodes
    /// whatever the number of threads.
    ///
    /// # Panics
    /// With more than [`MAX_PHOTONS`] photons (more than a storage binding can hold).
    pub fn build(photons: &[Photon]) -> PhotonKdTree {
        assert!(
            photons.len() <= MAX_PHOTONS,
            "a photon kd-tree holds at most {MAX_PHOTONS} photons, not {}",
            photons.len()
        );
        let mut items: Vec<Entry> = photons
            .par_iter()
            .enumerate()
            .filter(|(_, photon)| photon.is_stored())
            .map(|(index, photon)| Entry {
                position: photon.position,
                photon_axis: index as u32,
            })
            .collect();
        let mut heap_of = vec![0u32; items.len()];
        split(&mut items, &mut heap_of, 0);
        // Gathering the photons is random access: invert the permutation (a small array) so
        // that the nodes can be filled in parallel, in order.
        let mut entry_of = vec![0u32; items.len()];
        for (entry, &heap) in heap_of.iter().enumerate() {
            entry_of[heap as usize] = entry as u32;
        }
        let nodes = entry_of
            .par_iter()
            .map(|&entry| {
                let item = &items[entry as usize];
                let photon = &photons[(item.photon_axis & PHOTON_MASK) as usize];
                KdNode {
                    position: photon.position,
                    normal: photon.normal,
                    flux: photon.flux,
                    photon_axis: item.photon_axis,
                }
            })
            .collect();
        PhotonKdTree { nodes }
    }

    /// The nodes in heap order, ready for a storage buffer.
    pub fn nodes(&self) -> &[KdNode] {
        &self.nodes
    }

    /// Number of nodes (stored photons).
    pub fn len(&self) -> usize {
        self.nodes.len()
    }

    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    /// Levels of the tree: ⌊log₂ n⌋ + 1, 0 when empty; at most [`MAX_DEPTH`].
    pub fn depth(&self) -> u32 {
        depth_of(self.nodes.len())
    }

    /// The photons within `radius` of `position` (squared distance < radius²) whose normal
    /// faces `normal` (dot > 0): how many, and the sum of their flux. Visits nodes in
    /// `kd_gather`'s order.
    pub fn query(&self, position: Vec3, radius: f32, normal: Vec3) -> (u32, Vec3) {
        let [(c, caustic), (i, indirect)] = self.query_classes(position, [radius; 2], normal);
        (c + i, caustic + indirect)
    }

    /// [`Self::query`] for caustic and indirect photons apart ([`crate::packing::is_caustic`]),
    /// each within its own radius (`radii`: caustic, indirect): their counts and fluxes.
    /// Volume photons ([`crate::packing::is_volume`]) are not counted.
    pub fn query_classes(&self, position: Vec3, radii: [f32; 2], normal: Vec3) -> [(u32, Vec3); 2] {
        let mut sums = [(0u32, Vec3::ZERO); 2];
        self.visit(position, radii[0].max(radii[1]), |kd| {
            let offset = Vec3::from(kd.position) - position;
            let class = !crate::packing::is_caustic(kd.normal) as usize;
            if offset.length_squared() < radii[class] * radii[class]
                && !crate::packing::is_volume(kd.normal)
                && unpack_normal(kd.normal).dot(normal) > 0.0
            {
                sums[class].0 += 1;
                sums[class].1 += Vec3::from(kd.flux);
            }
        });
        sums
    }

    /// Calls `visit` on every node the search around `position` within `radius` reaches (all
    /// those within it, and some beyond), in `kd_gather`'s order.
    pub fn visit(&self, position: Vec3, radius: f32, mut visit: impl FnMut(&KdNode)) {
        let count = self.nodes.len();
        let radius_sq = radius * radius;
        let mut stack = [0u32; STACK_SIZE];
        let mut top = 0;
        let mut node = 0;
        loop {
            while node < count {
                let kd = self.nodes[node];
                let offset = Vec3::from(kd.position) - position;
                visit(&kd);
                // The split plane is `offset[axis]` away: the query lies on the left (lower)
                // side when the plane is ahead of it.
                let to_plane = offset[kd.axis()];
                let left = 2 * node + 1;
                let (near, far) = if to_plane > 0.0 {
                    (left, left + 1)
                } else {
                    (left + 1, left)
                };
                if far < count && to_plane * to_plane < radius_sq {
                    stack[top] = far as u32;
                    top += 1;
                }
                node = near;
            }
            if top == 0 {
                return;
            }
            top -= 1;
            node = stack[top] as usize;
        }
    }
}

/// What [`PhotonKdTree::query`] finds, by testing every stored photon (for tests).
pub fn gather_brute_force(
    photons: &[Photon],
    position: Vec3,
    radius: f32,
    normal: Vec3,
) -> (u32, Vec3) {
    let [(c, caustic), (i, indirect)] =
        gather_brute_force_classes(photons, position, [radius; 2], normal);
    (c + i, caustic + indirect)
}

/// What [`PhotonKdTree::query_classes`] finds, by testing every stored photon (for tests).
pub fn gather_brute_force_classes(
    photons: &[Photon],
    position: Vec3,
    radii: [f32; 2],
    normal: Vec3,
) -> [(u32, Vec3); 2] {
    let mut sums = [(0, Vec3::ZERO); 2];
    for photon in photons.iter().filter(|photon| photon.is_stored()) {
        let class = !crate::packing::is_caustic(photon.normal) as usize;
        let offset = Vec3::from(photon.position) - position;
        let near = offset.length_squared() < radii[class] * radii[class];
        let surface = !crate::packing::is_volume(photon.normal);
        if near && surface && unpack_normal(photon.normal).dot(normal) > 0.0 {
            sums[class].0 += 1;
            sums[class].1 += Vec3::from(photon.flux);
        }
    }
    sums
}

/// Levels of a complete binary tree of `count` nodes.
pub fn depth_of(count: usize) -> u32 {
    usize::BITS - count.leading_zeros()
}

/// Nodes in the left subtree of a left-balanced tree of `count` nodes: the full levels' share
/// and as much of the last level as fills the left half first.
fn left_subtree_size(count: usize) -> usize {
    let levels = depth_of(count);
    if levels <= 1 {
        return 0;
    }
    let full = (1usize << (levels - 1)) - 1;
    let half_of_last = 1usize << (levels - 2);
    (half_of_last - 1) + (count - full).min(half_of_last)
}

/// Builds the subtree of `items` rooted at heap index `heap`: the median along the widest
/// axis goes to its left-balanced position, `heap_of` records each item's heap index.
fn split(items: &mut [Entry], heap_of: &mut [u32], heap: u32) {
    if items.is_empty() {
        return;
    }
    let count = items.len();
    let left = left_subtree_size(count);
    let axis = if count == 1 { 0 } else { widest_axis(items) };
    items.select_nth_unstable_by(left, |a, b| a.position[axis].total_cmp(&b.position[axis]));
    items[left].photon_axis |= (axis as u32) << AXIS_SHIFT;
    heap_of[left] = heap;
    let (left_items, rest) = items.split_at_mut(left);
    let (left_heap, rest_heap) = heap_of.split_at_mut(left);
    let right_items = &mut rest[1..];
    let right_heap = &mut rest_heap[1..];
    let (left_root, right_root) = (2 * heap + 1, 2 * heap + 2);
    if count >= PARALLEL_MIN {
        rayon::join(
            || split(left_items, left_heap, left_root),
            || split(right_items, right_heap, right_root),
        );
    } else {
        split(left_items, left_heap, left_root);
        split(right_items, right_heap, right_root);
    }
}

/// The axis along which `items`' bounding box is widest (the lowest on ties).
fn widest_axis(items: &[Entry]) -> usize {
    let bounds = |(lo, hi): (Vec3, Vec3), item: &Entry| {
        let p = Vec3::from(item.position);
        (lo.min(p), hi.max(p))
    };
    let empty = (Vec3::INFINITY, Vec3::NEG_INFINITY);
    let (lo, hi) = if items.len() >= PARALLEL_MIN {
        items
            .par_iter()
            .fold(|| empty, bounds)
            .reduce(|| empty, |a, b| (a.0.min(b.0), a.1.max(b.1)))
    } else {
        items.iter().fold(empty, bounds)
    };
    let extent = hi - lo;
    if extent.x >= extent.y && extent.x >= extent.z {
        0
    } else if extent.y >= extent.z {
        1
    } else {
        2
    }
}

#[cfg(test)]
mod tests;
