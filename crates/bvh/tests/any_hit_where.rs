//! Any-hit queries that count only some hits (`any_hit_cpu_where`, `any_hit_mtbvh_where`: shadow
//! rays through alpha cut-outs) answer what brute force answers: whether some triangle is hit
//! within the ray's reach at a point the filter calls occluding. The filter depends on the
//! triangle and on the barycentrics, so a traversal that passed the wrong lane's `u, v`, or let
//! a rejected hit shorten the ray, would disagree.

use bvh::intersect::intersect_triangle;
use bvh::testing::{is_fragile_hit, random_rays, random_soup};
use bvh::wide::WideMtbvh;
use bvh::{BuildOptions, Hit, PackedBvh, Ray, any_hit_cpu_where, any_hit_mtbvh_where};
use proptest::prelude::*;

/// Holes: a third of the triangles (by their first vertex, which split references share) are
/// open where u > 0.3; the rest are solid.
fn occludes(bvh: &PackedBvh, hit: &Hit) -> bool {
    let x = bvh.triangles[hit.triangle as usize].positions()[0].x;
    !(x * 1000.0).to_bits().is_multiple_of(3) || hit.u <= 0.3
}

/// The occluding hits brute force finds, nearest first.
fn brute_force(bvh: &PackedBvh, ray: &Ray) -> Vec<Hit> {
    let mut hits: Vec<Hit> = (0..bvh.triangles.len() as u32)
        .filter_map(|triangle| {
            let tri = &bvh.triangles[triangle as usize];
            intersect_triangle(tri, ray.origin, ray.direction, ray.t_max).map(|(u, v, t)| Hit {
                triangle,
                t,
                u,
                v,
            })
        })
        .filter(|hit| occludes(bvh, hit))
        .collect();
    hits.sort_by(|a, b| a.t.total_cmp(&b.t));
    hits
}

/// Rays where some traversal disagrees with brute force, and the rays where some hit at all
/// is rejected by the filter (so the test exercises it).
fn check_soup(seed: u64, triangle_count: usize, ray_count: usize) -> (usize, usize) {
    let triangles = random_soup(seed, triangle_count);
    let rays = random_rays(seed ^ 0xa1f, ray_count, &triangles);
    // A ray whose hits are all fragile may be culled by every traversal at every leaf size:
    // it counts once.
    let mut fragile_rays = vec![false; rays.len()];
    let mut filtered = 0;
    for max_leaf_size in [1, 2, 4] {
        let options = BuildOptions {
            max_leaf_size,
            ..BuildOptions::default()
        };
        let bvh = PackedBvh::build(&triangles, &options);
        let wide = WideMtbvh::new(&bvh).expect("small leaves");
        for (i, ray) in rays.iter().enumerate() {
            let want = brute_force(&bvh, ray);
            let any_at_all = (0..bvh.triangles.len()).any(|t| {
                intersect_triangle(&bvh.triangles[t], ray.origin, ray.direction, ray.t_max)
                    .is_some()
            });
            filtered += usize::from(any_at_all && want.is_empty());
            let occludes = |hit: &Hit| occludes(&bvh, hit);
            for (name, got) in [
                ("wide", any_hit_cpu_where(&bvh, Some(&wide), ray, occludes)),
                ("binary", any_hit_cpu_where(&bvh, None, ray, occludes)),
                ("mtbvh", any_hit_mtbvh_where(&bvh, ray, occludes)),
            ] {
                let blocked = !want.is_empty();
                if got != blocked {
                    // A traversal may cull a hit that rounding puts outside its own box.
                    assert!(
                        !got && want.iter().all(|h| is_fragile_hit(&bvh, ray, h)),
                        "{name}: {got}, brute force {want:?}, {ray:?}"
                    );
                    fragile_rays[i] = true;
                }
            }
        }
    }
    let fragile = fragile_rays.iter().filter(|&&f| f).count();
    (fragile, filtered)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    #[test]
    fn filtered_any_hit_matches_brute_force(seed in any::<u64>(), count in 1usize..300) {
        let (fragile, _) = check_soup(seed, count, 48);
        prop_assert!(fragile <= 1, "{fragile} fragile rays");
    }
}

#[test]
fn filtered_any_hit_matches_brute_force_on_a_larger_soup() {
    let rays = 3000;
    let (fragile, filtered) = check_soup(77, 4000, rays);
    // Rays that hit only holes: the filter must decide some of them for the test to mean much.
    assert!(filtered * 50 > rays, "{filtered} rays met only holes");
    assert!(fragile * 1000 <= rays * 9, "{fragile} fragile rays");
}
