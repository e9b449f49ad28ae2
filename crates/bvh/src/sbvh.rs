//! SAH build with spatial splits (Stich, Friedrich and Dietrich, "Spatial splits in bounding
//! volume hierarchies", 2009).
//!
//! Where a node's best object split leaves its two children overlapping by more than a small
//! share of the scene's area, planes that cut triangles are priced too: references are chopped
//! into equal-width bins across the node, each piece bounded by the part of the triangle inside
//! it, and a reference that straddles the chosen plane goes to both sides with the box of its
//! part on each, unless keeping it whole on one side is cheaper ("reference unsplitting"). The
//! references a tree may add are capped by a budget, after which nodes take object splits only.
//! The build starts from references that a small share of the budget has already cut on a grid
//! (module `presplit`), which spatial splits alone do not find for the biggest slanted
//! triangles. The output is the binned builder's: depth-first nodes and a triangle order in
//! which a triangle appears once per leaf that references it.

use glam::Vec3A;
use rayon::prelude::*;
use scene::Triangle;

use crate::aabb::Aabb;
use crate::binning::{BinMapper, Scratch, find_split};
use crate::build_sah::{BuildOptions, MAX_BINS, PARALLEL_BUILD_MIN, ceil_log2, triangle_box};
use crate::presplit::{cut, intersect, presplit};
use crate::tree::{Bvh, INTERSECTION_COST, MAX_DEPTH, Node, TRAVERSAL_COST};

/// Spatial splits are tried where the object split's children overlap by more than this share
/// of the root's surface area (the paper's α). The paper's 1e-5 built Crytek Sponza's tree
/// 1.6× slower than 1e-4 for the same SAH cost (66.70 against 66.72) and traversal speed.
const OVERLAP_SHARE: f32 = 1e-4;
/// One part in this of the budget pre-splits the largest slanted triangles (module `presplit`)
/// before the build; the spatial splits spend the rest. Crytek Sponza's MTBVH4 then tests
/// 94 boxes per primary ray and 91 per diffuse ray, against 122 and 102 with spatial splits
/// alone and 118 and 104 with pre-splitting alone (30 % budget; a share of 1/20 to 1/4 did
/// about as well, 1/2 and more worse; Dabrovic within ±5 % of spatial splits alone).
const PRESPLIT_SHARE: usize = 10;
/// Bins per axis for spatial splits.
const SPATIAL_BINS: usize = 32;

/// One reference: a triangle and the box of its part in this subtree.
#[derive(Clone, Copy, Debug)]
struct Reference {
    bounds: Aabb,
    id: u32,
}

struct Builder<'a> {
    triangles: &'a [Triangle],
    options: BuildOptions,
    /// Overlap above which spatial splits are tried.
    min_overlap: f32,
}

/// A subtree in the binned builder's layout, indices counted from its own start.
#[derive(Default)]
struct Subtree {
    nodes: Vec<Node>,
    order: Vec<u32>,
}

impl Subtree {
    /// Appends `other`, moving its indices past what is here.
    fn append(&mut self, other: Subtree) {
        let (node_offset, order_offset) = (self.nodes.len() as u32, self.order.len() as u32);
        self.nodes.extend(other.nodes.into_iter().map(|mut n| {
            n.first_or_right += if n.triangle_count > 0 {
                order_offset
            } else {
                node_offset
            };
            n
        }));
        self.order.extend(other.order);
    }
}

/// Builds the tree over `triangles`, adding at most `extra` references (a tenth of them by
/// pre-splitting, the rest by spatial splits).
pub fn build_sbvh(triangles: &[Triangle], options: &BuildOptions, extra: usize) -> Bvh {
    if triangles.is_empty() {
        return Bvh::default();
    }
    let boxes: Vec<Aabb> = triangles.par_iter().map(triangle_box).collect();
    let scene = boxes.iter().fold(Aabb::EMPTY, |s, b| s.union(*b));
    let (boxes, ids) = presplit(triangles, &boxes, &scene, extra / PRESPLIT_SHARE);
    let extra = extra.saturating_sub(boxes.len() - triangles.len());
    let references: Vec<Reference> = boxes
        .into_iter()
        .zip(ids)
        .map(|(bounds, id)| Reference { bounds, id })
        .collect();
    // The pieces cover their triangles' corners and stay inside their boxes: same bounds.
    let bounds = scene;
    let options = BuildOptions {
        max_leaf_size: options.max_leaf_size.max(1),
        bins: options.bins.clamp(2, MAX_BINS),
        ..*options
    };
    let builder = Builder {
        triangles,
        options,
        min_overlap: OVERLAP_SHARE * bounds.half_area(),
    };
    let mut tree = Subtree::default();
    let scratch = &mut Scratch::new(options.bins);
    builder.build(references, bounds, 1, extra, &mut tree, scratch);
    Bvh {
        nodes: tree.nodes,
        triangle_order: tree.order,
    }
}

fn union(references: &[Reference]) -> Aabb {
    references
        .iter()
        .fold(Aabb::EMPTY, |b, r| b.union(r.bounds))
}

/// A split the builder may take.
enum Choice {
    Leaf,
    /// References whose centre's bin on `axis` is below `bin` go left (binned object split).
    Object {
        axis: usize,
        bin: u32,
        mapper: BinMapper,
    },
    /// Plane `position` on `axis` cuts references.
    Spatial {
        axis: usize,
        position: f32,
    },
    /// Halves by centre order (depth limit, or centres all in one bin).
    Median,
}

impl Builder<'_> {
    /// Builds the subtree over `references` (bounded by `bounds`) at `level`, adding at most
    /// `budget` references, onto `out`.
    fn build(
        &self,
        references: Vec<Reference>,
        bounds: Aabb,
        level: usize,
        budget: usize,
        out: &mut Subtree,
        scratch: &mut Scratch,
    ) {
        let (index, count) = (out.nodes.len(), references.len());
        out.nodes.push(Node {
            bounds: bounds.to_bounds(),
            first_or_right: 0,
            triangle_count: 0,
        });
        let (left, right) = match self.choose(&references, &bounds, level, budget, scratch) {
            Choice::Leaf => {
                let first = out.order.len();
                for r in &references {
                    // Two pieces of one triangle in one leaf are listed once.
                    if !out.order[first..].contains(&r.id) {
                        out.order.push(r.id);
                    }
                }
                out.nodes[index].first_or_right = first as u32;
                out.nodes[index].triangle_count = (out.order.len() - first) as u32;
                return;
            }
            Choice::Object { axis, bin, mapper } => references
                .into_iter()
                .partition(|r| mapper.bins(r.bounds.center())[axis] < bin),
            Choice::Median => halve_by_centre(references),
            Choice::Spatial { axis, position } => {
                self.split_spatial(references, axis, position, budget)
            }
        };
        // What is left of the budget goes to the children by reference count, so the tree does
        // not depend on which child is built first.
        let added = (left.len() + right.len()).saturating_sub(count);
        let budget = budget.saturating_sub(added);
        let left_budget = budget * left.len() / (left.len() + right.len());
        let right_budget = budget - left_budget;
        let (left_bounds, right_bounds) = (union(&left), union(&right));
        if left.len() + right.len() >= PARALLEL_BUILD_MIN {
            let apart = |references, bounds, budget| {
                let mut tree = Subtree::default();
                let scratch = &mut Scratch::new(self.options.bins);
                self.build(references, bounds, level + 1, budget, &mut tree, scratch);
                tree
            };
            let (l, r) = rayon::join(
                || apart(left, left_bounds, left_budget),
                || apart(right, right_bounds, right_budget),
            );
            out.append(l);
            out.nodes[index].first_or_right = out.nodes.len() as u32;
            out.append(r);
        } else {
            self.build(left, left_bounds, level + 1, left_budget, out, scratch);
            out.nodes[index].first_or_right = out.nodes.len() as u32;
            self.build(right, right_bounds, level + 1, right_budget, out, scratch);
        }
    }

    fn choose(
        &self,
        references: &[Reference],
        bounds: &Aabb,
        level: usize,
        budget: usize,
        scratch: &mut Scratch,
    ) -> Choice {
        let count = references.len();
        let may_be_leaf = count <= self.options.max_leaf_size;
        if count == 1 {
            return Choice::Leaf;
        }
        // Halving must still reach single references within MAX_DEPTH; spatial splits, which
        // may not shrink a side by much, stop well before.
        let halving_depth = level + 1 + ceil_log2(count - 1);
        if halving_depth > MAX_DEPTH {
            return if may_be_leaf {
                Choice::Leaf
            } else {
                Choice::Median
            };
        }
        let area = bounds.half_area();
        let leaf_cost = INTERSECTION_COST * area * count as f32;
        let centres = centre_bounds(references);
        let mapper = BinMapper::new(&centres, self.options.bins.min(2 * count));
        let boxes: Vec<Aabb> = references.iter().map(|r| r.bounds).collect();
        let object = find_split(&boxes, &mapper, scratch);
        let mut best_cost = object.map_or(f32::INFINITY, |s| s.cost);
        let mut choice = match object {
            Some(s) => Choice::Object {
                axis: s.axis,
                bin: s.bin,
                mapper,
            },
            None => Choice::Median,
        };
        let overlap = object.map_or(f32::INFINITY, |s| {
            intersect(s.left, s.right).map_or(0.0, |o| o.half_area())
        });
        let try_spatial =
            overlap > self.min_overlap && budget > 0 && halving_depth + 8 <= MAX_DEPTH;
        if let Some((cost, axis, position)) = try_spatial
            .then(|| self.best_spatial(references, bounds))
            .flatten()
            && cost < best_cost
        {
            best_cost = cost;
            choice = Choice::Spatial { axis, position };
        }
        let split_cost = TRAVERSAL_COST * area + INTERSECTION_COST * best_cost;
        if may_be_leaf && (leaf_cost <= split_cost || matches!(choice, Choice::Median)) {
            Choice::Leaf
        } else {
            choice
        }
    }

    /// The cheapest spatial plane: `(SA·N left + SA·N right, axis, position)`.
    fn best_spatial(&self, references: &[Reference], bounds: &Aabb) -> Option<(f32, usize, f32)> {
        let mut best: Option<(f32, usize, f32)> = None;
        let count = references.len();
        for axis in 0..3 {
            let (lo, extent) = (bounds.min[axis], bounds.max[axis] - bounds.min[axis]);
            if extent.is_nan() || extent <= 0.0 {
                continue;
            }
            let bins = SPATIAL_BINS;
            let width = extent / bins as f32;
            let bin_of = |x: f32| (((x - lo) / width) as usize).min(bins - 1);
            let plane = |b: usize| lo + width * b as f32;
            let mut boxes = [Aabb::EMPTY; SPATIAL_BINS];
            let mut enter = [0u32; SPATIAL_BINS];
            let mut exit = [0u32; SPATIAL_BINS];
            for r in references {
                let (first, last) = (bin_of(r.bounds.min[axis]), bin_of(r.bounds.max[axis]));
                enter[first] += 1;
                exit[last] += 1;
                // Chop the reference bin by bin; its part in each grows that bin's box.
                let mut rest = Some(r.bounds);
                for (b, bin_box) in boxes.iter_mut().enumerate().take(last).skip(first) {
                    let Some(bounds) = rest else { break };
                    let (left, right) = self.split_box(r.id, &bounds, axis, plane(b + 1));
                    *bin_box = bin_box.union(left.unwrap_or(Aabb::EMPTY));
                    rest = right;
                }
                boxes[last] = boxes[last].union(rest.unwrap_or(Aabb::EMPTY));
            }
            // Sweep: right side's SA·N for planes 1..bins, then the left side.
            let mut right_cost = [0.0f32; SPATIAL_BINS];
            let mut right_count = [0u32; SPATIAL_BINS];
            let (mut acc, mut n) = (Aabb::EMPTY, 0u32);
            for b in (1..bins).rev() {
                acc = acc.union(boxes[b]);
                n += exit[b];
                right_count[b] = n;
                right_cost[b] = if n == 0 {
                    0.0
                } else {
                    acc.half_area() * n as f32
                };
            }
            let (mut acc, mut n) = (Aabb::EMPTY, 0u32);
            for b in 1..bins {
                acc = acc.union(boxes[b - 1]);
                n += enter[b - 1];
                let n_right = right_count[b];
                if n == 0 || n_right == 0 || n as usize >= count || n_right as usize >= count {
                    continue;
                }
                let cost = acc.half_area() * n as f32 + right_cost[b];
                if best.is_none_or(|(c, _, _)| cost < c) {
                    best = Some((cost, axis, plane(b)));
                }
            }
        }
        best
    }

    /// The boxes of triangle `id`'s part inside `bounds` on either side of the plane
    /// `axis = position` (`None` for a side it does not reach).
    fn split_box(
        &self,
        id: u32,
        bounds: &Aabb,
        axis: usize,
        position: f32,
    ) -> (Option<Aabb>, Option<Aabb>) {
        let corners = self.triangles[id as usize].positions().map(Vec3A::from);
        cut(&corners, bounds, axis, position)
    }

    /// Partitions `references` by the plane, duplicating at most `budget` straddlers, and none
    /// that costs less kept whole on one side.
    fn split_spatial(
        &self,
        references: Vec<Reference>,
        axis: usize,
        position: f32,
        mut budget: usize,
    ) -> (Vec<Reference>, Vec<Reference>) {
        let (mut left, mut right, mut straddling) = (Vec::new(), Vec::new(), Vec::new());
        for r in references {
            if r.bounds.max[axis] <= position {
                left.push(r);
            } else if r.bounds.min[axis] >= position {
                right.push(r);
            } else {
                straddling.push(r);
            }
        }
        let (mut left_box, mut right_box) = (union(&left), union(&right));
        let (mut n_left, mut n_right) = (
            left.len() + straddling.len(),
            right.len() + straddling.len(),
        );
        for r in straddling {
            let (l, rr) = match self.split_box(r.id, &r.bounds, axis, position) {
                (Some(l), Some(rr)) => (l, rr),
                // Nothing of it on one side after all: it goes whole to the other.
                (None, _) => {
                    right_box = right_box.union(r.bounds);
                    right.push(r);
                    n_left -= 1;
                    continue;
                }
                (_, None) => {
                    left_box = left_box.union(r.bounds);
                    left.push(r);
                    n_right -= 1;
                    continue;
                }
            };
            let split = left_box.union(l).half_area() * n_left as f32
                + right_box.union(rr).half_area() * n_right as f32;
            let whole_left = left_box.union(r.bounds).half_area() * n_left as f32
                + right_box.half_area() * (n_right - 1) as f32;
            let whole_right = left_box.half_area() * (n_left - 1) as f32
                + right_box.union(r.bounds).half_area() * n_right as f32;
            if budget > 0 && split < whole_left && split < whole_right {
                budget -= 1;
                left_box = left_box.union(l);
                right_box = right_box.union(rr);
                left.push(Reference {
                    bounds: l,
                    id: r.id,
                });
                right.push(Reference {
                    bounds: rr,
                    id: r.id,
                });
            } else if whole_left <= whole_right {
                left_box = left_box.union(r.bounds);
                left.push(r);
                n_right -= 1;
            } else {
                right_box = right_box.union(r.bounds);
                right.push(r);
                n_left -= 1;
            }
        }
        if left.is_empty() || right.is_empty() {
            // Everything ended on one side: fall back to halving by centre.
            left.append(&mut right);
            return halve_by_centre(left);
        }
        (left, right)
    }
}

/// The references in two halves by centre along the axis their centres spread most on.
fn halve_by_centre(mut references: Vec<Reference>) -> (Vec<Reference>, Vec<Reference>) {
    let axis = largest_axis(&centre_bounds(&references));
    references.sort_by(|a, b| a.bounds.center()[axis].total_cmp(&b.bounds.center()[axis]));
    let right = references.split_off(references.len() / 2);
    (references, right)
}

fn centre_bounds(references: &[Reference]) -> Aabb {
    references
        .iter()
        .fold(Aabb::EMPTY, |b, r| b.grow(r.bounds.center()))
}

fn largest_axis(b: &Aabb) -> usize {
    let e = b.extent();
    if e.x >= e.y && e.x >= e.z {
        0
    } else if e.y >= e.z {
        1
    } else {
        2
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::build_sah::build_sah;
    use crate::testing::{Rng, random_soup};

    fn contains(b: &scene::Bounds, p: Vec3A) -> bool {
        Vec3A::from(b.min).cmple(p).all() && p.cmple(Vec3A::from(b.max)).all()
    }

    fn options() -> BuildOptions {
        BuildOptions {
            split_percent: 100,
            ..BuildOptions::default()
        }
    }

    /// Every point of every triangle lies in the box of a leaf that lists it (so traversal
    /// finds every hit), and the references added stay within the budget.
    #[test]
    fn leaves_cover_their_triangles_within_the_budget() {
        // The soup holds long slivers: the triangles spatial splits are for.
        let triangles = random_soup(3, 300);
        let extra = 150;
        let bvh = build_sbvh(&triangles, &options(), extra);
        let references = bvh.triangle_order.len();
        assert!(references > triangles.len(), "no spatial split");
        assert!(
            references <= triangles.len() + extra,
            "{references} references"
        );
        let mut leaves_of = vec![Vec::new(); triangles.len()];
        for node in bvh.nodes.iter().filter(|n| n.is_leaf()) {
            let first = node.first_or_right as usize;
            for &id in &bvh.triangle_order[first..first + node.triangle_count as usize] {
                leaves_of[id as usize].push(node.bounds);
            }
        }
        let mut rng = Rng::new(9);
        for (id, triangle) in triangles.iter().enumerate() {
            let leaves = &leaves_of[id];
            let [a, b, c] = triangle.positions().map(Vec3A::from);
            let mut points = vec![a, b, c];
            for _ in 0..300 {
                let (mut u, mut v) = (rng.unit(), rng.unit());
                if u + v > 1.0 {
                    (u, v) = (1.0 - u, 1.0 - v);
                }
                points.push(a + u * (b - a) + v * (c - a));
            }
            for p in points {
                assert!(
                    leaves.iter().any(|l| contains(l, p)),
                    "triangle {id}: {p} in none of its {} leaves",
                    leaves.len()
                );
            }
        }
    }

    /// Subtrees built in parallel share the budget by reference count: the same tree every
    /// time.
    #[test]
    fn the_same_tree_every_time() {
        let triangles = random_soup(5, 20_000);
        let first = build_sbvh(&triangles, &options(), 5_000);
        for _ in 0..3 {
            let again = build_sbvh(&triangles, &options(), 5_000);
            assert_eq!(again.triangle_order, first.triangle_order);
            assert_eq!(again.nodes, first.nodes);
        }
    }

    #[test]
    fn no_budget_references_each_triangle_once() {
        let triangles = random_soup(4, 2_000);
        let bvh = build_sbvh(&triangles, &options(), 0);
        let mut order = bvh.triangle_order.clone();
        order.sort_unstable();
        assert_eq!(order, (0..2_000).collect::<Vec<u32>>());
    }

    /// Where long slanted triangles overlap, cutting them prices lower than any object split.
    #[test]
    fn spatial_splits_lower_the_sah_cost() {
        let triangles = random_soup(6, 5_000);
        let plain = build_sah(
            &triangles,
            &BuildOptions {
                split_percent: 0,
                ..BuildOptions::default()
            },
        );
        let split = build_sbvh(&triangles, &options(), 1_500);
        assert!(
            split.sah_cost() < 0.95 * plain.sah_cost(),
            "SAH {} against {}",
            split.sah_cost(),
            plain.sah_cost()
        );
    }
}
