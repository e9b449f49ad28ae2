//! Invariants of the SAH build.

use bvh::testing::{Rng, random_soup};
use bvh::{
    BuildOptions, Bvh, MAX_DEPTH, PackedBvh, build_sah, closest_hit_brute_force, closest_hit_mtbvh,
    closest_hit_stack,
};
use glam::Vec3;
use scene::{Bounds, Triangle};

fn contains(outer: &Bounds, inner: &Bounds) -> bool {
    outer.min.cmple(inner.min).all() && outer.max.cmpge(inner.max).all()
}

/// Every triangle in exactly one leaf (at least one where triangles are split), boxes nested,
/// leaves no bigger than allowed, depth capped.
fn check_invariants(triangles: &[Triangle], bvh: &Bvh, options: &BuildOptions) {
    let split = options.split_percent > 0;
    let mut seen = vec![0u32; triangles.len()];
    for &id in &bvh.triangle_order {
        seen[id as usize] += 1;
    }
    assert!(
        split || seen.iter().all(|&n| n == 1),
        "triangle_order is not a permutation"
    );
    let mut covered = vec![0u32; triangles.len()];
    for (index, node) in bvh.nodes.iter().enumerate() {
        if let Some((left, right)) = bvh.children(index as u32) {
            assert!(
                left as usize > index && right > left,
                "node {index} not in pre-order"
            );
            for child in [left, right] {
                assert!(
                    contains(&node.bounds, &bvh.nodes[child as usize].bounds),
                    "node {index}"
                );
            }
        } else {
            check_leaf(triangles, bvh, index, options, &mut covered);
        }
    }
    assert!(
        covered.iter().all(|&n| n == 1 || (split && n > 1)),
        "leaves do not cover the triangles once each"
    );
    assert!(bvh.depth() <= MAX_DEPTH);
    let leaves: usize = bvh.leaf_size_histogram().iter().sum();
    assert_eq!(leaves, bvh.leaf_count());
    assert_eq!(bvh.node_count(), 2 * leaves - 1);
}

/// A leaf's size is allowed and its box holds its triangles; counts them in `covered`.
fn check_leaf(
    triangles: &[Triangle],
    bvh: &Bvh,
    index: usize,
    options: &BuildOptions,
    covered: &mut [u32],
) {
    let node = &bvh.nodes[index];
    let size = node.triangle_count as usize;
    assert!(
        (1..=options.max_leaf_size).contains(&size),
        "leaf of {size}"
    );
    let range = node.first_or_right as usize..node.first_or_right as usize + size;
    let ids = &bvh.triangle_order[range];
    for (k, &id) in ids.iter().enumerate() {
        covered[id as usize] += 1;
        let bounds = triangles[id as usize].bounds();
        if options.split_percent == 0 {
            assert!(contains(&node.bounds, &bounds), "leaf {index}");
        } else {
            // A leaf holds a piece of a split triangle: its box overlaps the triangle's.
            let overlap =
                node.bounds.min.cmple(bounds.max).all() && bounds.min.cmple(node.bounds.max).all();
            assert!(overlap, "leaf {index}");
            assert!(
                !ids[..k].contains(&id),
                "leaf {index} holds triangle {id} twice"
            );
        }
    }
}

#[test]
fn random_soups_satisfy_the_invariants() {
    for (seed, count) in [(1, 1), (2, 2), (3, 5), (4, 100), (5, 5000), (6, 30_000)] {
        let triangles = random_soup(seed, count);
        for max_leaf_size in [1, 2, 4, 8] {
            for bins in [2, 8, 32] {
                for split_percent in [0, 30, 100] {
                    let options = BuildOptions {
                        max_leaf_size,
                        bins,
                        split_percent,
                        probe_split: false,
                    };
                    check_invariants(&triangles, &build_sah(&triangles, &options), &options);
                }
            }
        }
    }
}

fn tiny_triangle(center: Vec3) -> Triangle {
    let mut t = random_soup(0, 1)[0];
    let offsets = [
        Vec3::ZERO,
        Vec3::new(1e-3, 0.0, 0.0),
        Vec3::new(0.0, 1e-3, 0.0),
    ];
    for (v, o) in t.vertices.iter_mut().zip(offsets) {
        v.position = center + o;
    }
    t
}

#[test]
fn identical_triangles_split_by_count() {
    let triangles = vec![tiny_triangle(Vec3::ONE); 1000];
    for max_leaf_size in [1, 4] {
        let options = BuildOptions {
            max_leaf_size,
            ..Default::default()
        };
        let bvh = build_sah(&triangles, &options);
        check_invariants(&triangles, &bvh, &options);
        assert!(bvh.depth() <= 12, "depth {}", bvh.depth());
    }
}

#[test]
fn skewed_input_traverses_correctly() {
    // Centres growing geometrically make every SAH split peel off a few triangles.
    let triangles: Vec<Triangle> = (0..3000)
        .map(|k| tiny_triangle(Vec3::new(1.02f32.powi(k), 0.0, 0.0)))
        .collect();
    let options = BuildOptions::default();
    let bvh = build_sah(&triangles, &options);
    check_invariants(&triangles, &bvh, &options);
    let packed = PackedBvh::from_bvh(&triangles, &bvh);
    let mut rng = Rng::new(3);
    for _ in 0..500 {
        let x = 1.02f32.powf(rng.range(0.0, 3000.0));
        let ray = bvh::Ray {
            origin: Vec3::new(x, 2e-4, 1.0),
            direction: Vec3::new(rng.range(-1e-3, 1e-3), 0.0, -1.0),
            t_max: f32::INFINITY,
        };
        let want = closest_hit_brute_force(&packed, &ray).map(|h| h.t);
        assert_eq!(closest_hit_stack(&packed, &ray).map(|h| h.t), want);
        assert_eq!(closest_hit_mtbvh(&packed, &ray).map(|h| h.t), want);
    }
}

#[test]
fn statistics_of_a_small_tree() {
    let triangles = random_soup(8, 64);
    let options = BuildOptions {
        max_leaf_size: 1,
        split_percent: 0,
        ..BuildOptions::default()
    };
    let bvh = build_sah(&triangles, &options);
    assert_eq!(bvh.node_count(), 2 * 64 - 1);
    assert_eq!(bvh.leaf_size_histogram(), vec![0, 64]);
    // Every triangle's leaf is at most the root's area, and the root alone costs 1.
    let cost = bvh.sah_cost();
    assert!(cost > 1.0 && cost < 64.0 + 63.0, "{cost}");
    assert!(bvh.depth() >= 7);
}

fn unit_triangle(x: f32) -> Triangle {
    let mut t = random_soup(0, 1)[0];
    let corners = [
        Vec3::new(x, 0.0, 0.0),
        Vec3::new(x + 1.0, 0.0, 0.0),
        Vec3::new(x, 1.0, 0.0),
    ];
    for (v, p) in t.vertices.iter_mut().zip(corners) {
        v.position = p;
    }
    t
}

#[test]
fn sah_cost_by_hand() {
    // Two unit triangles 3 apart: boxes of area 2 under a root of area 8. Splitting
    // (8 + 2 + 2 = 12) beats a leaf of two (2 · 8 = 16): cost 1 + (2 + 2) / 8.
    let apart = [unit_triangle(0.0), unit_triangle(3.0)];
    for max_leaf_size in [1, 2] {
        let options = BuildOptions {
            max_leaf_size,
            ..Default::default()
        };
        let bvh = build_sah(&apart, &options);
        assert_eq!(bvh.node_count(), 3);
        assert_eq!(bvh.sah_cost(), 1.5);
    }
    // Two copies of one triangle: a leaf of two (2 · 2 = 4) beats splitting (2 + 2 + 2).
    let stacked = [unit_triangle(0.0), unit_triangle(0.0)];
    let bvh = build_sah(
        &stacked,
        &BuildOptions {
            max_leaf_size: 2,
            ..Default::default()
        },
    );
    assert_eq!(bvh.node_count(), 1);
    assert_eq!(bvh.sah_cost(), 2.0);
    assert_eq!(bvh.leaf_size_histogram(), vec![0, 0, 1]);
}

#[test]
fn empty_input_gives_an_empty_tree() {
    let bvh = build_sah(&[], &BuildOptions::default());
    assert_eq!(bvh.node_count(), 0);
    assert_eq!(bvh.depth(), 0);
    assert_eq!(bvh.sah_cost(), 0.0);
    let packed = PackedBvh::from_bvh(&[], &bvh);
    let ray = bvh::Ray {
        origin: Vec3::ZERO,
        direction: Vec3::X,
        t_max: 1.0,
    };
    assert!(closest_hit_stack(&packed, &ray).is_none());
    assert!(closest_hit_mtbvh(&packed, &ray).is_none());
}

/// With triangles split into pieces, every traversal still finds brute force's closest hit
/// (except where that hit is one rounding lets no box see: `is_fragile_hit`).
#[test]
fn split_triangles_keep_the_closest_hits() {
    for (seed, split_percent) in [(21, 30), (22, 100), (23, 300)] {
        let triangles = random_soup(seed, 2000);
        let options = BuildOptions {
            split_percent,
            ..BuildOptions::default()
        };
        let bvh = build_sah(&triangles, &options);
        check_invariants(&triangles, &bvh, &options);
        assert!(bvh.triangle_order.len() > triangles.len());
        let packed = PackedBvh::from_bvh(&triangles, &bvh);
        let mut fragile = 0;
        for ray in bvh::testing::random_rays(seed, 3000, &triangles) {
            let want = closest_hit_brute_force(&packed, &ray);
            if want.is_some_and(|h| bvh::testing::is_fragile_hit(&packed, &ray, &h)) {
                fragile += 1;
                continue;
            }
            let want = want.map(|h| h.t);
            assert_eq!(
                closest_hit_stack(&packed, &ray).map(|h| h.t),
                want,
                "{ray:?}"
            );
            assert_eq!(
                closest_hit_mtbvh(&packed, &ray).map(|h| h.t),
                want,
                "{ray:?}"
            );
        }
        // The soup holds degenerate and sliver triangles on purpose; most hits are not fragile.
        assert!(fragile < 3000 / 100, "{fragile} fragile hits");
    }
}
