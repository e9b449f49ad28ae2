//! Choosing between two trees by tracing a sample of rays through both.
//!
//! Whether spatial splits ([`crate::sbvh`]) pay depends on the scene: on the Sponzas they cut
//! the boxes a ray tests by a sixth to a quarter, on a scanned model or a box of a
//! few walls it only deepens the tree. The SAH cost is no reliable guide (with the triangle
//! pre-splitting used before session 10 it rose on Crytek Sponza while traversal got cheaper), so the build traces the same probe rays through
//! both trees with the MTBVH and keeps the one that tested less. The work is counted, not
//! timed, so the choice is the same on every machine and run.
//!
//! Probe rays leave random points of the scene's surfaces (uniform by area) in random
//! directions: the secondary rays that photon and eye paths trace most.

use rayon::prelude::*;
use scene::Triangle;

use crate::build_sah::{BuildOptions, build_sah};
use crate::intersect::Ray;
use crate::pack::PackedBvh;
use crate::testing::Rng;
use crate::traverse::{Query, TraversalCounters, trace_mtbvh};
use crate::tree::Bvh;

/// Rays per probe: enough that the counts settle to a percent, few enough to cost
/// milliseconds.
pub const PROBE_RAYS: usize = 8192;
/// What a triangle test costs against a box test, roughly (a box test is six multiplies and
/// a few min/max; the triangle test two cross products, four dots and three divisions).
const TRIANGLE_COST: f64 = 3.0;

/// The tree over `triangles` for `options`, with its packing: where splitting is asked for
/// with [`BuildOptions::probe_split`], the split tree only if the probe rays test less in it
/// than in the tree without splits. Each candidate is packed once, for the probe and for
/// the caller.
pub fn build_chosen(triangles: &[Triangle], options: &BuildOptions) -> (Bvh, PackedBvh) {
    let pack = |tree: Bvh| {
        let packed = PackedBvh::from_bvh(triangles, &tree);
        (tree, packed)
    };
    let split = pack(build_sah(triangles, options));
    if options.split_percent == 0 || !options.probe_split {
        return split;
    }
    let unsplit_options = BuildOptions {
        split_percent: 0,
        ..*options
    };
    let unsplit = pack(build_sah(triangles, &unsplit_options));
    let rays = probe_rays(triangles);
    if probe_cost(&split.1, &rays) < probe_cost(&unsplit.1, &rays) {
        split
    } else {
        unsplit
    }
}

/// The probe rays over `triangles`, the same for every tree built over them: origins uniform
/// over the scene's surface area (as the bounces of photon and eye paths are spread, roughly),
/// directions uniform over the sphere.
pub fn probe_rays(triangles: &[Triangle]) -> Vec<Ray> {
    let mut total = 0.0f64;
    let cumulative: Vec<f64> = triangles
        .iter()
        .map(|t| {
            total += f64::from(t.area());
            total
        })
        .collect();
    if triangles.is_empty() || total <= 0.0 {
        return Vec::new();
    }
    let mut rng = Rng::new(0x9e0b_e5ee_d5a1_7e57);
    (0..PROBE_RAYS)
        .map(|_| {
            let target = f64::from(rng.unit()) * total;
            let index = cumulative
                .partition_point(|&c| c <= target)
                .min(triangles.len() - 1);
            let [a, b, c] = triangles[index].positions();
            let (mut u, mut v) = (rng.unit(), rng.unit());
            if u + v > 1.0 {
                (u, v) = (1.0 - u, 1.0 - v);
            }
            let direction = rng.direction();
            let origin = a + u * (b - a) + v * (c - a);
            // Start a little off the surface so the ray does not find its own triangle.
            let offset = 1e-4 * (b - a).length().max((c - a).length());
            Ray {
                origin: origin + offset * direction,
                direction,
                t_max: f32::INFINITY,
            }
        })
        .collect()
}

/// The traversal work of `rays` through `bvh` (closest hits, MTBVH), in box tests.
pub fn probe_cost(bvh: &PackedBvh, rays: &[Ray]) -> f64 {
    let work = rays
        .par_chunks(256)
        .map(|chunk| {
            let mut counters = TraversalCounters::default();
            for ray in chunk {
                trace_mtbvh(bvh, ray, Query::Closest, &mut counters);
            }
            counters
        })
        .reduce(TraversalCounters::default, |a, b| a + b);
    work.boxes as f64 + TRIANGLE_COST * work.triangles as f64
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn probe_rays_are_fixed_and_start_near_the_triangles() {
        let triangles = crate::testing::random_soup(2, 300);
        let rays = probe_rays(&triangles);
        assert_eq!(rays, probe_rays(&triangles));
        assert_eq!(rays.len(), PROBE_RAYS);
        let bvh = PackedBvh::build(&triangles, &BuildOptions::default());
        let cost = probe_cost(&bvh, &rays);
        // Every ray tests at least the root; a tree that tested every box would cost far more.
        assert!(cost >= PROBE_RAYS as f64 && cost < (PROBE_RAYS * bvh.nodes.len()) as f64);
        assert!(probe_rays(&[]).is_empty());
    }

    /// The tree kept is the one the probe finds cheaper; with probing off, the split one.
    #[test]
    fn build_keeps_the_cheaper_tree() {
        for seed in 1..6 {
            let triangles = crate::testing::random_soup(seed, 400);
            let rays = probe_rays(&triangles);
            let options = BuildOptions::default();
            let forced = |percent| {
                let tree = build_sah(
                    &triangles,
                    &BuildOptions {
                        split_percent: percent,
                        ..options
                    },
                );
                probe_cost(&PackedBvh::from_bvh(&triangles, &tree), &rays)
            };
            let chosen = probe_cost(&PackedBvh::build(&triangles, &options), &rays);
            assert_eq!(
                chosen,
                forced(options.split_percent).min(forced(0)),
                "soup {seed}"
            );
            let unprobed = BuildOptions {
                probe_split: false,
                ..options
            };
            let kept = probe_cost(&PackedBvh::build(&triangles, &unprobed), &rays);
            assert_eq!(kept, forced(options.split_percent), "soup {seed}");
        }
    }
}
