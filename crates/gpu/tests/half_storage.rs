//! Photons and visible points stored in f16 (`render::half_storage`, issue 6, table 7) on the
//! GPU: what the f16 kernels store is the f32 kernels' result rounded as the CPU twin rounds it
//! (to within one f16 step: WGSL lets `pack2x16float` round either way), murky glass's volume
//! points with the share of their gather inside the medium in their weight
//! (`render::volume_boundary::share_in_weight`), and a render with f16 storage stays close to
//! the f32 one.

use bvh::{BuildOptions, PackedBvh};
use glam::Vec3;
use gpu::GpuContext;
use gpu::sppm::GpuBackend;
use render::buffers::vec3;
use render::half_storage::{Precision, round_photon, round_visible_point};
use render::volume_boundary::share_in_weight;
use render::{Backend, Budget, Image, Settings, Sppm};

fn context() -> GpuContext {
    GpuContext::new(None).unwrap_or_else(|e| {
        panic!("no usable GPU adapter in the test environment (CI installs Mesa lavapipe): {e}")
    })
}

fn render(context: &GpuContext, precision: Precision, seed: u32) -> Sppm<GpuBackend> {
    render_scene(context, scene::testing::cornell_caustics(), precision, seed)
}

fn render_scene(
    context: &GpuContext,
    scene: scene::Scene,
    precision: Precision,
    seed: u32,
) -> Sppm<GpuBackend> {
    let bvh = PackedBvh::build(&scene.triangles, &BuildOptions::default());
    let camera = scene.camera(None).expect("a camera");
    let settings = Settings {
        seed,
        eye_every: 2,
        precision,
        ..Settings::new(32, 32, 4096)
    };
    let backend = GpuBackend::new(context.clone(), &scene, bvh).expect("gpu backend");
    Sppm::new(backend, &scene, &camera, settings).expect("render started")
}

/// Two steps of f16 (2^-10) relative to `scale`: either rounding of the same value.
fn within_f16(a: Vec3, b: Vec3, scale: Vec3) -> bool {
    ((a - b).abs() - scale.abs() * (2.0f32).powi(-10)).max_element() <= 1e-30
}

#[test]
fn f16_kernels_store_the_f32_results_rounded() {
    let volume_points =
        f16_kernels_store_the_f32_results_rounded_in(scene::testing::cornell_caustics);
    assert_eq!(volume_points, 0);
}

/// The same in murky glass, whose volume points carry the share in their weight.
#[test]
fn f16_kernels_store_murky_glass_s_results_rounded() {
    let volume_points = f16_kernels_store_the_f32_results_rounded_in(scene::testing::cornell_murky);
    assert!(
        volume_points > 20,
        "{volume_points} volume points cut by their medium's surfaces"
    );
}

/// Compares one pass of `scene` with f16 and f32 storage; the volume points whose gather's
/// sphere the medium's surfaces cut, counted.
fn f16_kernels_store_the_f32_results_rounded_in(scene: fn() -> scene::Scene) -> usize {
    let context = context();
    let (mut full, mut half) = (
        render_scene(&context, scene(), Precision::F32, 5),
        render_scene(&context, scene(), Precision::F16, 5),
    );
    // The radii the first eye pass finds.
    let radii: Vec<f32> = (half.backend().read_statistics().expect("statistics").pixels)
        .iter()
        .map(|s| s.volume_radius)
        .collect();
    full.pass();
    half.pass();
    let params = {
        let scene = scene();
        let camera = scene.camera(None).unwrap();
        let lights = render::emission::light_table(&scene);
        let mut params =
            render::integrator::params(&scene, &camera, full.settings(), lights.len() as u32);
        params.storage_flux_scale = render::half_storage::flux_scale(&lights);
        params
    };
    let (origin, scale) = (vec3(params.storage_origin), params.storage_flux_scale);
    let photons = full.backend().read_photons().expect("f32 photons");
    let stored = half.backend().read_photons().expect("f16 photons");
    let mut compared = 0;
    for (f32_photon, f16_photon) in photons.iter().zip(&stored) {
        assert_eq!(f32_photon.is_stored(), f16_photon.is_stored());
        if !f32_photon.is_stored() {
            continue;
        }
        let twin = round_photon(f32_photon, origin, scale);
        assert_eq!(f16_photon.normal, twin.normal);
        let offset = vec3(twin.position) - origin;
        assert!(within_f16(
            vec3(f16_photon.position),
            vec3(twin.position),
            offset
        ));
        assert!(within_f16(
            vec3(f16_photon.flux),
            vec3(twin.flux),
            vec3(twin.flux)
        ));
        compared += 1;
    }
    assert!(compared > 1000, "{compared} photons stored");
    let points = full.backend().read_visible_points().expect("f32 points");
    let stored = half.backend().read_visible_points().expect("f16 points");
    let mut cut = 0;
    for ((f32_point, f16_point), &radius) in points.iter().zip(&stored).zip(&radii) {
        let kept = share_in_weight(f32_point, radius);
        cut += usize::from(kept.weight != f32_point.weight);
        let twin = round_visible_point(&kept, origin);
        assert_eq!(f16_point.is_valid(), twin.is_valid());
        if twin.is_valid() {
            let offset = vec3(twin.position) - origin;
            assert!(within_f16(
                vec3(f16_point.position),
                vec3(twin.position),
                offset
            ));
            assert!(within_f16(
                vec3(f16_point.weight),
                vec3(twin.weight),
                vec3(twin.weight)
            ));
        }
    }
    cut
}

fn rel_mse(a: &Image, b: &Image) -> f64 {
    let pairs = a.pixels.iter().zip(&b.pixels);
    let sum: f64 = pairs
        .map(|(p, q)| {
            let (p, q) = (p.as_dvec3(), q.as_dvec3());
            ((p - q) * (p - q) / (q * q + 1e-2)).element_sum() / 3.0
        })
        .sum();
    sum / a.pixels.len() as f64
}

/// Same seed: the f16 render differs from the f32 one by far less than another seed's does.
#[test]
fn f16_storage_renders_the_f32_picture() {
    let context = context();
    let image = |precision, seed| {
        let mut sppm = render(&context, precision, seed);
        sppm.run(Budget::Passes(8), &mut |_| {}).unwrap().image
    };
    let full = image(Precision::F32, 5);
    let half = image(Precision::F16, 5);
    let other_seed = image(Precision::F32, 6);
    let (rounding, noise) = (rel_mse(&half, &full), rel_mse(&other_seed, &full));
    println!("relMSE to f32: f16 {rounding:.6}, another seed {noise:.6}");
    assert!(
        rounding < 0.05 * noise,
        "f16 {rounding} against seed noise {noise}"
    );
    let mean = |i: &Image| i.mean().as_dvec3().element_sum();
    assert!((mean(&half) / mean(&full) - 1.0).abs() < 0.01);
}
