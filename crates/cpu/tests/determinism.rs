//! Same seed, same backend → the same image, bit for bit (the CPU backend's atomics only count
//! and take maxima, so thread timing cannot change a result); another seed → another image.

use render::{Budget, Image, Settings, Sppm};

fn render(seed: u32) -> Image {
    let scene = scene::testing::cornell_caustics();
    let bvh = bvh::PackedBvh::build(&scene.triangles, &bvh::BuildOptions::default());
    let camera = scene.camera(None).unwrap();
    let backend = cpu::CpuBackend::new(cpu::SceneData::new(&scene, bvh));
    let settings = Settings {
        seed,
        eye_every: 2,
        ..Settings::new(24, 24, 4096)
    };
    let mut sppm = Sppm::new(backend, &scene, &camera, settings).unwrap();
    sppm.run(Budget::Passes(6), &mut |_| {}).unwrap().image
}

#[test]
fn same_seed_gives_the_same_image() {
    let (a, b) = (render(5), render(5));
    assert!(a.pixels.iter().any(|p| p.max_element() > 0.0));
    assert_eq!(a, b);
    assert_ne!(a, render(6));
}
