//! Every traversal (stack, TBVH, MTBVH) × leaf sizes {1, 4} returns what brute force returns,
//! on random soups and rays: the same `t`, the same triangle or one hit at exactly that `t`.
//! The one exception is a brute-force hit that rounding puts outside its own triangle's box
//! ([`is_fragile_hit`]), which a box test may rightly cull; those are counted, and must stay
//! rare.

use bvh::intersect::intersect_triangle;
use bvh::testing::{is_fragile_hit, random_rays, random_soup};
use bvh::{
    BuildOptions, Hit, PackedBvh, Ray, any_hit_brute_force, any_hit_mtbvh, any_hit_stack,
    any_hit_tbvh, closest_hit_brute_force, closest_hit_mtbvh, closest_hit_stack, closest_hit_tbvh,
};
use proptest::prelude::*;

type ClosestHit = fn(&PackedBvh, &Ray) -> Option<Hit>;
type AnyHit = fn(&PackedBvh, &Ray) -> bool;

const CLOSEST: [(&str, ClosestHit); 3] = [
    ("stack", closest_hit_stack),
    ("tbvh", closest_hit_tbvh),
    ("mtbvh", closest_hit_mtbvh),
];
const ANY: [(&str, AnyHit); 3] = [
    ("stack", any_hit_stack),
    ("tbvh", any_hit_tbvh),
    ("mtbvh", any_hit_mtbvh),
];

/// Outcome of one comparison.
#[derive(Default)]
struct Tally {
    /// Comparisons made.
    checked: usize,
    /// Disagreements explained by a fragile brute-force hit.
    fragile: usize,
}

/// One variant's closest hit against brute force. The same `t` (a tie between triangles at
/// exactly the same `t` may go either way; `==` so that +0 and −0 agree), and for the same
/// triangle the same barycentrics. Any other answer is allowed only if brute force's hit is
/// fragile (outside its own triangle's box by rounding, see [`is_fragile_hit`]: then no box
/// test can be relied on to reach it), and then only a farther hit or none, since a
/// traversal tests a subset of the triangles.
fn check_closest(
    bvh: &PackedBvh,
    ray: &Ray,
    name: &str,
    got: Option<Hit>,
    want: Option<Hit>,
    tally: &mut Tally,
) {
    tally.checked += 1;
    match (got, want) {
        (None, None) => {}
        (Some(g), Some(w)) if g.t == w.t => {
            if bvh.triangle_ids[g.triangle as usize] == bvh.triangle_ids[w.triangle as usize] {
                assert_eq!(
                    (g.u, g.v),
                    (w.u, w.v),
                    "{name}: barycentrics differ for {ray:?}"
                );
            }
        }
        (g, Some(w)) if is_fragile_hit(bvh, ray, &w) && g.is_none_or(|g| g.t > w.t) => {
            tally.fragile += 1
        }
        _ => panic!("{name}: {got:?} but brute force says {want:?} for {ray:?}"),
    }
}

/// Any-hit against brute force: a miss where brute force hits is allowed only if every hit
/// brute force finds is fragile.
fn check_any(bvh: &PackedBvh, ray: &Ray, name: &str, got: bool, tally: &mut Tally) {
    tally.checked += 1;
    let hits: Vec<Hit> = (0..bvh.triangles.len() as u32)
        .filter_map(|triangle| {
            let (u, v, t) = intersect_triangle(
                &bvh.triangles[triangle as usize],
                ray.origin,
                ray.direction,
                ray.t_max,
            )?;
            Some(Hit { triangle, t, u, v })
        })
        .collect();
    assert_eq!(any_hit_brute_force(bvh, ray), !hits.is_empty());
    let want = !hits.is_empty();
    if got != want {
        assert!(
            !got && hits.iter().all(|h| is_fragile_hit(bvh, ray, h)),
            "{name} any-hit says {got} for {ray:?}"
        );
        tally.fragile += 1;
    }
}

fn check_all(seed: u64, triangle_count: usize, ray_count: usize) -> Tally {
    let triangles = random_soup(seed, triangle_count);
    let rays = random_rays(seed ^ 0x5eed, ray_count, &triangles);
    let mut tally = Tally::default();
    for (max_leaf_size, split_percent) in [(1, 0), (4, 0), (2, 30)] {
        let options = BuildOptions {
            max_leaf_size,
            split_percent,
            ..BuildOptions::default()
        };
        let bvh = PackedBvh::build(&triangles, &options);
        for ray in &rays {
            let want = closest_hit_brute_force(&bvh, ray);
            for (name, closest) in CLOSEST {
                check_closest(&bvh, ray, name, closest(&bvh, ray), want, &mut tally);
            }
            for (name, any) in ANY {
                check_any(&bvh, ray, name, any(&bvh, ray), &mut tally);
            }
        }
    }
    tally
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(96))]

    #[test]
    fn traversals_match_brute_force(seed in any::<u64>(), triangle_count in 1usize..300) {
        check_all(seed, triangle_count, 64);
    }
}

#[test]
fn traversals_match_brute_force_on_a_larger_soup() {
    let tally = check_all(42, 3000, 2000);
    // Fragile disagreements are rare even though many rays aim at edges and vertices; many
    // of them would hide a real bug.
    println!(
        "{} of {} comparisons disagree on fragile hits",
        tally.fragile, tally.checked
    );
    assert!(
        tally.fragile * 1000 <= tally.checked,
        "{} of {} fragile",
        tally.fragile,
        tally.checked
    );
}

#[test]
fn single_triangle_trees_work() {
    check_all(9, 1, 200);
}
