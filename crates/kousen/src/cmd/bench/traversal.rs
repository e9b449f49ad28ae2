//! `kousen bench traversal SCENE...`: Mrays/s of the stack, TBVH, MTBVH, compact MTBVH
//! ("mtbvh16", `bvh::compact`) and four-wide MTBVH ("mtbvh4", `bvh::wide`, which the CPU
//! backend renders with) traversals on the GPU adapter and of their CPU twins (rayon, all
//! cores), on ANCHORS.md's primary and diffuse rays, measured side by side in one run (a
//! warm-up, then the median of `--runs`), with every variant's hits checked against the CPU
//! stack traversal's.

use std::path::Path;
use std::time::Instant;

use anyhow::{Context, bail};
use rayon::prelude::*;
use serde::Serialize;

use bvh::bench_rays::{self, BenchCamera, View};
use bvh::traverse::{Query, TraversalCounters, hits_agree};
use bvh::{CompactMtbvh, Hit, PackedBvh, Ray, WideMtbvh};
use gpu::traversal::RayKind;
use gpu::types::GpuRay;
use gpu::{GpuContext, GpuScene, RayBatch, TraversalKernels, Variant};

use super::host::{cpu_model, median};
use crate::cli::{BenchView, TraversalArgs};

/// The JSON report (a contract for scripts: adapter, cpu_model, results[...] with scene, rays,
/// variant, device, rays_traced, mrays_per_s, mismatches; the other keys are extras).
#[derive(Serialize)]
struct Report {
    adapter: Option<AdapterReport>,
    cpu_model: String,
    cpu_threads: usize,
    /// "timestamp" (GPU timestamp queries) or "wall" (submit and wait), null without a GPU.
    gpu_timing: Option<&'static str>,
    /// "buffers" or "texels": where the GPU kernels read the scene from; null without a GPU.
    scene_storage: Option<&'static str>,
    view: &'static str,
    image_side: u32,
    runs: u32,
    results: Vec<Row>,
}

#[derive(Serialize)]
struct AdapterReport {
    name: String,
    backend: String,
    driver: String,
}

#[derive(Serialize)]
struct Row {
    /// The scene file's stem.
    scene: String,
    /// The scene file as given.
    path: String,
    rays: &'static str,
    variant: &'static str,
    device: &'static str,
    rays_traced: usize,
    mrays_per_s: f64,
    /// Rays whose answer disagrees with the CPU stack traversal's (see `bvh::traverse::hits_agree`).
    mismatches: usize,
    hits: usize,
    /// Work per ray (the same on both devices: one algorithm), from the CPU twin.
    box_tests_per_ray: f64,
    triangle_tests_per_ray: f64,
}

/// The device side of the bench: context, kernels.
struct Gpu {
    context: GpuContext,
    kernels: TraversalKernels,
}

/// One scene's rays of one kind, on the host and (with a GPU) on the device.
struct RaySet {
    kind: RayKind,
    rays: Vec<Ray>,
    batch: Option<RayBatch>,
}

pub fn run(args: &TraversalArgs) -> anyhow::Result<()> {
    // Fail on an unwritable JSON path before minutes of measuring.
    let json_file = args
        .json
        .as_deref()
        .map(crate::output_file::PendingFile::create)
        .transpose()?;
    let gpu = open_gpu(args)?;
    let view = match args.view {
        BenchView::Outside => View::Outside,
        BenchView::Inside => View::Inside,
    };
    let mut report = Report {
        adapter: gpu.as_ref().map(|g| AdapterReport {
            name: g.context.info.name.clone(),
            backend: g.context.info.backend.to_string(),
            driver: gpu::device::driver(&g.context.info),
        }),
        cpu_model: cpu_model(),
        cpu_threads: rayon::current_num_threads(),
        gpu_timing: gpu.as_ref().map(|g| {
            if g.kernels.has_timestamps() {
                "timestamp"
            } else {
                "wall"
            }
        }),
        scene_storage: gpu.as_ref().map(|g| g.context.scene_storage.name()),
        view: match view {
            View::Outside => "outside",
            View::Inside => "inside",
        },
        image_side: args.size,
        runs: args.runs,
        results: Vec::new(),
    };
    print_header(&report, gpu.as_ref());
    for path in &args.scenes {
        let rows = bench_scene(args, gpu.as_ref(), path, view)
            .with_context(|| format!("{}", path.display()))?;
        report.results.extend(rows);
    }
    if let Some(mut file) = json_file {
        serde_json::to_writer_pretty(file.file(), &report)?;
        file.commit()?;
    }
    let mismatches: usize = report.results.iter().map(|r| r.mismatches).sum();
    if mismatches > 0 {
        bail!(
            "{mismatches} rays where a traversal disagrees with the CPU stack traversal: a bug, see the table"
        );
    }
    Ok(())
}

/// The GPU when `--devices` includes it, with the traversal kernels compiled.
fn open_gpu(args: &TraversalArgs) -> anyhow::Result<Option<Gpu>> {
    let context = super::host::open_gpu(&args.devices, args.adapter.as_deref())?;
    Ok(context.map(|mut context| {
        if let Some(storage) = args.scene_storage {
            context.scene_storage = storage.storage();
        }
        let kernels = TraversalKernels::new(&context);
        Gpu { context, kernels }
    }))
}

fn print_header(report: &Report, gpu: Option<&Gpu>) {
    match gpu {
        Some(g) => println!(
            "gpu: {} (timing: {}, scene in {})",
            g.context.description(),
            report.gpu_timing.unwrap_or("none"),
            g.context.scene_storage.name()
        ),
        None => println!("gpu: none"),
    }
    println!(
        "cpu: {} ({} threads); {} view, {}² primary rays, median of {} runs after a warm-up",
        report.cpu_model, report.cpu_threads, report.view, report.image_side, report.runs
    );
    println!(
        "{:<16} {:<8} {:<7} {:<4} {:>9} {:>9} {:>8} {:>9} {:>9} {:>10}",
        "scene",
        "rays",
        "variant",
        "dev",
        "rays",
        "Mrays/s",
        "×tbvh",
        "boxes/ray",
        "tris/ray",
        "mismatches"
    );
}

fn print_row(row: &Row, tbvh_rate: Option<f64>) {
    let ratio = tbvh_rate.map_or("".to_owned(), |t| format!("{:.2}", row.mrays_per_s / t));
    println!(
        "{:<16} {:<8} {:<7} {:<4} {:>9} {:>9.2} {:>8} {:>9.1} {:>9.1} {:>10}",
        row.scene,
        row.rays,
        row.variant,
        row.device,
        row.rays_traced,
        row.mrays_per_s,
        ratio,
        row.box_tests_per_ray,
        row.triangle_tests_per_ray,
        row.mismatches
    );
}

fn bench_scene(
    args: &TraversalArgs,
    gpu: Option<&Gpu>,
    path: &Path,
    view: View,
) -> anyhow::Result<Vec<Row>> {
    let scene = scene::load(path)?;
    crate::cmd::info::check_bvh_limits(&scene)?;
    let bvh = PackedBvh::build(&scene.triangles, &crate::cmd::info::build_options(args.bvh));
    // The compact MTBVH is measured where the scene's coordinates allow it.
    let compact = match CompactMtbvh::new(&bvh) {
        Ok(compact) => Some(compact),
        Err(error) => {
            eprintln!("kousen: {}: {error}; mtbvh16 not measured", path.display());
            None
        }
    };
    let wide = WideMtbvh::new(&bvh)
        .inspect_err(|error| eprintln!("kousen: {}: {error}; mtbvh4 not measured", path.display()))
        .ok();
    let bounds = scene.bounds();
    let camera = BenchCamera::new(bounds, view, args.size);
    let diagonal = bounds.extent().length();
    let gpu_scene = gpu
        .map(|g| -> anyhow::Result<GpuScene> {
            let mut gpu_scene = GpuScene::upload(&g.context, &bvh, &scene.materials)?;
            if let Some(compact) = &compact {
                gpu_scene.upload_compact(&g.context, compact)?;
            }
            if let Some(wide) = &wide {
                gpu_scene.upload_wide(&g.context, wide)?;
            }
            Ok(gpu_scene)
        })
        .transpose()?;
    let twins = Twins {
        bvh: &bvh,
        compact: compact.as_ref(),
        wide: wide.as_ref(),
    };
    let device = gpu.zip(gpu_scene.as_ref());
    let stem = path
        .file_stem()
        .map_or_else(String::new, |s| s.to_string_lossy().into_owned());

    let primary = primary_rays(device, &camera, diagonal)?;
    let mut primary_hits: Option<Vec<Option<Hit>>> = None;
    let mut rows = Vec::new();
    for kind in RayKind::ALL {
        if !args.rays.iter().any(|r| r.kind() == kind) {
            continue;
        }
        let diffuse;
        let set = match kind {
            RayKind::Primary => &primary,
            RayKind::Diffuse => {
                let hits = primary_hits
                    .get_or_insert_with(|| cpu_trace(twins, &primary.rays, Variant::Stack).0);
                diffuse = diffuse_rays(device, &camera, diagonal, &primary, hits, &bvh, &scene)?;
                &diffuse
            }
        };
        let (reference, kind_rows) = bench_rays(args, device, twins, set, &stem, path)?;
        if kind == RayKind::Primary {
            primary_hits = Some(reference);
        }
        rows.extend(kind_rows);
    }
    Ok(rows)
}

/// The camera's primary rays: made on the GPU when there is one (the CPU twins then trace the
/// GPU's rays, so every variant sees identical rays), else by `bench_rays`.
fn primary_rays(
    device: Option<(&Gpu, &GpuScene)>,
    camera: &BenchCamera,
    diagonal: f32,
) -> anyhow::Result<RaySet> {
    let Some((gpu, scene)) = device else {
        return Ok(RaySet {
            kind: RayKind::Primary,
            rays: camera.primary_rays(),
            batch: None,
        });
    };
    let batch = gpu.kernels.batch(&gpu.context, camera.ray_count() as u32)?;
    gpu.kernels.generate(
        &gpu.context,
        scene,
        &batch,
        RayKind::Primary,
        camera,
        diagonal,
    )?;
    let rays = batch.read_rays(&gpu.context)?;
    Ok(RaySet {
        kind: RayKind::Primary,
        rays: rays.iter().map(GpuRay::to_ray).collect(),
        batch: Some(batch),
    })
}

/// One diffuse ray per primary hit, in pixel order: made on the GPU from its own primary hits
/// when there is one, else by `bench_rays` from `primary_hits`.
fn diffuse_rays(
    device: Option<(&Gpu, &GpuScene)>,
    camera: &BenchCamera,
    diagonal: f32,
    primary: &RaySet,
    primary_hits: &[Option<Hit>],
    bvh: &PackedBvh,
    scene: &scene::Scene,
) -> anyhow::Result<RaySet> {
    let Some((gpu, gpu_scene)) = device else {
        let rays = primary
            .rays
            .iter()
            .zip(primary_hits)
            .enumerate()
            .filter_map(|(i, (ray, hit))| {
                let hit = (*hit)?;
                let id = bvh.triangle_ids[hit.triangle as usize] as usize;
                let normal = scene.triangles[id].geometric_normal_unnormalized();
                Some(bench_rays::diffuse_ray(
                    i as u32, ray, hit.t, normal, diagonal,
                ))
            })
            .collect();
        return Ok(RaySet {
            kind: RayKind::Diffuse,
            rays,
            batch: None,
        });
    };
    let (context, kernels) = (&gpu.context, &gpu.kernels);
    // The primary rays have been measured (RayKind::ALL puts them first): their batch on the
    // device becomes the diffuse rays, in place. The host copy keeps the primary rays.
    let work = primary
        .batch
        .as_ref()
        .context("primary rays were made without the GPU")?;
    kernels.trace(context, gpu_scene, work, Variant::Mtbvh, Query::Closest)?;
    kernels.generate(context, gpu_scene, work, RayKind::Diffuse, camera, diagonal)?;
    let used: Vec<GpuRay> = work
        .read_rays(context)?
        .into_iter()
        .filter(GpuRay::is_used)
        .collect();
    Ok(RaySet {
        kind: RayKind::Diffuse,
        rays: used.iter().map(GpuRay::to_ray).collect(),
        batch: Some(kernels.upload_rays(context, &used)?),
    })
}

/// What the CPU twins traverse: the packed BVH and, where the scene allows them, its compact
/// and four-wide MTBVHs.
#[derive(Clone, Copy)]
struct Twins<'a> {
    bvh: &'a PackedBvh,
    compact: Option<&'a CompactMtbvh>,
    wide: Option<&'a WideMtbvh>,
}

impl Twins<'_> {
    /// The variants measured: all of them, less the compact and wide MTBVHs where they could
    /// not be made.
    fn variants(&self) -> Vec<Variant> {
        Variant::ALL
            .into_iter()
            .filter(|&v| v != Variant::MtbvhCompact || self.compact.is_some())
            .filter(|&v| v != Variant::Mtbvh4 || self.wide.is_some())
            .collect()
    }

    /// Runs `f` on the compact and wide MTBVHs (empty ones where they could not be made; their
    /// variants are not measured then).
    fn with_parts<R>(&self, f: impl FnOnce(&CompactMtbvh, &WideMtbvh) -> R) -> R {
        let (empty, empty_wide) = (CompactMtbvh::default(), WideMtbvh::default());
        f(
            self.compact.unwrap_or(&empty),
            self.wide.unwrap_or(&empty_wide),
        )
    }
}

/// Closest hits of `rays` by the CPU twin of `variant` on all cores and the seconds it took,
/// the work uncounted (as a render traces; counting costs a few percent).
fn cpu_trace(twins: Twins<'_>, rays: &[Ray], variant: Variant) -> (Vec<Option<Hit>>, f64) {
    twins.with_parts(|compact, wide| {
        let start = Instant::now();
        let hits = rays
            .par_iter()
            .with_min_len(256)
            .map(|ray| variant.cpu_closest_hit(twins.bvh, compact, wide, ray))
            .collect();
        (hits, start.elapsed().as_secs_f64())
    })
}

/// The work the CPU twin of `variant` does on `rays` (an untimed run).
fn cpu_work(twins: Twins<'_>, rays: &[Ray], variant: Variant) -> TraversalCounters {
    twins.with_parts(|compact, wide| {
        rays.par_chunks(256)
            .map(|chunk| {
                let mut work = TraversalCounters::default();
                for ray in chunk {
                    variant.cpu_trace(twins.bvh, compact, wide, ray, Query::Closest, &mut work);
                }
                work
            })
            .reduce(TraversalCounters::default, |a, b| a + b)
    })
}

/// Every variant on the CPU and the GPU over one ray set; returns the CPU stack hits (the
/// reference) and one row per variant and device.
fn bench_rays(
    args: &TraversalArgs,
    device: Option<(&Gpu, &GpuScene)>,
    twins: Twins<'_>,
    set: &RaySet,
    stem: &str,
    path: &Path,
) -> anyhow::Result<(Vec<Option<Hit>>, Vec<Row>)> {
    let rays = &set.rays;
    let count = rays.len().max(1) as f64;
    let mismatches = |reference: &[Option<Hit>], hits: &[Option<Hit>]| {
        reference
            .iter()
            .zip(hits)
            .filter(|(a, b)| !hits_agree(**a, **b))
            .count()
    };
    let mut reference: Vec<Option<Hit>> = Vec::new();
    let mut rows = Vec::new();
    let mut tbvh_rate = [None, None]; // cpu, gpu
    for variant in twins.variants() {
        let row = |device: &'static str,
                   hits: &[Option<Hit>],
                   seconds: f64,
                   work: TraversalCounters| Row {
            scene: stem.to_owned(),
            path: path.display().to_string(),
            rays: set.kind.name(),
            variant: variant.name(),
            device,
            rays_traced: rays.len(),
            mrays_per_s: rays.len() as f64 / seconds.max(1e-9) / 1e6,
            mismatches: 0,
            hits: hits.iter().filter(|h| h.is_some()).count(),
            box_tests_per_ray: work.boxes as f64 / count,
            triangle_tests_per_ray: work.triangles as f64 / count,
        };
        // CPU: the work counted in one run, a warm-up, then the median of the timed runs.
        let work = cpu_work(twins, rays, variant);
        let (mut hits, _) = cpu_trace(twins, rays, variant);
        let mut times = Vec::new();
        for _ in 0..args.runs {
            let (run_hits, seconds) = cpu_trace(twins, rays, variant);
            hits = run_hits;
            times.push(seconds);
        }
        if variant == Variant::Stack {
            reference = hits.clone();
        }
        let mut cpu_row = row("cpu", &hits, median(&times), work);
        cpu_row.mismatches = mismatches(&reference, &hits);
        let mut variant_rows = vec![cpu_row];

        if let (Some((gpu, scene)), Some(batch)) = (device, set.batch.as_ref()) {
            let (context, kernels) = (&gpu.context, &gpu.kernels);
            kernels.trace(context, scene, batch, variant, Query::Closest)?;
            let mut times = Vec::new();
            for _ in 0..args.runs {
                times.push(kernels.trace(context, scene, batch, variant, Query::Closest)?);
            }
            let gpu_hits: Vec<Option<Hit>> = batch
                .read_hits(context)?
                .iter()
                .map(|h| h.to_hit())
                .collect();
            let mut gpu_row = row("gpu", &gpu_hits, median(&times), work);
            gpu_row.mismatches = mismatches(&reference, &gpu_hits);
            variant_rows.push(gpu_row);
        }
        for (i, row) in variant_rows.into_iter().enumerate() {
            if variant == Variant::Tbvh {
                tbvh_rate[i] = Some(row.mrays_per_s);
            }
            print_row(&row, tbvh_rate[i]);
            rows.push(row);
        }
    }
    Ok((reference, rows))
}
