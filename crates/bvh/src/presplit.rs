//! Splitting the boxes of large, slanted triangles before the build, so that the SAH builder
//! sees several tight boxes instead of one loose one (the triangle splitting of Karras and
//! Aila, "Fast parallel construction of high-quality bounding volume hierarchies", HPG 2013;
//! earlier, Ernst and Greiner's early split clipping, 2007).
//!
//! A long diagonal triangle (Sponza's floors, arches and drapes) has a box mostly of empty
//! space, which every ray through that space must enter. Cutting the box at a plane and
//! keeping, on each side, only the box of the triangle's part there gives references that
//! hug the triangle; the builder then places each reference on its own. A triangle thus
//! lives in several leaves, tested where a ray meets one of its boxes. Every point of the
//! triangle stays inside at least one of its references' boxes, so traversal finds the same
//! closest hit.
//!
//! The budget is a number of extra references, shared out in proportion to a priority: the
//! empty area a triangle's box carries (box area − 2 · triangle area), flattened by a square
//! root so that the budget spreads over many triangles as Karras and Aila's flattening does
//! (on the Sponzas the square root visited fewer boxes per ray than the cube or fifth root or
//! none; `kousen bench traversal --split-percent`, BENCHMARKS §2). Cuts fall on the planes of
//! a power-of-two grid over the scene, the coarsest one crossing the reference along its
//! longest axis: cuts of neighbouring triangles then coincide, and so can the planes that the
//! builder chooses between nodes.
//!
//! Since session 10 this spends a tenth of the budget, ahead of the spatial splits of module
//! `sbvh`, which spend the rest and reuse [`cut`].

use glam::Vec3A;
use rayon::prelude::*;
use scene::Triangle;

use crate::aabb::Aabb;

/// Finest grid level searched for a cut (2²⁰ cells along an axis).
const MAX_GRID_LEVEL: u32 = 20;
/// Triangles with less area than this fraction of their box's half area are not split.
const MIN_AREA_RATIO: f32 = 1e-3;
/// Pieces' boxes are widened at the cut by this fraction of the cut edge's length (and by a
/// few units in the last place), so that hits the triangle test reports just off an edge
/// (its error on the thinnest triangles split) stay inside some piece.
const CUT_SLACK: f32 = 1e-4;

/// The references: `(boxes[i], ids[i])` is one box around (part of) triangle `ids[i]`.
/// `extra` references are shared out beyond one per triangle; `triangle_boxes[i]` is the box
/// of `triangles[i]` and `scene` their union.
pub(crate) fn presplit(
    triangles: &[Triangle],
    triangle_boxes: &[Aabb],
    scene: &Aabb,
    extra: usize,
) -> (Vec<Aabb>, Vec<u32>) {
    let priorities: Vec<f32> = triangles
        .par_iter()
        .zip(triangle_boxes)
        .map(|(t, b)| priority(t, b))
        .collect();
    let scale = budget_scale(&priorities, extra);
    let grid = Grid::new(scene);
    let pieces: Vec<(Vec<Aabb>, u32)> = triangles
        .par_iter()
        .zip(triangle_boxes)
        .zip(&priorities)
        .enumerate()
        .map(|(id, ((triangle, bounds), &p))| {
            let cuts = (p * scale) as usize;
            let mut boxes = Vec::with_capacity(cuts + 1);
            let corners = triangle.positions().map(Vec3A::from);
            split(&corners, *bounds, cuts, &grid, &mut boxes);
            (boxes, id as u32)
        })
        .collect();
    let mut boxes = Vec::with_capacity(triangles.len() + extra);
    let mut ids = Vec::with_capacity(triangles.len() + extra);
    for (parts, id) in pieces {
        ids.extend(std::iter::repeat_n(id, parts.len()));
        boxes.extend(parts);
    }
    (boxes, ids)
}

/// How much a triangle gains from being split: the empty area its box carries. Zero for a
/// triangle with less area than [`MIN_AREA_RATIO`] of its box's: the triangle test is not
/// reliable on such a sliver (it may report hits off the triangle, though inside its box),
/// so it keeps its one box.
fn priority(triangle: &Triangle, bounds: &Aabb) -> f32 {
    // Half the box's surface against the triangle's one face.
    let (box_area, area) = (bounds.half_area(), triangle.area());
    if area < MIN_AREA_RATIO * box_area {
        return 0.0;
    }
    (box_area - area).max(0.0).sqrt()
}

/// The factor `s` for which `Σ floor(s · priority)` comes closest to `extra` without passing
/// it (bisection).
fn budget_scale(priorities: &[f32], extra: usize) -> f32 {
    let cuts = |s: f32| -> usize { priorities.par_iter().map(|&p| (p * s) as usize).sum() };
    let total: f64 = priorities.par_iter().map(|&p| f64::from(p)).sum();
    if extra == 0 || total <= 0.0 {
        return 0.0;
    }
    let (mut low, mut high) = (0.0f32, (2.0 * extra as f64 / total) as f32 + 1.0);
    while cuts(high) <= extra {
        high *= 2.0;
    }
    for _ in 0..32 {
        let mid = 0.5 * (low + high);
        if cuts(mid) <= extra {
            low = mid;
        } else {
            high = mid;
        }
    }
    low
}

/// The scene's power-of-two grid of cutting planes.
struct Grid {
    origin: Vec3A,
    extent: Vec3A,
}

impl Grid {
    fn new(scene: &Aabb) -> Grid {
        Grid {
            origin: scene.min,
            extent: scene.extent(),
        }
    }

    /// The coarsest grid plane on `axis` strictly between `low` and `high`, if any.
    fn plane(&self, axis: usize, low: f32, high: f32) -> Option<f32> {
        let (origin, extent) = (self.origin[axis], self.extent[axis]);
        if extent <= 0.0 {
            return None;
        }
        (1..=MAX_GRID_LEVEL).find_map(|level| {
            let cell = extent / (1u32 << level) as f32;
            let plane = origin + ((low - origin) / cell).floor() * cell + cell;
            (plane > low && plane < high).then_some(plane)
        })
    }
}

/// Appends to `out` the boxes of `cuts + 1` pieces of the triangle with `corners` inside
/// `bounds` (fewer where a cut leaves nothing on one side or no grid plane crosses).
fn split(corners: &[Vec3A; 3], bounds: Aabb, cuts: usize, grid: &Grid, out: &mut Vec<Aabb>) {
    if cuts == 0 {
        out.push(bounds);
        return;
    }
    let extent = bounds.extent();
    let axis = extent.max_position();
    let Some(plane) = grid.plane(axis, bounds.min[axis], bounds.max[axis]) else {
        out.push(bounds);
        return;
    };
    let (left, right) = cut(corners, &bounds, axis, plane);
    match (left, right) {
        (Some(left), Some(right)) => {
            // Share the remaining cuts by the pieces' sizes along the cut axis.
            let rest = cuts - 1;
            let left_share =
                (left.extent()[axis] / (extent[axis].max(f32::MIN_POSITIVE))).clamp(0.0, 1.0);
            let left_cuts = ((rest as f32 * left_share).round() as usize).min(rest);
            split(corners, left, left_cuts, grid, out);
            split(corners, right, rest - left_cuts, grid, out);
        }
        (Some(only), None) | (None, Some(only)) => split(corners, only, cuts - 1, grid, out),
        (None, None) => out.push(bounds),
    }
}

/// The boxes, within `bounds`, of the triangle's parts below and above `plane` on `axis`
/// (`None` for a side it does not reach). Conservative: the parts' points all lie inside.
pub(crate) fn cut(
    corners: &[Vec3A; 3],
    bounds: &Aabb,
    axis: usize,
    plane: f32,
) -> (Option<Aabb>, Option<Aabb>) {
    let (mut below, mut above) = (Aabb::EMPTY, Aabb::EMPTY);
    for i in 0..3 {
        let (a, b) = (corners[i], corners[(i + 1) % 3]);
        if a[axis] <= plane {
            below = below.grow(a);
        }
        if a[axis] >= plane {
            above = above.grow(a);
        }
        let crosses = (a[axis] < plane && b[axis] > plane) || (a[axis] > plane && b[axis] < plane);
        if crosses {
            let s = (plane - a[axis]) / (b[axis] - a[axis]);
            let mut point = a + s * (b - a);
            point[axis] = plane;
            // Rounding puts the crossing a little off the true edge, and the triangle test
            // may report hits a little outside the triangle: widen the crossing (see
            // CUT_SLACK) so that the pieces' boxes still cover what the whole box would.
            let slack = (point.abs() + (b - a).abs()) * (8.0 * f32::EPSILON)
                + Vec3A::splat(CUT_SLACK * (b - a).length());
            for p in [point - slack, point + slack] {
                let mut p = p;
                p[axis] = plane;
                below = below.grow(p);
                above = above.grow(p);
            }
        }
    }
    let mut below_bounds = *bounds;
    below_bounds.max[axis] = plane;
    let mut above_bounds = *bounds;
    above_bounds.min[axis] = plane;
    (
        intersect(below, below_bounds),
        intersect(above, above_bounds),
    )
}

/// The common part of two boxes, or `None` if they do not overlap.
pub(crate) fn intersect(a: Aabb, b: Aabb) -> Option<Aabb> {
    let common = Aabb {
        min: a.min.max(b.min),
        max: a.max.min(b.max),
    };
    common.min.cmple(common.max).all().then_some(common)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::Rng;

    fn triangle_box(t: &Triangle) -> Aabb {
        let [a, b, c] = t.positions().map(Vec3A::from);
        Aabb {
            min: a.min(b).min(c),
            max: a.max(b).max(c),
        }
    }

    fn contains(b: &Aabb, p: Vec3A) -> bool {
        b.min.cmple(p).all() && p.cmple(b.max).all()
    }

    /// Every point of every triangle lies in one of its references' boxes, each reference's
    /// box lies within its triangle's box, and the budget is spent but not overspent.
    #[test]
    fn references_cover_their_triangles_within_the_budget() {
        // The soup holds long slivers: the triangles the splitting is for.
        let triangles = crate::testing::random_soup(3, 200);
        let boxes: Vec<Aabb> = triangles.iter().map(triangle_box).collect();
        let scene = boxes.iter().fold(Aabb::EMPTY, |s, b| s.union(*b));
        let extra = 100;
        let (refs, ids) = presplit(&triangles, &boxes, &scene, extra);
        assert_eq!(refs.len(), ids.len());
        assert!(
            refs.len() > triangles.len() + extra / 2,
            "{} references",
            refs.len()
        );
        assert!(
            refs.len() <= triangles.len() + extra,
            "{} references",
            refs.len()
        );
        let most_pieces = (0..triangles.len() as u32)
            .map(|t| ids.iter().filter(|&&id| id == t).count())
            .max();
        assert!(most_pieces > Some(2), "at most {most_pieces:?} pieces");
        let mut rng = Rng::new(9);
        for (id, triangle) in triangles.iter().enumerate() {
            let mine: Vec<&Aabb> = refs
                .iter()
                .zip(&ids)
                .filter(|(_, i)| **i == id as u32)
                .map(|(b, _)| b)
                .collect();
            assert!(!mine.is_empty());
            for b in &mine {
                assert!(contains(&boxes[id], b.min) && contains(&boxes[id], b.max));
            }
            let [a, b, c] = triangle.positions().map(Vec3A::from);
            for _ in 0..500 {
                let (mut u, mut v) = (rng.unit(), rng.unit());
                if u + v > 1.0 {
                    (u, v) = (1.0 - u, 1.0 - v);
                }
                let p = a + u * (b - a) + v * (c - a);
                assert!(
                    mine.iter().any(|r| contains(r, p)),
                    "triangle {id}: {p} outside its pieces"
                );
            }
            for corner in [a, b, c] {
                assert!(mine.iter().any(|r| contains(r, corner)));
            }
        }
    }

    #[test]
    fn no_budget_keeps_one_reference_per_triangle() {
        let triangles = crate::testing::random_soup(4, 50);
        let boxes: Vec<Aabb> = triangles.iter().map(triangle_box).collect();
        let scene = boxes.iter().fold(Aabb::EMPTY, |s, b| s.union(*b));
        let (refs, ids) = presplit(&triangles, &boxes, &scene, 0);
        assert_eq!(refs, boxes);
        assert_eq!(ids, (0..50).collect::<Vec<u32>>());
    }

    #[test]
    fn grid_planes_are_the_coarsest_inside() {
        let grid = Grid::new(&Aabb {
            min: Vec3A::ZERO,
            max: Vec3A::splat(8.0),
        });
        assert_eq!(grid.plane(0, 1.0, 7.0), Some(4.0));
        assert_eq!(grid.plane(0, 4.5, 7.5), Some(6.0));
        assert_eq!(grid.plane(0, 4.0, 6.0), Some(5.0));
        assert_eq!(grid.plane(0, 3.0, 3.0), None);
    }
}
