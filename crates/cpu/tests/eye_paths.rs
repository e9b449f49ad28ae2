//! The extra eye paths of pixels that show a specular surface
//! (`render::buffers::SPECULAR_EXTRA_PATHS`): the same expectation as the first path alone,
//! with less variance; exact where every path is.

use cpu::kernels;
use glam::Vec3;
use render::Settings;
use render::buffers::SPECULAR_EXTRA_PATHS;
use render::{Backend, Sppm, Statistics};
use scene::testing;

/// Through the glass pane every eye path sees exactly the same (its way not taken counted at
/// once, `analytic.rs`), so the second eye pass, which traces extra paths in every pixel (each
/// met the glass first in the first pass), still adds exactly that: the average is
/// normalised right.
#[test]
fn glass_pane_stays_exact_with_extra_paths() {
    let scene = testing::glass_pane();
    let camera = scene.camera(None).expect("a camera");
    let expected = testing::glass_pane_radiance(1.0, render::optics::fresnel_dielectric);
    let settings = Settings {
        eye_every: 1,
        ..Settings::new(8, 8, 256)
    };
    let bvh = bvh::PackedBvh::build(&scene.triangles, &bvh::BuildOptions::default());
    let backend = cpu::CpuBackend::new(cpu::SceneData::new(&scene, bvh));
    let mut sppm = Sppm::new(backend, &scene, &camera, settings).expect("render started");
    sppm.pass();
    sppm.pass();
    let Statistics { pixels, .. } = sppm.backend().read_statistics().expect("statistics");
    for (i, p) in pixels.iter().enumerate() {
        assert_eq!(p.specular_seen, 1, "pixel {i} saw the glass first");
        for value in p.direct {
            assert!(
                (value / 2.0 / expected - 1.0).abs() < 1e-4,
                "pixel {i}: {value} over two passes against {expected} each"
            );
        }
    }
}

/// Per pass, for every pixel whose first pass met a specular surface first, the direct
/// estimate of the first path alone and with the extra paths averaged in: the same pass
/// index, so both start from the same first path and differ only by the extra paths.
#[test]
fn extra_paths_keep_the_expectation_and_cut_the_variance() {
    let scene = testing::cornell_caustics();
    let bvh = bvh::PackedBvh::build(&scene.triangles, &bvh::BuildOptions::default());
    let data = cpu::SceneData::new(&scene, bvh);
    let camera = scene.camera(None).expect("a camera");
    let settings = Settings {
        eye_every: 1,
        ..Settings::new(24, 24, 1024)
    };
    let params = render::integrator::params(&scene, &camera, &settings, data.lights.len() as u32);
    let pixels = params.pixel_count();
    let flagged: Vec<u32> = (0..pixels)
        .filter(|&i| kernels::eye_pass(&data, &params, 0, i, 0).specular_first)
        .collect();
    assert!(
        flagged.len() > 20,
        "{} pixels show the spheres",
        flagged.len()
    );

    let passes = 1000;
    let brightness = |v: Vec3| f64::from(v.element_sum());
    let (mut differences, mut squared_differences) = (0.0, 0.0);
    let (mut variance_alone, mut variance_extra) = (0.0, 0.0);
    for &pixel in &flagged {
        let (mut alone, mut extra) = (Vec::new(), Vec::new());
        for pass in 1..=passes {
            let first = kernels::eye_pass(&data, &params, pass, pixel, 0).direct;
            let averaged = kernels::eye_pass(&data, &params, pass, pixel, SPECULAR_EXTRA_PATHS);
            let (a, b) = (brightness(first), brightness(averaged.direct));
            differences += b - a;
            squared_differences += (b - a) * (b - a);
            alone.push(a);
            extra.push(b);
        }
        variance_alone += variance(&alone);
        variance_extra += variance(&extra);
    }
    let n = (flagged.len() * passes as usize) as f64;
    let mean = differences / n;
    let standard_error = ((squared_differences / n - mean * mean) / (n - 1.0)).sqrt();
    assert!(
        mean.abs() < 4.0 * standard_error,
        "extra paths moved the mean by {mean:e} (standard error {standard_error:e})"
    );
    let ratio = variance_extra / variance_alone;
    assert!(
        ratio < 0.8,
        "variance with the extra paths {ratio:.3} of the first path's alone"
    );
}

fn variance(values: &[f64]) -> f64 {
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    values.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>() / (n - 1.0)
}
