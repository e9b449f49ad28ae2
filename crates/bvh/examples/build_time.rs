//! Times the SAH build: `cargo run --release -p bvh --example build_time -- [SCENE.obj]
//! [--leaf N] [--bins N] [--runs N]`. Without a file it builds a 1M-triangle random soup.
//! Prints the median and fastest build, the threading and packing times, and the tree's
//! statistics, after checking that the tree holds every triangle once.

#[path = "support/obj.rs"]
mod obj;

use std::path::Path;
use std::time::Instant;

use bvh::mtbvh::thread_all;
use bvh::testing::random_soup;
use bvh::{BuildOptions, Bvh, PackedBvh, build_sah};
use scene::Triangle;

fn main() -> Result<(), String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let flag = |name: &str| -> Option<usize> {
        let at = args.iter().position(|a| a == name)?;
        args.get(at + 1)?.parse().ok()
    };
    let defaults = BuildOptions::default();
    let options = BuildOptions {
        max_leaf_size: flag("--leaf").unwrap_or(defaults.max_leaf_size),
        bins: flag("--bins").unwrap_or(defaults.bins),
        // Without split triangles unless asked: the build time compared with Embree in
        // BENCHMARKS §1.
        split_percent: flag("--split").map_or(0, |p| p as u32),
        probe_split: false,
    };
    let runs = flag("--runs").unwrap_or(7).max(1);
    let triangles = match args.first().filter(|a| !a.starts_with("--")) {
        Some(path) => obj::read_triangles(Path::new(path))?,
        None => random_soup(1, 1_000_000),
    };
    let threads = rayon::current_num_threads();
    println!(
        "{} triangles, {options:?}, {threads} threads",
        triangles.len()
    );
    let bvh = time_runs(&triangles, &options, runs);
    check(&bvh, triangles.len(), options.split_percent > 0)?;
    report(&triangles, &bvh);
    Ok(())
}

/// Builds `runs` times after a warm-up, printing median and fastest times; returns the tree.
fn time_runs(triangles: &[Triangle], options: &BuildOptions, runs: usize) -> Bvh {
    let ms = |start: Instant| start.elapsed().as_secs_f64() * 1e3;
    let (mut build, mut thread, mut pack) = (Vec::new(), Vec::new(), Vec::new());
    let mut bvh = build_sah(triangles, options);
    for _ in 0..runs {
        let start = Instant::now();
        bvh = build_sah(triangles, options);
        build.push(ms(start));
        let start = Instant::now();
        std::hint::black_box(thread_all(&bvh));
        thread.push(ms(start));
        let start = Instant::now();
        std::hint::black_box(PackedBvh::from_bvh(triangles, &bvh));
        pack.push(ms(start));
    }
    for v in [&mut build, &mut thread, &mut pack] {
        v.sort_by(f64::total_cmp);
    }
    let median = |v: &[f64]| v[v.len() / 2];
    println!(
        "build ms: median {:.1}, min {:.1} ({runs} runs)",
        median(&build),
        build[0]
    );
    println!(
        "threading (7 orders) ms: median {:.1}; threading + packing ms: median {:.1}",
        median(&thread),
        median(&pack)
    );
    bvh
}

/// Every triangle in a leaf (in several only if triangles were split).
fn check(bvh: &Bvh, count: usize, split: bool) -> Result<(), String> {
    let mut seen = vec![false; count];
    for node in bvh.nodes.iter().filter(|n| n.is_leaf()) {
        let first = node.first_or_right as usize;
        for &id in &bvh.triangle_order[first..first + node.triangle_count as usize] {
            if std::mem::replace(&mut seen[id as usize], true) && !split {
                return Err(format!("triangle {id} is in two leaves"));
            }
        }
    }
    match seen.iter().position(|s| !s) {
        Some(id) => Err(format!("triangle {id} is in no leaf")),
        None => Ok(()),
    }
}

fn report(triangles: &[Triangle], bvh: &Bvh) {
    println!(
        "SAH cost {:.2}, nodes {}, depth {}, leaves by size {:?}",
        bvh.sah_cost(),
        bvh.node_count(),
        bvh.depth(),
        bvh.leaf_size_histogram()
    );
    let memory = PackedBvh::from_bvh(triangles, bvh).memory();
    let mib = |bytes: usize| bytes as f64 / (1 << 20) as f64;
    let per_triangle = |bytes: usize| bytes as f64 / 4.0 / triangles.len() as f64;
    println!(
        "memory: TBVH {:.1} MiB ({:.1} floats/triangle), MTBVH {:.1} MiB ({:.1} floats/triangle)",
        mib(memory.tbvh_bytes),
        per_triangle(memory.tbvh_bytes),
        mib(memory.mtbvh_bytes),
        per_triangle(memory.mtbvh_bytes),
    );
}
