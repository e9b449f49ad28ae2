//! Traversal speed against leaf size: `cargo run --release -p bvh --example leaf_size --
//! SCENE.obj [--inside] [--leaves 1,2,4,8]`. For each leaf size it builds the tree, checks
//! that the stack, TBVH and MTBVH traversals agree on every ray (and with brute force on a
//! sample), then reports Mrays/s and boxes/triangles tested per ray for ANCHORS.md's primary
//! and diffuse rays.

#[path = "support/obj.rs"]
mod obj;

use std::path::Path;
use std::time::Instant;

use bvh::bench_rays::{self, BenchCamera, View};
use bvh::testing::is_fragile_hit;
use bvh::traverse::{Query, TraversalCounters, trace_mtbvh, trace_stack, trace_tbvh};
use bvh::{
    BuildOptions, BvhNode, Hit, Links, PackedBvh, PackedTriangle, Ray, closest_hit_brute_force,
};
use rayon::prelude::*;
use scene::Triangle;

type Trace = fn(&PackedBvh, &Ray, Query, &mut TraversalCounters) -> Option<Hit>;
const VARIANTS: [(&str, Trace); 3] = [
    ("stack", trace_stack),
    ("tbvh", trace_tbvh),
    ("mtbvh", trace_mtbvh),
];

fn main() -> Result<(), String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let path = args
        .first()
        .ok_or("usage: leaf_size SCENE.obj [--inside] [--leaves 1,2,4,8]")?;
    let inside = args.iter().any(|a| a == "--inside");
    let leaves: Vec<usize> = match args.iter().position(|a| a == "--leaves") {
        Some(at) => args[at + 1]
            .split(',')
            .filter_map(|s| s.parse().ok())
            .collect(),
        None => vec![1, 2, 4, 8],
    };
    let triangles = obj::read_triangles(Path::new(path))?;
    let view = if inside { View::Inside } else { View::Outside };
    let primary =
        BenchCamera::new(bounds(&triangles), view, bench_rays::DEFAULT_SIDE).primary_rays();
    println!(
        "{path}: {} triangles, {} threads",
        triangles.len(),
        rayon::current_num_threads()
    );
    println!("bytes/ray: what a GPU reads: node + links per box, 3 positions per triangle test");
    for max_leaf_size in leaves {
        run_leaf_size(&triangles, &primary, max_leaf_size)?;
    }
    Ok(())
}

/// Builds with leaf size `max_leaf_size`, validates, and prints one row per variant.
fn run_leaf_size(
    triangles: &[Triangle],
    primary: &[Ray],
    max_leaf_size: usize,
) -> Result<(), String> {
    let options = BuildOptions {
        max_leaf_size,
        ..BuildOptions::default()
    };
    let tree = bvh::build_sah(triangles, &options);
    let bvh = PackedBvh::from_bvh(triangles, &tree);
    let hits = validate(&bvh, primary)?;
    let diffuse = diffuse_rays(&bvh, triangles, primary, &hits);
    validate(&bvh, &diffuse)?;
    let cost = tree.sah_cost();
    println!(
        "leaf {max_leaf_size}: {} nodes, leaves by size {:?}, MTBVH {:.1} MiB",
        tree.node_count(),
        tree.leaf_size_histogram(),
        bvh.memory().mtbvh_bytes as f64 / (1 << 20) as f64
    );
    println!(
        "leaf | SAH cost | variant | primary Mrays/s | boxes/ray | tris/ray | bytes/ray | diffuse Mrays/s | boxes/ray | tris/ray | bytes/ray"
    );
    let per = |c: u64, n: usize| c as f64 / n as f64;
    let box_bytes = (size_of::<BvhNode>() + size_of::<Links>()) as u64;
    // The test reads only the (position, u) row of each vertex, half of a PackedVertex.
    let triangle_bytes = (size_of::<PackedTriangle>() / 2) as u64;
    let bytes =
        |c: TraversalCounters, n: usize| per(box_bytes * c.boxes + triangle_bytes * c.triangles, n);
    for (name, trace) in VARIANTS {
        let (p_rate, p_counts) = measure(&bvh, primary, trace);
        let (d_rate, d_counts) = measure(&bvh, &diffuse, trace);
        println!(
            "{max_leaf_size:4} | {cost:8.2} | {name:7} | {p_rate:15.2} | {:9.2} | {:8.2} | {:9.0} | {d_rate:15.2} | {:9.2} | {:8.2} | {:9.0}",
            per(p_counts.boxes, primary.len()),
            per(p_counts.triangles, primary.len()),
            bytes(p_counts, primary.len()),
            per(d_counts.boxes, diffuse.len()),
            per(d_counts.triangles, diffuse.len()),
            bytes(d_counts, diffuse.len()),
        );
    }
    Ok(())
}

/// Whether two answers for `ray` agree: the same distance, or else the nearer one is a hit
/// the triangle test cannot decide reliably (see [`is_fragile_hit`]), which the other
/// traversal may rightly cull.
fn agree(bvh: &PackedBvh, ray: &Ray, a: Option<Hit>, b: Option<Hit>) -> bool {
    let t = |h: Option<Hit>| h.map_or(f32::INFINITY, |h| h.t);
    let nearer = if t(a) < t(b) { a } else { b };
    t(a) == t(b) || nearer.is_some_and(|h| is_fragile_hit(bvh, ray, &h))
}

/// Checks that all variants agree on every ray and with brute force on a sample, up to fragile
/// hits (whose count it prints); returns the stack traversal's hits.
fn validate(bvh: &PackedBvh, rays: &[Ray]) -> Result<Vec<Option<Hit>>, String> {
    let closest = |trace: Trace, ray: &Ray| {
        trace(bvh, ray, Query::Closest, &mut TraversalCounters::default())
    };
    let hits: Vec<Option<Hit>> = rays.par_iter().map(|r| closest(trace_stack, r)).collect();
    let mut fragile = Vec::new();
    for (name, trace) in VARIANTS {
        let differ =
            |(r, h): &(&Ray, &Option<Hit>)| closest(trace, r).map(|x| x.t) != h.map(|x| x.t);
        let pairs: Vec<_> = rays.iter().zip(&hits).collect();
        let different: Vec<_> = pairs.par_iter().filter(|p| differ(p)).collect();
        if let Some((r, _)) = different
            .iter()
            .find(|(r, h)| !agree(bvh, r, closest(trace, r), **h))
        {
            return Err(format!(
                "{name} disagrees with the stack traversal on {r:?}"
            ));
        }
        fragile.push(format!("{name} {}", different.len()));
    }
    let step = (rays.len() / 500).max(1);
    let sample: Vec<(&Ray, &Option<Hit>)> = rays.iter().zip(&hits).step_by(step).collect();
    if let Some((r, _)) = sample
        .par_iter()
        .find_any(|(r, h)| !agree(bvh, r, closest_hit_brute_force(bvh, r), **h))
    {
        return Err(format!("brute force disagrees on {r:?}"));
    }
    println!(
        "validated {} rays; fragile differences from the stack traversal: {}",
        rays.len(),
        fragile.join(", ")
    );
    Ok(hits)
}

fn diffuse_rays(
    bvh: &PackedBvh,
    triangles: &[Triangle],
    primary: &[Ray],
    hits: &[Option<Hit>],
) -> Vec<Ray> {
    let diagonal = bounds(triangles).extent().length();
    primary
        .iter()
        .zip(hits)
        .enumerate()
        .filter_map(|(i, (ray, hit))| {
            let hit = (*hit)?;
            let id = bvh.triangle_ids[hit.triangle as usize] as usize;
            let normal = triangles[id].geometric_normal_unnormalized();
            Some(bench_rays::diffuse_ray(
                i as u32, ray, hit.t, normal, diagonal,
            ))
        })
        .collect()
}

fn bounds(triangles: &[Triangle]) -> scene::Bounds {
    triangles
        .iter()
        .fold(scene::Bounds::EMPTY, |b, t| b.union(t.bounds()))
}

/// Median Mrays/s over 3 runs on all threads, and the work done per run.
fn measure(bvh: &PackedBvh, rays: &[Ray], trace: Trace) -> (f64, TraversalCounters) {
    let mut rates = Vec::new();
    let mut counts = TraversalCounters::default();
    for _ in 0..3 {
        let start = Instant::now();
        counts = rays
            .par_chunks(4096)
            .map(|chunk| {
                let mut c = TraversalCounters::default();
                for ray in chunk {
                    std::hint::black_box(trace(bvh, ray, Query::Closest, &mut c));
                }
                c
            })
            .reduce(TraversalCounters::default, |a, b| a + b);
        rates.push(rays.len() as f64 / start.elapsed().as_secs_f64() / 1e6);
    }
    rates.sort_by(f64::total_cmp);
    (rates[1], counts)
}
