//! SPPM converges: on the Cornell box, renders with more passes come closer to a reference
//! rendered with many more passes (another seed), at a rate SPPM's analysis predicts.

use render::{Budget, Image, Settings, Sppm};
use scene::{Scene, testing};

/// 2^12 photon slots a pass: at 32×32 the hash's cells (2 R wide) each still receive tens
/// of photons a pass, and a cell keeps one, so more photons a pass would add little; more
/// passes are what lowers the error.
const PHOTONS: u32 = 1 << 12;
const REFERENCE_PASSES: u32 = 768;

fn render(scene: &Scene, passes: u32, seed: u32) -> Rendered {
    let bvh = bvh::PackedBvh::build(&scene.triangles, &bvh::BuildOptions::default());
    let backend = cpu::CpuBackend::new(cpu::SceneData::new(scene, bvh));
    let camera = scene.camera(None).unwrap();
    // An eye pass every pass: with the default (one per 8) a 4-pass render has a single
    // eye sample per pixel, and the pixels on the light's edges (radiance 17 over part of
    // the pixel) dominate the error with anti-aliasing noise, the reference's included.
    let settings = Settings {
        seed,
        eye_every: 1,
        ..Settings::new(32, 32, PHOTONS)
    };
    let mut sppm = Sppm::new(backend, scene, &camera, settings).unwrap();
    let out = sppm.run(Budget::Passes(passes), &mut |_| {}).unwrap();
    Rendered {
        image: out.image,
        seconds: out.seconds,
    }
}

struct Rendered {
    image: Image,
    seconds: f64,
}

/// Mean over pixels and channels of (a − b)² / (b² + 10⁻²).
fn rel_mse(image: &Image, reference: &Image) -> f64 {
    let sum: f64 = image
        .pixels
        .iter()
        .zip(&reference.pixels)
        .flat_map(|(a, b)| (0..3).map(move |c| (a[c] as f64, b[c] as f64)))
        .map(|(a, b)| (a - b).powi(2) / (b * b + 1e-2))
        .sum();
    sum / (3 * reference.pixels.len()) as f64
}

/// relMSE against a 768-pass reference at 4, 16 and 64 passes falls at every step, and the
/// log-log slope from 4 to 64 passes is below −0.45.
///
/// SPPM's error falls roughly as passes^(−2/3) … passes^(−1) (variance and radius bias both
/// shrink); the reference's own error (relMSE 0.0025 between two 1024-pass references, so
/// about 0.0015 each at 768 passes, 7% of the 64-pass error) flattens the measured slope a
/// little. Measured (seed 2 against seed 1): relMSE 0.129, 0.052, 0.023 at 4, 16, 64 passes,
/// slope −0.62 (−0.72 out to 256 passes); seeds 3, 4, 5 give slopes −0.59, −0.69, −0.61. The
/// bound −0.45 leaves room for another seed's luck (a factor 1.6 in the 64-pass error) while
/// failing an estimator that stops converging (slope 0) or converges only as slowly as the
/// radius alone shrinks.
#[test]
fn cornell_box_converges_towards_a_reference() {
    let scene = testing::cornell_box();
    let reference = render(&scene, REFERENCE_PASSES, 1);
    println!(
        "reference: {REFERENCE_PASSES} passes × {PHOTONS} slots in {:.2} s, mean {}",
        reference.seconds,
        reference.image.mean()
    );
    let passes = [4u32, 16, 64];
    let errors: Vec<f64> = passes
        .iter()
        .map(|&n| {
            let rendered = render(&scene, n, 2);
            let error = rel_mse(&rendered.image, &reference.image);
            println!(
                "{n:3} passes: relMSE {error:.5} in {:.2} s, mean {}",
                rendered.seconds,
                rendered.image.mean()
            );
            error
        })
        .collect();
    let slope = (errors[2] / errors[0]).ln() / (passes[2] as f64 / passes[0] as f64).ln();
    println!(
        "log-log slope from {} to {} passes: {slope:.3}",
        passes[0], passes[2]
    );

    assert!(errors.iter().all(|e| e.is_finite()), "{errors:?}");
    for k in 1..errors.len() {
        assert!(
            errors[k] < errors[k - 1],
            "relMSE rose from {} passes ({}) to {} passes ({})",
            passes[k - 1],
            errors[k - 1],
            passes[k],
            errors[k]
        );
    }
    assert!(
        slope < -0.45,
        "relMSE falls as passes^{slope:.3}, slower than passes^-0.45: {errors:?}"
    );
}
