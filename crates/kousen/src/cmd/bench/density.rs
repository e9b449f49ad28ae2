//! `kousen bench density SCENE...`: the density-estimation methods the talk compares (issue 6,
//! tables 4 and 5), each rendering the same scene, camera and photons on the GPU adapter and
//! the CPU backend:
//!
//! - the stochastic spatial hash (one photon kept per entry) with 1 entry per 64, 8 and 1
//!   photon slots;
//! - a full spatial hash keeping every photon, its lists built by a counting sort on the device;
//! - a kd-tree over each pass's photons, built on the CPU (the GPU's photons read back) and
//!   queried on the device.
//!
//! Per pass, the bench waits for the device after each phase, so it can give the hash build's
//! and the gather's time alone (median over the passes). Each method first runs a short
//! warm-up render. Image error (relMSE, both images scaled so the reference's mean is 0.18) is
//! measured against a reference at checkpoints (passes 1, 2, 4, ... and the last), outside the
//! timing: at equal passes, and at equal time — the
//! time the fastest method took for all its passes, each method's error there interpolated
//! (log–log) between its checkpoints.

mod report;

use render::tonemap::Look;
use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, bail, ensure};

use bvh::PackedBvh;
use cpu::{CpuBackend, SceneData};
use gpu::GpuContext;
use gpu::sppm::GpuBackend;
use render::half_storage::Precision;
use render::integrator::Phase;
use render::{Backend, Density, Image, Settings, Sppm};

use super::host::{BenchHost, median, open_gpu};
use crate::cli::{BenchDevice, DensityArgs, DensityMethod};
use crate::image_io::{ExrPrecision, Output, read_image};
use crate::image_metrics::mean_ratio;
use report::{
    Checkpoint, ReferenceReport, Report, Row, equal_time, print_header, print_row, print_speedups,
    scaled_rel_mse, speedups,
};

/// Passes of each method's warm-up render.
const WARM_UP_PASSES: u32 = 2;
/// Seed offset of the rendered reference, so its noise is independent of the methods'.
const REFERENCE_SEED_OFFSET: u32 = 7919;

/// One method's measured render before its equal-time error is known.
struct Measured {
    row: Row,
    image: Image,
}

pub fn run(args: &DensityArgs) -> anyhow::Result<()> {
    ensure!(!args.methods.is_empty(), "--methods names no method");
    let json_file = args
        .json
        .as_deref()
        .map(crate::output_file::PendingFile::create)
        .transpose()?;
    if let Some(dir) = &args.images {
        std::fs::create_dir_all(dir)
            .with_context(|| format!("cannot create the image folder {}", dir.display()))?;
    }
    let gpu = open_gpu(&args.devices, args.adapter.as_deref())?;
    let mut report = Report {
        host: BenchHost::here(
            gpu.as_ref(),
            "wall time, the device waited for after each phase",
        ),
        width: args.width,
        height: args.height,
        photon_slots: args.photons,
        passes: args.passes,
        eye_every: render::settings::DEFAULT_EYE_EVERY,
        seed: args.seed,
        references: Vec::new(),
        results: Vec::new(),
        gpu_over_cpu: Vec::new(),
    };
    match &gpu {
        Some(context) if context.is_cpu_device() => println!(
            "gpu: {} — a CPU-type adapter standing in for a GPU",
            context.description()
        ),
        Some(context) => println!("gpu: {}", context.description()),
        None => println!("gpu: none"),
    }
    println!(
        "cpu: {} ({} threads); {}×{}, {} photon slots, {} passes per method",
        report.host.cpu_model,
        report.host.cpu_threads,
        args.width,
        args.height,
        args.photons,
        args.passes
    );
    for path in &args.scenes {
        let (reference, rows) =
            bench_scene(args, gpu.as_ref(), path).with_context(|| format!("{}", path.display()))?;
        report.references.push(reference);
        report.gpu_over_cpu.extend(speedups(&rows));
        report.results.extend(rows);
    }
    print_speedups(&report.gpu_over_cpu);
    if let Some(mut file) = json_file {
        serde_json::to_writer_pretty(file.file(), &report)?;
        file.commit()?;
    }
    Ok(())
}

/// What every render of a scene shares.
struct Bench<'a> {
    args: &'a DensityArgs,
    scene: scene::Scene,
    camera: scene::Camera,
    bvh: PackedBvh,
    stem: String,
}

impl Bench<'_> {
    fn settings(&self, method: DensityMethod, precision: Precision, seed: u32) -> Settings {
        let (density, hash_ratio) = method.density();
        Settings {
            seed,
            density,
            hash_ratio,
            precision,
            initial_radius: render::integrator::initial_radius_from_view(
                &self.bvh,
                &self.camera,
                self.args.width,
                self.args.height,
            ),
            ..Settings::new(self.args.width, self.args.height, self.args.photons)
        }
    }

    fn gpu_backend(&self, context: &GpuContext) -> anyhow::Result<GpuBackend> {
        Ok(GpuBackend::new(
            context.clone(),
            &self.scene,
            self.bvh.clone(),
        )?)
    }

    fn cpu_backend(&self) -> CpuBackend {
        CpuBackend::new(SceneData::new(&self.scene, self.bvh.clone()))
    }
}

fn bench_scene(
    args: &DensityArgs,
    gpu: Option<&GpuContext>,
    path: &Path,
) -> anyhow::Result<(ReferenceReport, Vec<Row>)> {
    let scene = scene::load(path)?;
    crate::cmd::info::check_bvh_limits(&scene)?;
    let bvh = PackedBvh::build(&scene.triangles, &crate::cmd::info::build_options(args.bvh));
    let camera = scene.camera(None).context("the scene has no camera")?;
    let stem = path
        .file_stem()
        .map_or_else(String::new, |s| s.to_string_lossy().into_owned());
    let bench = Bench {
        args,
        scene,
        camera,
        bvh,
        stem,
    };
    let (reference, source) = reference(&bench, gpu)?;
    println!("reference: {source}");
    if let Some(dir) = &args.images {
        let file = dir.join(format!("density-{}-reference.exr", bench.stem));
        Output::create_with(&file, ExrPrecision::Float)?.commit(&reference, Look::default())?;
    }
    let mut rows = Vec::new();
    let mut images_written = false;
    let devices: Vec<BenchDevice> = [BenchDevice::Gpu, BenchDevice::Cpu]
        .into_iter()
        .filter(|d| args.devices.contains(d) && (*d == BenchDevice::Cpu || gpu.is_some()))
        .collect();
    for device in devices {
        print_header();
        let measured = match (device, gpu) {
            (BenchDevice::Gpu, Some(context)) => {
                measure_methods(&bench, bench.gpu_backend(context)?, "gpu", &reference)?
            }
            _ => measure_methods(&bench, bench.cpu_backend(), "cpu", &reference)?,
        };
        if let (Some(dir), false) = (&args.images, images_written) {
            for m in &measured {
                let file = image_path(dir, &bench.stem, &m.row.label());
                Output::create_with(&file, ExrPrecision::Float)?
                    .commit(&m.image, Look::exposure(args.exposure))?;
            }
            images_written = true;
        }
        rows.extend(equal_time(measured.into_iter().map(|m| m.row).collect()));
    }
    let reference = ReferenceReport {
        scene: bench.stem.clone(),
        source,
    };
    Ok((reference, rows))
}

fn image_path(dir: &Path, stem: &str, label: &str) -> PathBuf {
    dir.join(format!("density-{stem}-{label}.png"))
}

/// The reference image: the file given, or a render with the full hash, another seed and
/// `--reference-passes` passes on the GPU if there is one.
fn reference(bench: &Bench, gpu: Option<&GpuContext>) -> anyhow::Result<(Image, String)> {
    let args = bench.args;
    if let Some(file) = &args.reference {
        let image = read_image(file)?;
        if (image.width, image.height) != (args.width, args.height) {
            bail!(
                "the reference {} is {}×{}, the bench renders {}×{}",
                file.display(),
                image.width,
                image.height,
                args.width,
                args.height
            );
        }
        return Ok((image, file.display().to_string()));
    }
    let settings = bench.settings(
        DensityMethod::Full,
        Precision::F32,
        args.seed.wrapping_add(REFERENCE_SEED_OFFSET),
    );
    let budget = render::Budget::Passes(args.reference_passes);
    let (image, device) = match gpu {
        Some(context) => {
            let mut sppm = Sppm::new(
                bench.gpu_backend(context)?,
                &bench.scene,
                &bench.camera,
                settings,
            )?;
            (sppm.run(budget, &mut |_| {})?.image, "gpu")
        }
        None => {
            let mut sppm = Sppm::new(bench.cpu_backend(), &bench.scene, &bench.camera, settings)?;
            (sppm.run(budget, &mut |_| {})?.image, "cpu")
        }
    };
    let source = format!(
        "rendered: full hash, {} passes, seed {}, {device}",
        args.reference_passes,
        args.seed.wrapping_add(REFERENCE_SEED_OFFSET)
    );
    Ok((image, source))
}

/// Every method of `--methods` in every `--precision` on one backend, one after another.
fn measure_methods<B: Backend>(
    bench: &Bench,
    backend: B,
    device: &'static str,
    reference: &Image,
) -> anyhow::Result<Vec<Measured>> {
    let mut backend = Some(backend);
    let mut measured = Vec::new();
    let variants = bench.args.methods.iter().flat_map(|&method| {
        let precisions = bench.args.precision.iter();
        precisions.map(move |p| (method, p.precision()))
    });
    for (method, precision) in variants {
        let start = |backend: B, seed| {
            Sppm::new(
                backend,
                &bench.scene,
                &bench.camera,
                bench.settings(method, precision, seed),
            )
        };
        let mut warm = start(backend.take().expect("backend"), bench.args.seed)?;
        for _ in 0..WARM_UP_PASSES {
            warm.pass();
        }
        warm.backend().synchronize()?;
        let mut sppm = start(warm.into_backend(), bench.args.seed)?;
        let m = measure(&mut sppm, bench, method, precision, device, reference)?;
        print_row(&m.row);
        measured.push(m);
        backend = Some(sppm.into_backend());
    }
    Ok(measured)
}

/// Per-phase times of one render, with its error at the checkpoints.
fn measure<B: Backend>(
    sppm: &mut Sppm<B>,
    bench: &Bench,
    method: DensityMethod,
    precision: Precision,
    device: &'static str,
    reference: &Image,
) -> anyhow::Result<Measured> {
    let passes = bench.args.passes;
    let (mut eye, mut photons, mut hash, mut gather) = (vec![], vec![], vec![], vec![]);
    let mut seconds = 0.0;
    let mut checkpoints = Vec::new();
    let mut failure = None;
    for pass in 1..=passes {
        let mut last = Instant::now();
        sppm.pass_phases(|backend, phase| {
            if let Err(e) = backend.synchronize() {
                failure.get_or_insert(e);
            }
            let now = Instant::now();
            let ms = (now - last).as_secs_f64() * 1e3;
            last = now;
            seconds += ms / 1e3;
            match phase {
                Phase::Eye => eye.push(ms),
                Phase::Photons => photons.push(ms),
                Phase::Hash => hash.push(ms),
                Phase::Gather => gather.push(ms),
            }
        });
        if let Some(e) = failure.take() {
            return Err(e.into());
        }
        if pass.is_power_of_two() || pass == passes {
            let image = sppm.image()?;
            checkpoints.push(Checkpoint {
                passes: pass,
                seconds,
                rel_mse: scaled_rel_mse(&image, reference),
            });
        }
    }
    let image = sppm.image()?;
    let memory = sppm.backend_ref().memory();
    let bytes_of = |kinds: &[&str]| {
        memory
            .iter()
            .filter(|(kind, _)| kinds.contains(kind))
            .map(|(_, bytes)| bytes)
            .sum()
    };
    let density_bytes = bytes_of(&["hash"]);
    let point_bytes = bytes_of(&["photons", "visible_points"]);
    let (density, ratio) = method.density();
    let row = Row {
        scene: bench.stem.clone(),
        device,
        method: method.name(),
        precision: precision.name(),
        table_ratio: (density != Density::KdTree).then_some(ratio),
        passes,
        hash_build_ms: median(&hash),
        gather_ms: median(&gather),
        photon_pass_ms: median(&photons),
        eye_pass_ms: if eye.is_empty() { 0.0 } else { median(&eye) },
        iteration_ms: seconds * 1e3 / f64::from(passes),
        seconds,
        density_bytes,
        point_bytes,
        rel_mse_equal_passes: checkpoints.last().map_or(f64::NAN, |c| c.rel_mse),
        mean_ratio: mean_ratio(&image, reference).overall,
        rel_mse_equal_time: None,
        equal_time_seconds: 0.0,
        checkpoints,
    };
    Ok(Measured { row, image })
}
