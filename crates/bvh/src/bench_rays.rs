//! The benchmark rays of ANCHORS.md ("Rays"): the CPU twin of the GPU ray-generation kernels,
//! and the rays Embree's figures were measured on, so traversal figures compare.
//!
//! Primary rays: one per pixel of a square image from a camera placed by the scene's bounding
//! box ([`View`]). Diffuse rays: one cosine-distributed ray per primary hit, with random numbers
//! from a PCG hash of the pixel index (Aila & Laine's "diffuse" rays, made reproducible).

use glam::Vec3;
use scene::Bounds;

use crate::intersect::Ray;

/// Image side of the benchmark (1024² rays).
pub const DEFAULT_SIDE: u32 = 1024;

/// Vertical field of view of the benchmark camera, in degrees.
pub const FOV_DEGREES: f32 = 50.0;

/// Where the benchmark camera stands.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum View {
    /// Outside the bounding box, looking at its centre (bunny, Cornell box).
    Outside,
    /// Inside, near one end, looking along the long axis (the Sponzas).
    Inside,
}

/// A pinhole camera over a square image, in the orthonormal basis of ANCHORS.md.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BenchCamera {
    /// Where every primary ray starts.
    pub eye: Vec3,
    /// Unit view direction.
    pub forward: Vec3,
    /// Unit image-plane x axis.
    pub right: Vec3,
    /// Unit image-plane y axis.
    pub up: Vec3,
    /// tan(fov / 2).
    pub tan_half_fov: f32,
    /// Image side in pixels.
    pub side: u32,
}

impl BenchCamera {
    /// The camera of `view` for a scene with (non-empty) `bounds`.
    pub fn new(bounds: Bounds, view: View, side: u32) -> BenchCamera {
        let (lo, hi) = (bounds.min, bounds.max);
        let (eye, look) = match view {
            View::Outside => {
                let (center, diagonal) = ((lo + hi) / 2.0, (hi - lo).length());
                (center + diagonal * Vec3::new(0.5, 0.35, 0.8), center)
            }
            View::Inside => (
                lo + (hi - lo) * Vec3::new(0.85, 0.25, 0.5),
                lo + (hi - lo) * Vec3::new(0.0, 0.35, 0.5),
            ),
        };
        let forward = (look - eye).normalize();
        let right = forward.cross(Vec3::Y).normalize();
        let up = right.cross(forward);
        BenchCamera {
            eye,
            forward,
            right,
            up,
            tan_half_fov: (FOV_DEGREES / 2.0).to_radians().tan(),
            side,
        }
    }

    /// Number of primary rays (pixels).
    pub fn ray_count(&self) -> usize {
        self.side as usize * self.side as usize
    }

    /// The primary ray through the centre of pixel `index` (row-major, row 0 at the top).
    pub fn primary_ray(&self, index: u32) -> Ray {
        let (x, y) = ((index % self.side) as f32, (index / self.side) as f32);
        let side = self.side as f32;
        let u = ((x + 0.5) / side * 2.0 - 1.0) * self.tan_half_fov;
        let v = (1.0 - (y + 0.5) / side * 2.0) * self.tan_half_fov;
        Ray {
            origin: self.eye,
            direction: (self.forward + u * self.right + v * self.up).normalize(),
            t_max: f32::INFINITY,
        }
    }

    /// Every primary ray in pixel order.
    pub fn primary_rays(&self) -> Vec<Ray> {
        (0..self.ray_count() as u32)
            .map(|i| self.primary_ray(i))
            .collect()
    }
}

/// The PCG hash of ANCHORS.md (Jarzynski & Olano 2020's `pcg`), wrapping u32 arithmetic.
pub fn pcg_hash(x: u32) -> u32 {
    let state = x.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
    let word = ((state >> ((state >> 28) + 4)) ^ state).wrapping_mul(277_803_737);
    (word >> 22) ^ word
}

/// `2⁻³²`: maps a u32 to [0, 1).
const U32_TO_UNIT: f32 = 1.0 / 4_294_967_296.0;

/// The cosine-weighted diffuse ray leaving the hit of primary ray `index` at distance `t`, on a
/// triangle with geometric normal `normal` (any length, either side). `diagonal` is the scene's
/// bounding-box diagonal; the origin is offset by `1e-4 · diagonal` along the normal.
pub fn diffuse_ray(index: u32, primary: &Ray, t: f32, normal: Vec3, diagonal: f32) -> Ray {
    let n = normal.normalize();
    let n = if n.dot(primary.direction) > 0.0 {
        -n
    } else {
        n
    };
    let u1 = pcg_hash(2 * index) as f32 * U32_TO_UNIT;
    let u2 = pcg_hash(2 * index + 1) as f32 * U32_TO_UNIT;
    let phi = 2.0 * std::f32::consts::PI * u2;
    let r = u1.sqrt();
    let (x, y, z) = (r * phi.cos(), r * phi.sin(), (1.0 - u1).sqrt());
    // Duff et al. 2017's branchless orthonormal basis around n.
    let s = 1f32.copysign(n.z);
    let a = -1.0 / (s + n.z);
    let b = n.x * n.y * a;
    let t1 = Vec3::new(1.0 + s * n.x * n.x * a, s * b, -s * n.x);
    let t2 = Vec3::new(b, s + n.y * n.y * a, -n.y);
    let point = primary.origin + t * primary.direction;
    Ray {
        origin: point + 1e-4 * diagonal * n,
        direction: x * t1 + y * t2 + z * n,
        t_max: f32::INFINITY,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit_bounds() -> Bounds {
        Bounds {
            min: Vec3::ZERO,
            max: Vec3::ONE,
        }
    }

    #[test]
    fn pcg_hash_matches_reference_values() {
        // From the definition, by hand: s = 2891336453; s >> 28 = 10; ...
        let s: u32 = 2_891_336_453;
        let w = ((s >> ((s >> 28) + 4)) ^ s).wrapping_mul(277_803_737);
        assert_eq!(pcg_hash(0), (w >> 22) ^ w);
        assert_ne!(pcg_hash(1), pcg_hash(2));
    }

    #[test]
    fn outside_camera_looks_at_the_centre_through_the_middle_pixels() {
        let camera = BenchCamera::new(unit_bounds(), View::Outside, 2);
        // The four centre-adjacent pixels are symmetric about the view direction.
        let sum: Vec3 = camera.primary_rays().iter().map(|r| r.direction).sum();
        assert!(sum.normalize().dot(camera.forward) > 0.999_999, "{sum}");
        let to_centre = (Vec3::splat(0.5) - camera.eye).normalize();
        assert!(to_centre.dot(camera.forward) > 0.999_999);
        assert!(camera.right.dot(camera.up).abs() < 1e-6);
        assert!(camera.up.y > 0.0, "row 0 is the top: up points up");
    }

    #[test]
    fn primary_rays_span_the_field_of_view() {
        let camera = BenchCamera::new(unit_bounds(), View::Inside, 64);
        let top = camera.primary_ray(32);
        let bottom = camera.primary_ray(63 * 64 + 32);
        let angle = top.direction.angle_between(bottom.direction).to_degrees();
        assert!((angle - FOV_DEGREES).abs() < 1.0, "{angle}");
        assert!(top.direction.dot(camera.up) > 0.0);
    }

    #[test]
    fn diffuse_rays_leave_the_surface_on_the_side_of_the_incoming_ray() {
        let primary = Ray {
            origin: Vec3::new(0.0, 1.0, 0.0),
            direction: Vec3::NEG_Y,
            t_max: f32::INFINITY,
        };
        for index in 0..1000 {
            // The normal's given sign must not matter.
            for normal in [Vec3::Y, Vec3::NEG_Y * 3.0] {
                let ray = diffuse_ray(index, &primary, 1.0, normal, 10.0);
                assert!(ray.direction.y > 0.0, "{index}: {}", ray.direction);
                assert!((ray.direction.length() - 1.0).abs() < 1e-5);
                assert!((ray.origin - Vec3::new(0.0, 1e-3, 0.0)).length() < 1e-6);
            }
        }
    }

    #[test]
    fn diffuse_directions_are_cosine_distributed() {
        // E[cos θ] = 2/3 for a cosine-weighted hemisphere.
        let primary = Ray {
            origin: Vec3::new(0.3, 0.2, 1.0),
            direction: Vec3::NEG_Z,
            t_max: f32::INFINITY,
        };
        let n = 100_000;
        let mean: f32 = (0..n)
            .map(|i| diffuse_ray(i, &primary, 1.0, Vec3::Z, 1.0).direction.z)
            .sum::<f32>()
            / n as f32;
        assert!((mean - 2.0 / 3.0).abs() < 0.005, "{mean}");
    }
}
