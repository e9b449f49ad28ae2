//! The kernels' random generators on the GPU against their `render::random` twins
//! (issue 6, table 6), on whatever adapter wgpu finds (lavapipe in CI):
//!
//! - `draws_match_the_cpu_twins`: a small kernel writes each generator's first draws of many
//!   streams; PCG and TEA (integer-only) equal the CPU's bit for bit, the talk's float
//!   generator within 2⁻²² (exact integer states, a rounded output sum), and the noise
//!   function, whose GPU `sin` is approximate, in distribution (two-sample chi-square);
//! - `photon_pass_matches_its_cpu_twin_per_generator`: the photon pass compiled with each
//!   generator against `cpu::kernels::photon_pass_with` on the GPU's own slots, three passes
//!   on the shipped caustics scene; the noise function by the share of paths emitted only.

use std::path::PathBuf;

use bvh::{BuildOptions, PackedBvh};
use cpu::{SceneData, kernels};
use gpu::GpuContext;
use gpu::random_variants::{Generator, generator_source, sppm_source_with};
use gpu::readback::read_buffer;
use gpu::sppm::GpuBackend;
use render::buffers::{PathSlot, Photon, SLOT_IDLE, SppmParams, vec3};
use render::random::{FractSin, Pcg, StreamRng, TalkFloat, Tea};
use render::rng::PHOTON_STREAM;
use render::{Backend, PhotonTracing, Settings, Sppm};
use scene::Scene;

const STREAMS: u32 = 8192;
const DRAWS: u32 = 8;
const SEED: u32 = 7;
const SLOTS: u32 = 4096;
/// Share of slots whose GPU step may differ from the twin's (a rounding that flips a branch),
/// as `sppm_twins.rs` allows.
const MAX_DIVERGED: f64 = 0.005;
const POSITION_TOLERANCE: f32 = 1e-4;
const RELATIVE_TOLERANCE: f32 = 1e-4;

fn context() -> GpuContext {
    GpuContext::new(None).unwrap_or_else(|e| {
        panic!("no usable GPU adapter in the test environment (CI installs Mesa lavapipe): {e}")
    })
}

/// Draw k of stream i (pass i mod 5) lands at i · DRAWS + k.
const DRAW_KERNEL: &str = r#"
@group(0) @binding(0) var<storage, read_write> draws: array<f32>;

@compute @workgroup_size(64)
fn write_draws(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&draws) / DRAWS {
        return;
    }
    var rng = rng_start(SEED, PHOTON_STREAM, i % 5u, i);
    for (var k = 0u; k < DRAWS; k++) {
        draws[i * DRAWS + k] = next_f32(&rng);
    }
}
"#;

fn gpu_draws(context: &GpuContext, generator: Generator) -> Vec<f32> {
    let source = format!(
        "{}\nconst DRAWS: u32 = {DRAWS}u;\nconst SEED: u32 = {SEED}u;\n{DRAW_KERNEL}",
        generator_source(generator)
    );
    let device = &context.device;
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("write_draws"),
        source: wgpu::ShaderSource::Wgsl(source.into()),
    });
    let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some("write_draws"),
        layout: None,
        module: &module,
        entry_point: Some("write_draws"),
        compilation_options: Default::default(),
        cache: None,
    });
    let count = (STREAMS * DRAWS) as usize;
    let buffer = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("draws"),
        size: (count * size_of::<f32>()) as u64,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("draws"),
        layout: &pipeline.get_bind_group_layout(0),
        entries: &[wgpu::BindGroupEntry {
            binding: 0,
            resource: buffer.as_entire_binding(),
        }],
    });
    let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor::default());
    {
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor::default());
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &bind_group, &[]);
        pass.dispatch_workgroups(STREAMS.div_ceil(64), 1, 1);
    }
    context.queue.submit([encoder.finish()]);
    read_buffer(context, &buffer, count).expect("draws read back")
}

fn cpu_draws<G: StreamRng>() -> Vec<f32> {
    (0..STREAMS)
        .flat_map(|i| {
            let mut rng = G::start(SEED, PHOTON_STREAM, i % 5, i);
            (0..DRAWS).map(move |_| rng.next_f32())
        })
        .collect()
}

fn twin_draws(generator: Generator) -> Vec<f32> {
    match generator {
        Generator::Pcg => cpu_draws::<Pcg>(),
        Generator::TalkFloat => cpu_draws::<TalkFloat>(),
        Generator::Tea => cpu_draws::<Tea>(),
        Generator::FractSin => cpu_draws::<FractSin>(),
    }
}

/// Two-sample chi-square over 32 bins (equal sample sizes).
fn two_sample_chi_square(a: &[f32], b: &[f32]) -> f64 {
    let histogram = |v: &[f32]| {
        let mut h = [0u32; 32];
        for &x in v {
            h[((x * 32.0) as usize).min(31)] += 1;
        }
        h
    };
    let (ha, hb) = (histogram(a), histogram(b));
    ha.iter()
        .zip(&hb)
        .filter(|(x, y)| **x + **y > 0)
        .map(|(&x, &y)| (f64::from(x) - f64::from(y)).powi(2) / f64::from(x + y))
        .sum()
}

#[test]
fn draws_match_the_cpu_twins() {
    let context = context();
    for generator in Generator::ALL {
        let name = generator.name();
        let gpu = gpu_draws(&context, generator);
        let cpu = twin_draws(generator);
        assert!(
            gpu.iter().all(|x| (0.0..1.0).contains(x)),
            "{name}: a GPU draw outside [0, 1)"
        );
        match generator {
            Generator::Pcg | Generator::Tea => {
                let differing = gpu.iter().zip(&cpu).filter(|(g, c)| g != c).count();
                assert_eq!(differing, 0, "{name}: draws differ from the CPU twin's");
            }
            Generator::TalkFloat => {
                // Distance on the circle: a sum rounding either side of an integer wraps.
                let worst = gpu
                    .iter()
                    .zip(&cpu)
                    .map(|(g, c)| {
                        let d = (g - c).abs();
                        d.min(1.0 - d)
                    })
                    .fold(0.0, f32::max);
                assert!(
                    worst <= 1.0 / 4_194_304.0,
                    "{name}: worst difference {worst}"
                );
            }
            Generator::FractSin => {
                // chi-square with 31 degrees of freedom: 61.1 at significance 0.001.
                let chi2 = two_sample_chi_square(&gpu, &cpu);
                let same = gpu.iter().zip(&cpu).filter(|(g, c)| g == c).count();
                eprintln!(
                    "{name}: chi2 {chi2:.1}, {same} of {} draws equal",
                    gpu.len()
                );
                assert!(
                    chi2 < 61.1,
                    "{name}: GPU and CPU distributions differ, chi2 {chi2}"
                );
            }
        }
    }
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
        let settings = Settings {
            seed: 3,
            ..Settings::new(16, 16, SLOTS)
        };
        Fixture {
            scene,
            bvh,
            settings,
        }
    }

    fn gpu(&self, context: GpuContext, generator: Generator) -> Sppm<GpuBackend> {
        let source = sppm_source_with(generator);
        let backend =
            GpuBackend::with_kernels(context, &self.scene, self.bvh.clone(), "sppm", source)
                .expect("gpu backend");
        let camera = self.scene.camera(None).expect("a camera");
        Sppm::new(backend, &self.scene, &camera, self.settings.clone()).expect("render started")
    }

    fn params(&self) -> SppmParams {
        let camera = self.scene.camera(None).expect("a camera");
        let lights = render::emission::light_table(&self.scene).len() as u32;
        render::integrator::params(&self.scene, &camera, &self.settings, lights)
    }
}

fn twin_step(
    generator: Generator,
    data: &SceneData,
    params: &SppmParams,
    pass: u32,
    slots: &[PathSlot],
) -> Vec<kernels::PhotonStep> {
    let step = match generator {
        Generator::Pcg => kernels::photon_pass_with::<Pcg>,
        Generator::TalkFloat => kernels::photon_pass_with::<TalkFloat>,
        Generator::Tea => kernels::photon_pass_with::<Tea>,
        Generator::FractSin => kernels::photon_pass_with::<FractSin>,
    };
    slots
        .iter()
        .enumerate()
        .map(|(i, &slot)| step(data, params, pass, i as u32, slot))
        .collect()
}

fn close(a: [f32; 3], b: [f32; 3], tolerance: f32) -> bool {
    (vec3(a) - vec3(b)).abs().max_element() <= tolerance
}

fn slots_agree(g: &PathSlot, c: &PathSlot, diagonal: f32) -> bool {
    let scale = vec3(g.flux).abs().max(vec3(c.flux).abs()).max_element();
    g.depth == c.depth
        && g.pass_throughs == c.pass_throughs
        && close(g.origin, c.origin, POSITION_TOLERANCE * diagonal)
        && close(g.direction, c.direction, POSITION_TOLERANCE)
        && close(g.flux, c.flux, RELATIVE_TOLERANCE * scale)
}

fn photons_agree(g: &Photon, c: &Photon, diagonal: f32) -> bool {
    let scale = vec3(g.flux).abs().max(vec3(c.flux).abs()).max_element();
    g.is_stored() == c.is_stored()
        && close(g.position, c.position, POSITION_TOLERANCE * diagonal)
        && close(g.flux, c.flux, RELATIVE_TOLERANCE * scale)
}

#[test]
fn photon_pass_matches_its_cpu_twin_per_generator() {
    let fixture = Fixture::caustics();
    let data = SceneData::new(&fixture.scene, fixture.bvh.clone());
    let params = fixture.params();
    let diagonal = fixture.scene.bounds().extent().length();
    let context = context();
    for generator in Generator::ALL {
        let name = generator.name();
        let mut sppm = fixture.gpu(context.clone(), generator);
        let gpu = sppm.backend();
        for pass in 0..3u32 {
            let before = gpu.read_slots().expect("slots");
            gpu.photon_pass();
            gpu.finish_pass();
            let slots = gpu.read_slots().expect("slots");
            let photons = gpu.read_photons().expect("photons");
            let twin = twin_step(generator, &data, &params, pass, &before);
            let idle = |s: &[PathSlot]| s.iter().filter(|s| s.depth == SLOT_IDLE).count();
            let stored = |p: &[Photon]| p.iter().filter(|p| p.is_stored()).count();
            let twin_slots: Vec<PathSlot> = twin.iter().map(|t| t.slot).collect();
            let twin_photons: Vec<Photon> = twin.iter().map(|t| t.photon).collect();
            assert!(
                stored(&twin_photons) > SLOTS as usize / 8,
                "{name}: few photons"
            );
            if generator == Generator::FractSin {
                // Other draws, same physics: ended paths and stored photons in like shares
                // (within 5 % of the slots).
                let near = |a: usize, b: usize| a.abs_diff(b) < SLOTS as usize / 20;
                assert!(
                    near(idle(&slots), idle(&twin_slots)),
                    "{name}: pass {pass} idle"
                );
                assert!(
                    near(stored(&photons), stored(&twin_photons)),
                    "{name}: stored"
                );
                continue;
            }
            let diverged = (0..SLOTS as usize)
                .filter(|&i| {
                    !slots_agree(&slots[i], &twin_slots[i], diagonal)
                        || !photons_agree(&photons[i], &twin_photons[i], diagonal)
                })
                .count();
            assert!(
                diverged as f64 <= MAX_DIVERGED * f64::from(SLOTS),
                "{name}: pass {pass}: {diverged} of {SLOTS} slots differ from the CPU twin"
            );
        }
    }
}
