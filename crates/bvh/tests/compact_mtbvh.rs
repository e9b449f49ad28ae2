//! The compact MTBVH (16-bit boxes rounded outward, 16-bit links) returns what the exact MTBVH
//! returns — the same triangle and the same `t` — on random soups and rays, and what brute force
//! returns on a sample. Its boxes contain the exact ones, so it tests every box the exact MTBVH
//! tests and more.
//!
//! The one allowed difference: a hit that rounding places outside its own triangle's box
//! ([`is_fragile_hit`]) may be culled by the exact boxes and reached through the larger ones.
//! The compact answer is then either that closer, fragile hit, or a farther one: a fragile hit
//! the larger boxes reached first can cull the box of the fragile hit the exact MTBVH found
//! (seen on a sliver triangle whose computed `t` lies 6e-4 before its box). Either way the
//! nearer of the two answers is fragile ([`nearer_is_fragile`]). Such cases are counted and
//! must be rare.

use bvh::testing::{is_fragile_hit, nearer_is_fragile, random_rays, random_soup};
use bvh::traverse::{Query, TraversalCounters, trace_mtbvh};
use bvh::{
    BuildOptions, CompactMtbvh, Hit, PackedBvh, Ray, any_hit_brute_force, any_hit_mtbvh,
    any_hit_mtbvh_compact, closest_hit_brute_force, trace_mtbvh_compact,
};
use proptest::prelude::*;

#[derive(Default, Debug)]
struct Tally {
    rays: usize,
    /// Rays where the compact answer differs from the exact one through a fragile hit.
    fragile: usize,
    exact_boxes: u64,
    compact_boxes: u64,
}

/// Compact against exact MTBVH on one ray; brute force too when `brute` (a sample).
fn check_ray(bvh: &PackedBvh, compact: &CompactMtbvh, ray: &Ray, brute: bool, tally: &mut Tally) {
    tally.rays += 1;
    let mut exact_work = TraversalCounters::default();
    let mut compact_work = TraversalCounters::default();
    let exact = trace_mtbvh(bvh, ray, Query::Closest, &mut exact_work);
    let got = trace_mtbvh_compact(bvh, compact, ray, Query::Closest, &mut compact_work);
    if bvh::testing::same_hit(bvh, got, exact) {
        // Box counts compare only where the answers agree: a fragile hit that the larger
        // boxes reach first culls boxes the exact traversal still tests.
        tally.exact_boxes += exact_work.boxes;
        tally.compact_boxes += compact_work.boxes;
    } else {
        // A compact miss visited a superset of the exact MTBVH's boxes: never allowed.
        assert!(got.is_some(), "compact misses, exact {exact:?}, {ray:?}");
        // Otherwise only rounding, through a hit the exact boxes cannot be relied on to reach.
        assert!(
            nearer_is_fragile(bvh, ray, got, exact),
            "compact {got:?}, exact {exact:?}, {ray:?}"
        );
        tally.fragile += 1;
    }
    let any_compact = any_hit_mtbvh_compact(bvh, compact, ray);
    let any_exact = any_hit_mtbvh(bvh, ray);
    assert!(
        any_compact == any_exact || (any_compact && got.is_some()),
        "any-hit: compact {any_compact}, exact {any_exact}, {ray:?}"
    );
    if brute {
        let want = closest_hit_brute_force(bvh, ray);
        match (got, want) {
            (None, None) => {}
            (Some(g), Some(w)) if g.t == w.t => {}
            (g, Some(w)) if is_fragile_hit(bvh, ray, &w) && g.is_none_or(|g| g.t > w.t) => {}
            _ => panic!("compact {got:?}, brute force {want:?}, {ray:?}"),
        }
        assert!(!any_compact || any_hit_brute_force(bvh, ray), "{ray:?}");
    }
}

fn check_soup(seed: u64, triangle_count: usize, ray_count: usize, brute_every: usize) -> Tally {
    let triangles = random_soup(seed, triangle_count);
    let rays = random_rays(seed ^ 0xc0de, ray_count, &triangles);
    let mut tally = Tally::default();
    for max_leaf_size in [1, 2, 4] {
        let options = BuildOptions {
            max_leaf_size,
            ..BuildOptions::default()
        };
        let bvh = PackedBvh::build(&triangles, &options);
        let compact = CompactMtbvh::new(&bvh).expect("compactable");
        for (i, ray) in rays.iter().enumerate() {
            check_ray(&bvh, &compact, ray, i % brute_every == 0, &mut tally);
        }
    }
    // Superset of boxes: never fewer tests than the exact boxes on the rays both answer alike.
    assert!(tally.compact_boxes >= tally.exact_boxes, "{tally:?}");
    tally
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn compact_matches_exact_mtbvh(seed in any::<u64>(), triangle_count in 1usize..400) {
        check_soup(seed, triangle_count, 64, 4);
    }
}

#[test]
fn compact_matches_exact_mtbvh_on_larger_soups() {
    // 40k triangles with leaf 1 make ~80k nodes: far links are exercised.
    for (seed, count, rays) in [(11, 3000, 4000), (12, 40_000, 3000)] {
        let tally = check_soup(seed, count, rays, 16);
        println!(
            "{count} triangles: {} rays, {} fragile, boxes compact/exact {:.4}",
            tally.rays,
            tally.fragile,
            tally.compact_boxes as f64 / tally.exact_boxes as f64
        );
        assert!(tally.fragile * 1000 <= tally.rays, "{tally:?}");
    }
}

#[test]
fn compact_hit_is_exactly_the_mtbvh_hit() {
    // Same triangle, t, u and v: one algorithm over the same triangles.
    let triangles = random_soup(21, 2000);
    let bvh = PackedBvh::build(&triangles, &BuildOptions::default());
    let compact = CompactMtbvh::new(&bvh).expect("compactable");
    let mut hits = 0;
    for ray in random_rays(22, 3000, &triangles) {
        let exact = trace_mtbvh(
            &bvh,
            &ray,
            Query::Closest,
            &mut TraversalCounters::default(),
        );
        let got: Option<Hit> = trace_mtbvh_compact(
            &bvh,
            &compact,
            &ray,
            Query::Closest,
            &mut TraversalCounters::default(),
        );
        if got.is_some() && got == exact {
            hits += 1;
        }
    }
    assert!(hits > 1000, "{hits} identical hits");
}
