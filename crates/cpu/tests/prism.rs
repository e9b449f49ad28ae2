//! Newton's experiment end to end (`scene::testing::prism`, shipped as `scenes/prism.gltf`):
//! SPPM on the CPU backend spreads the spot's beam through the flint prism into a band on
//! the floor, in the order the Cauchy index gives (violet bent most, nearest the prism) and
//! with every hue between.

use render::{Budget, Settings, Sppm};
use scene::testing;

/// The band's pixels by their brightest channel: along the image's x (the floor's, away from
/// the prism), blue first, then green, then red; and hues between among them (yellow: red
/// and green over 0.35 of the brightest channel, blue under half of them; cyan: green and
/// blue). 128 × 96 pixels, 2¹⁶ photon slots, 32 passes: the band's pixels are those at least
/// 4× the floor's median brightness with one channel below a quarter of the brightest.
/// Seeds 1–10: 22–31 band pixels, centroids blue 86.3–88.4, green 92.8–94.5, red 97.4–98.7;
/// 7–13 yellow and 1–7 cyan pixels (cyan is a narrow part of the spectrum in sRGB).
/// Tolerances: the centroids a pixel apart in order; a yellow pixel and four between.
#[test]
fn the_prism_spreads_its_beam_into_a_spectrum() {
    let scene = testing::prism();
    let camera = scene.camera(None).unwrap();
    let bvh = bvh::PackedBvh::build(&scene.triangles, &bvh::BuildOptions::default());
    let backend = cpu::CpuBackend::new(cpu::SceneData::new(&scene, bvh));
    let settings = Settings::new(128, 96, 1 << 16);
    let mut sppm = Sppm::new(backend, &scene, &camera, settings).unwrap();
    let image = sppm.run(Budget::Passes(32), &mut |_| {}).unwrap().image;

    let mut brightness: Vec<f32> = image.pixels.iter().map(|p| p.element_sum()).collect();
    brightness.sort_by(f32::total_cmp);
    let median = brightness[brightness.len() / 2];
    // Each band pixel: its column and colour.
    let band: Vec<(f32, glam::Vec3)> = (image.pixels.iter().enumerate())
        .filter(|(_, p)| p.element_sum() > 4.0 * median && p.min_element() < 0.25 * p.max_element())
        .map(|(i, p)| ((i % image.width as usize) as f32, *p))
        .collect();
    let centroid = |channel: usize| {
        let columns: Vec<f32> = (band.iter())
            .filter(|(_, p)| p.max_element() == p[channel])
            .map(|(x, _)| *x)
            .collect();
        assert!(
            columns.len() >= 3,
            "channel {channel}: {} pixels",
            columns.len()
        );
        columns.iter().sum::<f32>() / columns.len() as f32
    };
    let [red, green, blue] = [0, 1, 2].map(centroid);
    let between = |a: usize, b: usize, off: usize| {
        (band.iter())
            .filter(|(_, p)| {
                p[a].min(p[b]) > 0.35 * p.max_element() && p[off] < 0.5 * p[a].min(p[b])
            })
            .count()
    };
    let (yellow, cyan) = (between(0, 1, 2), between(1, 2, 0));
    println!(
        "prism: {} band pixels; centroids blue {blue:.1}, green {green:.1}, red {red:.1}; \
         yellow {yellow}, cyan {cyan}",
        band.len()
    );
    assert!(
        blue + 1.0 < green && green + 1.0 < red,
        "the band's order: blue {blue}, green {green}, red {red}"
    );
    assert!(
        yellow >= 1 && yellow + cyan >= 4,
        "hues between: yellow {yellow}, cyan {cyan}"
    );
}
