#[path = "support/obj.rs"]
mod obj;
use bvh::*;
use glam::Vec3;
fn main() {
    let triangles = obj::read_triangles(std::path::Path::new(
        "/work/shared/scenes/crytek-sponza/sponza.obj",
    ))
    .unwrap();
    let bvh = PackedBvh::build(
        &triangles,
        &BuildOptions {
            max_leaf_size: 1,
            bins: 32,
        },
    );
    let ray = Ray {
        origin: Vec3::new(1240.9375, 262.38287, -38.75),
        direction: Vec3::new(-0.96994686, -0.065417826, 0.23435773),
        t_max: f32::INFINITY,
    };
    for (n, h) in [
        ("stack", closest_hit_stack(&bvh, &ray)),
        ("tbvh", closest_hit_tbvh(&bvh, &ray)),
        ("mtbvh", closest_hit_mtbvh(&bvh, &ray)),
        ("brute", closest_hit_brute_force(&bvh, &ray)),
    ] {
        println!("{n}: {h:?}");
        if let Some(h) = h {
            println!(
                "   tri {:?} fragile {}",
                bvh.triangles[h.triangle as usize].positions(),
                bvh::testing::is_fragile_hit(&bvh, &ray, &h)
            );
            let p = ray.origin + h.t * ray.direction;
            println!("   p {p:?}");
            // find leaf
            let leaf = bvh
                .nodes
                .iter()
                .position(|n| {
                    n.triangle_count > 0
                        && n.first_or_right <= h.triangle
                        && h.triangle < n.first_or_right + n.triangle_count
                })
                .unwrap();
            let node = bvh.nodes[leaf];
            println!(
                "   leaf {leaf} box {:?} {:?} entry {}",
                node.min,
                node.max,
                bvh::intersect::intersect_box(
                    &node,
                    ray.origin,
                    ray.direction.recip(),
                    f32::INFINITY
                )
            );
        }
    }
}
