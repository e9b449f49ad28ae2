//! Build time of the photon kd-tree over one pass's worth of photons (2¹⁸), and its query rate
//! against brute force, on all cores: `cargo run --release -p render --example kdtree_build`.
//! The queries are checked against brute force before any rate is printed.

use std::time::Instant;

use glam::Vec3;
use rayon::prelude::*;
use render::buffers::Photon;
use render::kdtree::{PhotonKdTree, gather_brute_force};
use render::packing::surface_normal;

const PHOTONS: usize = 1 << 18;
const QUERIES: usize = 1 << 16;
const BRUTE_QUERIES: usize = 256;

/// A hashed stream of floats in [0, 1).
fn unit(i: u64) -> f32 {
    let mut z = i.wrapping_mul(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    ((z ^ (z >> 31)) >> 40) as f32 / (1u64 << 24) as f32
}

fn point(i: u64) -> Vec3 {
    Vec3::new(unit(3 * i), unit(3 * i + 1), unit(3 * i + 2))
}

/// Photons on the faces of a unit box (like a Cornell box's walls), a quarter of them packed
/// into a caustic-like spot on the floor.
fn photons() -> Vec<Photon> {
    (0..PHOTONS as u64)
        .map(|i| {
            let p = point(i);
            let (position, normal) = if i % 4 == 0 {
                (Vec3::new(0.4 + 0.2 * p.x, 0.0, 0.4 + 0.2 * p.y), Vec3::Y)
            } else {
                let face = (i % 3) as usize;
                let mut q = p;
                q[face] = if i % 2 == 0 { 0.0 } else { 1.0 };
                let mut n = Vec3::ZERO;
                n[face] = if i % 2 == 0 { 1.0 } else { -1.0 };
                (q, n)
            };
            Photon {
                position: position.to_array(),
                normal: surface_normal(normal),
                flux: [1e-5; 3],
                pad: 0,
            }
        })
        .collect()
}

fn main() {
    let photons = photons();
    let mut times = Vec::new();
    let mut tree = PhotonKdTree::default();
    for _ in 0..11 {
        let start = Instant::now();
        tree = PhotonKdTree::build(&photons);
        times.push(start.elapsed().as_secs_f64());
    }
    times.sort_by(f64::total_cmp);
    println!(
        "build: {} photons, depth {}, median {:.2} ms (min {:.2} ms) on {} threads",
        tree.len(),
        tree.depth(),
        times[times.len() / 2] * 1e3,
        times[0] * 1e3,
        rayon::current_num_threads()
    );
    // Queries on the photons' surfaces, radius 0.005 (about a pixel's footprint in a 512² Cornell box).
    let queries: Vec<(Vec3, Vec3)> = (0..QUERIES as u64)
        .map(|i| {
            let photon = &photons[(unit(7 * i + 1) * PHOTONS as f32) as usize % PHOTONS];
            let normal = render::packing::unpack_normal(photon.normal);
            (Vec3::from(photon.position), normal)
        })
        .collect();
    let radius = 0.005;
    for (position, normal) in &queries[..BRUTE_QUERIES] {
        let (found, _) = tree.query(*position, radius, *normal);
        let (want, _) = gather_brute_force(&photons, *position, radius, *normal);
        assert_eq!(found, want, "tree and brute force disagree at {position}");
    }
    let tree_rate = |queries: &[(Vec3, Vec3)]| {
        let start = Instant::now();
        let found: u64 = queries
            .par_iter()
            .map(|(p, n)| u64::from(tree.query(*p, radius, *n).0))
            .sum();
        (queries.len() as f64 / start.elapsed().as_secs_f64(), found)
    };
    let (random_rate, found) = tree_rate(&queries);
    // Pixels gather in image order, near one another: the same queries sorted along a grid.
    let mut coherent = queries.clone();
    let cell = |p: Vec3| (p * 64.0).floor().to_array().map(|c| c as i32);
    coherent.sort_by_key(|(p, _)| {
        let [x, y, z] = cell(*p);
        (z, y, x)
    });
    let (coherent_rate, _) = tree_rate(&coherent);
    let start = Instant::now();
    let brute: u64 = queries[..BRUTE_QUERIES]
        .par_iter()
        .map(|(p, n)| u64::from(gather_brute_force(&photons, *p, radius, *n).0))
        .sum();
    let brute_rate = BRUTE_QUERIES as f64 / start.elapsed().as_secs_f64();
    println!(
        "query r = {radius}: {:.1} photons found each; tree {:.3} Mqueries/s in random order, {:.3} in grid order; brute force {:.4} Mqueries/s ({:.1} found each): tree {:.0}x faster",
        found as f64 / QUERIES as f64,
        random_rate * 1e-6,
        coherent_rate * 1e-6,
        brute_rate * 1e-6,
        brute as f64 / BRUTE_QUERIES as f64,
        random_rate / brute_rate
    );
}
