//! The naive photon-tracing scheme (`photon_trace_naive.wgsl`, `render::PhotonTracing`) that
//! `kousen bench photons` measures against asynchronous path regeneration:
//!
//! - `photon_trace_naive_matches_its_cpu_twin`: per path, the same segment count and last
//!   photon as `cpu::kernels::photon_trace_naive`, on the GPU and through the CPU backend;
//! - `naive_paths_are_the_first_paths_photon_pass_traces`: naive path `i` of pass 0 is the
//!   first path slot `i` traces under `photon_pass`, one bounce per pass, on the GPU;
//! - `naive_module_binds_one_buffer_more_than_the_sppm_kernels`: the storage-buffer count the
//!   backend checks against the device's limit.
//!
//! Runs on whatever adapter wgpu finds (lavapipe in CI), on the shipped caustics scene (glass,
//! mirror and diffuse walls: paths of every length).

use std::path::PathBuf;

use bvh::{BuildOptions, PackedBvh};
use cpu::{CpuBackend, SceneData, kernels};
use gpu::GpuContext;
use gpu::shader::Module;
use gpu::sppm::{GpuBackend, NAIVE_STORAGE_BUFFERS};
use render::buffers::{Photon, SLOT_IDLE, SppmParams, counter, vec3};
use render::{Backend, PhotonTracing, Settings, Sppm};
use scene::Scene;

const SLOTS: u32 = 4096;
/// Positions: absolute, × the scene's diagonal (as `sppm_twins.rs`).
const POSITION_TOLERANCE: f32 = 1e-4;
/// Fluxes: relative. Looser than `sppm_twins.rs`'s 1e-4 because a naive path runs its whole
/// length here, and every bounce weighs its flux by the hit's shading-normal factors
/// (`render::normal_map`), which follow the hit point and its interpolated normal: through the
/// glass sphere's chain a rounding apart in position (2e-5 of the diagonal) became 3e-4 in one
/// ceiling photon's flux.
const RELATIVE_TOLERANCE: f32 = 1e-3;

fn context() -> GpuContext {
    GpuContext::new(None).unwrap_or_else(|e| {
        panic!("no usable GPU adapter in the test environment (CI installs Mesa lavapipe): {e}")
    })
}

struct Fixture {
    scene: Scene,
    bvh: PackedBvh,
    settings: Settings,
}

impl Fixture {
    fn caustics() -> Fixture {
        let path =
            PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../scenes/cornell-caustics.gltf");
        let scene = scene::load(&path).expect("the shipped caustics scene loads");
        let bvh = PackedBvh::build(&scene.triangles, &BuildOptions::default());
        Fixture {
            scene,
            bvh,
            settings: Settings {
                seed: 3,
                // The talk's path length, as `kousen bench photons` runs it. Much longer
                // chains through the glass sphere amplify the last bits in which the GPU's
                // sin and cos differ from the CPU's past the position tolerance (at 32, one
                // path of 17 segments ended 0.16 from its twin in a room of 550).
                max_depth: render::settings::GLSLPPM_MAX_DEPTH,
                ..Settings::new(16, 16, SLOTS)
            },
        }
    }

    fn start<B: PhotonTracing>(&self, backend: B) -> Sppm<B> {
        let camera = self.scene.camera(None).expect("a camera");
        Sppm::new(backend, &self.scene, &camera, self.settings.clone()).expect("render started")
    }

    fn gpu(&self, context: GpuContext) -> Sppm<GpuBackend> {
        let backend = GpuBackend::new(context, &self.scene, self.bvh.clone()).expect("gpu backend");
        self.start(backend)
    }

    fn scene_data(&self) -> SceneData {
        SceneData::new(&self.scene, self.bvh.clone())
    }

    fn params(&self) -> SppmParams {
        let camera = self.scene.camera(None).expect("a camera");
        let lights = render::emission::light_table(&self.scene).len() as u32;
        render::integrator::params(&self.scene, &camera, &self.settings, lights)
    }

    fn diagonal(&self) -> f32 {
        self.scene.bounds().extent().length()
    }
}

/// Two naive passes (pass 0, then pass 1 after `finish_pass`): the segments and photons of the
/// second, and the counters' pass and emitted total.
fn two_naive_passes<B: PhotonTracing>(
    backend: &mut B,
    photons: impl Fn(&mut B) -> Vec<Photon>,
) -> (Vec<u32>, Vec<Photon>, u64) {
    backend.photon_trace_naive();
    backend.finish_pass();
    backend.photon_trace_naive();
    backend.finish_pass();
    let segments = backend.read_path_segments().expect("segments");
    let emitted = backend.emitted_paths().expect("emitted");
    (segments, photons(backend), emitted)
}

/// Photons equal up to rounding: both stored or neither, positions and fluxes within tolerance.
fn photons_agree(g: &Photon, c: &Photon, diagonal: f32) -> bool {
    if g.is_stored() != c.is_stored() {
        return false;
    }
    let position = (vec3(g.position) - vec3(c.position)).abs().max_element();
    let scale = vec3(g.flux).abs().max(vec3(c.flux).abs()).max_element();
    let flux = (vec3(g.flux) - vec3(c.flux)).abs().max_element();
    position <= POSITION_TOLERANCE * diagonal && flux <= RELATIVE_TOLERANCE * scale
}

#[test]
fn photon_trace_naive_matches_its_cpu_twin() {
    let fixture = Fixture::caustics();
    let params = fixture.params();
    let data = fixture.scene_data();
    let twin: Vec<kernels::NaivePath> = (0..SLOTS)
        .map(|i| kernels::photon_trace_naive(&data, &params, 1, i))
        .collect();
    let twin_segments: Vec<u32> = twin.iter().map(|p| p.segments).collect();

    let mut gpu = fixture.gpu(context());
    let gpu_backend = gpu.backend();
    let (segments, photons, emitted) =
        two_naive_passes(gpu_backend, |b| b.read_photons().expect("photons"));
    let counters = gpu_backend.counters().expect("counters");
    assert_eq!(counters[counter::PASS], 2);
    assert_eq!(
        emitted,
        2 * SLOTS as u64,
        "every naive invocation emits one path"
    );

    let differing: Vec<usize> = (0..SLOTS as usize)
        .filter(|&i| segments[i] != twin_segments[i])
        .collect();
    assert!(
        differing.is_empty(),
        "{} of {SLOTS} paths differ in length, first: {:?}",
        differing.len(),
        differing
            .iter()
            .take(3)
            .map(|&i| (i, segments[i], twin_segments[i]))
            .collect::<Vec<_>>()
    );
    let diagonal = fixture.diagonal();
    let photons_differ = photons
        .iter()
        .zip(&twin)
        .filter(|(g, c)| !photons_agree(g, &c.photon, diagonal))
        .count();
    assert_eq!(photons_differ, 0, "last photons differ");

    // Paths of every kind: some escape at once, some bounce many times (glass, mirror).
    let longest = *twin_segments.iter().max().unwrap();
    let mean = twin_segments.iter().sum::<u32>() as f64 / SLOTS as f64;
    let stored = twin.iter().filter(|p| p.photon.is_stored()).count();
    eprintln!(
        "mean {mean:.2} segments per path, longest {longest}, {stored} paths stored a photon"
    );
    assert!(mean > 1.5 && longest >= 8, "mean {mean}, longest {longest}");
    assert!(
        stored > SLOTS as usize / 2,
        "{stored} paths stored a photon"
    );

    // The CPU backend runs the same kernel over its slots.
    let mut cpu = fixture.start(CpuBackend::new(fixture.scene_data()));
    let (cpu_segments, cpu_photons, cpu_emitted) =
        two_naive_passes(cpu.backend(), |b| b.photons().to_vec());
    assert_eq!(cpu_segments, twin_segments);
    assert!(cpu_photons.iter().zip(&twin).all(|(p, t)| *p == t.photon));
    assert_eq!(cpu_emitted, emitted);
}

#[test]
fn naive_paths_are_the_first_paths_photon_pass_traces() {
    let fixture = Fixture::caustics();
    let limit = kernels::naive_segment_limit(&fixture.params());
    let context = context();

    // One bounce per pass: the pass after which each slot first fell idle ends its first path.
    let mut asynchronous = fixture.gpu(context.clone());
    let backend = asynchronous.backend();
    let mut first_path = vec![0u32; SLOTS as usize];
    for pass in 0..limit {
        backend.photon_pass();
        backend.finish_pass();
        let slots = backend.read_slots().expect("slots");
        for (length, slot) in first_path.iter_mut().zip(&slots) {
            if *length == 0 && slot.depth == SLOT_IDLE {
                *length = pass + 1;
            }
        }
        if first_path.iter().all(|&l| l > 0) {
            break;
        }
    }
    assert!(
        first_path.iter().all(|&l| l > 0),
        "a path outlived its limit"
    );

    let mut naive = fixture.gpu(context);
    let backend = naive.backend();
    backend.photon_trace_naive();
    let segments = backend.read_path_segments().expect("segments");
    let differing = first_path
        .iter()
        .zip(&segments)
        .filter(|(a, b)| a != b)
        .count();
    assert_eq!(
        differing, 0,
        "naive path lengths differ from photon_pass's first paths"
    );
    assert!(segments.iter().any(|&s| s > 3), "only short paths");
}

#[test]
fn naive_module_binds_one_buffer_more_than_the_sppm_kernels() {
    let source = Module::PhotonTraceNaive.source();
    let module = naga::front::wgsl::parse_str(&source).expect("photon_trace_naive.wgsl parses");
    let storage = module
        .global_variables
        .iter()
        .filter(|(_, v)| matches!(v.space, naga::AddressSpace::Storage { .. }))
        .count();
    assert_eq!(storage as u32, NAIVE_STORAGE_BUFFERS);
    assert!(
        module
            .entry_points
            .iter()
            .any(|e| e.name == "photon_trace_naive")
    );
}
