//! Same seed, same backend → the same image, bit for bit, with every density estimator (the
//! CPU backend's atomics only count and take maxima, and the full hash's lists are filled in
//! photon order, so thread timing cannot change a result); another seed → another image.

use render::{Budget, Density, Image, Settings, Sppm};

fn render(seed: u32, density: Density) -> Image {
    let scene = scene::testing::cornell_caustics();
    let bvh = bvh::PackedBvh::build(&scene.triangles, &bvh::BuildOptions::default());
    let camera = scene.camera(None).unwrap();
    let backend = cpu::CpuBackend::new(cpu::SceneData::new(&scene, bvh));
    let settings = Settings {
        seed,
        eye_every: 2,
        density,
        ..Settings::new(24, 24, 4096)
    };
    let mut sppm = Sppm::new(backend, &scene, &camera, settings).unwrap();
    sppm.run(Budget::Passes(6), &mut |_| {}).unwrap().image
}

#[test]
fn same_seed_gives_the_same_image() {
    for density in Density::ALL {
        let (a, b) = (render(5, density), render(5, density));
        assert!(
            a.pixels.iter().any(|p| p.max_element() > 0.0),
            "{density:?}"
        );
        assert_eq!(a, b, "{density:?}");
        assert_ne!(a, render(6, density), "{density:?}");
    }
}
