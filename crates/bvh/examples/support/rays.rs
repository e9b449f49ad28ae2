//! The benchmark rays of ANCHORS.md ("Rays"), so CPU figures compare with Embree's.

use glam::Vec3;

use bvh::Ray;
use scene::Triangle;

/// Image side in pixels.
pub const SIDE: usize = 1024;

/// One primary ray per pixel of a 1024² image with a 50° vertical field of view, from the
/// outside camera or (sponzas) the inside one.
pub fn primary_rays(triangles: &[Triangle], inside: bool) -> Vec<Ray> {
    let (lo, hi) = triangles
        .iter()
        .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), t| {
            let b = t.bounds();
            (lo.min(b.min), hi.max(b.max))
        });
    let (center, diagonal) = ((lo + hi) / 2.0, (hi - lo).length());
    let (eye, look) = if inside {
        (
            lo + (hi - lo) * Vec3::new(0.85, 0.25, 0.5),
            lo + (hi - lo) * Vec3::new(0.0, 0.35, 0.5),
        )
    } else {
        (center + diagonal * Vec3::new(0.5, 0.35, 0.8), center)
    };
    let forward = (look - eye).normalize();
    let right = forward.cross(Vec3::Y).normalize();
    let up = right.cross(forward);
    let tan = 25f32.to_radians().tan();
    let side = SIDE as f32;
    (0..SIDE * SIDE)
        .map(|i| {
            let (x, y) = ((i % SIDE) as f32, (i / SIDE) as f32);
            let u = ((x + 0.5) / side * 2.0 - 1.0) * tan;
            let v = (1.0 - (y + 0.5) / side * 2.0) * tan;
            Ray {
                origin: eye,
                direction: (forward + u * right + v * up).normalize(),
                t_max: f32::INFINITY,
            }
        })
        .collect()
}

/// The scene's bounding-box diagonal, for the diffuse rays' offset.
pub fn diagonal(triangles: &[Triangle]) -> f32 {
    let b = triangles
        .iter()
        .fold(scene::Bounds::EMPTY, |b, t| b.union(t.bounds()));
    b.extent().length()
}

fn pcg(x: u32) -> u32 {
    let s = x.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
    let w = ((s >> ((s >> 28) + 4)) ^ s).wrapping_mul(277_803_737);
    (w >> 22) ^ w
}

/// The cosine-weighted diffuse ray leaving primary hit `i` at `point` on a triangle with
/// geometric normal `normal` (any length), as ANCHORS.md specifies.
pub fn diffuse_ray(i: u32, primary: &Ray, point: Vec3, normal: Vec3, diagonal: f32) -> Ray {
    let n = normal.normalize();
    let n = if n.dot(primary.direction) > 0.0 {
        -n
    } else {
        n
    };
    let u1 = pcg(2 * i) as f32 / 4_294_967_296.0;
    let u2 = pcg(2 * i + 1) as f32 / 4_294_967_296.0;
    let phi = 2.0 * std::f32::consts::PI * u2;
    let (x, y, z) = (
        u1.sqrt() * phi.cos(),
        u1.sqrt() * phi.sin(),
        (1.0 - u1).sqrt(),
    );
    let s = 1f32.copysign(n.z);
    let a = -1.0 / (s + n.z);
    let b = n.x * n.y * a;
    let t1 = Vec3::new(1.0 + s * n.x * n.x * a, s * b, -s * n.x);
    let t2 = Vec3::new(b, s + n.y * n.y * a, -n.y);
    Ray {
        origin: point + 1e-4 * diagonal * n,
        direction: x * t1 + y * t2 + z * n,
        t_max: f32::INFINITY,
    }
}
