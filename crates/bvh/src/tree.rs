//! The binary BVH that [`crate::build_sah()`] produces, and its statistics.
//!
//! Nodes are stored in depth-first, left-first pre-order: an internal node's left (first) child
//! is the next node in the array and its right (second) child is wherever
//! [`Node::first_or_right`] says. A leaf refers to a run of [`Bvh::triangle_order`]. The same
//! order becomes the GPU layout ([`crate::pack::BvhNode`]) and the TBVH's threading, whose hit
//! link is then always "the next node in the array", as in the talk.

use scene::Bounds;

/// Levels a tree may have (a lone leaf is one level). The builder guarantees it, so a
/// traversal stack of this many entries never overflows.
pub const MAX_DEPTH: usize = 64;

/// SAH cost of visiting a node (the talk's `C_trav`).
pub const TRAVERSAL_COST: f32 = 1.0;
/// SAH cost of one ray-triangle test (`C_isect`).
pub const INTERSECTION_COST: f32 = 1.0;

/// One node of the tree.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Node {
    /// Box around every triangle below this node.
    pub bounds: Bounds,
    /// Leaf: position in [`Bvh::triangle_order`] of its first triangle. Internal: index of its
    /// right (second) child; the left (first) child is the next node, `index + 1`.
    pub first_or_right: u32,
    /// Leaf: its number of triangles (at least 1). Internal: 0.
    pub triangle_count: u32,
}

impl Node {
    /// Whether the node holds triangles (else it has two children).
    pub fn is_leaf(&self) -> bool {
        self.triangle_count > 0
    }
}

/// A bounding volume hierarchy over a triangle slice.
#[derive(Clone, Debug, Default)]
pub struct Bvh {
    /// Nodes in depth-first, left-first order; node 0 is the root. Empty for no triangles.
    pub nodes: Vec<Node>,
    /// Input triangle indices in leaf order: a leaf with `first_or_right = f` and
    /// `triangle_count = c` holds triangles `triangle_order[f..f + c]`. A permutation of the
    /// input unless triangles were split (`BuildOptions::split_percent`): then an id may
    /// appear in several leaves, and entries no leaf holds may follow a leaf's own.
    pub triangle_order: Vec<u32>,
}

impl Bvh {
    /// Number of nodes, internal and leaves.
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// Number of leaves.
    pub fn leaf_count(&self) -> usize {
        self.nodes.iter().filter(|n| n.is_leaf()).count()
    }

    /// `(left, right)` children of an internal node, `None` for a leaf.
    pub fn children(&self, index: u32) -> Option<(u32, u32)> {
        let node = &self.nodes[index as usize];
        (!node.is_leaf()).then_some((index + 1, node.first_or_right))
    }

    /// Nodes on the longest root-to-leaf path (a lone leaf: 1; no nodes: 0).
    pub fn depth(&self) -> usize {
        // Pre-order: a node's level is known before its children are reached.
        let mut level = vec![0usize; self.nodes.len()];
        let mut deepest = 0;
        for index in 0..self.nodes.len() {
            let here = if index == 0 { 1 } else { level[index] };
            deepest = deepest.max(here);
            if let Some((left, right)) = self.children(index as u32) {
                level[left as usize] = here + 1;
                level[right as usize] = here + 1;
            }
        }
        deepest
    }

    /// The SAH cost of the tree relative to its root: Σ over internal nodes of
    /// `SA(node)/SA(root) · C_trav` plus Σ over leaves of `SA(leaf)/SA(root) · C_isect · count`.
    /// Zero for an empty tree or a root box without area.
    pub fn sah_cost(&self) -> f64 {
        let Some(root) = self.nodes.first() else {
            return 0.0;
        };
        let root_area = f64::from(root.bounds.surface_area());
        if root_area == 0.0 {
            return 0.0;
        }
        let weighted: f64 = self
            .nodes
            .iter()
            .map(|n| {
                let area = f64::from(n.bounds.surface_area());
                if n.is_leaf() {
                    area * f64::from(INTERSECTION_COST) * f64::from(n.triangle_count)
                } else {
                    area * f64::from(TRAVERSAL_COST)
                }
            })
            .sum();
        weighted / root_area
    }

    /// `histogram[s]` = number of leaves holding `s` triangles (index 0 is always 0).
    pub fn leaf_size_histogram(&self) -> Vec<usize> {
        let mut histogram = Vec::new();
        for node in self.nodes.iter().filter(|n| n.is_leaf()) {
            let size = node.triangle_count as usize;
            if histogram.len() <= size {
                histogram.resize(size + 1, 0);
            }
            histogram[size] += 1;
        }
        histogram
    }
}
