//! The GPU kernels against their CPU twins on the same rays: every variant's closest hit has
//! the same triangle and t (relative 1e-5), misses agree, any-hit answers agree; ray generation
//! matches `bvh::bench_rays`. The compact MTBVH (`mtbvh16`) and the four-wide one (`mtbvh4`)
//! are variants too, and on the GPU too return exactly the MTBVH's hits. Runs on whatever
//! adapter wgpu finds (lavapipe in CI).

use std::path::Path;

use bvh::bench_rays::{self, BenchCamera, View};
use bvh::traverse::{Query, TraversalCounters};
use bvh::{BuildOptions, CompactMtbvh, PackedBvh, Ray, WideMtbvh};
use glam::Vec3;
use gpu::traversal::RayKind;
use gpu::types::{GpuHit, GpuRay};
use gpu::{GpuContext, GpuScene, SceneStorage, TraversalKernels, Variant};
use scene::Material;

/// Relative tolerance on t between a GPU kernel and its twin.
const T_TOLERANCE: f32 = 1e-5;

fn context() -> GpuContext {
    GpuContext::new(None).unwrap_or_else(|e| {
        panic!("no usable GPU adapter in the test environment (CI installs Mesa lavapipe): {e}")
    })
}

/// Describes every disagreement between the GPU's `hits` and the CPU twin on `rays`.
fn disagreements(
    (bvh, compact, wide): (&PackedBvh, &CompactMtbvh, &WideMtbvh),
    rays: &[GpuRay],
    hits: &[GpuHit],
    variant: Variant,
    query: Query,
) -> Vec<String> {
    let mut found = Vec::new();
    for (i, (gpu_ray, gpu_hit)) in rays.iter().zip(hits).enumerate() {
        let ray = gpu_ray.to_ray();
        let mut counters = TraversalCounters::default();
        let cpu = variant.cpu_trace(bvh, compact, wide, &ray, query, &mut counters);
        let gpu = gpu_hit.to_hit();
        let agree = match (query, cpu, gpu) {
            (_, None, None) => true,
            (Query::Any, Some(_), Some(_)) => true,
            (Query::Closest, Some(c), Some(g)) => {
                c.triangle == g.triangle && (c.t - g.t).abs() <= T_TOLERANCE * c.t.abs()
            }
            _ => false,
        };
        if !agree {
            found.push(format!("ray {i} {ray:?}: cpu {cpu:?}, gpu {gpu:?}"));
        }
    }
    found
}

/// [`assert_twins_agree_from`] with the scene in storage buffers and in texels.
fn assert_twins_agree(context: &GpuContext, name: &str, bvh: &PackedBvh, rays: &[GpuRay]) {
    for storage in [SceneStorage::Buffers, SceneStorage::Texels] {
        let mut context = context.clone();
        context.scene_storage = storage;
        assert_twins_agree_from(&context, &format!("{name} ({})", storage.name()), bvh, rays);
    }
}

/// Traces `rays` with every GPU variant and query and compares with the twins; the compact
/// and wide MTBVHs' closest hits must also be the MTBVH's on the GPU (`same_hit`), except
/// where they reach a closer fragile hit (`bvh::testing::is_fragile_hit`).
fn assert_twins_agree_from(context: &GpuContext, name: &str, bvh: &PackedBvh, rays: &[GpuRay]) {
    let kernels = TraversalKernels::new(context);
    let mut scene = GpuScene::upload(context, bvh, &vec![Material::default(); 8]).expect("upload");
    let compact = CompactMtbvh::new(bvh).expect("compactable");
    scene
        .upload_compact(context, &compact)
        .expect("compact upload");
    let wide = WideMtbvh::new(bvh).expect("leaves of at most 255 triangles");
    scene.upload_wide(context, &wide).expect("wide upload");
    let batch = kernels.upload_rays(context, rays).expect("ray batch");
    let mut report = Vec::new();
    let mut closest_hits = 0;
    let mut closest_by_variant = Vec::new();
    for variant in Variant::ALL {
        for query in [Query::Closest, Query::Any] {
            kernels
                .trace(context, &scene, &batch, variant, query)
                .expect("trace");
            let hits = batch.read_hits(context).expect("read hits");
            if query == Query::Closest {
                closest_hits = hits.iter().filter(|h| h.to_hit().is_some()).count();
                closest_by_variant.push((variant, hits.clone()));
            }
            let bad = disagreements((bvh, &compact, &wide), rays, &hits, variant, query);
            if !bad.is_empty() {
                report.push(format!(
                    "{name} {} {query:?}: {} of {} rays disagree, first: {}",
                    variant.name(),
                    bad.len(),
                    rays.len(),
                    bad[0]
                ));
            }
        }
    }
    assert!(report.is_empty(), "{}", report.join("\n"));
    let gpu_closest = |v: Variant| {
        &closest_by_variant
            .iter()
            .find(|(variant, _)| *variant == v)
            .expect("traced")
            .1
    };
    let exact = gpu_closest(Variant::Mtbvh);
    for other in [Variant::MtbvhCompact, Variant::Mtbvh4] {
        for (i, (e, o)) in exact.iter().zip(gpu_closest(other)).enumerate() {
            let (e, o) = (e.to_hit(), o.to_hit());
            if !bvh::testing::same_hit(bvh, e, o) {
                let ray = rays[i].to_ray();
                assert!(
                    bvh::testing::nearer_is_fragile(bvh, &ray, e, o),
                    "{name}: ray {i} {ray:?}: gpu mtbvh {e:?}, gpu {} {o:?}",
                    other.name()
                );
            }
        }
    }
    // The test means something only if the rays hit and miss.
    assert!(
        closest_hits > rays.len() / 10 && closest_hits < rays.len(),
        "{name}: {closest_hits} of {} rays hit",
        rays.len()
    );
}

#[test]
fn kernels_match_cpu_twins_on_random_soups_and_rays() {
    let context = context();
    for seed in [1, 2] {
        let triangles = bvh::testing::random_soup(seed, 3000);
        let rays: Vec<GpuRay> = bvh::testing::random_rays(seed + 100, 20_000, &triangles)
            .iter()
            .map(GpuRay::from_ray)
            .collect();
        for max_leaf_size in [1, 4] {
            let options = BuildOptions {
                max_leaf_size,
                ..BuildOptions::default()
            };
            let bvh = PackedBvh::build(&triangles, &options);
            let name = format!("soup {seed}, leaf {max_leaf_size}");
            assert_twins_agree(&context, &name, &bvh, &rays);
        }
    }
}

#[test]
fn compact_kernels_follow_far_links_on_a_large_soup() {
    // 40k triangles in leaves of 1 make ~80k nodes: links near the root pass 16 bits.
    let triangles = bvh::testing::random_soup(5, 40_000);
    let options = BuildOptions {
        max_leaf_size: 1,
        ..BuildOptions::default()
    };
    let bvh = PackedBvh::build(&triangles, &options);
    let far = CompactMtbvh::new(&bvh).expect("compactable").far_count();
    assert!(far > 0, "no far records: the test would not test them");
    let rays: Vec<GpuRay> = bvh::testing::random_rays(105, 20_000, &triangles)
        .iter()
        .map(GpuRay::from_ray)
        .collect();
    assert_twins_agree(&context(), "soup 5, 40k triangles", &bvh, &rays);
}

#[test]
fn kernels_match_cpu_twins_on_the_shipped_cornell_box() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/cornell-caustics.gltf");
    let scene = scene::load(&path).expect("shipped scene loads");
    let bvh = PackedBvh::build(&scene.triangles, &BuildOptions::default());
    let camera = BenchCamera::new(scene.bounds(), View::Outside, 160);
    // Camera rays, then one bounce in random directions from where they land.
    let mut rng = bvh::testing::Rng::new(7);
    let mut rays: Vec<Ray> = camera.primary_rays();
    let bounced: Vec<Ray> = rays
        .iter()
        .filter_map(|ray| {
            let hit = bvh::closest_hit_mtbvh(&bvh, ray)?;
            Some(Ray {
                origin: ray.origin + hit.t * ray.direction,
                direction: rng.direction(),
                t_max: f32::INFINITY,
            })
        })
        .collect();
    rays.extend(bounced);
    let rays: Vec<GpuRay> = rays.iter().map(GpuRay::from_ray).collect();
    assert_twins_agree(&context(), "cornell-caustics", &bvh, &rays);
}

fn assert_close(a: Vec3, b: Vec3, tolerance: f32, what: &str) {
    assert!(
        (a - b).abs().max_element() <= tolerance,
        "{what}: gpu {a}, cpu {b}"
    );
}

#[test]
fn ray_generation_matches_bench_rays() {
    let context = context();
    let kernels = TraversalKernels::new(&context);
    let cornell = scene::testing::cornell_caustics();
    let triangles = &cornell.triangles;
    let bvh = PackedBvh::build(triangles, &BuildOptions::default());
    let scene = GpuScene::upload(&context, &bvh, &[Material::default()]).expect("upload");
    // A trace that cannot run is refused in words, containing `needle`.
    let assert_refused = |scene: &GpuScene, variant: Variant, needle: &str| {
        let refused = kernels
            .batch(&context, 1)
            .and_then(|b| kernels.trace(&context, scene, &b, variant, Query::Closest));
        assert!(
            refused.is_err_and(|e| e.to_string().contains(needle)),
            "{} expected to be refused with {needle:?}",
            variant.name()
        );
    };
    // Without their uploads the compact and wide kernels refuse.
    assert_refused(&scene, Variant::MtbvhCompact, "upload_compact");
    assert_refused(&scene, Variant::Mtbvh4, "upload_wide");
    // So do the kernels a scene stored otherwise than they read it.
    let mut other = context.clone();
    other.scene_storage = context.scene_storage.other();
    let other_scene = GpuScene::upload(&other, &bvh, &[Material::default()]).expect("upload");
    assert_refused(
        &other_scene,
        Variant::Mtbvh,
        "traversal kernels read it from",
    );
    let bounds = cornell.bounds();
    let diagonal = bounds.extent().length();
    let camera = BenchCamera::new(bounds, View::Outside, 96);
    let batch = kernels
        .batch(&context, camera.ray_count() as u32)
        .expect("batch");

    kernels
        .generate(
            &context,
            &scene,
            &batch,
            RayKind::Primary,
            &camera,
            diagonal,
        )
        .expect("primary rays");
    let primary = batch.read_rays(&context).expect("read rays");
    for (i, gpu) in primary.iter().enumerate() {
        let cpu = camera.primary_ray(i as u32);
        let gpu = gpu.to_ray();
        assert_eq!(gpu.origin, cpu.origin, "ray {i}");
        assert_eq!(gpu.t_max, f32::INFINITY, "ray {i}");
        // WGSL's normalize may round differently from glam's.
        assert_close(gpu.direction, cpu.direction, 1e-6, &format!("primary {i}"));
    }

    kernels
        .trace(&context, &scene, &batch, Variant::Mtbvh, Query::Closest)
        .expect("trace");
    let hits = batch.read_hits(&context).expect("read hits");
    kernels
        .generate(
            &context,
            &scene,
            &batch,
            RayKind::Diffuse,
            &camera,
            diagonal,
        )
        .expect("diffuse rays");
    let diffuse = batch.read_rays(&context).expect("read rays");
    let mut used = 0;
    for (i, ((gpu, hit), primary)) in diffuse.iter().zip(&hits).zip(&primary).enumerate() {
        let Some(hit) = hit.to_hit() else {
            assert!(!gpu.is_used(), "ray {i}: no primary hit, so no diffuse ray");
            continue;
        };
        used += 1;
        let id = bvh.triangle_ids[hit.triangle as usize] as usize;
        let normal = triangles[id].geometric_normal_unnormalized();
        let cpu = bench_rays::diffuse_ray(i as u32, &primary.to_ray(), hit.t, normal, diagonal);
        let gpu = gpu.to_ray();
        assert_close(
            gpu.origin,
            cpu.origin,
            1e-5 * diagonal,
            &format!("origin {i}"),
        );
        // Vulkan allows sin and cos an absolute error of 2^-11.
        assert_close(
            gpu.direction,
            cpu.direction,
            2e-3,
            &format!("direction {i}"),
        );
    }
    assert!(used > camera.ray_count() / 4, "{used} diffuse rays");
}
