//! CPU traversals of a [`PackedBvh`]: the twins of the WGSL kernels.
//!
//! Three ways through the same nodes and triangles, each for the closest hit or any hit:
//! - **stack**: test both children's boxes, go to the nearer, push the farther on a fixed-size
//!   array ([`MAX_DEPTH`] entries, which the builder guarantees is enough);
//! - **TBVH**: stackless, following the left-first threading's hit/miss links;
//! - **MTBVH**: stackless, following the links of the ray's major direction
//!   ([`direction_index`]), so boxes come roughly front to back.
//!
//! All three test the same triangles with the same arithmetic as the brute-force loop, and a
//! box is culled only when the ray misses it or enters it beyond the best hit so far, so they
//! return the same closest distance as [`closest_hit_brute_force`] (between triangles hit at
//! exactly the same distance, any of them). The one exception: a hit that rounding in the
//! triangle test places outside its own triangle's box, which the slab test may rightly cull
//! ([`crate::testing::is_fragile_hit`]; about 1 ray in a million on Crytek Sponza). Every loop
//! is written as its shader will be: no recursion, no allocation.

use crate::intersect::{Hit, Ray, SlabRay, intersect_box, intersect_triangle};
use crate::mtbvh::LINK_END;
use crate::pack::{BvhNode, Links, PackedBvh, direction_index};
use crate::tree::MAX_DEPTH;

/// What a traversal looks for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Query {
    /// The hit with the smallest `t` in `[0, t_max)`.
    Closest,
    /// Any hit in `[0, t_max)` (shadow and visibility rays): stops at the first.
    Any,
}

/// Work done by traversals, summed over rays.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct TraversalCounters {
    /// Ray-box tests.
    pub boxes: u64,
    /// Ray-triangle tests.
    pub triangles: u64,
}

impl std::ops::Add for TraversalCounters {
    type Output = TraversalCounters;

    fn add(self, other: TraversalCounters) -> TraversalCounters {
        TraversalCounters {
            boxes: self.boxes + other.boxes,
            triangles: self.triangles + other.triangles,
        }
    }
}

/// Where a traversal tallies its work. [`TraversalCounters`] counts; [`Uncounted`] compiles the
/// tally away, so renders and timed benchmark runs pay nothing for it (~4 % of the four-wide
/// traversal's time, measured in session 10).
pub trait WorkTally {
    fn add_boxes(&mut self, n: u64);
    fn add_triangles(&mut self, n: u64);
}

impl WorkTally for TraversalCounters {
    #[inline(always)]
    fn add_boxes(&mut self, n: u64) {
        self.boxes += n;
    }

    #[inline(always)]
    fn add_triangles(&mut self, n: u64) {
        self.triangles += n;
    }
}

/// A tally that keeps nothing.
#[derive(Clone, Copy, Debug, Default)]
pub struct Uncounted;

impl WorkTally for Uncounted {
    #[inline(always)]
    fn add_boxes(&mut self, _: u64) {}

    #[inline(always)]
    fn add_triangles(&mut self, _: u64) {}
}

/// The signature every traversal shares (see [`trace_stack`], [`trace_tbvh`], [`trace_mtbvh`]).
pub type TraceFn = fn(&PackedBvh, &Ray, Query, &mut TraversalCounters) -> Option<Hit>;

/// Every hit blocks an any-hit query: the occluder test of plain shadow rays.
#[inline(always)]
pub fn every_hit(_: &Hit) -> bool {
    true
}

/// Tests a leaf's triangles, updating `best`; true if one was hit. An any-hit query takes only
/// a hit that `occludes` (an alpha cut-out's hole does not); a closest-hit query takes all.
pub(crate) fn test_leaf<W: WorkTally>(
    bvh: &PackedBvh,
    leaf: &BvhNode,
    ray: &Ray,
    query: Query,
    best: &mut Option<Hit>,
    counters: &mut W,
    occludes: &impl Fn(&Hit) -> bool,
) -> bool {
    let mut found = false;
    let first = leaf.first_or_right;
    for triangle in first..first + leaf.triangle_count {
        counters.add_triangles(1);
        let t_best = best.map_or(ray.t_max, |h| h.t);
        let tri = &bvh.triangles[triangle as usize];
        if let Some((u, v, t)) = intersect_triangle(tri, ray.origin, ray.direction, t_best) {
            let hit = Hit { triangle, t, u, v };
            if query == Query::Any {
                if occludes(&hit) {
                    *best = Some(hit);
                    return true;
                }
                continue;
            }
            *best = Some(hit);
            found = true;
        }
    }
    found
}

/// The children of internal node `node` whose boxes the ray enters before `t_best`, nearer
/// first (ties: the left child); [`LINK_END`] in place of a child it misses.
fn hit_children<W: WorkTally>(
    nodes: &[BvhNode],
    node: u32,
    slab_ray: &SlabRay,
    t_best: f32,
    counters: &mut W,
) -> (u32, u32) {
    let (left, right) = (node + 1, nodes[node as usize].first_or_right);
    counters.add_boxes(2);
    let t_left = intersect_box(&nodes[left as usize], slab_ray, t_best);
    let t_right = intersect_box(&nodes[right as usize], slab_ray, t_best);
    let (near, far, t_near, t_far) = if t_right < t_left {
        (right, left, t_right, t_left)
    } else {
        (left, right, t_left, t_right)
    };
    let near = if t_near < f32::INFINITY {
        near
    } else {
        LINK_END
    };
    let far = if t_far < f32::INFINITY { far } else { LINK_END };
    (near, far)
}

/// Stack traversal; `counters` accumulate the work done.
pub fn trace_stack<W: WorkTally>(
    bvh: &PackedBvh,
    ray: &Ray,
    query: Query,
    counters: &mut W,
) -> Option<Hit> {
    let nodes = &bvh.nodes;
    let slab_ray = SlabRay::new(ray);
    let mut best: Option<Hit> = None;
    let mut stack = [0u32; MAX_DEPTH];
    let mut stack_len = 0;
    counters.add_boxes(1);
    if nodes.is_empty() || intersect_box(&nodes[0], &slab_ray, ray.t_max) == f32::INFINITY {
        return None;
    }
    let mut node = 0u32;
    loop {
        let current = &nodes[node as usize];
        let t_best = best.map_or(ray.t_max, |h| h.t);
        let mut next = LINK_END;
        if current.triangle_count > 0 {
            if test_leaf(bvh, current, ray, query, &mut best, counters, &every_hit)
                && query == Query::Any
            {
                return best;
            }
        } else {
            let (near, far) = hit_children(nodes, node, &slab_ray, t_best, counters);
            next = near;
            if far != LINK_END {
                stack[stack_len] = far;
                stack_len += 1;
            }
        }
        if next == LINK_END {
            if stack_len == 0 {
                return best;
            }
            stack_len -= 1;
            next = stack[stack_len];
        }
        node = next;
    }
}

/// Stackless traversal along one threading: `links` per node, starting at `root`; an any-hit
/// query stops at the first hit that `occludes`.
fn trace_threaded<W: WorkTally>(
    bvh: &PackedBvh,
    links: &[Links],
    root: u32,
    ray: &Ray,
    query: Query,
    counters: &mut W,
    occludes: &impl Fn(&Hit) -> bool,
) -> Option<Hit> {
    let slab_ray = SlabRay::new(ray);
    let mut best: Option<Hit> = None;
    let mut t_best = ray.t_max;
    let mut node = root;
    while node != LINK_END {
        let current = &bvh.nodes[node as usize];
        let link = links[node as usize];
        counters.add_boxes(1);
        let entered = intersect_box(current, &slab_ray, t_best) < f32::INFINITY;
        if entered
            && current.triangle_count > 0
            && test_leaf(bvh, current, ray, query, &mut best, counters, occludes)
        {
            if query == Query::Any {
                return best;
            }
            t_best = best.map_or(t_best, |h| h.t);
        }
        // A select rather than a branch: whether a box is entered is close to a coin toss,
        // which a branch predictor cannot learn.
        node = if entered { link.hit } else { link.miss };
    }
    best
}

/// TBVH traversal (left-first threading); `counters` accumulate the work done.
pub fn trace_tbvh<W: WorkTally>(
    bvh: &PackedBvh,
    ray: &Ray,
    query: Query,
    counters: &mut W,
) -> Option<Hit> {
    trace_threaded(
        bvh,
        &bvh.tbvh_links,
        bvh.tbvh_root,
        ray,
        query,
        counters,
        &every_hit,
    )
}

/// MTBVH traversal (the threading of the ray's major direction); `counters` accumulate the
/// work done.
pub fn trace_mtbvh<W: WorkTally>(
    bvh: &PackedBvh,
    ray: &Ray,
    query: Query,
    counters: &mut W,
) -> Option<Hit> {
    trace_mtbvh_where(bvh, ray, query, counters, &every_hit)
}

/// [`trace_mtbvh`] where an any-hit query stops only at a hit that `occludes`.
fn trace_mtbvh_where<W: WorkTally>(
    bvh: &PackedBvh,
    ray: &Ray,
    query: Query,
    counters: &mut W,
    occludes: &impl Fn(&Hit) -> bool,
) -> Option<Hit> {
    let direction = direction_index(ray.direction);
    let links = bvh.direction_links(direction);
    let root = bvh.mtbvh_roots[direction];
    trace_threaded(bvh, links, root, ray, query, counters, occludes)
}

/// Whether a hit that `occludes` lies at `t` in `[0, t_max)`, MTBVH traversal: shadow rays
/// through alpha cut-outs, whose holes are hits that do not occlude.
pub fn any_hit_mtbvh_where(bvh: &PackedBvh, ray: &Ray, occludes: impl Fn(&Hit) -> bool) -> bool {
    trace_mtbvh_where(bvh, ray, Query::Any, &mut Uncounted, &occludes).is_some()
}

/// Closest hit, stack traversal.
pub fn closest_hit_stack(bvh: &PackedBvh, ray: &Ray) -> Option<Hit> {
    trace_stack(bvh, ray, Query::Closest, &mut Uncounted)
}

/// Closest hit, TBVH traversal.
pub fn closest_hit_tbvh(bvh: &PackedBvh, ray: &Ray) -> Option<Hit> {
    trace_tbvh(bvh, ray, Query::Closest, &mut Uncounted)
}

/// Closest hit, MTBVH traversal.
pub fn closest_hit_mtbvh(bvh: &PackedBvh, ray: &Ray) -> Option<Hit> {
    trace_mtbvh(bvh, ray, Query::Closest, &mut Uncounted)
}

/// Whether anything is hit at `t` in `[0, t_max)`, stack traversal.
pub fn any_hit_stack(bvh: &PackedBvh, ray: &Ray) -> bool {
    trace_stack(bvh, ray, Query::Any, &mut Uncounted).is_some()
}

/// Whether anything is hit at `t` in `[0, t_max)`, TBVH traversal.
pub fn any_hit_tbvh(bvh: &PackedBvh, ray: &Ray) -> bool {
    trace_tbvh(bvh, ray, Query::Any, &mut Uncounted).is_some()
}

/// Whether anything is hit at `t` in `[0, t_max)`, MTBVH traversal.
pub fn any_hit_mtbvh(bvh: &PackedBvh, ray: &Ray) -> bool {
    trace_mtbvh(bvh, ray, Query::Any, &mut Uncounted).is_some()
}

/// Closest hit by testing every triangle in order (the reference for tests). Of triangles hit
/// at exactly the same `t`, the first in [`PackedBvh::triangles`] wins.
pub fn closest_hit_brute_force(bvh: &PackedBvh, ray: &Ray) -> Option<Hit> {
    let mut best: Option<Hit> = None;
    for (index, triangle) in bvh.triangles.iter().enumerate() {
        let t_best = best.map_or(ray.t_max, |h| h.t);
        if let Some((u, v, t)) = intersect_triangle(triangle, ray.origin, ray.direction, t_best) {
            best = Some(Hit {
                triangle: index as u32,
                t,
                u,
                v,
            });
        }
    }
    best
}

/// Whether any triangle is hit at `t` in `[0, t_max)`, testing every one.
pub fn any_hit_brute_force(bvh: &PackedBvh, ray: &Ray) -> bool {
    bvh.triangles
        .iter()
        .any(|t| intersect_triangle(t, ray.origin, ray.direction, ray.t_max).is_some())
}

/// Relative distance within which two different triangles count as the same hit: a ray through
/// a shared edge or vertex hits every triangle there at (almost) the same `t`.
pub const TIE_TOLERANCE: f32 = 1e-4;

/// Whether two traversals' answers for one ray agree: both miss, or both hit the same
/// triangle, or different triangles at distances within [`TIE_TOLERANCE`] (relative).
pub fn hits_agree(a: Option<Hit>, b: Option<Hit>) -> bool {
    match (a, b) {
        (None, None) => true,
        (Some(a), Some(b)) => {
            a.triangle == b.triangle
                || (a.t - b.t).abs() <= TIE_TOLERANCE * a.t.abs().max(b.t.abs())
        }
        _ => false,
    }
}
