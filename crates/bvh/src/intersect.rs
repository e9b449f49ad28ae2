//! The two tests every traversal runs: Möller–Trumbore in the talk's form, and the slab test.
//!
//! Both are written as the WGSL kernels will be (plain arithmetic, selects, no early returns
//! that a shader would not have) and take the packed data, so the CPU and GPU test the same
//! numbers.

use glam::{BVec3, Vec3};

use crate::pack::{BvhNode, PackedTriangle};

/// A ray; hits count for `t` in `[0, t_max)` (distances in units of `direction`'s length).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    /// Where the ray starts.
    pub origin: Vec3,
    /// Where it goes; need not be unit length, must be finite and not zero.
    pub direction: Vec3,
    /// Hits at `t ≥ t_max` do not count; may be `f32::INFINITY`.
    pub t_max: f32,
}

/// A ray-triangle hit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Index into [`crate::pack::PackedBvh::triangles`] (see `triangle_ids` for the scene's).
    pub triangle: u32,
    /// Distance along the ray, in units of its direction's length.
    pub t: f32,
    /// Barycentric weight of vertex 1.
    pub u: f32,
    /// Barycentric weight of vertex 2 (vertex 0 has `1 − u − v`).
    pub v: f32,
}

/// `1 + 2γ₃` (Ize, "Robust BVH ray traversal", 2013): widening the slab exit distance by this
/// factor covers the rounding of the slab test, so a box is never missed by a ray that
/// reaches it. Public so that the WGSL prelude can take it from here.
pub const ROBUST_EXIT: f32 = {
    let half_epsilon = f32::EPSILON / 2.0;
    let gamma3 = 3.0 * half_epsilon / (1.0 - 3.0 * half_epsilon);
    1.0 + 2.0 * gamma3
};

/// The talk's Möller–Trumbore test: `(u, v, t)` if the ray hits `triangle` at
/// `0 ≤ t < t_best`, else `None`.
///
/// As in the talk, `u = tv·pv / det`, `v = d·qv / det`, `t = e1·qv / det`, `w = 1 − u − v`,
/// and a hit needs `u, v, w, t ≥ 0` and `t < t_best`:
/// - `t == 0` counts (a ray starting on a surface hits it); callers offset secondary origins;
/// - `u`, `v` or `w` exactly 0 counts, so a ray through a shared edge hits both triangles at
///   the same `t`;
/// - `det == 0` (the ray parallel to the triangle's plane, or a degenerate triangle) is no hit.
///   It is tested explicitly and the divisions never see 0, since WGSL lets an implementation
///   assume infinities and NaNs never occur.
#[inline]
pub fn intersect_triangle(
    triangle: &PackedTriangle,
    origin: Vec3,
    direction: Vec3,
    t_best: f32,
) -> Option<(f32, f32, f32)> {
    let [p0, p1, p2] = triangle.positions();
    let e0 = p1 - p0;
    let e1 = p2 - p0;
    let pv = direction.cross(e1);
    let det = e0.dot(pv);
    let tv = origin - p0;
    let qv = tv.cross(e0);
    // Divide by 1 instead of 0 so no inf or NaN is ever made; det == 0 is rejected below.
    let safe_det = if det != 0.0 { det } else { 1.0 };
    let u = tv.dot(pv) / safe_det;
    let v = direction.dot(qv) / safe_det;
    let t = e1.dot(qv) / safe_det;
    let w = 1.0 - u - v;
    let hit = det != 0.0 && u >= 0.0 && v >= 0.0 && w >= 0.0 && t >= 0.0 && t < t_best;
    hit.then_some((u, v, t))
}

/// A ray prepared for slab tests: the inverse direction, with axes the ray runs parallel to
/// handled explicitly rather than through `±inf` and NaN.
///
/// WGSL lets an implementation assume infinities and NaNs never occur, so the shader cannot
/// rely on `1 / 0 = inf` and `0 · inf = NaN` the way an IEEE slab test does; this twin follows
/// the shader. An axis is parallel when `|direction| < f32::MIN_POSITIVE` (zero or denormal,
/// which a GPU may flush to zero anyway); its inverse is set to 0 and it only asks that the
/// origin lie between the box's planes (inclusive: a ray in a face's plane is inside).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SlabRay {
    /// The ray's origin.
    pub origin: Vec3,
    /// `1 / direction`, 0 on parallel axes.
    pub inv_direction: Vec3,
    /// Which axes the ray runs parallel to.
    pub parallel: BVec3,
    /// Whether any is (the slab test's slow path).
    pub any_parallel: bool,
}

/// Below this a direction component counts as zero in the slab test (the smallest normal f32).
pub const PARALLEL_LIMIT: f32 = f32::MIN_POSITIVE;

impl SlabRay {
    /// Prepares `ray` for [`intersect_box`].
    pub fn new(ray: &Ray) -> SlabRay {
        let parallel = ray.direction.abs().cmplt(Vec3::splat(PARALLEL_LIMIT));
        let safe_direction = Vec3::select(parallel, Vec3::ONE, ray.direction);
        SlabRay {
            origin: ray.origin,
            inv_direction: Vec3::select(parallel, Vec3::ZERO, safe_direction.recip()),
            parallel,
            any_parallel: parallel.any(),
        }
    }
}

/// Distance at which a ray enters `node`'s box, or `f32::INFINITY` if it misses the box or
/// enters it beyond `t_far`.
///
/// Per axis the slab distances are `(min − o) / d` and `(max − o) / d`; the entry is the
/// largest near distance (and 0), the exit the smallest far distance (and `t_far`), widened by
/// `1 + 2γ₃` against rounding. Parallel axes add no distances and miss when the origin is
/// outside their slab (see [`SlabRay`]).
#[inline]
pub fn intersect_box(node: &BvhNode, ray: &SlabRay, t_far: f32) -> f32 {
    let (lo, hi) = (Vec3::from(node.min), Vec3::from(node.max));
    let t_lo = (lo - ray.origin) * ray.inv_direction;
    let t_hi = (hi - ray.origin) * ray.inv_direction;
    let t_near = t_lo.min(t_hi);
    let t_far_axes = t_lo.max(t_hi);
    let t_enter = t_near.max_element().max(0.0);
    let inside = if ray.any_parallel {
        // Rare: the parallel axes add no far distance, and the origin must lie in their slab.
        let t_far_axes = Vec3::select(ray.parallel, Vec3::INFINITY, t_far_axes);
        let t_exit = t_far_axes.min_element().min(t_far) * ROBUST_EXIT;
        let outside = ray.parallel & (ray.origin.cmplt(lo) | ray.origin.cmpgt(hi));
        t_enter <= t_exit && !outside.any()
    } else {
        t_enter <= t_far_axes.min_element().min(t_far) * ROBUST_EXIT
    };
    if inside { t_enter } else { f32::INFINITY }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn slab(origin: Vec3, direction: Vec3) -> SlabRay {
        SlabRay::new(&Ray {
            origin,
            direction,
            t_max: f32::INFINITY,
        })
    }

    fn unit_box() -> BvhNode {
        BvhNode {
            min: [0.0; 3],
            max: [1.0; 3],
            ..Default::default()
        }
    }

    #[test]
    fn box_entry_distance_and_misses() {
        let b = unit_box();
        let o = Vec3::new(-1.0, 0.5, 0.5);
        assert_eq!(intersect_box(&b, &slab(o, Vec3::X), f32::INFINITY), 1.0);
        assert_eq!(
            intersect_box(&b, &slab(o, Vec3::NEG_X), f32::INFINITY),
            f32::INFINITY
        );
        assert_eq!(intersect_box(&b, &slab(o, Vec3::X), 0.5), f32::INFINITY);
        let inside = Vec3::splat(0.5);
        assert_eq!(intersect_box(&b, &slab(inside, Vec3::NEG_Y), 1.0), 0.0);
    }

    #[test]
    fn rays_in_a_face_plane_count_as_inside() {
        let b = unit_box();
        for face_x in [0.0, 1.0] {
            for dir in [
                Vec3::new(0.0, 0.0, 1.0),
                Vec3::new(-0.0, 0.0, -1.0),
                Vec3::new(0.0, 1.0, 0.0),
            ] {
                let o = Vec3::new(face_x, 0.5, 0.5) - 2.0 * dir;
                let t = intersect_box(&b, &slab(o, dir), f32::INFINITY);
                assert_eq!(t, 1.5, "x = {face_x}, {dir}");
            }
        }
        // Just outside the plane: a miss.
        let o = Vec3::new(1.0f32.next_up(), 0.5, -1.0);
        assert_eq!(
            intersect_box(&b, &slab(o, Vec3::Z), f32::INFINITY),
            f32::INFINITY
        );
    }

    fn triangle(p: [Vec3; 3]) -> PackedTriangle {
        let mut t = PackedTriangle::default();
        for (v, p) in t.vertices.iter_mut().zip(p) {
            v.position = p.to_array();
        }
        t
    }

    #[test]
    fn triangle_hit_barycentrics_and_edges() {
        let tri = triangle([Vec3::ZERO, Vec3::X, Vec3::Y]);
        let hit = intersect_triangle(&tri, Vec3::new(0.25, 0.5, 1.0), -Vec3::Z, f32::INFINITY);
        assert_eq!(hit, Some((0.25, 0.5, 1.0)));
        // On the edge u = 0, at a vertex, and at t = 0.
        assert!(intersect_triangle(&tri, Vec3::new(0.0, 0.5, 1.0), -Vec3::Z, 2.0).is_some());
        assert!(intersect_triangle(&tri, Vec3::new(1.0, 0.0, 1.0), -Vec3::Z, 2.0).is_some());
        assert_eq!(
            intersect_triangle(&tri, Vec3::new(0.2, 0.2, 0.0), -Vec3::Z, 2.0),
            Some((0.2, 0.2, 0.0))
        );
        // Behind, beyond t_best, outside, parallel, degenerate.
        assert!(intersect_triangle(&tri, Vec3::new(0.25, 0.25, 1.0), Vec3::Z, 9.0).is_none());
        assert!(intersect_triangle(&tri, Vec3::new(0.25, 0.25, 1.0), -Vec3::Z, 1.0).is_none());
        assert!(intersect_triangle(&tri, Vec3::new(0.75, 0.5, 1.0), -Vec3::Z, 9.0).is_none());
        assert!(intersect_triangle(&tri, Vec3::new(0.2, 0.2, 0.0), Vec3::X, 9.0).is_none());
        let flat = triangle([Vec3::ZERO, Vec3::X, 2.0 * Vec3::X]);
        assert!(intersect_triangle(&flat, Vec3::new(0.5, 0.0, 1.0), -Vec3::Z, 9.0).is_none());
    }
}
