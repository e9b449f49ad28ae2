//! The four-wide MTBVH (`bvh::wide`) returns what the binary MTBVH returns — the same `t`, and on
//! one input triangle the same barycentrics — on random soups and rays, for every leaf size, and
//! what brute force returns on a sample; any-hit queries agree too.
//!
//! Its boxes are the binary tree's, minus the levels it collapses, and it visits them in
//! another order, so where a hit lies outside its own triangle's box by rounding
//! ([`is_fragile_hit`]) one tree may reach it and the other rightly cull it: then the nearer
//! of the two answers is that fragile hit. Such cases are counted and must be rare.

use bvh::testing::{is_fragile_hit, nearer_is_fragile, random_rays, random_soup, same_hit};
use bvh::traverse::{Query, TraversalCounters, trace_mtbvh};
use bvh::wide::{WideMtbvh, any_hit_wide, trace_wide};
use bvh::{
    BuildOptions, PackedBvh, Ray, any_hit_brute_force, any_hit_mtbvh, closest_hit_brute_force,
};
use proptest::prelude::*;

#[derive(Default, Debug)]
struct Tally {
    rays: usize,
    hits: usize,
    /// Rays where the wide answer differs from the binary one through a fragile hit.
    fragile: usize,
    binary_boxes: u64,
    wide_boxes: u64,
}

/// Wide against binary MTBVH on one ray; brute force too when `brute` (a sample).
fn check_ray(bvh: &PackedBvh, wide: &WideMtbvh, ray: &Ray, brute: bool, tally: &mut Tally) {
    tally.rays += 1;
    let mut binary_work = TraversalCounters::default();
    let mut wide_work = TraversalCounters::default();
    let binary = trace_mtbvh(bvh, ray, Query::Closest, &mut binary_work);
    let got = trace_wide(wide, ray, Query::Closest, &mut wide_work);
    tally.binary_boxes += binary_work.boxes;
    tally.wide_boxes += wide_work.boxes;
    tally.hits += usize::from(got.is_some());
    if !same_hit(bvh, got, binary) {
        assert!(
            nearer_is_fragile(bvh, ray, got, binary),
            "wide {got:?}, binary {binary:?}, {ray:?}"
        );
        tally.fragile += 1;
    }
    let any_wide = any_hit_wide(wide, ray);
    let any_binary = any_hit_mtbvh(bvh, ray);
    assert!(
        any_wide == any_binary || (any_wide && got.is_some()),
        "any-hit: wide {any_wide}, binary {any_binary}, {ray:?}"
    );
    assert_eq!(any_wide, got.is_some(), "any-hit against closest, {ray:?}");
    if brute {
        let want = closest_hit_brute_force(bvh, ray);
        match (got, want) {
            (None, None) => {}
            (Some(g), Some(w)) if g.t == w.t => {}
            (g, Some(w)) if is_fragile_hit(bvh, ray, &w) && g.is_none_or(|g| g.t > w.t) => {}
            _ => panic!("wide {got:?}, brute force {want:?}, {ray:?}"),
        }
        assert!(!any_wide || any_hit_brute_force(bvh, ray), "{ray:?}");
    }
}

fn check_soup(seed: u64, triangle_count: usize, ray_count: usize, brute_every: usize) -> Tally {
    let triangles = random_soup(seed, triangle_count);
    let rays = random_rays(seed ^ 0x51de, ray_count, &triangles);
    let mut tally = Tally::default();
    for max_leaf_size in [1, 2, 4, 8] {
        let options = BuildOptions {
            max_leaf_size,
            ..BuildOptions::default()
        };
        let bvh = PackedBvh::build(&triangles, &options);
        let wide = WideMtbvh::new(&bvh).expect("leaves of at most 8 triangles");
        for (i, ray) in rays.iter().enumerate() {
            check_ray(&bvh, &wide, ray, i % brute_every == 0, &mut tally);
        }
    }
    tally
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn wide_matches_binary_mtbvh(seed in any::<u64>(), triangle_count in 1usize..400) {
        check_soup(seed, triangle_count, 64, 4);
    }
}

#[test]
fn wide_matches_binary_mtbvh_on_larger_soups() {
    for (seed, count, rays) in [(31, 3000, 4000), (32, 40_000, 3000)] {
        let tally = check_soup(seed, count, rays, 16);
        println!(
            "{count} triangles: {} rays, {} hits, {} fragile, boxes wide/binary {:.3}",
            tally.rays,
            tally.hits,
            tally.fragile,
            tally.wide_boxes as f64 / tally.binary_boxes as f64
        );
        assert!(
            tally.hits * 4 > tally.rays,
            "the rays must mostly hit: {tally:?}"
        );
        assert!(tally.fragile * 1000 <= tally.rays, "{tally:?}");
    }
}

#[test]
fn leaf_lanes_hold_the_binary_leaves_triangles() {
    let triangles = random_soup(41, 5000);
    for max_leaf_size in [1, 2, 4, 8] {
        let options = BuildOptions {
            max_leaf_size,
            ..BuildOptions::default()
        };
        let bvh = PackedBvh::build(&triangles, &options);
        let wide = WideMtbvh::new(&bvh).unwrap();
        // What the binary leaves reference (with split triangles, not every packed one).
        let mut binary = vec![0u32; bvh.triangles.len()];
        for leaf in bvh.nodes.iter().filter(|n| n.triangle_count > 0) {
            for t in leaf.first_or_right..leaf.first_or_right + leaf.triangle_count {
                binary[t as usize] += 1;
            }
        }
        let mut seen = vec![0u32; bvh.triangles.len()];
        for leaf in &wide.leaves {
            assert!((1..=4).contains(&leaf.count), "{leaf:?}");
            for lane in 0..leaf.count {
                seen[(leaf.first + lane) as usize] += 1;
            }
        }
        assert_eq!(seen, binary, "leaf size {max_leaf_size}");
        // Every node but the root has its parent, which points at it.
        for (index, node) in wide.nodes.iter().enumerate().skip(1) {
            let parent = &wide.nodes[node.parent as usize];
            let slots = (0..4).filter(|&s| parent.valid & (1 << s) != 0);
            let pointing = slots
                .filter(|&s| parent.count[s] == 0 && parent.child[s] == index as u32)
                .count();
            assert_eq!(pointing, 1, "node {index}");
        }
    }
}

#[test]
fn empty_tree_misses() {
    let wide = WideMtbvh::default();
    let ray = Ray {
        origin: glam::Vec3::ZERO,
        direction: glam::Vec3::X,
        t_max: f32::INFINITY,
    };
    assert!(
        trace_wide(
            &wide,
            &ray,
            Query::Closest,
            &mut TraversalCounters::default()
        )
        .is_none()
    );
    assert!(!any_hit_wide(&wide, &ray));
}

#[test]
fn wide_matches_binary_mtbvh_inside_the_caustics_box_on_anchors_rays() {
    use bvh::bench_rays::{BenchCamera, View, diffuse_ray};
    let scene = scene::testing::cornell_caustics();
    let bvh = PackedBvh::build(&scene.triangles, &BuildOptions::default());
    let wide = WideMtbvh::new(&bvh).unwrap();
    let bounds = scene.bounds();
    let diagonal = bounds.extent().length();
    let primary = BenchCamera::new(bounds, View::Inside, 96).primary_rays();
    let mut tally = Tally::default();
    let mut diffuse = Vec::new();
    for (i, ray) in primary.iter().enumerate() {
        check_ray(&bvh, &wide, ray, i % 8 == 0, &mut tally);
        if let Some(hit) = bvh::closest_hit_mtbvh(&bvh, ray) {
            let id = bvh.triangle_ids[hit.triangle as usize] as usize;
            let normal = scene.triangles[id].geometric_normal_unnormalized();
            diffuse.push(diffuse_ray(i as u32, ray, hit.t, normal, diagonal));
        }
    }
    for (i, ray) in diffuse.iter().enumerate() {
        check_ray(&bvh, &wide, ray, i % 8 == 0, &mut tally);
    }
    assert!(tally.hits * 2 > tally.rays, "{tally:?}");
    assert_eq!(tally.fragile, 0, "{tally:?}");
}

/// The words `traverse_wide.wgsl` reads: a header, eight words a node (six rows of planes, the
/// children, then counts, orders, valid mask and parent), ten a leaf (nine rows, then first
/// triangle and count), little-endian bytes within a word as on every GPU wgpu drives.
#[test]
fn gpu_words_are_a_header_then_nodes_then_leaves() {
    let bvh = PackedBvh::build(&random_soup(51, 500), &BuildOptions::default());
    let wide = WideMtbvh::new(&bvh).unwrap();
    let words = wide.gpu_words();
    let (nodes, leaves) = (wide.nodes.len(), wide.leaves.len());
    assert!(nodes > 2 && leaves > 2);
    assert_eq!(words[0], [1 + 8 * nodes as u32, nodes as u32, 0, 0]);
    assert_eq!(words.len(), 1 + 8 * nodes + 10 * leaves);
    for (index, node) in wide.nodes.iter().enumerate() {
        let at = |k: usize| words[1 + 8 * index + k];
        for (row, plane) in node.planes.iter().enumerate() {
            assert_eq!(at(row), plane.map(f32::to_bits));
        }
        assert_eq!(at(6), node.child);
        let [counts, low_orders, high, parent] = at(7);
        assert_eq!(counts, u32::from_le_bytes(node.count));
        for d in 0..4 {
            assert_eq!((low_orders >> (8 * d)) & 0xff, u32::from(node.order[d]));
        }
        assert_eq!(high & 0xff, u32::from(node.order[4]));
        assert_eq!((high >> 8) & 0xff, u32::from(node.order[5]));
        assert_eq!((high >> 16) & 0xf, u32::from(node.valid));
        assert_eq!(parent, node.parent);
    }
    for (index, leaf) in wide.leaves.iter().enumerate() {
        let at = |k: usize| words[1 + 8 * nodes + 10 * index + k];
        for (row, values) in leaf.rows.iter().enumerate() {
            assert_eq!(at(row), values.map(f32::to_bits));
        }
        assert_eq!(at(9)[..2], [leaf.first, leaf.count]);
    }
}
