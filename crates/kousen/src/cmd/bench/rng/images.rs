//! `kousen bench rng --image DIR`: SPPM renders with each generator, and plots of successive
//! pairs of each generator's draws (where a coarse generator's lattice shows).

use render::tonemap::Look;
use std::path::Path;
use std::time::Instant;

use serde::Serialize;

use gpu::GpuContext;
use gpu::random_variants::{Generator, sppm_source_with};
use gpu::sppm::GpuBackend;
use render::random::{FractSin, Pcg, StreamRng, TalkFloat, Tea};
use render::{Settings, Sppm};

use super::load;
use crate::cli::RngArgs;

#[derive(Serialize)]
pub(super) struct ImageRow {
    generator: &'static str,
    path: String,
    width: u32,
    height: u32,
    passes: u32,
    seconds: f64,
}

/// Side of the pair plots, in pixels.
const PAIRS_SIDE: u32 = 256;
/// The pair plots show [0, 1/16)²: zoomed so that a coarse output's lattice is plain.
const PAIRS_ZOOM: f32 = 16.0;
/// Streams drawn for the pair plots (4 pairs each): about 16 k pairs land in the plot.
const PAIRS_STREAMS: u32 = 1 << 20;

/// Successive draws (2k, 2k + 1) of `G`'s CPU twin, plotted where both fall in [0, 1/16):
/// white where at least one pair landed.
fn pairs_image<G: StreamRng>() -> render::Image {
    let side = PAIRS_SIDE as usize;
    let mut lit = vec![false; side * side];
    for index in 0..PAIRS_STREAMS {
        let mut rng = G::start(1, render::rng::PHOTON_STREAM, 0, index);
        for _ in 0..4 {
            let (x, y) = (rng.next_f32() * PAIRS_ZOOM, rng.next_f32() * PAIRS_ZOOM);
            if x < 1.0 && y < 1.0 {
                let (i, j) = ((x * side as f32) as usize, (y * side as f32) as usize);
                lit[(side - 1 - j.min(side - 1)) * side + i.min(side - 1)] = true;
            }
        }
    }
    let pixels = lit
        .into_iter()
        .map(|l| glam::Vec3::splat(if l { 1.0 } else { 0.0 }))
        .collect();
    render::Image::new(PAIRS_SIDE, PAIRS_SIDE, pixels)
}

fn write_pairs_images(dir: &Path) -> anyhow::Result<()> {
    let images = [
        (Pcg::NAME, pairs_image::<Pcg>()),
        (TalkFloat::NAME, pairs_image::<TalkFloat>()),
        (Tea::NAME, pairs_image::<Tea>()),
        (FractSin::NAME, pairs_image::<FractSin>()),
    ];
    for (name, image) in images {
        let file = dir.join(format!("rng-pairs-{name}.png"));
        crate::image_io::Output::create_with(&file, Default::default())?
            .commit(&image, Look::default())?;
        println!("image {}: successive pairs in [0, 1/16)²", file.display());
    }
    Ok(())
}

/// SPPM on the GPU with each generator: `--image-size`², `--image-passes` passes, one photon
/// slot per pixel, the same seed; PNGs at exposure 0.
pub(super) fn render_images(
    args: &RngArgs,
    context: &GpuContext,
    path: &Path,
    dir: &Path,
) -> anyhow::Result<Vec<ImageRow>> {
    let loaded = load(args, path)?;
    let side = args.image_size;
    let settings = Settings {
        initial_radius: render::integrator::initial_radius_from_view(
            &loaded.bvh,
            &loaded.camera,
            side,
            side,
        ),
        ..Settings::new(side, side, side * side)
    };
    write_pairs_images(dir)?;
    let mut rows = Vec::new();
    for g in Generator::ALL {
        let file = dir.join(format!("rng-{}.png", g.name()));
        let output = crate::image_io::Output::create_with(&file, Default::default())?;
        let backend = GpuBackend::with_kernels(
            context.clone(),
            &loaded.scene,
            loaded.bvh.clone(),
            g.part().0,
            sppm_source_with(g),
        )?;
        let mut sppm = Sppm::new(backend, &loaded.scene, &loaded.camera, settings.clone())?;
        let started = Instant::now();
        for _ in 0..args.image_passes {
            sppm.pass();
        }
        let image = sppm.image()?;
        let seconds = started.elapsed().as_secs_f64();
        output.commit(&image, Look::default())?;
        println!(
            "image {}: {} passes in {seconds:.1} s on the GPU",
            file.display(),
            args.image_passes
        );
        rows.push(ImageRow {
            generator: g.name(),
            path: file.display().to_string(),
            width: side,
            height: side,
            passes: args.image_passes,
            seconds,
        });
    }
    Ok(rows)
}
