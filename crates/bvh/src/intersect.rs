//! The two tests every traversal runs: Möller–Trumbore in the talk's form, and the slab test.
//!
//! Both are written as the WGSL kernels will be (plain arithmetic, selects, no early returns
//! that a shader would not have) and take the packed data, so the CPU and GPU test the same
//! numbers.

use glam::Vec3;

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
///   It is tested explicitly rather than left to the `±inf`/NaN the divisions would give,
///   since WGSL lets an implementation assume those never occur.
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
    let u = tv.dot(pv) / det;
    let v = direction.dot(qv) / det;
    let t = e1.dot(qv) / det;
    let w = 1.0 - u - v;
    let hit = det != 0.0 && u >= 0.0 && v >= 0.0 && w >= 0.0 && t >= 0.0 && t < t_best;
    hit.then_some((u, v, t))
}

/// Distance at which a ray enters `node`'s box, or `f32::INFINITY` if it misses the box or
/// enters it beyond `t_far`. `inv_direction` is `1 / direction` per component.
///
/// Per axis, the near plane is `min` for a positive inverse and `max` for a negative one, so
/// `t0 ≤ t1` without a swap. A zero direction component gives an inverse of `±inf`, and then:
/// - origin strictly between the planes: `t0 = −inf`, `t1 = +inf`, no constraint;
/// - origin outside: both `+inf` or both `−inf`, a miss;
/// - origin exactly on a plane: `0 · inf = NaN` for that plane. NaN fails every comparison, so
///   the updates below skip it and the ray, lying in the face's plane, counts as inside that
///   slab, as it should, whichever sign the zero has.
///
/// A denormal component also inverts to `±inf` and is treated as zero here. The exit
/// distance is widened by `1 + 2γ₃` against rounding.
#[inline]
pub fn intersect_box(node: &BvhNode, origin: Vec3, inv_direction: Vec3, t_far: f32) -> f32 {
    let mut t_enter = 0.0f32;
    let mut t_exit = f32::INFINITY;
    for axis in 0..3 {
        let inv = inv_direction[axis];
        let (near, far) = if inv < 0.0 {
            (node.max[axis], node.min[axis])
        } else {
            (node.min[axis], node.max[axis])
        };
        let t0 = (near - origin[axis]) * inv;
        let t1 = (far - origin[axis]) * inv;
        if t0 > t_enter {
            t_enter = t0;
        }
        if t1 < t_exit {
            t_exit = t1;
        }
    }
    let t_exit = t_exit.min(t_far) * ROBUST_EXIT;
    if t_enter <= t_exit {
        t_enter
    } else {
        f32::INFINITY
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
        assert_eq!(
            intersect_box(&b, o, Vec3::new(1.0, 0.0, 0.0).recip(), f32::INFINITY),
            1.0
        );
        assert_eq!(
            intersect_box(&b, o, Vec3::new(-1.0, 0.0, 0.0).recip(), f32::INFINITY),
            f32::INFINITY
        );
        assert_eq!(
            intersect_box(&b, o, Vec3::new(1.0, 0.0, 0.0).recip(), 0.5),
            f32::INFINITY
        );
        let inside = Vec3::splat(0.5);
        assert_eq!(
            intersect_box(&b, inside, Vec3::new(0.0, -1.0, 0.0).recip(), 1.0),
            0.0
        );
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
                let t = intersect_box(&b, o, dir.recip(), f32::INFINITY);
                assert_eq!(t, 1.5, "x = {face_x}, {dir}");
            }
        }
        // Just outside the plane: a miss.
        let o = Vec3::new(1.0f32.next_up(), 0.5, -1.0);
        assert_eq!(
            intersect_box(&b, o, Vec3::Z.recip(), f32::INFINITY),
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
