//! Denoising guides (`render::guides`) read off the CPU backend's eye passes: exact where
//! every pixel shows one flat surface, directly or in a tinted mirror.

use glam::Vec3;
use render::guides::{GUIDE_EYE_PASSES, Guides};
use render::{Budget, Settings, Sppm};
use scene::{Camera, Scene, testing};

/// The guides of a `side`² render of `scene` through `camera` with an eye pass every pass.
fn guides_of(scene: &Scene, camera: &Camera, side: u32, passes: u32) -> Guides {
    let bvh = bvh::PackedBvh::build(&scene.triangles, &bvh::BuildOptions::default());
    let backend = cpu::CpuBackend::new(cpu::SceneData::new(scene, bvh));
    let settings = Settings {
        eye_every: 1,
        ..Settings::new(side, side, 1024)
    };
    let mut sppm = Sppm::new(backend, scene, camera, settings).expect("render started");
    sppm.collect_guides();
    sppm.run(Budget::Passes(passes), &mut |_| {})
        .expect("rendered");
    sppm.guides().expect("guides collected").clone()
}

fn sky_lit(mut scene: Scene) -> Scene {
    let bounds = scene.bounds();
    scene.lights.set_sky(Vec3::ONE, bounds);
    scene
}

fn assert_every_pixel(what: &str, pixels: &[Vec3], expected: Vec3, tolerance: f32) {
    for (i, p) in pixels.iter().enumerate() {
        assert!(
            p.abs_diff_eq(expected, tolerance),
            "{what}, pixel {i}: {p} against {expected}"
        );
    }
}

/// Looking straight down at the diffuse plane (albedo 0.5), which fills the view: every
/// pixel's albedo is the plane's and its normal +y, whatever the jitter.
#[test]
fn guides_show_the_plane_s_albedo_and_normal() {
    let scene = sky_lit(testing::punctual_plane(&[]));
    let above = Vec3::new(0.0, 0.5, 0.0);
    let camera = Camera::look_at(above, Vec3::ZERO, Vec3::NEG_Z, 60f32.to_radians()).unwrap();
    let guides = guides_of(&scene, &camera, 16, 3);
    assert_eq!(guides.eye_passes(), 3);
    let albedo = Vec3::splat(testing::LIT_PLANE_ALBEDO);
    assert_every_pixel("albedo", &guides.albedo().pixels, albedo, 1e-6);
    assert_every_pixel("normal", &guides.normal().pixels, Vec3::Y, 1e-4);
}

/// Seen only in a tinted mirror, the plane's albedo comes times the tint, and the normal is
/// the plane's (+y), not the mirror's: the guides show what the pixels gather at.
#[test]
fn guides_see_through_a_mirror_with_its_tint() {
    let scene = sky_lit(testing::plane_in_a_mirror());
    let camera = scene.camera(None).expect("the fixture's camera");
    let guides = guides_of(&scene, &camera, 16, 2);
    let albedo = testing::MIRROR_TINT * testing::LIT_PLANE_ALBEDO;
    assert_every_pixel("albedo", &guides.albedo().pixels, albedo, 1e-6);
    assert_every_pixel("normal", &guides.normal().pixels, Vec3::Y, 1e-4);
}

/// A long render reads back the first eye passes only.
#[test]
fn guides_average_their_share_of_eye_passes() {
    let scene = sky_lit(testing::punctual_plane(&[]));
    let camera = scene.camera(None).expect("the fixture's camera");
    let guides = guides_of(&scene, &camera, 4, GUIDE_EYE_PASSES + 6);
    assert_eq!(guides.eye_passes(), GUIDE_EYE_PASSES);
}
