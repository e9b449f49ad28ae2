//! `kousen bench rng SCENE...`: the kernels' random generators side by side (issue 6, table
//! 6), after the talk's slides on random numbers:
//!
//! - **speed**: photon paths per second of the photon pass (one bounce per pass with
//!   asynchronous regeneration, as renders run it) compiled with each generator
//!   (`gpu::random_variants`), and of its CPU twin (`cpu::kernels::photon_pass_with` over
//!   the same slots on all cores, photons not kept). Two warm-up runs of each, then `--runs`
//!   runs of each, the generators alternating; medians. GPU time is wall time from the first
//!   submission to the device idle.
//! - **quality**: `render::random::battery` on each generator's CPU twin.
//! - **generators alone**: draws per second of `gpu::random_variants::DrawRate` (each
//!   invocation sums 256 draws of its stream) and its CPU twin, the sums checked against each
//!   other first.
//! - **images** (`--image DIR`): the first scene rendered with SPPM on the GPU with each
//!   generator, equal passes, `DIR/rng-<name>.png`; and plots of successive pairs of each
//!   generator's draws, `DIR/rng-pairs-<name>.png`.
//!
//! Before it reports a GPU figure, one more pass is checked against the CPU twin slot by slot
//! (path depth and stored photon); the noise function is exempt (GPU `sin` is approximate).

use std::path::Path;
use std::time::Instant;

use anyhow::{Context, bail};
use rayon::prelude::*;

use bvh::PackedBvh;
use cpu::{SceneData, kernels};
use gpu::GpuContext;
use gpu::random_variants::{Generator, sppm_source_with};
use gpu::sppm::GpuBackend;
use render::buffers::{PathSlot, SppmParams, counter};
use render::random::{FractSin, Pcg, TalkFloat, Tea, battery};
use render::{Backend, BackendError, PhotonTracing, Settings, Sppm};

use super::host::{BenchHost, median, open_gpu};
use crate::cli::{BenchDevice, RngArgs};

mod draws;
mod images;
mod report;

use report::{Report, Row, battery_rows, print_battery, print_row, print_speed_header, row};

/// Image side of the (unused) pixel buffers the speed runs allocate.
const PIXELS_SIDE: u32 = 16;
/// Share of slots whose GPU step may differ from the CPU twin's (a rounding that flips a
/// branch) before the bench refuses to report.
const MAX_DIVERGED: f64 = 0.01;

/// One timed run: paths emitted and the seconds taken.
#[derive(Clone, Copy, Debug)]
pub(super) struct Run {
    paths: u64,
    seconds: f64,
}

type Step = fn(&SceneData, &SppmParams, u32, u32, PathSlot) -> kernels::PhotonStep;

/// The CPU twin of the photon pass with `generator`.
fn cpu_step(generator: Generator) -> Step {
    match generator {
        Generator::Pcg => kernels::photon_pass_with::<Pcg>,
        Generator::TalkFloat => kernels::photon_pass_with::<TalkFloat>,
        Generator::Tea => kernels::photon_pass_with::<Tea>,
        Generator::FractSin => kernels::photon_pass_with::<FractSin>,
    }
}

pub fn run(args: &RngArgs) -> anyhow::Result<()> {
    let json_file = args
        .json
        .as_deref()
        .map(crate::output_file::PendingFile::create)
        .transpose()?;
    if let Some(dir) = &args.image {
        std::fs::create_dir_all(dir)
            .with_context(|| format!("{}: cannot create the image directory", dir.display()))?;
    }
    let gpu = open_gpu(&args.devices, args.adapter.as_deref())?;
    if args.image.is_some() && gpu.is_none() {
        bail!("--image renders on the GPU, and no GPU adapter is in use (see --devices)");
    }
    let mut report = Report {
        host: BenchHost::here(gpu.as_ref(), "wall"),
        photon_slots: args.photons,
        passes: args.passes,
        runs: args.runs,
        battery_draws: args.battery_draws,
        significance: battery::SIGNIFICANCE,
        battery: Vec::new(),
        draw_rates: Vec::new(),
        results: Vec::new(),
        images: Vec::new(),
    };
    match &gpu {
        Some(context) => println!("gpu: {}", context.description()),
        None => println!("gpu: none"),
    }
    println!(
        "cpu: {} ({} threads); {} slots, runs of {} photon passes; warm-up, then median of {} \
         runs, generators alternating",
        report.host.cpu_model, report.host.cpu_threads, args.photons, args.passes, args.runs
    );
    print_speed_header();
    for path in &args.scenes {
        let rows =
            bench_scene(args, gpu.as_ref(), path).with_context(|| format!("{}", path.display()))?;
        report.results.extend(rows);
    }
    let n = args.battery_draws;
    report.battery = [
        battery_rows::<Pcg>(n),
        battery_rows::<TalkFloat>(n),
        battery_rows::<Tea>(n),
        battery_rows::<FractSin>(n),
    ]
    .into_iter()
    .flatten()
    .collect();
    print_battery(&report.battery, n);
    report.draw_rates = draws::draw_rates(args, gpu.as_ref())?;
    if let (Some(dir), Some(context)) = (&args.image, &gpu) {
        report.images = images::render_images(args, context, &args.scenes[0], dir)
            .with_context(|| format!("{}", args.scenes[0].display()))?;
    }
    if let Some(mut file) = json_file {
        serde_json::to_writer_pretty(file.file(), &report)?;
        file.commit()?;
    }
    for row in &report.results {
        if let Some(d) = row.diverged
            && d as f64 > MAX_DIVERGED * f64::from(row.photon_slots)
        {
            bail!(
                "{} ({}): {d} of {} slots differ between the GPU and the CPU twin: a bug",
                row.scene,
                row.generator,
                row.photon_slots
            );
        }
    }
    Ok(())
}

/// The scene, its BVH and the speed runs' settings.
struct Loaded {
    scene: scene::Scene,
    bvh: PackedBvh,
    camera: scene::Camera,
}

fn load(args: &RngArgs, path: &Path) -> anyhow::Result<Loaded> {
    let scene = scene::load(path)?;
    crate::cmd::info::check_bvh_limits(&scene)?;
    let bvh = PackedBvh::build(&scene.triangles, &crate::cmd::info::build_options(args.bvh));
    let camera = scene.camera(None).context("the scene has no camera")?;
    Ok(Loaded { scene, bvh, camera })
}

fn bench_scene(args: &RngArgs, gpu: Option<&GpuContext>, path: &Path) -> anyhow::Result<Vec<Row>> {
    let loaded = load(args, path)?;
    let settings = Settings::new(PIXELS_SIDE, PIXELS_SIDE, args.photons);
    let data = SceneData::new(&loaded.scene, loaded.bvh.clone());
    let lights = data.lights.len() as u32;
    let params = render::integrator::params(&loaded.scene, &loaded.camera, &settings, lights);
    let label = |device, generator: Generator, runs: &[Run], diverged| {
        let mut row = row(args, device, generator, runs, diverged);
        row.path = path.display().to_string();
        row.scene = path
            .file_stem()
            .map_or_else(String::new, |s| s.to_string_lossy().into_owned());
        row
    };
    let mut rows = Vec::new();
    if let Some(context) = gpu {
        let mut renders = Generator::ALL
            .iter()
            .map(|&g| {
                let backend = GpuBackend::with_kernels(
                    context.clone(),
                    &loaded.scene,
                    loaded.bvh.clone(),
                    g.part().0,
                    sppm_source_with(g),
                )?;
                Ok(Sppm::new(
                    backend,
                    &loaded.scene,
                    &loaded.camera,
                    settings.clone(),
                )?)
            })
            .collect::<anyhow::Result<Vec<_>>>()?;
        let runs = measure(&mut renders, args, |sppm, passes| {
            timed_gpu(sppm.backend(), passes)
        })?;
        for ((g, sppm), runs) in Generator::ALL.into_iter().zip(&mut renders).zip(&runs) {
            let diverged = if g == Generator::FractSin {
                None
            } else {
                Some(check_pass(sppm.backend(), &data, &params, cpu_step(g))?)
            };
            rows.push(label("gpu", g, runs, diverged));
        }
    }
    if args.devices.contains(&BenchDevice::Cpu) {
        let mut twins: Vec<CpuSlots> = Generator::ALL
            .iter()
            .map(|&g| CpuSlots {
                step: cpu_step(g),
                slots: vec![PathSlot::IDLE; args.photons as usize],
                pass: 0,
            })
            .collect();
        let runs = measure(&mut twins, args, |twin, passes| {
            Ok(twin.advance(&data, &params, passes))
        })?;
        for (g, runs) in Generator::ALL.into_iter().zip(&runs) {
            rows.push(label("cpu", g, runs, None));
        }
    }
    // ×pcg within each device: PCG is the first generator of each device's rows.
    for chunk in rows.chunks_mut(Generator::ALL.len()) {
        let pcg = chunk[0].photon_paths_per_s;
        for row in chunk.iter_mut() {
            row.over_pcg = row.photon_paths_per_s / pcg;
            print_row(row);
        }
    }
    Ok(rows)
}

/// Two warm-up runs of every variant (the first fills every slot with a path in flight), then
/// `--runs` runs of each, alternating.
fn measure<V, R: Clone>(
    variants: &mut [V],
    args: &RngArgs,
    mut timed: impl FnMut(&mut V, u32) -> Result<R, BackendError>,
) -> Result<Vec<Vec<R>>, BackendError> {
    for _ in 0..2 {
        for variant in variants.iter_mut() {
            timed(variant, args.passes)?;
        }
    }
    let mut runs = vec![Vec::new(); variants.len()];
    for _ in 0..args.runs {
        for (variant, runs) in variants.iter_mut().zip(&mut runs) {
            runs.push(timed(variant, args.passes)?);
        }
    }
    Ok(runs)
}

fn timed_gpu(backend: &mut GpuBackend, passes: u32) -> Result<Run, BackendError> {
    let before = backend.emitted_paths()?;
    let started = Instant::now();
    for _ in 0..passes {
        backend.photon_pass();
        backend.finish_pass();
    }
    backend.synchronize()?;
    let seconds = started.elapsed().as_secs_f64();
    let paths = backend.emitted_paths()? - before;
    Ok(Run { paths, seconds })
}

/// The CPU twin's slots, advanced pass by pass on all cores.
struct CpuSlots {
    step: Step,
    slots: Vec<PathSlot>,
    pass: u32,
}

impl CpuSlots {
    fn advance(&mut self, data: &SceneData, params: &SppmParams, passes: u32) -> Run {
        let started = Instant::now();
        let mut paths = 0u64;
        for _ in 0..passes {
            let (step, pass) = (self.step, self.pass);
            paths += self
                .slots
                .par_iter_mut()
                .enumerate()
                .map(|(i, slot)| {
                    let next = step(data, params, pass, i as u32, *slot);
                    *slot = next.slot;
                    u64::from(next.emitted)
                })
                .sum::<u64>();
            self.pass += 1;
        }
        let seconds = started.elapsed().as_secs_f64();
        Run { paths, seconds }
    }
}

/// One more GPU pass against the CPU twin on the GPU's slots: slots whose depth or stored
/// photon differ.
fn check_pass(
    backend: &mut GpuBackend,
    data: &SceneData,
    params: &SppmParams,
    step: Step,
) -> Result<usize, BackendError> {
    let pass = backend.counters()?[counter::PASS];
    let before = backend.read_slots()?;
    backend.photon_pass();
    backend.finish_pass();
    let slots = backend.read_slots()?;
    let photons = backend.read_photons()?;
    Ok((0..before.len())
        .into_par_iter()
        .filter(|&i| {
            let twin = step(data, params, pass, i as u32, before[i]);
            twin.slot.depth != slots[i].depth || twin.photon.is_stored() != photons[i].is_stored()
        })
        .count())
}
