//! The GPU backend's checkpoints: a render continued from one on a new device state equals
//! the render that was never stopped, bit for bit (f32 and f16 storage, stochastic hash and
//! sorted full lists), and a CPU backend's checkpoint, whose points are stored otherwise, is
//! refused in words rather than misread.

use gpu::GpuContext;
use gpu::sppm::GpuBackend;
use render::half_storage::Precision;
use render::{Backend, Budget, Density, Image, Settings, Sppm};

fn gpu_render(settings: &Settings) -> Sppm<GpuBackend> {
    let scene = scene::testing::cornell_caustics();
    let bvh = bvh::PackedBvh::build(&scene.triangles, &bvh::BuildOptions::default());
    let camera = scene.camera(None).unwrap();
    let context = GpuContext::new(None).unwrap_or_else(|e| {
        panic!("no usable GPU adapter in the test environment (CI installs Mesa lavapipe): {e}")
    });
    let backend = GpuBackend::new(context, &scene, bvh).expect("gpu backend");
    Sppm::new(backend, &scene, &camera, settings.clone()).expect("render started")
}

fn passes(sppm: &mut Sppm<GpuBackend>, total: u32) -> Image {
    sppm.run(Budget::Passes(total), &mut |_| {})
        .expect("render")
        .image
}

#[test]
fn gpu_render_continues_exactly_from_its_checkpoint() {
    for (density, precision) in [
        (Density::StochasticHash, Precision::F32),
        (Density::FullHash, Precision::F16),
    ] {
        let settings = Settings {
            seed: 4,
            eye_every: 3,
            density,
            precision,
            ..Settings::new(24, 20, 4096)
        };
        let straight = passes(&mut gpu_render(&settings), 6);
        let mut stopped = gpu_render(&settings);
        passes(&mut stopped, 4);
        let checkpoint = stopped.checkpoint().expect("checkpoint");
        let mut resumed = gpu_render(&settings);
        resumed.restore(&checkpoint).expect("restore");
        let continued = passes(&mut resumed, 6);
        assert!(straight.pixels.iter().any(|p| p.max_element() > 0.0));
        assert_eq!(continued, straight, "{density:?} {precision:?}");
        assert_eq!(
            resumed.backend().emitted_paths().unwrap(),
            gpu_render_paths(&settings, 6),
            "{density:?} {precision:?}: emitted paths"
        );
    }
}

fn gpu_render_paths(settings: &Settings, total: u32) -> u64 {
    let mut sppm = gpu_render(settings);
    passes(&mut sppm, total);
    sppm.backend().emitted_paths().unwrap()
}

#[test]
fn cpu_checkpoint_with_f16_points_is_refused_in_words() {
    let settings = Settings {
        precision: Precision::F16,
        ..Settings::new(24, 20, 4096)
    };
    let scene = scene::testing::cornell_caustics();
    let bvh = bvh::PackedBvh::build(&scene.triangles, &bvh::BuildOptions::default());
    let camera = scene.camera(None).unwrap();
    let cpu = cpu::CpuBackend::new(cpu::SceneData::new(&scene, bvh));
    let mut on_cpu = Sppm::new(cpu, &scene, &camera, settings.clone()).unwrap();
    on_cpu.pass();
    let checkpoint = on_cpu.checkpoint().unwrap();
    let message = gpu_render(&settings)
        .restore(&checkpoint)
        .unwrap_err()
        .to_string();
    assert!(message.contains("visible_points"), "{message}");
}
