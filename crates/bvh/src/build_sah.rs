//! Binned SAH build (Wald 2007), parallel with rayon.
//!
//! Each node bins its triangles' box centres (module `binning`), prices every bin plane with
//! the surface area heuristic and compares the best against keeping the node a leaf
//! (`C_trav = C_isect = 1`); above [`BuildOptions::max_leaf_size`] it splits whatever the cost.
//! The triangles' boxes and ids live in two arrays that every node partitions in place, so a
//! subtree owns one contiguous range of each, and the nodes go straight into their depth-first
//! slots: a subtree over `n` triangles has at most `2n − 1` nodes, so a node at slot `s` with
//! `l` triangles on its left puts its left child at `s + 1` and its right child at `s + 2l`.
//! Disjoint ranges let big subtrees build in parallel (`rayon::join`) with no locking; big nodes
//! also bin in parallel. When leaves hold several triangles some slots stay unused and one
//! final pass closes the gaps.
//!
//! Depth is capped at [`MAX_DEPTH`]: a node that could otherwise exceed it is split at its
//! median centre, which halves it.
//!
//! With [`BuildOptions::split_percent`] above 0 the tree is built with spatial splits instead
//! (module [`crate::sbvh`]).

use glam::Vec3A;
use rayon::prelude::*;
use scene::Triangle;

use crate::aabb::Aabb;
use crate::binning::{BinMapper, Scratch, Split, find_split};
use crate::tree::{Bvh, INTERSECTION_COST, MAX_DEPTH, Node, TRAVERSAL_COST};

/// Subtrees with at least this many triangles build their two children in parallel.
pub(crate) const PARALLEL_BUILD_MIN: usize = 1 << 12;
/// Most bins a build may ask for.
pub const MAX_BINS: usize = 256;
/// Most triangles a tree may hold: node indices and [`crate::mtbvh::LINK_END`] share a `u32`.
pub const MAX_TRIANGLES: usize = (u32::MAX / 2) as usize;

/// Build parameters.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BuildOptions {
    /// Largest leaf: bigger nodes are always split; smaller ones only where the SAH says so.
    /// At least 1.
    pub max_leaf_size: usize,
    /// Bins per axis, 2 to [`MAX_BINS`].
    pub bins: usize,
    /// Most extra references that spatial splits may add, in percent of the triangle count
    /// (module [`crate::sbvh`]); 0 builds over one box per triangle, binned.
    pub split_percent: u32,
    /// Whether [`crate::PackedBvh::build`] keeps the split tree only where probe rays test
    /// less in it than in the unsplit one ([`crate::probe`]); else splitting is forced.
    /// [`build_sah`] itself always splits as asked.
    pub probe_split: bool,
}

impl Default for BuildOptions {
    /// Two triangles per leaf at most, 32 bins, up to 30 % more references from pre-splitting
    /// and spatial splits where probe rays say they pay. On the Sponzas that made the CPU
    /// four-wide MTBVH 13–26 % faster than pre-splitting alone (BENCHMARKS §2, session 10);
    /// on the bunny or cornell-metal split trees only deepen the tree, which the probe avoids. Against one triangle per leaf (the talk's
    /// choice), the MTBVH traversal of ANCHORS.md's rays visits 4–6 % fewer boxes and reads
    /// 3–5 % fewer bytes, and the MTBVH takes 28 % less memory (bunny, Crytek Sponza); allowing
    /// 4 or 8 gains under 1 % more while the leaf loop a GPU thread may run grows. 32 bins price
    /// Crytek Sponza 1 % better than 16 and 3 % worse than 64, within the build-time budget.
    fn default() -> Self {
        BuildOptions {
            max_leaf_size: 2,
            bins: 32,
            split_percent: 30,
            probe_split: true,
        }
    }
}

impl BuildOptions {
    fn clamped(&self) -> BuildOptions {
        BuildOptions {
            max_leaf_size: self.max_leaf_size.max(1),
            bins: self.bins.clamp(2, MAX_BINS),
            split_percent: self.split_percent,
            probe_split: self.probe_split,
        }
    }
}

/// Builds the tree over `triangles`.
///
/// # Panics
/// With more than [`MAX_TRIANGLES`] triangles.
pub fn build_sah(triangles: &[Triangle], options: &BuildOptions) -> Bvh {
    let options = options.clamped();
    let count = triangles.len();
    assert!(
        count <= MAX_TRIANGLES,
        "{count} triangles: at most {MAX_TRIANGLES}"
    );
    if count == 0 {
        return Bvh::default();
    }
    if options.split_percent > 0 {
        let extra = (count as u64 * u64::from(options.split_percent) / 100) as usize;
        return crate::sbvh::build_sbvh(triangles, &options, extra.min(MAX_TRIANGLES - count));
    }
    let mut boxes: Vec<Aabb> = triangles.par_iter().map(triangle_box).collect();
    let mut ids: Vec<u32> = (0..count as u32).collect();
    let (bounds, centers) = boxes
        .par_iter()
        .fold(
            || (Aabb::EMPTY, Aabb::EMPTY),
            |(b, c), x| (b.union(*x), c.grow(x.center())),
        )
        .reduce(
            || (Aabb::EMPTY, Aabb::EMPTY),
            |(b0, c0), (b1, c1)| (b0.union(b1), c0.union(c1)),
        );
    let mut slots = Vec::new();
    (0..2 * count - 1)
        .into_par_iter()
        .map(|_| UNUSED)
        .collect_into_vec(&mut slots);
    let task = Task {
        boxes: &mut boxes,
        ids: &mut ids,
        first: 0,
        bounds,
        centers,
        level: 1,
    };
    let used = build_node(
        &options,
        task,
        &mut slots,
        0,
        &mut Scratch::new(options.bins),
    );
    if used < slots.len() {
        slots = close_gaps(slots);
    }
    Bvh {
        nodes: slots,
        triangle_order: ids,
    }
}

pub(crate) fn triangle_box(triangle: &Triangle) -> Aabb {
    let [p0, p1, p2] = triangle.positions().map(Vec3A::from);
    Aabb {
        min: p0.min(p1).min(p2),
        max: p0.max(p1).max(p2),
    }
}

/// Marks a node slot that no node took.
const UNUSED: Node = Node {
    bounds: scene::Bounds::EMPTY,
    first_or_right: 0,
    triangle_count: u32::MAX,
};

/// One subtree to build: its triangles' boxes and ids (partitioned in place) and their bounds.
struct Task<'a> {
    /// Boxes of the subtree's triangles.
    boxes: &'a mut [Aabb],
    /// Their input indices, kept in step with `boxes`.
    ids: &'a mut [u32],
    /// Position of `ids[0]` in the whole id array.
    first: u32,
    /// Union of `boxes`.
    bounds: Aabb,
    /// Bounds of the boxes' centres.
    centers: Aabb,
    /// Level of this node (the root is 1).
    level: usize,
}

/// What to do with a node.
enum Plan {
    /// Keep it a leaf.
    Leaf,
    /// Split at the bin plane.
    Binned(Split, BinMapper),
    /// Split at the median centre.
    Median,
    /// Split two triangles into one each.
    Pair,
}

/// Builds the subtree of `task` into `slots` (its `2n − 1` slots), whose first slot is node
/// `index` of the whole tree; returns how many nodes it made.
fn build_node(
    options: &BuildOptions,
    task: Task,
    slots: &mut [Node],
    index: u32,
    scratch: &mut Scratch,
) -> usize {
    let count = task.boxes.len();
    let bounds = task.bounds.to_bounds();
    let (left, right) = match plan(options, &task, scratch) {
        Plan::Leaf => {
            slots[0] = Node {
                bounds,
                first_or_right: task.first,
                triangle_count: count as u32,
            };
            return 1;
        }
        Plan::Binned(split, mapper) => split_binned(task, &split, &mapper),
        Plan::Median => split_median(task),
        Plan::Pair => split_at(task, 1),
    };
    let left_count = left.boxes.len();
    let right_index = index + 2 * left_count as u32;
    let (own, rest) = slots.split_at_mut(1);
    let (left_slots, right_slots) = rest.split_at_mut(2 * left_count - 1);
    own[0] = Node {
        bounds,
        first_or_right: right_index,
        triangle_count: 0,
    };
    let (left_used, right_used) = if count >= PARALLEL_BUILD_MIN {
        rayon::join(
            || build_node(options, left, left_slots, index + 1, scratch),
            || {
                let scratch = &mut Scratch::new(options.bins);
                build_node(options, right, right_slots, right_index, scratch)
            },
        )
    } else {
        let left_used = build_node(options, left, left_slots, index + 1, scratch);
        let right_used = build_node(options, right, right_slots, right_index, scratch);
        (left_used, right_used)
    };
    1 + left_used + right_used
}

fn plan(options: &BuildOptions, task: &Task, scratch: &mut Scratch) -> Plan {
    let count = task.boxes.len();
    let may_be_leaf = count <= options.max_leaf_size;
    if count == 1 {
        return Plan::Leaf;
    }
    // Children of up to `count − 1` triangles must still fit under MAX_DEPTH by halving.
    if task.level + 1 + ceil_log2(count - 1) > MAX_DEPTH {
        return if may_be_leaf {
            Plan::Leaf
        } else {
            Plan::Median
        };
    }
    // Small nodes need fewer bins: two per triangle prices about as well and costs less.
    if count == 2 {
        // Every split of two triangles is the same: no need to bin.
        let area = task.bounds.half_area();
        let leaf_cost = INTERSECTION_COST * area * 2.0;
        let split_cost = TRAVERSAL_COST * area
            + INTERSECTION_COST * (task.boxes[0].half_area() + task.boxes[1].half_area());
        return if may_be_leaf && leaf_cost <= split_cost {
            Plan::Leaf
        } else {
            Plan::Pair
        };
    }
    let mapper = BinMapper::new(&task.centers, options.bins.min(2 * count));
    match find_split(task.boxes, &mapper, scratch) {
        None if may_be_leaf => Plan::Leaf,
        None => Plan::Median,
        Some(split) => {
            let area = task.bounds.half_area();
            let leaf_cost = INTERSECTION_COST * area * count as f32;
            let split_cost = TRAVERSAL_COST * area + INTERSECTION_COST * split.cost;
            if may_be_leaf && leaf_cost <= split_cost {
                Plan::Leaf
            } else {
                Plan::Binned(split, mapper)
            }
        }
    }
}

pub(crate) fn ceil_log2(x: usize) -> usize {
    if x <= 1 {
        0
    } else {
        (x - 1).ilog2() as usize + 1
    }
}

/// Partitions the task by the split's bin plane; boxes come from the sweep, centre bounds from
/// the partition itself.
fn split_binned<'a>(task: Task<'a>, split: &Split, mapper: &BinMapper) -> (Task<'a>, Task<'a>) {
    let boxes = task.boxes;
    let ids = task.ids;
    let (mut i, mut j) = (0, boxes.len());
    let (mut left_centers, mut right_centers) = (Aabb::EMPTY, Aabb::EMPTY);
    while i < j {
        let center = boxes[i].center();
        if mapper.bins(center)[split.axis] < split.bin {
            left_centers = left_centers.grow(center);
            i += 1;
        } else {
            right_centers = right_centers.grow(center);
            j -= 1;
            boxes.swap(i, j);
            ids.swap(i, j);
        }
    }
    debug_assert_eq!(i, split.left_count);
    let sides = [(split.left, left_centers), (split.right, right_centers)];
    children(boxes, ids, task.first, task.level, i, sides)
}

/// Splits the task in two halves at the median centre along the widest centre axis.
fn split_median(task: Task) -> (Task, Task) {
    let boxes = task.boxes;
    let ids = task.ids;
    let axis = task.centers.extent().max_position();
    let mid = boxes.len() / 2;
    let mut pairs: Vec<(Aabb, u32)> = boxes.iter().copied().zip(ids.iter().copied()).collect();
    pairs.select_nth_unstable_by(mid, |a, b| {
        a.0.center()[axis].total_cmp(&b.0.center()[axis])
    });
    for (k, (b, id)) in pairs.into_iter().enumerate() {
        boxes[k] = b;
        ids[k] = id;
    }
    split_at(Task { boxes, ids, ..task }, mid)
}

/// Splits the task's ranges at `mid` as they are.
fn split_at(task: Task, mid: usize) -> (Task, Task) {
    let measure = |part: &[Aabb]| {
        part.iter().fold((Aabb::EMPTY, Aabb::EMPTY), |(b, c), x| {
            (b.union(*x), c.grow(x.center()))
        })
    };
    let sides = [measure(&task.boxes[..mid]), measure(&task.boxes[mid..])];
    children(task.boxes, task.ids, task.first, task.level, mid, sides)
}

/// The two child tasks of a node whose ranges were partitioned at `mid`; `sides` holds each
/// side's `(bounds, centre bounds)`.
fn children<'a>(
    boxes: &'a mut [Aabb],
    ids: &'a mut [u32],
    first: u32,
    level: usize,
    mid: usize,
    sides: [(Aabb, Aabb); 2],
) -> (Task<'a>, Task<'a>) {
    let (left_boxes, right_boxes) = boxes.split_at_mut(mid);
    let (left_ids, right_ids) = ids.split_at_mut(mid);
    let [(left_bounds, left_centers), (right_bounds, right_centers)] = sides;
    let left = Task {
        boxes: left_boxes,
        ids: left_ids,
        first,
        bounds: left_bounds,
        centers: left_centers,
        level: level + 1,
    };
    let right = Task {
        boxes: right_boxes,
        ids: right_ids,
        first: first + mid as u32,
        bounds: right_bounds,
        centers: right_centers,
        level: level + 1,
    };
    (left, right)
}

/// Removes unused slots, keeping the order, and renumbers the right-child indices.
fn close_gaps(slots: Vec<Node>) -> Vec<Node> {
    let unused = |node: &Node| node.triangle_count == UNUSED.triangle_count;
    if !slots.iter().any(unused) {
        return slots;
    }
    let mut new_index = Vec::with_capacity(slots.len());
    let mut next = 0u32;
    for slot in &slots {
        new_index.push(next);
        next += u32::from(!unused(slot));
    }
    slots
        .into_iter()
        .filter(|s| !unused(s))
        .map(|mut node| {
            if !node.is_leaf() {
                node.first_or_right = new_index[node.first_or_right as usize];
            }
            node
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A subtree of 100 triangles (which halving fits in 8 levels) started `levels_left` levels
    /// from the limit stays within it, whatever the SAH would have chosen.
    #[test]
    fn depth_guard_halves_nodes_near_the_limit() {
        let triangles = crate::testing::random_soup(5, 100);
        let options = BuildOptions {
            max_leaf_size: 1,
            ..BuildOptions::default()
        };
        for levels_left in [8, 9, 12] {
            let mut boxes: Vec<Aabb> = triangles.iter().map(triangle_box).collect();
            let mut ids: Vec<u32> = (0..100).collect();
            let bounds = boxes.iter().fold(Aabb::EMPTY, |b, x| b.union(*x));
            let centers = boxes.iter().fold(Aabb::EMPTY, |c, x| c.grow(x.center()));
            let level = MAX_DEPTH + 1 - levels_left;
            let task = Task {
                boxes: &mut boxes,
                ids: &mut ids,
                first: 0,
                bounds,
                centers,
                level,
            };
            let mut slots = vec![UNUSED; 2 * 100 - 1];
            build_node(
                &options,
                task,
                &mut slots,
                0,
                &mut Scratch::new(options.bins),
            );
            let subtree = Bvh {
                nodes: close_gaps(slots),
                triangle_order: ids,
            };
            assert!(
                subtree.depth() <= levels_left,
                "{} > {levels_left}",
                subtree.depth()
            );
            assert_eq!(subtree.leaf_count(), 100);
        }
    }

    #[test]
    fn a_node_that_fits_only_by_halving_is_split_at_the_median() {
        // Four triangles at level 62 fit under 64 levels only as 2 + 2.
        let triangles = crate::testing::random_soup(6, 4);
        let mut boxes: Vec<Aabb> = triangles.iter().map(triangle_box).collect();
        let mut ids = vec![0, 1, 2, 3];
        let bounds = boxes.iter().fold(Aabb::EMPTY, |b, x| b.union(*x));
        let centers = boxes.iter().fold(Aabb::EMPTY, |c, x| c.grow(x.center()));
        let task = Task {
            boxes: &mut boxes,
            ids: &mut ids,
            first: 0,
            bounds,
            centers,
            level: MAX_DEPTH - 2,
        };
        let plan = plan(&BuildOptions::default(), &task, &mut Scratch::new(32));
        assert!(matches!(plan, Plan::Median));
    }
}
