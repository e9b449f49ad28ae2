//! Thin-lens camera rays (`scene::Lens`): depth of field. An eye path through film point
//! (sx, sy) starts at a point of the lens's aperture (a disk of radius
//! `SppmParams::lens_radius` across the view about the eye, or the regular polygon of
//! `aperture_blades` sides inscribed in it: `crate::sampling::aperture_point`) and heads for where the pinhole ray through that film point meets the
//! plane in focus, `focus_distance` ahead of the eye: what lies on that plane is sharp, and a
//! point at depth d spreads over a disk of radius `radius · |1/focus − 1/d|` on the film plane
//! one unit ahead of the eye (the pinhole's image scale), or over the polygon scaled alike.
//! Radius 0 is the pinhole, ray for ray, so pinhole renders do not change. An orthographic
//! camera has no lens (`kousen render` refuses one): its rays leave the film along the view.
//!
//! Each first camera path of a pixel takes its lens point from [`crate::rng::pixel_lens`]
//! (a low-discrepancy sequence independent of the jitter's); the extra paths of pixels
//! showing glass draw theirs from the pixel's stream, after their jitter.

use glam::Vec3;

use crate::buffers::SppmParams;
use crate::integrator::camera_direction;
use crate::sampling::aperture_point;

/// The origin and unit direction of the camera ray through film point (sx, sy) ∈ [−1, 1]²
/// (+y up) that leaves the lens at the point `lens` ∈ [0, 1)² maps to.
pub fn camera_ray(params: &SppmParams, sx: f32, sy: f32, lens: [f32; 2]) -> (Vec3, Vec3) {
    let eye = Vec3::from_array(params.eye);
    let (right, up) = (Vec3::from_array(params.right), Vec3::from_array(params.up));
    if params.orthographic != 0 {
        let forward = Vec3::from_array(params.forward).normalize();
        return (eye + sx * right + sy * up, forward);
    }
    if params.lens_radius <= 0.0 {
        return (eye, camera_direction(params, sx, sy));
    }
    let through = Vec3::from_array(params.forward) + sx * right + sy * up;
    let lens_disk = [right.normalize(), up.normalize()];
    let lens_shape = scene::Lens {
        radius: params.lens_radius,
        focus_distance: params.focus_distance,
        blades: params.aperture_blades,
        rotation: params.aperture_rotation,
    };
    thin_lens_ray(eye, through, lens_disk, lens_shape, lens)
}

/// [`camera_ray`] from `camera` itself, for an image of aspect ratio `aspect` (the path
/// tracer's): the pinhole's ray is `scene::Camera::direction`'s.
pub fn camera_lens_ray(
    camera: &scene::Camera,
    (sx, sy): (f32, f32),
    aspect: f32,
    lens: [f32; 2],
) -> (Vec3, Vec3) {
    if camera.lens.is_pinhole() || camera.is_orthographic() {
        return camera.ray(sx, sy, aspect);
    }
    let (right, up) = camera.film_half_extents(aspect);
    let through = camera.forward + sx * right + sy * up;
    let lens_disk = [camera.right(), camera.up];
    thin_lens_ray(camera.eye, through, lens_disk, camera.lens, lens)
}

/// The ray from the point of the lens disk (spanned by unit `right` and `up` about `eye`)
/// that `lens` maps to, towards where the pinhole ray `through` (its step along the view 1)
/// meets the plane in focus: `focus_distance` times itself ahead of the eye.
fn thin_lens_ray(
    eye: Vec3,
    through: Vec3,
    [right, up]: [Vec3; 2],
    shape: scene::Lens,
    lens: [f32; 2],
) -> (Vec3, Vec3) {
    let focus = eye + shape.focus_distance * through;
    let disk = shape.radius * aperture_point(lens[0], lens[1], shape.blades, shape.rotation);
    let origin = eye + disk.x * right + disk.y * up;
    (origin, (focus - origin).normalize())
}

/// The distance ahead of `camera`'s eye of what the image's centre shows, for a lens focused
/// there; `None` where the centre sees nothing.
pub fn autofocus(bvh: &bvh::PackedBvh, camera: &scene::Camera) -> Option<f32> {
    depth_along_view(bvh, camera, (0.0, 0.0), 1.0)
}

/// How far ahead along the view (the depth of the plane a lens focused there needs) `camera`'s
/// pinhole ray through film point (sx, sy) of an image of aspect ratio `aspect` meets a
/// surface; `None` where it meets none.
pub fn depth_along_view(
    bvh: &bvh::PackedBvh,
    camera: &scene::Camera,
    (sx, sy): (f32, f32),
    aspect: f32,
) -> Option<f32> {
    let (origin, direction) = camera.ray(sx, sy, aspect);
    let ray = bvh::Ray {
        origin,
        direction,
        t_max: f32::INFINITY,
    };
    bvh::closest_hit_mtbvh(bvh, &ray).map(|hit| hit.t * direction.dot(camera.forward))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn params(lens_radius: f32, focus_distance: f32) -> SppmParams {
        SppmParams {
            eye: [1.0, 2.0, 3.0],
            forward: [0.0, 0.0, -1.0],
            right: [0.8, 0.0, 0.0],
            up: [0.0, 0.6, 0.0],
            lens_radius,
            focus_distance,
            ..SppmParams::default()
        }
    }

    /// A pinhole's rays are the eye kernels' pinhole rays, bit for bit.
    #[test]
    fn a_pinhole_is_unchanged() {
        let pinhole = params(0.0, 0.0);
        for (sx, sy) in [(0.0, 0.0), (-0.7, 0.3), (1.0, -1.0)] {
            let (origin, direction) = camera_ray(&pinhole, sx, sy, [0.3, 0.8]);
            assert_eq!(origin, Vec3::new(1.0, 2.0, 3.0));
            assert_eq!(direction, camera_direction(&pinhole, sx, sy));
        }
    }

    /// Every ray through one film point starts on the lens disk, across the view, and meets
    /// the others on the plane in focus, where the pinhole ray through that point meets it;
    /// evenly spread numbers cover the disk evenly (mean squared radius R²/2).
    #[test]
    fn rays_through_a_film_point_meet_on_the_plane_in_focus() {
        let lens = params(0.25, 4.0);
        let eye = Vec3::from_array(lens.eye);
        let mut squared_radii = 0.0;
        let n = 64;
        for (sx, sy) in [(0.0, 0.0), (-0.7, 0.3), (1.0, -1.0)] {
            let pinhole = camera_direction(&lens, sx, sy);
            let focus = eye + pinhole * (4.0 / pinhole.dot(Vec3::NEG_Z));
            for i in 0..n {
                for j in 0..n {
                    let u = [(i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32];
                    let (origin, direction) = camera_ray(&lens, sx, sy, u);
                    let offset = origin - eye;
                    assert!(offset.z.abs() < 1e-6 && offset.length() <= 0.25 + 1e-6);
                    squared_radii += offset.length_squared() as f64;
                    let t = (focus - origin).length();
                    assert!((origin + t * direction).distance(focus) < 1e-5);
                    assert!((direction.length() - 1.0).abs() < 1e-6);
                }
            }
        }
        let mean = squared_radii / (3 * n * n) as f64;
        assert!((mean / (0.25f64 * 0.25 / 2.0) - 1.0).abs() < 1e-3, "{mean}");
    }

    /// An orthographic camera's rays leave the film point `eye + sx·right + sy·up` (its half
    /// extents) along the view, whatever the lens, as the camera itself makes them.
    #[test]
    fn orthographic_rays_leave_the_film_along_the_view() {
        let camera = scene::Camera::look_at(Vec3::ONE, Vec3::ZERO, Vec3::Y, 0.7)
            .unwrap()
            .orthographic(2.0)
            .unwrap();
        let aspect = 1.5;
        let (right, up) = camera.film_half_extents(aspect);
        assert!((right.length() - 3.0).abs() < 1e-6 && (up.length() - 2.0).abs() < 1e-6);
        let params = SppmParams {
            eye: camera.eye.to_array(),
            forward: camera.forward.to_array(),
            right: right.to_array(),
            up: up.to_array(),
            orthographic: 1,
            ..params(0.25, 4.0)
        };
        for (sx, sy, u) in [(0.0, 0.0, [0.5, 0.5]), (-0.7, 0.3, [0.1, 0.9])] {
            let (origin, direction) = camera_ray(&params, sx, sy, u);
            assert!(direction.abs_diff_eq(camera.forward, 1e-6));
            let film = camera.eye + sx * right + sy * up;
            assert!(origin.abs_diff_eq(film, 1e-6), "{origin} {film}");
            let (o2, d2) = camera_lens_ray(&camera, (sx, sy), aspect, u);
            assert!(o2.abs_diff_eq(origin, 1e-6) && d2.abs_diff_eq(direction, 1e-6));
        }
    }

    /// The path tracer's rays from a `scene::Camera` are the kernels' from its params.
    #[test]
    fn a_camera_and_its_params_make_the_same_rays() {
        let camera = scene::Camera::look_at(Vec3::ONE, Vec3::ZERO, Vec3::Y, 0.7)
            .unwrap()
            .with_lens(scene::Lens::new(0.1, 2.5).unwrap());
        let tan_half = (0.5 * camera.yfov).tan();
        let aspect = 1.5;
        let params = SppmParams {
            eye: camera.eye.to_array(),
            forward: camera.forward.to_array(),
            right: (camera.right() * tan_half * aspect).to_array(),
            up: (camera.up * tan_half).to_array(),
            lens_radius: camera.lens.radius,
            focus_distance: camera.lens.focus_distance,
            ..SppmParams::default()
        };
        for (sx, sy, u) in [
            (0.0, 0.0, [0.5, 0.5]),
            (-0.7, 0.3, [0.1, 0.9]),
            (1.0, -1.0, [0.8, 0.2]),
        ] {
            let (o1, d1) = camera_ray(&params, sx, sy, u);
            let (o2, d2) = camera_lens_ray(&camera, (sx, sy), aspect, u);
            assert!(
                o1.distance(o2) < 1e-6 && d1.distance(d2) < 1e-6,
                "{o1} {d1} / {o2} {d2}"
            );
        }
    }
}
