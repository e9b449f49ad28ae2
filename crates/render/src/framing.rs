//! The view of a scene that brings no camera.
//!
//! ANCHORS.md's outside view of the bounding box suits closed models (a bunny, a statue) but
//! not a room open on one side, such as the Cornell box as OBJ files ship it: from outside it
//! shows the backs of the walls, unlit, and none of the room. So the outside view is kept
//! unless another view of its kind, from one of the box's other quadrants or straight at one
//! of its sides, sees clearly more surfaces from their front (the side their winding faces,
//! which modellers point at the viewer): probe rays through a coarse grid of each view count
//! the front faces they meet.

use bvh::{PackedBvh, Ray};
use glam::Vec3;
use scene::camera::OUTSIDE_VIEW_OFFSET;
use scene::{Bounds, Camera};

/// Probe rays per side of each candidate view's grid.
const PROBE_SIDE: u32 = 24;
/// The lower height of the views straight at a side, in diagonals above the centre.
const SIDE_VIEW_LOW: f32 = 0.1;
/// How much larger a share of front faces another view must see to replace the outside view.
const MARGIN: f32 = 0.1;

/// ANCHORS.md's outside view, or the candidate of its kind that sees the most front faces when
/// that share beats the outside view's by [`MARGIN`].
pub fn framed_view(bvh: &PackedBvh, bounds: Bounds) -> Camera {
    let default = Camera::outside_view(bounds);
    let default_share = front_share(bvh, &default);
    let (x, y, z) = (
        OUTSIDE_VIEW_OFFSET.x,
        OUTSIDE_VIEW_OFFSET.y,
        OUTSIDE_VIEW_OFFSET.z,
    );
    let quadrants = [
        Vec3::new(-x, y, z),
        Vec3::new(x, y, -z),
        Vec3::new(-x, y, -z),
    ];
    // Straight at each side, from the outside view's height and from nearly level (which
    // looks through an opening without looking down over its top edge).
    let sides = [y, SIDE_VIEW_LOW].into_iter().flat_map(|height| {
        let level = (1.0 - height * height).sqrt();
        [
            Vec3::new(0.0, height, level),
            Vec3::new(0.0, height, -level),
            Vec3::new(level, height, 0.0),
            Vec3::new(-level, height, 0.0),
        ]
    });
    let best = quadrants
        .into_iter()
        .chain(sides)
        .map(|offset| {
            let camera =
                Camera::outside_view_from(bounds, offset).named("auto (outside, open side)");
            (front_share(bvh, &camera), camera)
        })
        .max_by(|a, b| a.0.total_cmp(&b.0));
    match best {
        Some((share, camera)) if share > default_share + MARGIN => camera,
        _ => default,
    }
}

/// The share of a grid of `camera`'s rays (square image) that meet a triangle's front face.
pub fn front_share(bvh: &PackedBvh, camera: &Camera) -> f32 {
    let n = PROBE_SIDE;
    let mut fronts = 0;
    for j in 0..n {
        for i in 0..n {
            let sx = (i as f32 + 0.5) / n as f32 * 2.0 - 1.0;
            let sy = 1.0 - (j as f32 + 0.5) / n as f32 * 2.0;
            let (origin, direction) = camera.ray(sx, sy, 1.0);
            let ray = Ray {
                origin,
                direction,
                t_max: f32::INFINITY,
            };
            if let Some(hit) = bvh::closest_hit_mtbvh(bvh, &ray) {
                let triangle = bvh.triangles[hit.triangle as usize].unpack();
                if triangle.geometric_normal_unnormalized().dot(direction) < 0.0 {
                    fronts += 1;
                }
            }
        }
    }
    fronts as f32 / (n * n) as f32
}

#[cfg(test)]
mod tests {
    use super::*;

    fn packed(scene: &scene::Scene) -> PackedBvh {
        PackedBvh::build(&scene.triangles, &bvh::BuildOptions::default())
    }

    /// The Cornell box without its camera, as OBJ files ship it: its walls face inward and
    /// its open side is −z, so the view chosen looks into the room along +z and sees fronts,
    /// where the outside view sees mostly the walls' backs.
    #[test]
    fn a_room_open_on_one_side_is_seen_through_its_opening() {
        let mut room = scene::testing::cornell_box();
        room.cameras.clear();
        let bvh = packed(&room);
        let outside = Camera::outside_view(room.bounds());
        let chosen = framed_view(&bvh, room.bounds());
        let (outside_share, chosen_share) =
            (front_share(&bvh, &outside), front_share(&bvh, &chosen));
        assert!(
            chosen.forward.z > 0.8,
            "looks into the room: {:?}",
            chosen.forward
        );
        assert!(
            chosen_share > outside_share + MARGIN && chosen_share > 0.5,
            "fronts seen: chosen {chosen_share}, outside view {outside_share}"
        );
    }

    /// A closed model seen from every side alike keeps ANCHORS.md's outside view.
    #[test]
    fn a_closed_model_keeps_the_outside_view() {
        let sphere = scene::testing::furnace_sphere();
        let bvh = packed(&sphere);
        let chosen = framed_view(&bvh, sphere.bounds());
        assert_eq!(chosen, Camera::outside_view(sphere.bounds()));
    }
}
