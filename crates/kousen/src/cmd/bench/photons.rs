//! `kousen bench photons SCENE...`: photon paths per second and per minute on the GPU adapter
//! and the CPU backend, for the two ways of tracing photons the talk compares (issue 6):
//!
//! - **async**: one bounce per pass with asynchronous path regeneration (`photon_pass`, as
//!   renders run it, without the hash and gather): every slot advances one segment per pass and
//!   an ended path is replaced in the same pass;
//! - **naive**: every slot traces a new path to its end in one pass (`photon_trace_naive`), so
//!   a SIMD group waits for its longest path.
//!
//! Both run the same bounce code on the same number of slots. Each run of the async scheme is
//! `--passes` passes from a steady state (every slot in flight); each naive run traces as many
//! paths as a steady async run (measured in the warm-up), rounded to whole passes of slots. A
//! warm-up of each, then `--runs` runs of each, alternating; medians reported. GPU time is the wall time from the first submission to the
//! device idle (the emitted count is read before and after, outside the timing). Before it
//! reports, the bench checks the GPU's naive paths against the CPU twin, path by path.

use std::collections::BTreeMap;
use std::path::Path;
use std::time::Instant;

use anyhow::{Context, bail};
use rayon::prelude::*;
use serde::Serialize;

use bvh::PackedBvh;
use cpu::{CpuBackend, SceneData, kernels};
use gpu::GpuContext;
use gpu::sppm::GpuBackend;
use render::{BackendError, PhotonTracing, Settings, Sppm};

use super::host::{self, cpu_model, median, open_gpu};
use super::occupancy;
use crate::cli::{BenchDevice, PhotonsArgs};

/// Invocations per workgroup of the GPU kernels.
const WORKGROUP_SIZE: u32 = gpu::prelude::WORKGROUP_SIZE;
/// Lockstep widths at which the naive scheme's occupancy is also given: lavapipe's SIMD
/// groups, NVIDIA's warps, AMD GCN's waves and our workgroups.
const REPORTED_WIDTHS: [u32; 3] = [8, 32, 64];
/// Image side of the (unused) pixel buffers the render state allocates.
const PIXELS_SIDE: u32 = 16;
/// Share of naive paths whose GPU length may differ from the CPU twin's (a rounding that flips
/// a branch) before the bench refuses to report.
const MAX_MISMATCHED: f64 = 0.01;

/// The JSON report (a contract for scripts: adapter, cpu_model, results[...] with scene,
/// device, scheme, photon_paths, seconds, photon_paths_per_s, photon_paths_per_min, occupancy;
/// the other keys are extras).
#[derive(Serialize)]
struct Report {
    adapter: Option<AdapterReport>,
    cpu_model: String,
    cpu_threads: usize,
    /// "wall" (submit to idle), null without a GPU.
    gpu_timing: Option<&'static str>,
    photon_slots: u32,
    /// Passes per timed run of the async scheme.
    passes: u32,
    runs: u32,
    max_depth: u32,
    workgroup_size: u32,
    /// The command line that made this report.
    command: String,
    results: Vec<Row>,
}

#[derive(Serialize)]
struct AdapterReport {
    #[serde(flatten)]
    adapter: host::AdapterReport,
    /// The adapter's largest subgroup (SIMD) size: the lockstep width of the GPU rows.
    subgroup_size: u32,
}

#[derive(Serialize)]
struct Row {
    /// The scene file's stem.
    scene: String,
    /// The scene file as given.
    path: String,
    device: &'static str,
    /// "async" or "naive".
    scheme: &'static str,
    photon_slots: u32,
    /// Passes (dispatches) per run.
    passes: u32,
    /// Paths traced per run (median).
    photon_paths: u64,
    /// Seconds per run (median).
    seconds: f64,
    /// Median over the runs of paths / seconds.
    photon_paths_per_s: f64,
    photon_paths_per_min: f64,
    /// This row's paths/s over the naive scheme's on the same device (async rows).
    over_naive: Option<f64>,
    /// Mean segments (rays) per path.
    segments_per_path: f64,
    /// The longest path of the last naive pass (naive rows).
    longest_path: Option<u32>,
    /// Lanes that run in lockstep: the adapter's subgroup size on the GPU, 1 on the CPU
    /// (each rayon thread traces its paths one after another).
    lockstep_width: u32,
    /// Share of lane time spent tracing at `lockstep_width` (see `occupancy`).
    occupancy: f64,
    /// The same with whole 64-invocation workgroups in lockstep (GPU rows).
    occupancy_workgroup: Option<f64>,
    /// Naive rows: the occupancy the last pass's paths would give at widths 8, 32 and 64.
    occupancy_by_width: Option<BTreeMap<u32, f64>>,
    /// GPU naive rows: paths whose length differs from the CPU twin's.
    mismatches: Option<usize>,
}

/// One timed run: paths emitted and the seconds taken.
#[derive(Clone, Copy, Debug)]
struct Run {
    paths: u64,
    seconds: f64,
}

/// Both schemes measured on one backend.
struct Measurement {
    asynchronous: Vec<Run>,
    naive: Vec<Run>,
    /// Passes per run of each scheme.
    async_passes: u32,
    naive_passes: u32,
    /// Segment counts of the last naive pass, and that pass's index.
    segments: Vec<u32>,
    last_naive_pass: u32,
}

pub fn run(args: &PhotonsArgs) -> anyhow::Result<()> {
    let json_file = args
        .json
        .as_deref()
        .map(crate::output_file::PendingFile::create)
        .transpose()?;
    let gpu = open_gpu(&args.devices, args.adapter.as_deref())?;
    let mut report = Report {
        adapter: gpu.as_ref().map(adapter_report),
        cpu_model: cpu_model(),
        cpu_threads: rayon::current_num_threads(),
        gpu_timing: gpu.as_ref().map(|_| "wall"),
        photon_slots: args.photons,
        passes: args.passes,
        runs: args.runs,
        max_depth: args.max_depth,
        workgroup_size: WORKGROUP_SIZE,
        command: std::env::args().collect::<Vec<_>>().join(" "),
        results: Vec::new(),
    };
    print_header(&report, gpu.as_ref());
    for path in &args.scenes {
        let rows =
            bench_scene(args, gpu.as_ref(), path).with_context(|| format!("{}", path.display()))?;
        report.results.extend(rows);
    }
    if let Some(mut file) = json_file {
        serde_json::to_writer_pretty(file.file(), &report)?;
        file.commit()?;
    }
    for row in &report.results {
        if let Some(m) = row.mismatches
            && m as f64 > MAX_MISMATCHED * f64::from(row.photon_slots)
        {
            bail!(
                "{}: {m} of {} naive paths differ in length between the GPU and the CPU twin: a bug",
                row.scene,
                row.photon_slots
            );
        }
    }
    Ok(())
}

fn adapter_report(context: &GpuContext) -> AdapterReport {
    AdapterReport {
        adapter: host::AdapterReport::of(context),
        subgroup_size: lockstep_width(context),
    }
}

/// The GPU's lockstep width: the adapter's largest subgroup size (8 on lavapipe's 256-bit
/// vectors, 32 on NVIDIA), which gives the most idle lanes where sizes vary.
fn lockstep_width(context: &GpuContext) -> u32 {
    context.info.subgroup_max_size.max(1)
}

fn print_header(report: &Report, gpu: Option<&GpuContext>) {
    match gpu {
        Some(context) if context.is_cpu_device() => println!(
            "gpu: {} — a CPU-type adapter standing in for a GPU; subgroup size {}",
            context.description(),
            lockstep_width(context)
        ),
        Some(context) => println!(
            "gpu: {}; subgroup size {}",
            context.description(),
            lockstep_width(context)
        ),
        None => println!("gpu: none"),
    }
    println!(
        "cpu: {} ({} threads); {} slots, async runs of {} passes, naive runs of as many paths; \
         warm-up, then median of {} runs, schemes alternating",
        report.cpu_model, report.cpu_threads, report.photon_slots, report.passes, report.runs
    );
    println!(
        "{:<18} {:<4} {:<6} {:>6} {:>10} {:>8} {:>9} {:>10} {:>7} {:>8} {:>7} {:>6} {:>7} {:>10}",
        "scene",
        "dev",
        "scheme",
        "passes",
        "paths/run",
        "seconds",
        "Mpaths/s",
        "Mpaths/min",
        "×naive",
        "seg/path",
        "longest",
        "occ",
        "occ(64)",
        "mismatches"
    );
}

fn print_row(row: &Row) {
    let optional = |v: Option<String>| v.unwrap_or_else(|| "-".to_owned());
    println!(
        "{:<18} {:<4} {:<6} {:>6} {:>10} {:>8.3} {:>9.3} {:>10.1} {:>7} {:>8.2} {:>7} {:>6.3} {:>7} {:>10}",
        row.scene,
        row.device,
        row.scheme,
        row.passes,
        row.photon_paths,
        row.seconds,
        row.photon_paths_per_s / 1e6,
        row.photon_paths_per_min / 1e6,
        optional(row.over_naive.map(|r| format!("{r:.2}"))),
        row.segments_per_path,
        optional(row.longest_path.map(|l| l.to_string())),
        row.occupancy,
        optional(row.occupancy_workgroup.map(|o| format!("{o:.3}"))),
        optional(row.mismatches.map(|m| m.to_string())),
    );
}

fn bench_scene(
    args: &PhotonsArgs,
    gpu: Option<&GpuContext>,
    path: &Path,
) -> anyhow::Result<Vec<Row>> {
    let scene = scene::load(path)?;
    crate::cmd::info::check_bvh_limits(&scene)?;
    let bvh = PackedBvh::build(&scene.triangles, &crate::cmd::info::build_options(args.bvh));
    let camera = scene.camera(None).context("the scene has no camera")?;
    let settings = Settings {
        max_depth: args.max_depth,
        ..Settings::new(PIXELS_SIDE, PIXELS_SIDE, args.photons)
    };
    let stem = path
        .file_stem()
        .map_or_else(String::new, |s| s.to_string_lossy().into_owned());
    let label = |device| Label {
        scene: stem.clone(),
        path: path.display().to_string(),
        device,
        slots: args.photons,
    };
    let mut rows = Vec::new();
    if let Some(context) = gpu {
        let backend = GpuBackend::new(context.clone(), &scene, bvh.clone())?;
        let mut sppm = Sppm::new(backend, &scene, &camera, settings.clone())?;
        let measured = measure(sppm.backend(), args)?;
        // The GPU's last naive pass against the CPU twin, path by path.
        let data = SceneData::new(&scene, bvh.clone());
        let lights = data.lights.len() as u32;
        let params = render::integrator::params(&scene, &camera, &settings, lights);
        let mismatches = (0..args.photons)
            .into_par_iter()
            .filter(|&i| {
                let twin = kernels::photon_trace_naive(&data, &params, measured.last_naive_pass, i);
                twin.segments != measured.segments[i as usize]
            })
            .count();
        let width = lockstep_width(context);
        rows.extend(rows_for(label("gpu"), &measured, width, Some(mismatches)));
    }
    if args.devices.contains(&BenchDevice::Cpu) {
        let backend = CpuBackend::new(SceneData::new(&scene, bvh));
        let mut sppm = Sppm::new(backend, &scene, &camera, settings)?;
        let measured = measure(sppm.backend(), args)?;
        rows.extend(rows_for(label("cpu"), &measured, 1, None));
    }
    Ok(rows)
}

/// Which scene, device and slot count a row is about.
struct Label {
    scene: String,
    path: String,
    device: &'static str,
    slots: u32,
}

/// Warm-ups of each scheme, then `--runs` runs of each, alternating.
fn measure<B: PhotonTracing>(
    backend: &mut B,
    args: &PhotonsArgs,
) -> Result<Measurement, BackendError> {
    let mut passes_done = 0u32;
    let mut timed = |backend: &mut B, passes: u32, kernel: fn(&mut B)| {
        let before = backend.emitted_paths()?;
        let started = Instant::now();
        for _ in 0..passes {
            kernel(backend);
            backend.finish_pass();
        }
        backend.synchronize()?;
        let seconds = started.elapsed().as_secs_f64();
        passes_done += passes;
        let paths = backend.emitted_paths()? - before;
        Ok::<Run, BackendError>(Run { paths, seconds })
    };
    // Two warm-ups of the async scheme: the first fills every slot with a path in flight (its
    // first pass emits a path in every slot), the second, as steady as the timed runs, sizes
    // the naive runs.
    timed(backend, args.passes, B::photon_pass)?;
    let steady = timed(backend, args.passes, B::photon_pass)?;
    let naive_passes = ((steady.paths as f64 / f64::from(args.photons)).round() as u32).max(1);
    timed(backend, naive_passes, B::photon_trace_naive)?;
    let mut measurement = Measurement {
        asynchronous: Vec::new(),
        naive: Vec::new(),
        async_passes: args.passes,
        naive_passes,
        segments: Vec::new(),
        last_naive_pass: 0,
    };
    for _ in 0..args.runs {
        measurement
            .asynchronous
            .push(timed(backend, args.passes, B::photon_pass)?);
        measurement
            .naive
            .push(timed(backend, naive_passes, B::photon_trace_naive)?);
    }
    measurement.last_naive_pass = passes_done - 1;
    measurement.segments = backend.read_path_segments()?;
    Ok(measurement)
}

/// The async and naive rows of one device.
fn rows_for(
    label: Label,
    measured: &Measurement,
    width: u32,
    mismatches: Option<usize>,
) -> Vec<Row> {
    let on_gpu = mismatches.is_some();
    let segments = &measured.segments;
    let naive_row = {
        let mut row = row(&label, "naive", measured.naive_passes, &measured.naive);
        row.segments_per_path =
            segments.iter().map(|&s| f64::from(s)).sum::<f64>() / segments.len().max(1) as f64;
        row.longest_path = segments.iter().copied().max();
        row.lockstep_width = width;
        row.occupancy = occupancy::naive(segments, width as usize);
        row.occupancy_workgroup =
            on_gpu.then(|| occupancy::naive(segments, WORKGROUP_SIZE as usize));
        row.occupancy_by_width = Some(
            REPORTED_WIDTHS
                .iter()
                .map(|&w| (w, occupancy::naive(segments, w as usize)))
                .collect(),
        );
        row.mismatches = mismatches;
        row
    };
    let async_row = {
        let mut row = row(
            &label,
            "async",
            measured.async_passes,
            &measured.asynchronous,
        );
        // Every slot traces one segment per pass.
        let segments_traced = f64::from(label.slots) * f64::from(measured.async_passes);
        row.segments_per_path = segments_traced / (row.photon_paths.max(1) as f64);
        row.lockstep_width = width;
        row.occupancy = occupancy::asynchronous(label.slots, width);
        row.occupancy_workgroup =
            on_gpu.then(|| occupancy::asynchronous(label.slots, WORKGROUP_SIZE));
        row.over_naive = Some(row.photon_paths_per_s / naive_row.photon_paths_per_s);
        row
    };
    let rows = vec![async_row, naive_row];
    rows.iter().for_each(print_row);
    rows
}

/// A row's timing columns from its runs; the rest default.
fn row(label: &Label, scheme: &'static str, passes: u32, runs: &[Run]) -> Row {
    let rates: Vec<f64> = runs
        .iter()
        .map(|r| r.paths as f64 / r.seconds.max(1e-9))
        .collect();
    let paths: Vec<f64> = runs.iter().map(|r| r.paths as f64).collect();
    let seconds: Vec<f64> = runs.iter().map(|r| r.seconds).collect();
    let per_s = median(&rates);
    Row {
        scene: label.scene.clone(),
        path: label.path.clone(),
        device: label.device,
        scheme,
        photon_slots: label.slots,
        passes,
        photon_paths: median(&paths).round() as u64,
        seconds: median(&seconds),
        photon_paths_per_s: per_s,
        photon_paths_per_min: per_s * 60.0,
        over_naive: None,
        segments_per_path: 0.0,
        longest_path: None,
        lockstep_width: 1,
        occupancy: 1.0,
        occupancy_workgroup: None,
        occupancy_by_width: None,
        mismatches: None,
    }
}
