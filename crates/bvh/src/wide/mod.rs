//! The MTBVH made four-wide (`mtbvh4`): each node holds four children's boxes, tested at once
//! (SSE here; the WGSL twin, `traverse_wide.wgsl`, tests them as vec4 rows), and per ray
//! direction the order its children are visited in (the talk's multiple threading, one order
//! per major axis and sign). The traversal keeps no stack: a **trail** of four bits per level
//! (which of that level's entered children, in the direction's order, are still to visit) and
//! the nodes' parent links bring it back up, as Laine's restart trail does for binary trees.
//! Leaves of up to four triangles are tested at once too ([`Tri4`]).
//!
//! Built from a [`PackedBvh`] by collapsing it at least SAH cost ([`collapse`]: which binary
//! nodes become wide nodes, slots and leaves), it tests the same triangles with
//! [`intersect_triangle`]'s arithmetic operation for operation, so it returns the same hits
//! as [`crate::traverse::trace_mtbvh`] (but for a fragile hit, see
//! [`crate::testing::is_fragile_hit`], which a box the binary tree has and this one skips may
//! cull). Measured in docs/BENCHMARKS.md §2: on the CPU 1.2–2.4× the binary MTBVH (a wide step
//! costs about three binary steps and takes the place of three to four); through lavapipe
//! slower, so the GPU kernels render with the binary MTBVH and the CPU backend with this.
//!
//! [`intersect_triangle`]: crate::intersect::intersect_triangle

pub mod collapse;
mod simd;

use bytemuck::{Pod, Zeroable};

use collapse::Plan;

use crate::intersect::{Hit, Ray, SlabRay, intersect_box};
use crate::pack::{BvhNode, PackedBvh, direction_index};
use crate::traverse::{Query, Uncounted, WorkTally, every_hit};

/// Children per node.
pub const WIDTH: usize = 4;
/// Triangles per [`Tri4`] leaf record.
pub const LEAF_WIDTH: usize = 4;
/// No node (the root's parent).
const NONE: u32 = u32::MAX;
/// Levels the trail holds: [`crate::tree::MAX_DEPTH`] bounds the binary tree's depth, and a
/// wide level spans at least one binary level.
const TRAIL_LEVELS: usize = crate::tree::MAX_DEPTH;

/// One node: four children's boxes in SoA rows, what each child is, the visiting orders and
/// the parent link. 128 bytes, two cache lines.
#[repr(C, align(64))]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct WideNode {
    /// `planes[axis]`: the four children's minima along `axis`; `planes[3 + axis]`: their
    /// maxima. Unused slots hold zeros (masked by `valid`).
    pub planes: [[f32; WIDTH]; 6],
    /// Inner child: its node index. Leaf: its first [`Tri4`].
    pub child: [u32; WIDTH],
    /// Leaf: its triangle count; inner child: 0.
    pub count: [u8; WIDTH],
    /// Per direction ([`direction_index`]), the order the children are visited in: the slot
    /// visited `k`-th in bits `2k..2k + 2`.
    pub order: [u8; 6],
    /// Bit `s` set when slot `s` holds a child.
    pub valid: u8,
    pub pad: u8,
    /// The parent node (`u32::MAX` for the root).
    pub parent: u32,
}

const _: () = assert!(size_of::<WideNode>() == 128);

impl WideNode {
    fn len(&self) -> usize {
        self.valid.count_ones() as usize
    }
}

/// Up to four triangles of a leaf in SoA rows, `[p0, p1 − p0, p2 − p0]` per lane (160 bytes).
#[repr(C, align(16))]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct Tri4 {
    /// `rows[3 * k + axis][lane]`: point `k` (p0, e0, e1) of each lane's triangle.
    pub rows: [[f32; LEAF_WIDTH]; 9],
    /// Index in [`PackedBvh::triangles`] of lane 0's triangle (lane `i` is `first + i`).
    pub first: u32,
    /// Lanes in use.
    pub count: u32,
    pub pad: [u32; 2],
}

/// `POSITIONS[order][slot mask]`: the same set of slots as positions in `order` (a
/// [`WideNode::order`] byte).
const POSITIONS: [[u8; 16]; 256] = {
    let mut table = [[0u8; 16]; 256];
    let mut order = 0;
    while order < 256 {
        let mut mask = 0;
        while mask < 16 {
            let mut position = 0;
            while position < WIDTH {
                let slot = (order >> (2 * position)) & 3;
                if mask & (1 << slot) != 0 {
                    table[order][mask] |= 1 << position;
                }
                position += 1;
            }
            mask += 1;
        }
        order += 1;
    }
    table
};

/// The slot visited at `position` in `order`.
#[inline(always)]
fn slot_at(order: u8, position: u32) -> usize {
    (order >> (2 * position)) as usize & 3
}

/// The four-wide MTBVH of a [`PackedBvh`], whose triangles it copies into [`Tri4`] leaves.
#[derive(Clone, Debug, Default)]
pub struct WideMtbvh {
    /// Depth-first pre-order; 0 is the root.
    pub nodes: Vec<WideNode>,
    pub leaves: Vec<Tri4>,
    /// The tree's SAH cost in [`collapse`]'s units (a wide node test 1, a [`Tri4`] test
    /// [`collapse::LEAF_COST`]), per ray through the root's box.
    pub sah_cost: f64,
}

/// Why a [`PackedBvh`] has no wide form.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WideError {
    /// A leaf holds more triangles than a slot's count can say (255).
    LeafTooLarge(u32),
}

impl std::fmt::Display for WideError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            WideError::LeafTooLarge(n) => {
                write!(
                    f,
                    "a BVH leaf holds {n} triangles; the wide BVH takes at most 255"
                )
            }
        }
    }
}

impl std::error::Error for WideError {}

impl WideMtbvh {
    /// Collapses `bvh` at least SAH cost ([`collapse`]). A binary subtree of at most
    /// [`LEAF_WIDTH`] triangles stored contiguously may become one leaf; larger binary leaves
    /// span several [`Tri4`]s.
    pub fn new(bvh: &PackedBvh) -> Result<WideMtbvh, WideError> {
        let mut wide = WideMtbvh::default();
        if let Some(n) = bvh
            .nodes
            .iter()
            .map(|n| n.triangle_count)
            .find(|&c| c > 255)
        {
            return Err(WideError::LeafTooLarge(n));
        }
        if !bvh.nodes.is_empty() {
            let ranges = triangle_ranges(bvh);
            let plan = Plan::new(bvh, &ranges);
            wide.sah_cost = plan.root_cost(bvh);
            wide.collapse(bvh, &ranges, &plan, 0);
        }
        Ok(wide)
    }

    /// Bytes of nodes and leaves.
    pub fn bytes(&self) -> usize {
        size_of_val(self.nodes.as_slice()) + size_of_val(self.leaves.as_slice())
    }

    /// The tree as the GPU kernel reads it (`traverse_wide.wgsl`), in 16-byte words: a header
    /// `[first leaf word, node count, 0, 0]`, the nodes (eight words each), the leaves (ten).
    /// One buffer, so the kernel binds one storage buffer more than the others, not two.
    pub fn gpu_words(&self) -> Vec<[u32; 4]> {
        let leaf_base = 1 + self.nodes.len() * size_of::<WideNode>() / 16;
        let mut words = vec![[leaf_base as u32, self.nodes.len() as u32, 0, 0]];
        words.extend_from_slice(bytemuck::cast_slice(&self.nodes));
        words.extend_from_slice(bytemuck::cast_slice(&self.leaves));
        words
    }

    /// Appends the wide node made for binary node `b` (its slots as `plan` spends them, or
    /// `b` itself as the only slot if it makes one leaf) and its subtree; returns its index.
    fn collapse(
        &mut self,
        bvh: &PackedBvh,
        ranges: &[(u32, u32, u32)],
        plan: &Plan,
        b: u32,
    ) -> u32 {
        let index = self.nodes.len() as u32;
        self.nodes.push(WideNode::default());
        let children = plan.node_slots(bvh, b);
        let mut node = WideNode {
            parent: NONE,
            valid: (1u8 << children.len()) - 1,
            ..WideNode::default()
        };
        for (slot, &c) in children.iter().enumerate() {
            let bounds = &bvh.nodes[c as usize];
            for axis in 0..3 {
                node.planes[axis][slot] = bounds.min[axis];
                node.planes[3 + axis][slot] = bounds.max[axis];
            }
            if plan.is_leaf(c) {
                let (first, count) = leaf_range(bvh, ranges, c).expect("planned as a leaf");
                node.child[slot] = self.push_leaf(bvh, first, count);
                // At most 255: checked in new.
                node.count[slot] = count as u8;
            } else {
                let child = self.collapse(bvh, ranges, plan, c);
                self.nodes[child as usize].parent = index;
                node.child[slot] = child;
            }
        }
        node.order = std::array::from_fn(|d| visiting_order(&node, children.len(), d));
        self.nodes[index as usize] = node;
        index
    }

    /// Appends triangles `first..first + count` as [`Tri4`]s; returns the first's index.
    fn push_leaf(&mut self, bvh: &PackedBvh, first: u32, count: u32) -> u32 {
        let index = self.leaves.len() as u32;
        for start in (first..first + count).step_by(LEAF_WIDTH) {
            let lanes = (first + count - start).min(LEAF_WIDTH as u32);
            let mut tri = Tri4 {
                first: start,
                count: lanes,
                ..Tri4::default()
            };
            for lane in 0..lanes as usize {
                let [p0, p1, p2] = bvh.triangles[start as usize + lane].positions();
                for (k, p) in [p0, p1 - p0, p2 - p0].iter().enumerate() {
                    for axis in 0..3 {
                        tri.rows[3 * k + axis][lane] = p[axis];
                    }
                }
            }
            self.leaves.push(tri);
        }
        index
    }
}

/// Per binary node, the range of triangles its leaves hold, `(first, end, total)`: the
/// subtree's triangles are contiguous when `end − first == total`.
pub fn triangle_ranges(bvh: &PackedBvh) -> Vec<(u32, u32, u32)> {
    let mut ranges = vec![(0, 0, 0); bvh.nodes.len()];
    // Children follow their parents in pre-order: fill from the back.
    for index in (0..bvh.nodes.len()).rev() {
        let node = &bvh.nodes[index];
        ranges[index] = if node.triangle_count > 0 {
            let first = node.first_or_right;
            (first, first + node.triangle_count, node.triangle_count)
        } else {
            let (a, b) = (ranges[index + 1], ranges[node.first_or_right as usize]);
            (a.0.min(b.0), a.1.max(b.1), a.2 + b.2)
        };
    }
    ranges
}

/// Binary node `b` as one wide leaf `(first triangle, count)`: a binary leaf, or a subtree of
/// at most [`LEAF_WIDTH`] contiguous triangles.
fn leaf_range(bvh: &PackedBvh, ranges: &[(u32, u32, u32)], b: u32) -> Option<(u32, u32)> {
    let node = &bvh.nodes[b as usize];
    if node.triangle_count > 0 {
        return Some((node.first_or_right, node.triangle_count));
    }
    let (first, end, total) = ranges[b as usize];
    (total <= LEAF_WIDTH as u32 && end - first == total).then_some((first, total))
}

/// Half the surface area of a binary node's box.
fn half_area(node: &BvhNode) -> f32 {
    let e = [0, 1, 2].map(|a| (node.max[a] - node.min[a]).max(0.0));
    e[0] * e[1] + e[1] * e[2] + e[2] * e[0]
}

/// The order for direction `d` ([`WideNode::order`]): children by box centre along its axis,
/// in its sense; unused slots last, ties in slot order (the build's left first).
fn visiting_order(node: &WideNode, children: usize, d: usize) -> u8 {
    let (axis, negative) = (d / 2, d % 2 == 1);
    let key = |s: u8| {
        let s = s as usize;
        let centre = node.planes[axis][s] + node.planes[3 + axis][s];
        if s >= children {
            f32::INFINITY
        } else if negative {
            -centre
        } else {
            centre
        }
    };
    let mut slots = [0u8, 1, 2, 3];
    slots.sort_by(|&x, &y| key(x).total_cmp(&key(y)));
    slots
        .iter()
        .enumerate()
        .fold(0, |order, (position, &slot)| order | slot << (2 * position))
}

/// A ray prepared for four-box tests.
struct WideRay {
    ray: Ray,
    slab: SlabRay,
    fast: simd::Slab4,
}

impl WideRay {
    fn new(ray: &Ray) -> WideRay {
        let slab = SlabRay::new(ray);
        WideRay {
            ray: *ray,
            slab,
            fast: simd::Slab4::new(&slab),
        }
    }

    /// Bit `s` set when the ray enters slot `s`'s box before `t_far` (as [`intersect_box`]).
    #[inline(always)]
    fn entered(&self, node: &WideNode, t_far: f32, counters: &mut impl WorkTally) -> u32 {
        counters.add_boxes(node.len() as u64);
        if !self.slab.any_parallel {
            return self.fast.entered(node, t_far);
        }
        // Rare: an axis the ray runs parallel to; the binary test, box by box.
        (0..node.len()).fold(0, |mask, s| {
            let b = BvhNode {
                min: [0, 1, 2].map(|a| node.planes[a][s]),
                max: [0, 1, 2].map(|a| node.planes[3 + a][s]),
                ..BvhNode::default()
            };
            mask | u32::from(intersect_box(&b, &self.slab, t_far) < f32::INFINITY) << s
        })
    }

    /// Positions (in `order`) of the slots the ray enters before `t_far`.
    #[inline(always)]
    fn positions(&self, node: &WideNode, order: u8, t_far: f32, c: &mut impl WorkTally) -> u32 {
        POSITIONS[order as usize][self.entered(node, t_far, c) as usize] as u32
    }

    /// Tests the leaf at `leaf` (`count` triangles) for the closest hit; true if one was hit
    /// before `t_best`.
    #[inline(always)]
    fn test_leaf(
        &self,
        leaves: &[Tri4],
        leaf: u32,
        count: u32,
        best: &mut Option<Hit>,
        counters: &mut impl WorkTally,
    ) -> bool {
        let mut found = false;
        counters.add_triangles(count as u64);
        for tri in leaf_records(leaves, leaf, count) {
            let t_best = best.map_or(self.ray.t_max, |h| h.t);
            if let Some((lane, (u, v, t))) = simd::intersect4(tri, &self.ray, t_best) {
                let triangle = tri.first + lane;
                *best = Some(Hit { triangle, t, u, v });
                found = true;
            }
        }
        found
    }

    /// Tests the leaf at `leaf` for any hit that `occludes`; that hit, if there is one.
    #[inline(always)]
    fn test_leaf_any(
        &self,
        leaves: &[Tri4],
        leaf: u32,
        count: u32,
        counters: &mut impl WorkTally,
        occludes: &impl Fn(&Hit) -> bool,
    ) -> Option<Hit> {
        counters.add_triangles(count as u64);
        for tri in leaf_records(leaves, leaf, count) {
            let lanes = simd::intersect4_lanes(tri, &self.ray, self.ray.t_max);
            let mut mask = lanes.mask;
            while mask != 0 {
                let lane = mask.trailing_zeros() as usize;
                mask &= mask - 1;
                let hit = Hit {
                    triangle: tri.first + lane as u32,
                    t: lanes.t[lane],
                    u: lanes.u[lane],
                    v: lanes.v[lane],
                };
                if occludes(&hit) {
                    return Some(hit);
                }
            }
        }
        None
    }
}

/// The [`Tri4`] records of the leaf whose first is `leaf`, holding `count` triangles.
#[inline(always)]
fn leaf_records(leaves: &[Tri4], leaf: u32, count: u32) -> &[Tri4] {
    &leaves[leaf as usize..(leaf + count.div_ceil(LEAF_WIDTH as u32)) as usize]
}

/// The trail: four bits per level.
#[derive(Default)]
struct Trail([u64; TRAIL_LEVELS / 16]);

impl Trail {
    fn set(&mut self, level: usize, positions: u32) {
        self.0[level / 16] |= (positions as u64) << (4 * (level % 16));
    }

    /// Level `level`'s positions, cleared.
    fn take(&mut self, level: usize) -> u32 {
        let shift = 4 * (level % 16);
        let positions = (self.0[level / 16] >> shift) as u32 & 0xf;
        self.0[level / 16] &= !(0xf << shift);
        positions
    }
}

/// Stackless traversal of `wide` for `query`; `counters` count boxes and triangles tested.
pub fn trace_wide(
    wide: &WideMtbvh,
    ray: &Ray,
    query: Query,
    counters: &mut impl WorkTally,
) -> Option<Hit> {
    match query {
        Query::Closest => trace_wide_where::<false>(wide, ray, counters, &every_hit),
        Query::Any => trace_wide_where::<true>(wide, ray, counters, &every_hit),
    }
}

/// [`trace_wide`], for any hit (`ANY`) that `occludes` or for the closest. The query is a
/// constant so that the closest-hit loop compiles without the any-hit test (4 % faster on
/// Dabrovic Sponza's diffuse rays than with a run-time branch).
fn trace_wide_where<const ANY: bool>(
    wide: &WideMtbvh,
    ray: &Ray,
    counters: &mut impl WorkTally,
    occludes: &impl Fn(&Hit) -> bool,
) -> Option<Hit> {
    if wide.nodes.is_empty() {
        return None;
    }
    let d = direction_index(ray.direction);
    let r = WideRay::new(ray);
    let mut best: Option<Hit> = None;
    let t_best = |best: &Option<Hit>| best.map_or(ray.t_max, |h| h.t);
    let mut level = 0usize;
    let mut trail = Trail::default();
    // Levels at and above this one made their positions before the last hit.
    let mut fresh_from = 0usize;
    let mut current = &wide.nodes[0];
    let mut positions = r.positions(current, current.order[d], ray.t_max, counters);
    loop {
        let order = current.order[d];
        let mut next = NONE;
        while positions != 0 {
            let slot = slot_at(order, positions.trailing_zeros());
            positions &= positions - 1;
            let count = current.count[slot] as u32;
            if count == 0 {
                next = current.child[slot];
                break;
            }
            if ANY {
                let leaf = current.child[slot];
                let hit = r.test_leaf_any(&wide.leaves, leaf, count, counters, occludes);
                if hit.is_some() {
                    return hit;
                }
                continue;
            }
            if r.test_leaf(
                &wide.leaves,
                current.child[slot],
                count,
                &mut best,
                counters,
            ) {
                // Cull the siblings still to come against the nearer hit.
                positions &= r.positions(current, order, t_best(&best), counters);
                fresh_from = level;
            }
        }
        if next != NONE {
            trail.set(level, positions);
            level += 1;
            current = &wide.nodes[next as usize];
            positions = r.positions(current, current.order[d], t_best(&best), counters);
            continue;
        }
        // Up to the nearest level with children left to visit.
        loop {
            if level == 0 {
                return best;
            }
            level -= 1;
            current = &wide.nodes[current.parent as usize];
            positions = trail.take(level);
            if positions != 0 && level < fresh_from {
                // A hit since these were made: re-cull them.
                positions &= r.positions(current, current.order[d], t_best(&best), counters);
                fresh_from = level;
            }
            if positions != 0 {
                break;
            }
        }
    }
}

/// Closest hit through the wide MTBVH.
pub fn closest_hit_wide(wide: &WideMtbvh, ray: &Ray) -> Option<Hit> {
    trace_wide(wide, ray, Query::Closest, &mut Uncounted)
}

/// Whether anything is hit at `t` in `[0, t_max)`, through the wide MTBVH.
pub fn any_hit_wide(wide: &WideMtbvh, ray: &Ray) -> bool {
    trace_wide(wide, ray, Query::Any, &mut Uncounted).is_some()
}

/// The CPU's closest hit: through `wide` where the tree has one (see [`WideMtbvh::new`]), else
/// through the binary MTBVH of `bvh` it was made from.
pub fn closest_hit_cpu(bvh: &PackedBvh, wide: Option<&WideMtbvh>, ray: &Ray) -> Option<Hit> {
    match wide {
        Some(wide) => closest_hit_wide(wide, ray),
        None => crate::traverse::closest_hit_mtbvh(bvh, ray),
    }
}

/// [`closest_hit_cpu`]'s any-hit query.
pub fn any_hit_cpu(bvh: &PackedBvh, wide: Option<&WideMtbvh>, ray: &Ray) -> bool {
    match wide {
        Some(wide) => any_hit_wide(wide, ray),
        None => crate::traverse::any_hit_mtbvh(bvh, ray),
    }
}

/// [`any_hit_cpu`] counting only hits that `occludes` (shadow rays through alpha cut-outs).
pub fn any_hit_cpu_where(
    bvh: &PackedBvh,
    wide: Option<&WideMtbvh>,
    ray: &Ray,
    occludes: impl Fn(&Hit) -> bool,
) -> bool {
    match wide {
        Some(wide) => trace_wide_where::<true>(wide, ray, &mut Uncounted, &occludes).is_some(),
        None => crate::traverse::any_hit_mtbvh_where(bvh, ray, occludes),
    }
}
