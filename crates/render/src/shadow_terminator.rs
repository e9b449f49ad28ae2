//! Where shadow rays leave a smooth-shaded triangle: on the smooth surface its vertex normals
//! describe, not on the flat facet (Hanika 2021, "Hacking the shadow terminator", Ray Tracing
//! Gems II). Near the terminator of a coarse mesh (a sphere of a few hundred triangles) the
//! shading normal still faces the light where the facet's neighbour already blocks a ray from
//! the facet: the lit side ends in a staircase of facets instead of a smooth curve. Shared by
//! `cpu::surface`, the path tracer and their WGSL twin in `shading/normals.wgsl`.

use glam::Vec3;

/// `position` (on the triangle with `corners`, unit vertex `normals` and `barycentric`
/// weights) lifted onto each corner's tangent plane where it lies below that plane, the lifts
/// blended by the weights. Flat triangles (each vertex normal the face's) and concave corners
/// leave it where it is; a zero normal lifts nothing.
pub fn smooth_position(
    position: Vec3,
    corners: [Vec3; 3],
    normals: [Vec3; 3],
    barycentric: [f32; 3],
) -> Vec3 {
    let mut lifted = position;
    for i in 0..3 {
        let below = (position - corners[i]).dot(normals[i]).min(0.0);
        lifted -= (barycentric[i] * below) * normals[i];
    }
    lifted
}

/// Where shadow rays from a hit at `position`, met by a ray along `direction`, start: the
/// [`smooth_position`] when the ray came from the side the `interpolated` vertex normal faces
/// (so the smooth surface lies between the facet and the light), `position` itself otherwise.
pub fn shadow_origin(
    position: Vec3,
    direction: Vec3,
    interpolated: Vec3,
    corners: [Vec3; 3],
    normals: [Vec3; 3],
    barycentric: [f32; 3],
) -> Vec3 {
    if interpolated.dot(direction) < 0.0 {
        smooth_position(position, corners, normals, barycentric)
    } else {
        position
    }
}

/// How far above the facet (× the scene's ray epsilon) the lift must reach before the light
/// sample trusts the smooth surface over the facet; rounding lifts a flat triangle's points by
/// a millionth of that.
pub const LIFT_THRESHOLD: f32 = 0.01;

/// Whether a light the shading normal faces but the facet turns from may still reach the hit
/// (its shadow ray, from `shadow_origin`, decides): where the smooth surface rises above the
/// facet, as on the lit side of a coarse sphere's terminator. `geometric` is the facet's
/// normal on the side the ray came from, `epsilon` the scene's ray offset.
pub fn is_lifted(position: Vec3, shadow_origin: Vec3, geometric: Vec3, epsilon: f32) -> bool {
    (shadow_origin - position).dot(geometric) > LIFT_THRESHOLD * epsilon
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_flat_triangle_keeps_the_point() {
        let corners = [Vec3::ZERO, Vec3::X, Vec3::Y];
        let p = Vec3::new(0.25, 0.25, 0.0);
        let moved = smooth_position(p, corners, [Vec3::Z; 3], [0.5, 0.25, 0.25]);
        assert_eq!(moved, p);
    }

    #[test]
    fn a_facet_of_a_sphere_lifts_towards_the_sphere() {
        // Three points of the unit sphere, their normals the sphere's: the facet's centre lies
        // inside the sphere, and the lifted point lies closer to it than the centre did.
        let corners = [
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(0.0, 0.0, 1.0),
        ];
        let centre = corners.iter().sum::<Vec3>() / 3.0;
        let lifted = smooth_position(centre, corners, corners, [1.0 / 3.0; 3]);
        assert!((lifted - centre).dot(centre) > 0.0, "moved outwards");
        assert!((1.0 - lifted.length()).abs() < (1.0 - centre.length()).abs());
        // At a corner nothing moves: the point is on that corner's tangent plane.
        let at_corner = smooth_position(corners[0], corners, corners, [1.0, 0.0, 0.0]);
        assert_eq!(at_corner, corners[0]);
    }

    #[test]
    fn a_concave_facet_keeps_the_point() {
        // The inside of the sphere: normals point inwards, the facet lies above their planes.
        let corners = [
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(0.0, 0.0, 1.0),
        ];
        let centre = corners.iter().sum::<Vec3>() / 3.0;
        let inward = corners.map(|c| -c);
        assert_eq!(
            smooth_position(centre, corners, inward, [1.0 / 3.0; 3]),
            centre
        );
    }
}
