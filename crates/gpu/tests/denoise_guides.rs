//! Denoising guides (`render::guides`) on the GPU backend: read off its eye passes through
//! `Backend::read_visible_points`, they are the CPU backend's guides of the same render.

use bvh::{BuildOptions, PackedBvh};
use glam::Vec3;
use gpu::GpuContext;
use gpu::sppm::GpuBackend;
use render::guides::Guides;
use render::{Backend, Budget, Settings, Sppm};

/// Share of pixels allowed to differ: an eye path whose branch a rounding flipped (the
/// twins' allowance for visible points, `sppm_twins.rs`; none differ on lavapipe).
const MAX_DIVERGED: f64 = 0.005;

fn guides_on<B: Backend>(backend: B, scene: &scene::Scene) -> Guides {
    let camera = scene.camera(None).expect("a camera");
    let settings = Settings {
        seed: 3,
        eye_every: 1,
        ..Settings::new(32, 32, 4096)
    };
    let mut sppm = Sppm::new(backend, scene, &camera, settings).expect("render started");
    sppm.collect_guides();
    sppm.run(Budget::Passes(3), &mut |_| {}).expect("rendered");
    sppm.guides().expect("guides collected").clone()
}

/// Cornell box with a glass and a mirror ball: guides through glass and mirror chains too.
#[test]
fn gpu_guides_are_the_cpu_backend_s() {
    let scene = scene::testing::cornell_caustics();
    let bvh = PackedBvh::build(&scene.triangles, &BuildOptions::default());
    let context = GpuContext::new(None).unwrap_or_else(|e| {
        panic!("no usable GPU adapter in the test environment (CI installs Mesa lavapipe): {e}")
    });
    let gpu = GpuBackend::new(context, &scene, bvh.clone()).expect("gpu backend");
    let gpu = guides_on(gpu, &scene);
    let cpu = guides_on(
        cpu::CpuBackend::new(cpu::SceneData::new(&scene, bvh)),
        &scene,
    );
    assert_eq!((gpu.eye_passes(), cpu.eye_passes()), (3, 3));
    let (gpu_albedo, cpu_albedo) = (gpu.albedo().pixels, cpu.albedo().pixels);
    let mean = cpu_albedo.iter().sum::<Vec3>() / cpu_albedo.len() as f32;
    assert!(mean.min_element() > 0.1, "mean albedo {mean}");
    let (gpu_normal, cpu_normal) = (gpu.normal().pixels, cpu.normal().pixels);
    let diverged = (0..cpu_albedo.len())
        .filter(|&i| {
            !gpu_albedo[i].abs_diff_eq(cpu_albedo[i], 1e-4)
                || !gpu_normal[i].abs_diff_eq(cpu_normal[i], 1e-3)
        })
        .count();
    let allowed = (MAX_DIVERGED * cpu_albedo.len() as f64) as usize;
    assert!(
        diverged <= allowed,
        "{diverged} of {} pixels' guides differ (at most {allowed})",
        cpu_albedo.len()
    );
}
