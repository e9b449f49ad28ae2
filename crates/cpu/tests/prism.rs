//! Newton's experiment end to end (`scene::testing::prism`, shipped as `scenes/prism.gltf`):
//! SPPM on the CPU backend spreads the spot's beam through the flint prism into a band on
//! the floor, in the order the Cauchy index gives (violet bent most, nearest the prism),
//! with every hue between, each colour where Snell's law sends its wavelengths.

use glam::Vec3;
use render::dispersion::{WAVELENGTH_LEVELS, level_wavelength, level_weight, wavelength_ior};
use render::optics::refract;
use render::{Budget, Image, Settings, Sppm};
use scene::{Scene, Surface, testing};

const WIDTH: u32 = 128;
const HEIGHT: u32 = 96;

/// The prism scene rendered on the CPU backend: 2¹⁶ photon slots, `passes` passes.
fn render_prism(scene: &Scene, passes: u32) -> Image {
    let camera = scene.camera(None).unwrap();
    let bvh = bvh::PackedBvh::build(&scene.triangles, &bvh::BuildOptions::default());
    let backend = cpu::CpuBackend::new(cpu::SceneData::new(scene, bvh));
    let settings = Settings::new(WIDTH, HEIGHT, 1 << 16);
    let mut sppm = Sppm::new(backend, scene, &camera, settings).unwrap();
    sppm.run(Budget::Passes(passes), &mut |_| {}).unwrap().image
}

/// The band's pixels by their brightest channel: along the image's x (the floor's, away from
/// the prism), blue first, then green, then red; and hues between among them (yellow: red
/// and green over 0.35 of the brightest channel, blue under half of them; cyan: green and
/// blue). 128 × 96 pixels, 32 passes ([`render_prism`]): the band's pixels are those at least
/// 4× the floor's median brightness with one channel below a quarter of the brightest.
/// Seeds 1–10: 22–31 band pixels, centroids blue 86.3–88.4, green 92.8–94.5, red 97.4–98.7;
/// 7–13 yellow and 1–7 cyan pixels (cyan is a narrow part of the spectrum in sRGB).
/// Tolerances: the centroids a pixel apart in order; a yellow pixel and four between.
#[test]
fn the_prism_spreads_its_beam_into_a_spectrum() {
    let image = render_prism(&testing::prism(), 32);

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

/// Where the spot's central ray of `lambda` nm meets the floor (its x; it stays at z = 0):
/// refracted into the prism's left face and out of its right face by Snell's law at the
/// flint's index for that wavelength.
fn landing_x(scene: &Scene, lambda: f32) -> f32 {
    let light = scene.lights.punctual[0].light;
    let flint = (scene.materials.iter())
        .find(|m| m.dispersion > 0.0)
        .expect("the flint prism");
    let Surface::Dielectric { ior, .. } = flint.surface else {
        panic!("the prism is smooth glass");
    };
    let n = wavelength_ior(ior, flint.dispersion, lambda);
    let [left, right, apex] = testing::prism_cross_section();
    // A face's outward normal, from its corners in counter-clockwise order.
    let outward = |a: Vec3, b: Vec3| {
        let edge = (b - a).normalize();
        Vec3::new(edge.y, -edge.x, 0.0)
    };
    let (in_face, out_face) = (outward(apex, left), outward(right, apex));
    let meet = |origin: Vec3, direction: Vec3, corner: Vec3, normal: Vec3| {
        origin + direction * ((corner - origin).dot(normal) / direction.dot(normal))
    };
    let entry = meet(light.position, light.direction, left, in_face);
    let inside = refract(light.direction, in_face, 1.0 / n).expect("enters");
    let exit = meet(entry, inside, right, out_face);
    let out = refract(inside, -out_face, n).expect("leaves");
    exit.x - exit.y / out.y * out.x
}

/// Each colour's centroid on the floor against Snell's law: the band's red, green and blue
/// light, weighted by the pixels' radiance above the floor's, centres where the levels'
/// landing points weighted by their colours do (predicted 1.796, 1.718 and 1.541 m from the
/// prism's axis). Pixels are taken to the floor through the camera; those within 0.4 m of the
/// beam's plane and over twice the floor's brightness count. The prediction follows the
/// central ray (the 1° cone and the pixels blur the band around it). 96 passes, six seeds:
/// measured − predicted red −1.4 to −0.1 cm, green −0.4 to +0.7, blue +0.3 to +1.7 (the
/// blue's faint violet end, nearest the prism, falls under the brightness cut; at 32 passes
/// up to 3.4 cm off). Tolerance: 2.5 cm (green lies 8 cm from red and 18 cm from blue).
#[test]
fn each_colour_lands_where_snell_s_law_sends_it() {
    let scene = testing::prism();
    let image = render_prism(&scene, 96);
    let predicted = Vec3::from_array([0, 1, 2].map(|c| {
        let (mut sum, mut weight) = (0.0, 0.0);
        for level in 0..WAVELENGTH_LEVELS {
            let w = level_weight(level)[c];
            sum += w * landing_x(&scene, level_wavelength(level));
            weight += w;
        }
        sum / weight
    }));
    let camera = scene.camera(None).unwrap();
    let aspect = WIDTH as f32 / HEIGHT as f32;
    // The floor point each pixel sees, where it sees the floor near the beam's plane.
    let floor: Vec<(f32, Vec3)> = (0..WIDTH * HEIGHT)
        .filter_map(|i| {
            let (x, y) = (i % WIDTH, i / WIDTH);
            let sx = (x as f32 + 0.5) / WIDTH as f32 * 2.0 - 1.0;
            let sy = 1.0 - (y as f32 + 0.5) / HEIGHT as f32 * 2.0;
            let direction = camera.direction(sx, sy, aspect);
            let point = camera.eye - direction * (camera.eye.y / direction.y);
            (direction.y < 0.0 && point.z.abs() < 0.4 && point.x > 0.5 && point.x < 2.5)
                .then_some((point.x, image.pixels[i as usize]))
        })
        .collect();
    let mut sums: Vec<f32> = floor.iter().map(|(_, p)| p.element_sum()).collect();
    sums.sort_by(f32::total_cmp);
    let background = sums[sums.len() / 2];
    let lit: Vec<&(f32, Vec3)> = (floor.iter())
        .filter(|(_, p)| p.element_sum() > 2.0 * background)
        .collect();
    let measured = Vec3::from_array([0, 1, 2].map(|c| {
        let share = |p: Vec3| (p[c] - background / 3.0).max(0.0);
        let weight: f32 = lit.iter().map(|(_, p)| share(*p)).sum();
        lit.iter().map(|(x, p)| x * share(*p)).sum::<f32>() / weight
    }));
    println!("prism: colours' centroids measured {measured}, predicted {predicted}");
    assert!(
        (measured - predicted).abs().max_element() < 0.025,
        "measured {measured} against {predicted}"
    );
    assert!(predicted.z < predicted.y && predicted.y < predicted.x);
}
